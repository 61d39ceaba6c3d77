//! `tetkit probe`: values of every array at given points, located with the O(N) grid.

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use serde_json::{json, Value};
use std::path::PathBuf;

use crate::locate::{GridParams, TetLocator};
use crate::mesh::TetMesh;
use crate::partition::ORIGINAL_CELL_ID;
use formats::ArrayData;

#[derive(Args, Debug)]
pub struct ProbeArgs {
    /// Tet mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts), or - for stdin.
    pub input: PathBuf,
    /// Points: `x,y,z` (repeat the option or separate with `;`), or a text file with one point
    /// per line (numbers separated by spaces or commas; `#` starts a comment), or a CSV file
    /// with a header naming the coordinate columns (ParaView's `Points:0`, `Points:1`,
    /// `Points:2`, or `x`, `y`, `z`; other columns are ignored).
    #[arg(
        long,
        required = true,
        value_name = "X,Y,Z|FILE",
        allow_hyphen_values = true
    )]
    pub points: Vec<String>,
    /// Print one JSON object per point instead of CSV.
    #[arg(long)]
    pub json: bool,
    /// Print the grid's cell and reference counts (the paper's Table 1 measures) on stderr.
    #[arg(long)]
    pub grid_stats: bool,
    /// Grid density lambda (cells per primitive at each level).
    #[arg(long, default_value_t = 1.0)]
    pub lambda: f64,
    /// Algorithm 2's cell-to-primitive size ratio alpha.
    #[arg(long, default_value_t = 2.0)]
    pub alpha: f64,
    /// Smallest sub-grid (cells) worth building, gamma.
    #[arg(long, default_value_t = 16)]
    pub gamma: usize,
}

fn parse_point(s: &str, place: &str) -> Result<[f64; 3]> {
    let parts: Vec<&str> = s
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|p| !p.is_empty())
        .collect();
    if parts.len() != 3 {
        bail!("{place}: '{s}': expected three numbers x,y,z");
    }
    let mut p = [0.0; 3];
    for (k, t) in parts.iter().enumerate() {
        p[k] = finite(t, place)?;
    }
    Ok(p)
}

/// `t` as a finite number, or an error naming `place`.
fn finite(t: &str, place: &str) -> Result<f64> {
    t.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| anyhow!("{place}: '{t}' is not a finite number"))
}

/// Names a CSV header may give the x, y and z columns (compared without quotes or case):
/// ParaView's "Save Data" writes `Points:0`..`Points:2` (after the point arrays), other tools
/// `Points_0`.. or `x`, `y`, `z`.
const COORD_COLUMNS: [[&str; 4]; 3] = [
    ["points:0", "points_0", "x", "coordinates:0"],
    ["points:1", "points_1", "y", "coordinates:1"],
    ["points:2", "points_2", "z", "coordinates:2"],
];

/// The columns of x, y and z when `line` is a CSV header (a field that is not a number);
/// `None` when it is a line of numbers. A header without those columns is an error naming it.
fn header_columns(line: &str, place: &str) -> Result<Option<[usize; 3]>> {
    let fields: Vec<String> = line
        .split(',')
        .map(|f| f.trim().trim_matches('"').trim().to_ascii_lowercase())
        .collect();
    let numeric = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .all(|t| t.parse::<f64>().is_ok());
    if numeric {
        return Ok(None);
    }
    let mut cols = [0usize; 3];
    for (axis, names) in COORD_COLUMNS.iter().enumerate() {
        cols[axis] = fields
            .iter()
            .position(|f| names.contains(&f.as_str()))
            .ok_or_else(|| {
                anyhow!(
                    "{place}: a header without a column for {} (expected one of {}; \
                     ParaView's CSV export names them Points:0, Points:1, Points:2)",
                    ["x", "y", "z"][axis],
                    names.join(", ")
                )
            })?;
    }
    Ok(Some(cols))
}

/// The point in columns `cols` of the CSV line `line`.
fn csv_point(line: &str, cols: [usize; 3], place: &str) -> Result<[f64; 3]> {
    let fields: Vec<&str> = line
        .split(',')
        .map(|f| f.trim().trim_matches('"'))
        .collect();
    let mut p = [0.0; 3];
    for (k, &c) in cols.iter().enumerate() {
        let t = fields.get(c).ok_or_else(|| {
            anyhow!(
                "{place}: {} fields, but the header puts {} in column {}",
                fields.len(),
                ["x", "y", "z"][k],
                c + 1
            )
        })?;
        p[k] = finite(t, &format!("{place}, column {}", c + 1))?;
    }
    Ok(p)
}

