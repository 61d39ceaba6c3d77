//! Gmsh `.msh` meshes (MSH 4.1 and 2.2, ASCII and binary) read into a [`Grid`]; read only.

mod build;
mod cursor;
mod data;
mod read_v2;
mod read_v4;
mod types;

use crate::{FormatError, Grid, Result};
use cursor::{show, Cursor};
use data::DataKind;
use std::path::Path;

/// Array names the reader gives.
pub mod names {
    pub const NODE_TAG: &str = "gmsh:node_tag";
    pub const PARAMETRIC: &str = "gmsh:parametric";
    pub const PHYSICAL: &str = "gmsh:physical";
    pub const GEOMETRICAL: &str = "gmsh:geometrical";
    pub const ELEMENT_TAG: &str = "gmsh:element_tag";
    /// Partitioned MSH 4.1 files: the (first) partition of each cell's entity.
    pub const PARTITION: &str = "gmsh:partition";
    pub const PHYSICAL_NAMES: &str = "gmsh:physical_names";
    pub const PHYSICAL_DIMS: &str = "gmsh:physical_dims";
    pub const PHYSICAL_TAGS: &str = "gmsh:physical_tags";
    /// Field data `gmsh:time:NAME`: the times of view NAME's steps.
    pub const TIME_PREFIX: &str = "gmsh:time:";
}

pub(crate) use crate::warn;

/// Reads a `.msh` file (see [`read_from`] for what the grid holds).
pub fn read_path(path: &Path) -> Result<Grid> {
    let bytes = std::fs::read(path).map_err(|e| FormatError::io(path, e))?;
    read_from(&bytes, Some(path))
}

