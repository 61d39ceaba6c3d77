//! `tetkit convert`: any supported format to any other, optionally tetrahedralizing.

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use formats::{ArrayData, Compression, Encoding, Format, LegacyVersion, WriteOptions};
use std::path::PathBuf;

use crate::mesh::tetrahedralize::tetrahedralize;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum EncodingArg {
    Appended,
    Binary,
    Ascii,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CompressArg {
    None,
    Zlib,
    Lz4,
    Lzma,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum LegacyVersionArg {
    #[value(name = "4.2")]
    V42,
    #[value(name = "5.1")]
    V51,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input mesh (.vtu, .pvtu, .vtk, .node/.ele, .mesh, .msh, .exo, .vtkhdf, .vtm, .pvd, .vti/.vtr/.vts,
    /// FILE.pvd@STEP, FILE.exo@STEP), or - for stdin (VTU, legacy VTK, Medit, Gmsh MSH or Exodus II).
    pub input: PathBuf,
    /// Output mesh; the extension picks the format. - writes to stdout (see --to).
    #[arg(value_name = "OUTPUT", required_unless_present = "output_flag")]
    pub output: Option<PathBuf>,
    /// The output mesh as an option, as the other subcommands take it (`-o OUT`).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "OUTPUT",
        conflicts_with = "output"
    )]
    pub output_flag: Option<PathBuf>,
    /// VTU: appended raw (ParaView's default), inline base64 binary, or ascii. Legacy: binary or ascii.
    #[arg(long, value_enum, default_value = "appended")]
    pub encoding: EncodingArg,
    /// Compression of VTU binary data.
    #[arg(long = "compress", value_enum, default_value = "none")]
    pub compress: CompressArg,
    /// Legacy VTK file version to write.
    #[arg(long, value_enum, default_value = "5.1")]
    pub legacy_version: LegacyVersionArg,
    /// Split hexahedra, wedges, pyramids, voxels and quadratic tets into conforming linear tets.
    #[arg(long)]
    pub tetrahedralize: bool,
    /// Output format when writing to stdout: vtu, vtk or mesh (Medit).
    #[arg(long, default_value = "vtu")]
    pub to: String,
}

impl ConvertArgs {
    pub fn write_options(&self) -> WriteOptions {
        WriteOptions {
            encoding: match self.encoding {
                EncodingArg::Appended => Encoding::Appended,
                EncodingArg::Binary => Encoding::Binary,
                EncodingArg::Ascii => Encoding::Ascii,
            },
            compression: match self.compress {
                CompressArg::None => Compression::None,
                CompressArg::Zlib => Compression::Zlib,
                CompressArg::Lz4 => Compression::Lz4,
                CompressArg::Lzma => Compression::Lzma,
            },
            legacy_version: match self.legacy_version {
                LegacyVersionArg::V42 => LegacyVersion::V42,
                LegacyVersionArg::V51 => LegacyVersion::V51,
            },
        }
    }
}

pub fn run(args: &ConvertArgs) -> anyhow::Result<()> {
    let Some(output) = args.output.as_ref().or(args.output_flag.as_ref()) else {
        bail!("convert: no output named (give OUTPUT or -o OUTPUT)");
    };
    let to_stdout = output.as_os_str() == "-";
    // Decide the output format before reading, so a bad name fails fast and writes nothing.
    let format = if to_stdout {
        Format::from_name(&args.to)
            .filter(|f| matches!(f, Format::Vtu | Format::Legacy | Format::Medit))
            .with_context(|| format!("--to {}: stdout takes vtu, vtk or mesh", args.to))?
    } else {
        Format::for_output(output)?
    };
    let mut grid = super::read_input(&args.input)?;
    if args.tetrahedralize {
        let (tets, report) = tetrahedralize(&grid, true)
            .with_context(|| format!("{}: tetrahedralizing", args.input.display()))?;
        for line in report.lines() {
            eprintln!("tetkit: {line}");
        }
        grid = tets;
        if format == Format::TetGen {
            let quadratic = grid
                .cells
                .types
                .iter()
                .filter(|&&t| t == formats::cell_type::QUADRATIC_TRIANGLE)
                .count();
            if quadratic > 0 {
                grid = split_quadratic_triangles(&grid);
                eprintln!(
                    "tetkit: split {quadratic} quadratic triangles into 4 triangles each for the .face file"
                );
            }
            // TetGen files hold tets and boundary triangles (.face): other lower cells go.
            let keep: Vec<usize> = (0..grid.num_cells())
                .filter(|&i| {
                    matches!(
                        grid.cells.types[i],
                        formats::cell_type::TETRA | formats::cell_type::TRIANGLE
                    )
                })
                .collect();
            if keep.len() < grid.num_cells() {
                eprintln!(
                    "tetkit: dropped {} cells that TetGen files cannot hold (vertices, lines, quads, polygons...); tets and triangles are kept",
                    grid.num_cells() - keep.len()
                );
                grid = crate::partition::input::keep_cells(&grid, &keep);
            }
        }
    }
    if format == Format::Legacy && matches!(args.encoding, EncodingArg::Ascii) {
        // tetkit reads nan/inf back, VTK 9.1 does not (it stops reading the file there).
        let bad: Vec<&str> = std::iter::once(&grid.points)
            .chain(&grid.point_data.arrays)
            .chain(&grid.cell_data.arrays)
            .chain(&grid.field_data)
            .filter(|a| {
                a.data.scalar_type().is_some_and(|t| t.is_float())
                    && (0..a.data.len()).any(|i| !a.data.get_f64(i).is_finite())
            })
            .map(|a| a.name.as_str())
            .collect();
        if !bad.is_empty() {
            eprintln!(
                "tetkit: warning: {}: arrays {} hold NaN or infinite values, which VTK 9.1 cannot read from an ascii legacy file (tetkit can); --encoding binary keeps them readable by both",
                if to_stdout { "<stdout>".to_string() } else { output.display().to_string() },
                bad.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(", ")
            );
        }
    }
    if format == Format::TetGen && !to_stdout {
        // Said, not silent: what TetGen's columns of reals cannot hold.
        let mut lost: Vec<String> = Vec::new();
        for (what, attrs) in [("point", &grid.point_data), ("cell", &grid.cell_data)] {
            for a in attrs
                .arrays
                .iter()
                .filter(|a| a.data.scalar_type().is_none())
            {
                lost.push(format!("{what} array '{}' (strings)", a.name));
            }
        }
        lost.extend(
            grid.field_data
                .iter()
                .map(|a| format!("field data '{}'", a.name)),
        );
        use formats::cell_type as ct;
        // `.face` lines hold one marker: other cell arrays keep their tets' values only.
        let faces = grid
            .cells
            .types
            .iter()
            .filter(|&&t| matches!(t, ct::TRIANGLE | ct::QUADRATIC_TRIANGLE))
            .count();
        // The array the writer takes for the markers (a Gmsh mesh's `gmsh:physical` when there
        // is no `boundary_marker`).
        let markers = formats::tetgen::face_marker(&grid).map(|a| a.name.as_str());
        if let (true, Some("gmsh:physical")) = (faces > 0, markers) {
            eprintln!(
                "tetkit: note: {}: the boundary triangles' gmsh:physical written as their .face markers (read back as boundary_marker)",
                output.display()
            );
        }
        if faces > 0 {
            lost.extend(
                grid.cell_data
                    .arrays
                    .iter()
                    .filter(|a| a.data.scalar_type().is_some() && Some(a.name.as_str()) != markers)
                    .map(|a| {
                        format!(
                            "cell array '{}' on the {faces} boundary triangles (a .face line holds only boundary_marker)",
                            a.name
                        )
                    }),
            );
        }
        // Every value is written as a decimal real: integers past 2^53 do not survive.
        for (what, attrs) in [("point", &grid.point_data), ("cell", &grid.cell_data)] {
            for a in &attrs.arrays {
                let big = match &a.data {
                    ArrayData::Int64(v) => v.iter().any(|&x| x.unsigned_abs() > 1 << 53),
                    ArrayData::UInt64(v) => v.iter().any(|&x| x > 1 << 53),
                    _ => false,
                };
                if big {
                    lost.push(format!(
                        "{what} array '{}' exactly (integers past 2^53 are rounded to reals)",
                        a.name
                    ));
                }
            }
        }
        if let Some(i) = grid.cells.types.iter().position(|&t| {
            !matches!(
                t,
                ct::TETRA | ct::QUADRATIC_TETRA | ct::TRIANGLE | ct::QUADRATIC_TRIANGLE
            )
        }) {
            bail!(
                "{}: TetGen files hold tetrahedra and their boundary triangles only, but cell {i} is a {}; add --tetrahedralize",
                output.display(),
                ct::name(grid.cells.types[i])
            );
        }
        formats::write(output, &grid, &args.write_options())?;
        if !lost.is_empty() {
            eprintln!(
                "tetkit: {}: TetGen files cannot hold {}: not written (use .vtu or .vtk to keep them)",
                output.display(),
                lost.join(", ")
            );
        }
        return Ok(());
    }
    let opts = args.write_options();
    if to_stdout {
        // Encode fully before writing anything, so a failure leaves no partial stream.
        let mut buf = Vec::new();
        formats::write_to(&mut buf, format, &grid, &opts).map_err(|mut e| {
            // The writer knows no file name; without one the message would blame "<input>".
            e.file = Some("<stdout>".into());
            e
        })?;
        let mut out = std::io::stdout().lock();
        std::io::Write::write_all(&mut out, &buf)
            .and_then(|_| std::io::Write::flush(&mut out))
            .context("writing stdout")?;
        return Ok(());
    }
    formats::write(output, &grid, &opts)?;
    Ok(())
}

/// Quadratic triangles (TetGen's `-o2` `.face`, Gmsh's second-order boundary) as 4 linear ones
/// each, corner to mid-edge nodes: exactly the faces the 8 linear tets of their quadratic tets
/// show there, so the boundary and its markers survive `--tetrahedralize` to TetGen instead of
/// being dropped. Cell data is copied to each piece.
fn split_quadratic_triangles(grid: &formats::Grid) -> formats::Grid {
    use formats::cell_type::{QUADRATIC_TRIANGLE, TRIANGLE};
    let mut cells = formats::Cells::new();
    let mut parent = Vec::with_capacity(grid.num_cells());
    for i in 0..grid.num_cells() {
        let c = grid.cells.cell(i);
        if grid.cells.types[i] == QUADRATIC_TRIANGLE && c.len() == 6 {
            // VTK order: corners 0 1 2, then mid-edges 01, 12, 20.
            for t in [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]] {
                cells.push(TRIANGLE, &t.map(|k| c[k]));
                parent.push(i);
            }
        } else {
            cells.push(grid.cells.types[i], c);
            parent.push(i);
        }
    }
    let mut out = grid.clone();
    out.cells = cells;
    out.cell_data = grid.cell_data.gather(&parent);
    out
}