/// The points the options name, in order.
pub fn gather_points(specs: &[String]) -> Result<Vec<[f64; 3]>> {
    let mut out = Vec::new();
    for s in specs {
        let path = std::path::Path::new(s);
        if path.is_file() {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("{}: reading", path.display()))?;
            // Set by a header line (the file's first): the columns of x, y and z.
            let mut columns: Option<[usize; 3]> = None;
            let mut first = true;
            for (i, line) in text.lines().enumerate() {
                let line = line.split('#').next().unwrap_or("").trim();
                if line.is_empty() {
                    continue;
                }
                let place = format!("{}: line {}", path.display(), i + 1);
                if std::mem::take(&mut first) {
                    columns = header_columns(line, &place)?;
                    if columns.is_some() {
                        continue;
                    }
                }
                out.push(match columns {
                    Some(cols) => csv_point(line, cols, &place)?,
                    None => parse_point(line, &place)?,
                });
            }
        } else {
            for part in s.split(';').filter(|p| !p.trim().is_empty()) {
                out.push(parse_point(part, "--points")?);
            }
        }
    }
    if out.is_empty() {
        // An empty CSV with exit 0 reads as "probed, nothing found" in a script.
        bail!(
            "--points {}: no points given (expected x,y,z;x,y,z... or files of x y z lines)",
            specs
                .iter()
                .map(|s| format!("'{s}'"))
                .collect::<Vec<_>>()
                .join(" ")
        );
    }
    Ok(out)
}

/// One probed value, kept in its array's kind so integers (ids, flags, markers) print exactly
/// and strings print at all.
#[derive(Clone, Debug, PartialEq)]
pub enum Sample {
    Float(f64),
    Int(i128),
    Text(String),
}

impl Sample {
    /// Value `i` of `data` as it is stored.
    fn of(data: &ArrayData, i: usize) -> Sample {
        match data {
            ArrayData::Int8(v) => Sample::Int(v[i].into()),
            ArrayData::UInt8(v) => Sample::Int(v[i].into()),
            ArrayData::Int16(v) => Sample::Int(v[i].into()),
            ArrayData::UInt16(v) => Sample::Int(v[i].into()),
            ArrayData::Int32(v) => Sample::Int(v[i].into()),
            ArrayData::UInt32(v) => Sample::Int(v[i].into()),
            ArrayData::Int64(v) => Sample::Int(v[i].into()),
            ArrayData::UInt64(v) => Sample::Int(v[i].into()),
            ArrayData::Float32(v) => Sample::Float(v[i].into()),
            ArrayData::Float64(v) => Sample::Float(v[i]),
            ArrayData::String(v) => Sample::Text(v[i].clone()),
        }
    }

    fn to_json(&self) -> Value {
        match self {
            Sample::Float(x) => json!(x),
            // Every stored integer type fits i64 or u64.
            Sample::Int(x) => i64::try_from(*x)
                .map(Value::from)
                .or_else(|_| u64::try_from(*x).map(Value::from))
                .unwrap_or(Value::Null),
            Sample::Text(s) => json!(s),
        }
    }

    fn to_csv(&self) -> String {
        match self {
            Sample::Float(x) => csv_float(*x),
            Sample::Int(x) => x.to_string(),
            Sample::Text(s) => csv_field(s),
        }
    }
}