/// Reads `.msh` content from memory; `path`, when given, names it in errors.
///
/// Points are the nodes in file order, with their tags in the Int64 point array
/// `gmsh:node_tag` (tags may be sparse) and, when a node block carries them, parametric
/// coordinates in the 3-component Float64 point array `gmsh:parametric` (NaN where a node has
/// none). Elements of types 1-19 (points to pyramids, up to order 2) become cells of the
/// matching VTK type with Gmsh's node order mapped to VTK's (prisms are mirrored, as VTK's
/// wedge turns the other way; a 14-node pyramid loses its base centre, with a warning). Cell
/// arrays: `gmsh:physical` (Int32, the first physical group, 0 for none), `gmsh:geometrical`
/// (Int32, the elementary entity) and `gmsh:element_tag` (Int64). `$PhysicalNames` becomes the
/// field data `gmsh:physical_names` (String), `gmsh:physical_dims` and `gmsh:physical_tags`
/// (Int32). `$NodeData` and `$ElementData` views become Float64 point and cell arrays named by
/// the view (the first time step met as NAME, later ones NAME@STEP; NaN where the view gives no
/// value), with their times in the field data `gmsh:time:NAME`. `$ElementNodeData` is skipped
/// with a warning; unknown sections are skipped. MSH 1, 3 and 4.0 and elements of order 3 or
/// more are refused with an error that says so.
///
/// A partitioned MSH 4.1 file (`gmsh -part N`) has `$PartitionedEntities`, and its elements
/// name those entities: each cell's `gmsh:physical` is the partitioned entity's first physical
/// tag, else its parent model entity's, and the Int32 cell array `gmsh:partition` gives the
/// entity's partition (the first one listed for an entity on an interface between partitions,
/// with a warning); `gmsh:geometrical` is the partitioned entity's tag, as the file names it.
/// Ghost entities are skipped, as is `$GhostElements`.
///
/// MSH 2.2 has no entities: each element carries its physical and elementary tags, and Gmsh
/// writes an element that is in several physical groups once per group, under new element tags;
/// those copies stay separate cells.
pub fn read_from(bytes: &[u8], path: Option<&Path>) -> Result<Grid> {
    let mut c = Cursor::new(bytes, path);
    let version = mesh_format(&mut c)?;
    let mut b = build::Builder::new();
    let mut physicals = read_v4::Physicals::new();
    while !c.at_end() {
        let at = c.pos;
        let t = c.token("a section")?;
        let Some(name) = t.strip_prefix(b"$") else {
            return Err(c.err_at(
                at,
                format!(
                    "expected a section ($Nodes, $Elements, ...), found '{}'",
                    show(t)
                ),
            ));
        };
        let name = String::from_utf8_lossy(name).into_owned();
        // Binary data starts on the line after a section's name.
        c.end_line()?;
        let second = |c: &Cursor<'_>| c.err_at(at, format!("a second ${name} section"));
        match name.as_str() {
            "MeshFormat" => return Err(c.err_at(at, "a second $MeshFormat section")),
            "PhysicalNames" => data::physical_names(&mut c, &mut b)?,
            "Entities" if version == Version::V41 => read_v4::entities(&mut c, &mut physicals)?,
            "PartitionedEntities" if version == Version::V41 => {
                if physicals.is_partitioned {
                    return Err(second(&c));
                }
                if b.elements_read {
                    return Err(c.err_at(at, "$PartitionedEntities after the $Elements section"));
                }
                read_v4::partitioned_entities(&mut c, &mut physicals)?
            }
            "Nodes" => {
                if b.nodes_read {
                    return Err(second(&c));
                }
                match version {
                    Version::V41 => read_v4::nodes(&mut c, &mut b)?,
                    Version::V2 => read_v2::nodes(&mut c, &mut b)?,
                }
            }
            "ParametricNodes" if version == Version::V2 => {
                if b.nodes_read {
                    return Err(second(&c));
                }
                read_v2::parametric_nodes(&mut c, &mut b)?
            }
            "Elements" => {
                if b.elements_read {
                    return Err(second(&c));
                }
                if !b.nodes_read {
                    return Err(c.err_at(at, "$Elements before the $Nodes section"));
                }
                match version {
                    Version::V41 => read_v4::elements(&mut c, &mut b, &physicals)?,
                    Version::V2 => read_v2::elements(&mut c, &mut b)?,
                }
            }
            "NodeData" => data::data(&mut c, &mut b, DataKind::Node)?,
            "ElementData" => data::data(&mut c, &mut b, DataKind::Element)?,
            "ElementNodeData" => data::data(&mut c, &mut b, DataKind::ElementNode)?,
            n if n.starts_with("End") => {
                return Err(c.err_at(at, format!("${n} without its opening section")))
            }
            other => {
                // Gmsh skips sections it does not know; so does tetkit ($Periodic,
                // $InterpolationScheme, $Parametrizations, ...).
                c.skip_section(other)?
            }
        }
    }
    b.finish(&c.file_name())
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Version {
    V2,
    V41,
}

/// Reads `$MeshFormat`: the version, ASCII or binary, the size of `size_t` and the byte order.
fn mesh_format(c: &mut Cursor<'_>) -> Result<Version> {
    c.skip_space();
    let t = c.token("$MeshFormat")?;
    if t == b"$NOD" || t == b"$NOE" {
        return Err(c.err_at(
            0,
            "this is an MSH 1 file; tetkit reads MSH 4.1 and 2.2 (Gmsh converts: gmsh FILE -0 -format msh41)",
        ));
    }
    if t != b"$MeshFormat" {
        return Err(c.err_at(0, format!("expected $MeshFormat, found '{}'", show(t))));
    }
    let at = c.pos;
    let v = c.token("the MSH version")?;
    let vs = String::from_utf8_lossy(v).into_owned();
    let version = match vs.as_str() {
        "4.1" => Version::V41,
        "2.2" | "2.1" | "2" | "2.0" => Version::V2,
        _ => {
            let n: Option<f64> = vs.parse().ok();
            let why = match n {
                Some(x) if (4.0..4.1).contains(&x) => "MSH 4.0 (superseded by 4.1 in Gmsh 4.1)",
                Some(x) if (3.0..4.0).contains(&x) => "MSH 3 (a short-lived format of Gmsh 3)",
                _ => "a version tetkit does not know",
            };
            return Err(c.err_at(
                at,
                format!(
                    "MSH version {} is {why}; tetkit reads MSH 4.1 and 2.2 (Gmsh converts: gmsh FILE -0 -format msh41)",
                    show(v)
                ),
            ));
        }
    };
    let at_type = c.pos;
    let file_type = c.ascii_int("the file type (0 ASCII, 1 binary)")?;
    let at_size = c.pos;
    let data_size = c.ascii_int("the data size")?;
    let binary = match file_type {
        0 => false,
        1 => true,
        other => {
            return Err(c.err_at(
                at_type,
                format!("file type {other}: must be 0 (ASCII) or 1 (binary)"),
            ))
        }
    };
    // MSH 4.1 gives sizeof(size_t); 2.2 sizeof(double).
    let ok = match version {
        Version::V41 => data_size == 4 || data_size == 8,
        Version::V2 => data_size == 8,
    };
    if !ok {
        return Err(c.err_at(at_size, format!("data size {data_size} is not supported")));
    }
    c.size_t = data_size as usize;
    c.end_line()?;
    if binary {
        c.binary = true;
        let at = c.pos;
        let one = c.bin_i32("the byte order check (the integer 1)")?;
        if one == 1 {
            c.big_endian = false;
        } else if one.swap_bytes() == 1 {
            c.big_endian = true;
        } else {
            return Err(c.err_at(
                at,
                format!("the byte order check reads {one}, neither 1 nor 1 byte-swapped"),
            ));
        }
    }
    c.expect_end("MeshFormat")?;
    Ok(version)
}

#[cfg(test)]
mod tests;
