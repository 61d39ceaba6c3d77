//! Legacy VTK writer: 4.2 or 5.1, ASCII or big-endian binary, laid out as vtkDataWriter does
//! (field data, points, cells, cell data, point data) so that VTK 9.1 reads every array back.

use super::attributes::LOOKUP_TABLE_PREFIX;
use super::encode::{put_strings, put_values};
use super::names;
use crate::{
    cell_type, with_numeric, ArrayData, Attribute, Attributes, DataArray, Encoding, FormatError,
    Grid, LegacyVersion, Result, WriteOptions,
};
use std::borrow::Cow;
use std::io::{self, Write};

fn io_err(e: io::Error) -> FormatError {
    FormatError::whole(format!("write failed: {e}"))
}

/// Writes `grid` as legacy VTK (binary unless the encoding is ascii).
///
/// Active attributes are written with their keyword when the array fits it (SCALARS: 1-4
/// components; VECTORS, NORMALS: 3; TENSORS: 9, or TENSORS6 for 6; TEXTURE_COORDINATES: 1-3;
/// GLOBAL_IDS, PEDIGREE_IDS: 1, numeric), every other array in a FIELD block, so nothing is
/// dropped. Limits of the format: 4.2 stores cells as 32-bit ints (larger ids are an error:
/// write 5.1); VTK 9.1 cannot read `nan`/`inf` back from ASCII files (binary keeps them).
pub fn write(w: &mut dyn Write, grid: &Grid, opts: &WriteOptions) -> Result<()> {
    let binary = opts.encoding != Encoding::Ascii;
    let version = opts.legacy_version;
    // VTK reads a 4.2 file's higher-order hexahedra in its old edge order: written in it.
    let old_order;
    let grid = if version == LegacyVersion::V42 && grid.has_higher_order_hexahedra() {
        let mut g = grid.clone();
        g.swap_hex_edges_10_11();
        old_order = g;
        &old_order
    } else {
        grid
    };
    check_names(grid)?;
    let cells = cell_streams(grid)?;
    if version == LegacyVersion::V42 {
        check_32bit(&cells)?;
    }
    let luts = used_lookup_tables(grid);
    let mut w = Out { w, binary };
    w.text(&format!(
        "# vtk DataFile Version {}\nwritten by tetkit\n{}\nDATASET UNSTRUCTURED_GRID\n",
        if version == LegacyVersion::V42 {
            "4.2"
        } else {
            "5.1"
        },
        if binary { "BINARY" } else { "ASCII" }
    ))?;
    let field: Vec<&DataArray> = grid
        .field_data
        .iter()
        .filter(|a| !luts.contains(&a.name))
        .collect();
    if !field.is_empty() {
        w.field_block(&field)?;
    }
    let np = grid.num_points();
    w.text(&format!(
        "POINTS {np} {}\n",
        type_name(&grid.points.data, &grid.points.name)?
    ))?;
    w.data(&grid.points.data)?;
    w.metadata(&grid.points)?;
    let nc = grid.num_cells();
    if nc > 0 {
        match version {
            LegacyVersion::V51 => {
                w.text(&format!(
                    "CELLS {} {}\nOFFSETS vtktypeint64\n",
                    cells.offsets.len(),
                    cells.conn.len()
                ))?;
                put_values(w.w, &cells.offsets, binary).map_err(io_err)?;
                w.text("CONNECTIVITY vtktypeint64\n")?;
                put_values(w.w, &cells.conn, binary).map_err(io_err)?;
            }
            LegacyVersion::V42 => {
                let mut stream = Vec::with_capacity(nc + cells.conn.len());
                for i in 0..nc {
                    let s = &cells.conn[cells.offsets[i] as usize..cells.offsets[i + 1] as usize];
                    stream.push(s.len() as i32);
                    stream.extend(s.iter().map(|&x| x as i32));
                }
                w.text(&format!("CELLS {nc} {}\n", stream.len()))?;
                put_values(w.w, &stream, binary).map_err(io_err)?;
            }
        }
        w.text(&format!("CELL_TYPES {nc}\n"))?;
        let types: Vec<i32> = grid.cells.types.iter().map(|&t| t as i32).collect();
        put_values(w.w, &types, binary).map_err(io_err)?;
    }
    if !grid.cell_data.arrays.is_empty() {
        w.text(&format!("CELL_DATA {nc}\n"))?;
        w.section(&grid.cell_data, grid)?;
    }
    if !grid.point_data.arrays.is_empty() {
        w.text(&format!("POINT_DATA {np}\n"))?;
        w.section(&grid.point_data, grid)?;
    }
    w.w.flush().map_err(io_err)
}

/// Offsets and connectivity as the file stores them: a polyhedron's entry is its face stream
/// (borrowed from the grid when there are no polyhedra).
struct Streams<'g> {
    offsets: Cow<'g, [i64]>,
    conn: Cow<'g, [i64]>,
}