/// A float as the shortest text that reads back to it, with an exponent where plain digits
/// would run long (`1e308` printed 309 digits, `1e-30` thirty zeros).
fn csv_float(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// RFC 4180 quoting: a field holding a comma, a quote or a line break is quoted, its quotes
/// doubled (array names and string values come from the file, and may hold any of them).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The name each array is reported under: its own, or `point:NAME` / `cell:NAME` when point and
/// cell data both hold an array of that name (ParaView files often do), so neither hides the
/// other in the JSON object or the CSV header.
fn labels(mesh: &TetMesh) -> Vec<String> {
    let in_cells = |n: &str| mesh.cell_data.arrays.iter().any(|a| a.name == n);
    let in_points = |n: &str| mesh.point_data.arrays.iter().any(|a| a.name == n);
    let points = mesh.point_data.arrays.iter().map(|a| {
        if in_cells(&a.name) {
            format!("point:{}", a.name)
        } else {
            a.name.clone()
        }
    });
    let cells = mesh.cell_data.arrays.iter().map(|a| {
        if in_points(&a.name) {
            format!("cell:{}", a.name)
        } else {
            a.name.clone()
        }
    });
    points.chain(cells).collect()
}

/// A located point: its tet and, for every point then cell array, its tuple there.
pub type Probed = Option<(u32, Vec<Vec<Sample>>)>;

/// Each point's tet and every array's value there, `None` outside the mesh. Float point data is
/// interpolated linearly; integer and string point data take the nearest vertex's value (the
/// largest barycentric weight), since a blend of ids, flags or markers means nothing (as
/// `partition` does at new vertices); cell data is the containing tet's.
pub fn probe(mesh: &TetMesh, loc: &TetLocator, points: &[[f64; 3]]) -> Vec<Probed> {
    points
        .iter()
        .map(|p| {
            let (t, b) = loc.locate(&mesh.points, &mesh.tets, p)?;
            let tet = mesh.tets[t as usize];
            let nearest = (1..4).fold(0, |m, j| if b[j] > b[m] { j } else { m });
            let mut vals = Vec::new();
            for a in &mesh.point_data.arrays {
                let c = a.components.max(1);
                let float = matches!(a.data, ArrayData::Float32(_) | ArrayData::Float64(_));
                let v: Vec<Sample> = (0..c)
                    .map(|k| {
                        if float {
                            Sample::Float(
                                (0..4)
                                    .map(|j| b[j] * a.data.get_f64(tet[j] as usize * c + k))
                                    .sum(),
                            )
                        } else {
                            Sample::of(&a.data, tet[nearest] as usize * c + k)
                        }
                    })
                    .collect();
                vals.push(v);
            }
            for a in &mesh.cell_data.arrays {
                let c = a.components.max(1);
                let v = (0..c)
                    .map(|k| Sample::of(&a.data, t as usize * c + k))
                    .collect();
                vals.push(v);
            }
            Some((t, vals))
        })
        .collect()
}

pub fn run(args: &ProbeArgs) -> Result<()> {
    let points = gather_points(&args.points)?;
    let grid = super::read_input(&args.input)?;
    // Meshes with other cells (TetGen's .face triangles, Gmsh's boundary elements, quadratic
    // cells) are probed through their tets; `tet` reports the input cell that holds the point.
    let (mut mesh, input_cell) =
        super::tets_with_input_cells(&grid, &args.input.display().to_string())?;
    // Splitting other cells into tets adds `original_cell_id`; `tet` already reports the input
    // cell, and only the input's own arrays are probed.
    if grid.cell_data.get(ORIGINAL_CELL_ID).is_none() {
        mesh.cell_data.arrays.retain(|a| a.name != ORIGINAL_CELL_ID);
    }
    let params = GridParams {
        lambda: args.lambda,
        alpha: args.alpha,
        gamma: args.gamma,
        ..GridParams::default()
    };
    if !(params.lambda > 0.0 && params.alpha > 0.0) {
        bail!("--lambda and --alpha must be positive");
    }
    let t0 = std::time::Instant::now();
    let loc = TetLocator::build(&mesh.points, &mesh.tets, params);
    let build_s = t0.elapsed().as_secs_f64();
    if args.grid_stats {
        let s = loc.grid.stats;
        eprintln!(
            "grid over {} tets: {} cells ({:.2} per tet), {} references ({:.2} per tet), {} grids, {} levels, built in {:.3} s",
            s.primitives,
            s.cells,
            s.cells_per_primitive(),
            s.references,
            s.refs_per_primitive(),
            s.grids,
            s.depth,
            build_s
        );
    }
    let results: Vec<Probed> = probe(&mesh, &loc, &points)
        .into_iter()
        .map(|r| r.map(|(t, v)| (input_cell[t as usize] as u32, v)))
        .collect();
    let names = labels(&mesh);
    let mut out = String::new();
    if args.json {
        for (p, r) in points.iter().zip(&results) {
            let v: Value = match r {
                None => json!({"point": p, "tet": null}),
                Some((t, vals)) => {
                    let mut m = serde_json::Map::new();
                    for (n, v) in names.iter().zip(vals) {
                        let value = match v.as_slice() {
                            [one] => one.to_json(),
                            many => Value::Array(many.iter().map(Sample::to_json).collect()),
                        };
                        m.insert(n.clone(), value);
                    }
                    json!({"point": p, "tet": t, "values": m})
                }
            };
            out.push_str(&v.to_string());
            out.push('\n');
        }
    } else {
        // Header from the arrays (same for every point).
        let mut header = vec!["x".to_string(), "y".into(), "z".into(), "tet".into()];
        let mut width = 0;
        for (a, n) in mesh
            .point_data
            .arrays
            .iter()
            .chain(&mesh.cell_data.arrays)
            .zip(&names)
        {
            let c = a.components.max(1);
            width += c;
            if c == 1 {
                header.push(csv_field(n));
            } else {
                header.extend((0..c).map(|k| csv_field(&format!("{n}_{k}"))));
            }
        }
        out.push_str(&header.join(","));
        out.push('\n');
        for (p, r) in points.iter().zip(&results) {
            let mut row = vec![csv_float(p[0]), csv_float(p[1]), csv_float(p[2])];
            match r {
                None => {
                    row.push(String::new());
                    row.extend(std::iter::repeat_n(String::new(), width));
                }
                Some((t, vals)) => {
                    row.push(t.to_string());
                    for v in vals {
                        row.extend(v.iter().map(Sample::to_csv));
                    }
                }
            }
            out.push_str(&row.join(","));
            out.push('\n');
        }
    }
    use std::io::Write;
    std::io::stdout()
        .lock()
        .write_all(out.as_bytes())
        .context("writing stdout")?;
    Ok(())
}