fn cell_streams(grid: &Grid) -> Result<Streams<'_>> {
    let c = &grid.cells;
    if !c.types.contains(&cell_type::POLYHEDRON) {
        return Ok(Streams {
            offsets: Cow::Borrowed(&c.offsets),
            conn: Cow::Borrowed(&c.connectivity),
        });
    }
    let Some((faces, face_offsets)) = &c.polyhedron_faces else {
        return Err(FormatError::in_array(
            "faces",
            "the mesh has polyhedron cells but no face streams",
        ));
    };
    if face_offsets.len() != c.len() {
        return Err(FormatError::in_array(
            "faceoffsets",
            format!("{} entries for {} cells", face_offsets.len(), c.len()),
        ));
    }
    let mut offsets = vec![0];
    let mut conn = Vec::with_capacity(c.connectivity.len() + faces.len());
    let mut start = 0usize;
    for (i, &fo) in face_offsets.iter().enumerate() {
        if c.types[i] == cell_type::POLYHEDRON {
            let end = usize::try_from(fo)
                .ok()
                .filter(|&e| e >= start && e <= faces.len())
                .ok_or_else(|| {
                    FormatError::in_array(
                        "faceoffsets",
                        format!("polyhedron cell {i} has face offset {fo}"),
                    )
                })?;
            conn.extend_from_slice(&faces[start..end]);
            start = end;
        } else {
            conn.extend_from_slice(c.cell(i));
        }
        offsets.push(conn.len() as i64);
    }
    Ok(Streams {
        offsets: Cow::Owned(offsets),
        conn: Cow::Owned(conn),
    })
}

/// Names are whitespace-separated tokens in legacy files, so an empty one cannot be written.
fn check_names(grid: &Grid) -> Result<()> {
    for (what, arrays) in [
        ("point", &grid.point_data.arrays),
        ("cell", &grid.cell_data.arrays),
        ("field", &grid.field_data),
    ] {
        if let Some(k) = arrays.iter().position(|a| a.name.is_empty()) {
            return Err(FormatError::new(
                crate::Place::Other(format!("{what} data array {k}")),
                "legacy VTK needs a name for every array, and this one has none",
            ));
        }
    }
    Ok(())
}

fn check_32bit(s: &Streams) -> Result<()> {
    let total = s.conn.len() + s.offsets.len().saturating_sub(1);
    if i32::try_from(total).is_err() {
        return Err(FormatError::in_array(
            "CELLS",
            format!("{total} integers do not fit the 32-bit sizes of version 4.2; write 5.1"),
        ));
    }
    if let Some(x) = s.conn.iter().find(|&&x| i32::try_from(x).is_err()) {
        return Err(FormatError::in_array(
            "CELLS",
            format!("point id {x} does not fit the 32-bit ints of version 4.2; write 5.1"),
        ));
    }
    Ok(())
}

/// Field-data names of lookup tables that SCALARS arrays refer to (written as LOOKUP_TABLE
/// blocks beside them, not as field data).
fn used_lookup_tables(grid: &Grid) -> Vec<String> {
    let mut out = Vec::new();
    for attrs in [&grid.point_data, &grid.cell_data] {
        if let Some(s) = scalars_with_lut(attrs, grid) {
            out.push(s.1.name.clone());
        }
    }
    out
}

/// The active scalars' lookup table name and its field array, when both exist and fit.
fn scalars_with_lut<'g>(attrs: &Attributes, grid: &'g Grid) -> Option<(String, &'g DataArray)> {
    let active = attrs.active(Attribute::Scalars)?;
    let (_, lut) = attrs
        .lookup_tables
        .iter()
        .find(|(a, _)| *a == active.name)?;
    let name = format!("{LOOKUP_TABLE_PREFIX}{lut}");
    let table = grid.field_data.iter().find(|a| a.name == name)?;
    (table.components == 4 && table.data.scalar_type().is_some()).then(|| (lut.clone(), table))
}

fn type_name(data: &ArrayData, name: &str) -> Result<&'static str> {
    Ok(match data.scalar_type() {
        Some(t) => t.legacy_name(),
        None => {
            return Err(FormatError::in_array(
                name,
                "string arrays can only be written as field data",
            ))
        }
    })
}

/// A 64-bit vtkIdTypeArray's values as `vtkIdType` holds them in legacy files (32-bit ints, as
/// VTK writes them; read back as 64-bit ids), when every value fits; otherwise (and for Int32
/// ids, which `vtkIdType` would read back as Int64) the array is written by its type.
fn id_values(a: &DataArray) -> Option<ArrayData> {
    let ArrayData::Int64(v) = &a.data else {
        return None;
    };
    if !a.id_type {
        return None;
    }
    let v: Option<Vec<i32>> = v.iter().map(|&x| i32::try_from(x).ok()).collect();
    v.map(ArrayData::Int32)
}

/// The legacy type name an array is written with and the values to write.
fn legacy_values(a: &DataArray) -> (&'static str, Cow<'_, ArrayData>) {
    match id_values(a) {
        Some(v) => ("vtkIdType", Cow::Owned(v)),
        None => (
            a.data.scalar_type().map_or("string", |t| t.legacy_name()),
            Cow::Borrowed(&a.data),
        ),
    }
}

/// The keyword an active array is written with, or `None` when it does not fit one.
fn keyword(role: Attribute, a: &DataArray) -> Option<String> {
    let numeric = a.data.scalar_type().is_some();
    let n = names::encode(&a.name);
    let (ty, _) = legacy_values(a);
    let c = a.components;
    if !numeric {
        return None;
    }
    Some(match role {
        Attribute::Scalars if (1..=4).contains(&c) => format!("SCALARS {n} {ty} {c}"),
        Attribute::Vectors if c == 3 => format!("VECTORS {n} {ty}"),
        Attribute::Normals if c == 3 => format!("NORMALS {n} {ty}"),
        Attribute::Tensors if c == 9 => format!("TENSORS {n} {ty}"),
        Attribute::Tensors if c == 6 => format!("TENSORS6 {n} {ty}"),
        Attribute::TCoords if (1..=3).contains(&c) => format!("TEXTURE_COORDINATES {n} {c} {ty}"),
        Attribute::GlobalIds if c == 1 => format!("GLOBAL_IDS {n} {ty}"),
        Attribute::PedigreeIds if c == 1 => format!("PEDIGREE_IDS {n} {ty}"),
        _ => return None,
    })
}

struct Out<'w> {
    w: &'w mut dyn Write,
    binary: bool,
}

impl Out<'_> {
    fn text(&mut self, s: &str) -> Result<()> {
        self.w.write_all(s.as_bytes()).map_err(io_err)
    }

    fn data(&mut self, d: &ArrayData) -> Result<()> {
        let b = self.binary;
        with_numeric!(d, v => put_values(self.w, v, b), s => put_strings(self.w, s, b))
            .map_err(io_err)
    }

    /// Component names as VTK writes them: one %-encoded line each (empty when unnamed), then an
    /// empty line.
    fn metadata(&mut self, a: &DataArray) -> Result<()> {
        if a.component_names.iter().all(|n| n.is_empty()) {
            return Ok(());
        }
        let mut s = String::from("METADATA\nCOMPONENT_NAMES\n");
        for k in 0..a.components {
            s.push_str(&names::encode(a.component_names.get(k).map_or("", |n| n)));
            s.push('\n');
        }
        s.push('\n');
        self.text(&s)
    }

    fn field_block(&mut self, arrays: &[&DataArray]) -> Result<()> {
        self.text(&format!("FIELD FieldData {}\n", arrays.len()))?;
        for a in arrays {
            let (ty, values) = legacy_values(a);
            self.text(&format!(
                "{} {} {} {ty}\n",
                names::encode(&a.name),
                a.components,
                a.tuples()
            ))?;
            self.data(&values)?;
            self.metadata(a)?;
        }
        Ok(())
    }

    fn section(&mut self, attrs: &Attributes, grid: &Grid) -> Result<()> {
        // By identity, not name: arrays that share a name are each written.
        let mut written: Vec<&DataArray> = Vec::new();
        for role in Attribute::ALL {
            let Some(a) = attrs.active(role) else {
                continue;
            };
            if written.iter().any(|w| std::ptr::eq(*w, a)) {
                continue;
            }
            let Some(kw) = keyword(role, a) else { continue };
            self.text(&kw)?;
            self.text("\n")?;
            let lut = (role == Attribute::Scalars)
                .then(|| scalars_with_lut(attrs, grid))
                .flatten();
            if role == Attribute::Scalars {
                let name = attrs
                    .lookup_tables
                    .iter()
                    .find(|(n, _)| *n == a.name)
                    .map_or("default".to_string(), |(_, l)| names::encode(l));
                self.text(&format!("LOOKUP_TABLE {name}\n"))?;
            }
            self.data(&legacy_values(a).1)?;
            self.metadata(a)?;
            if let Some((name, table)) = lut {
                self.lookup_table(&name, table)?;
            }
            written.push(a);
        }
        let rest: Vec<&DataArray> = attrs
            .arrays
            .iter()
            .filter(|a| !written.iter().any(|w| std::ptr::eq(*w, *a)))
            .collect();
        if !rest.is_empty() {
            self.field_block(&rest)?;
        }
        Ok(())
    }

    /// `LOOKUP_TABLE name n`: RGBA bytes in binary, reals in 0..1 in ASCII.
    fn lookup_table(&mut self, name: &str, table: &DataArray) -> Result<()> {
        let vals = table.data.to_f64_vec();
        self.text(&format!(
            "LOOKUP_TABLE {} {}\n",
            names::encode(name),
            vals.len() / 4
        ))?;
        if self.binary {
            let bytes: Vec<u8> = vals
                .iter()
                .map(|x| (x * 255.0).round().clamp(0.0, 255.0) as u8)
                .collect();
            put_values(self.w, &bytes, true).map_err(io_err)
        } else {
            let f: Vec<f32> = vals.iter().map(|&x| x as f32).collect();
            put_values(self.w, &f, false).map_err(io_err)
        }
    }
}
