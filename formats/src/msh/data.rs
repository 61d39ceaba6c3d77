//! Sections both versions share: `$PhysicalNames` and the data views (`$NodeData`, ...).

use super::build::{to_i32, Builder};
use super::cursor::Cursor;
use super::warn;
use crate::Result;

pub(crate) fn physical_names(c: &mut Cursor<'_>, b: &mut Builder) -> Result<()> {
    let n = c.ascii_count("the number of physical names")?;
    b.physical_names.reserve(c.cap(n, 6));
    for _ in 0..n {
        let at = c.pos;
        let dim = c.ascii_int("the dimension of a physical group")?;
        let dim = to_i32(c, at, dim, "physical dimension")?;
        let at = c.pos;
        let tag = c.ascii_int("the tag of a physical group")?;
        let tag = to_i32(c, at, tag, "physical tag")?;
        let name = c.quoted("the name of a physical group")?;
        b.physical_names.push((dim, tag, name));
    }
    c.expect_end("PhysicalNames")
}

/// Which data section.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum DataKind {
    Node,
    Element,
    ElementNode,
}

impl DataKind {
    pub fn section(self) -> &'static str {
        match self {
            DataKind::Node => "NodeData",
            DataKind::Element => "ElementData",
            DataKind::ElementNode => "ElementNodeData",
        }
    }
}

/// The tags that open a data section: name, time, step, components, count.
struct Header {
    name: String,
    time: f64,
    step: i64,
    components: usize,
    count: u64,
}

fn header(c: &mut Cursor<'_>, kind: DataKind) -> Result<Header> {
    let sec = kind.section();
    // The tags are text even in binary files (errors there still give byte offsets).
    let at = c.pos;
    let h = {
        let ns = c.ascii_count(&format!("the number of string tags of ${sec}"))?;
        let mut name = None;
        for _ in 0..ns {
            let s = c.quoted(&format!("a string tag of ${sec}"))?;
            name.get_or_insert(s);
        }
        let nr = c.ascii_count(&format!("the number of real tags of ${sec}"))?;
        let mut time = None;
        for _ in 0..nr {
            let t = c.ascii_real(&format!("a real tag of ${sec}"))?;
            time.get_or_insert(t);
        }
        let ni = c.ascii_count(&format!("the number of integer tags of ${sec}"))?;
        let mut ints = Vec::new();
        for _ in 0..ni {
            ints.push(c.ascii_int(&format!("an integer tag of ${sec}"))?);
        }
        if ints.len() < 3 {
            return Err(c.err_at(
                at,
                format!(
                    "${sec} has {} integer tags; it needs 3 (time step, components, count)",
                    ints.len()
                ),
            ));
        }
        // Gmsh writes 1 (scalar), 3 (vector) or 9 (tensor); the bound also keeps a NaN-filled
        // array over every node from growing with a corrupt count.
        let components = usize::try_from(ints[1])
            .ok()
            .filter(|&n| (1..=9).contains(&n))
            .ok_or_else(|| {
                c.err_at(
                    at,
                    format!("${sec} has {} components; Gmsh writes 1 to 9", ints[1]),
                )
            })?;
        let count = u64::try_from(ints[2])
            .map_err(|_| c.err_at(at, format!("${sec} counts {} entities", ints[2])))?;
        Header {
            // A view without a name still needs one to be an array.
            name: name
                .filter(|n| !n.is_empty())
                .unwrap_or_else(|| "view".into()),
            time: time.unwrap_or(0.0),
            step: ints[0],
            components,
            count,
        }
    };
    if c.binary {
        c.end_line()?;
    }
    Ok(h)
}

/// Reads a data section after its `$NAME` line; node (element) data becomes a view over the
/// points (cells) read so far.
pub(crate) fn data(c: &mut Cursor<'_>, b: &mut Builder, kind: DataKind) -> Result<()> {
    let sec = kind.section();
    let start = c.pos;
    let h = header(c, kind)?;
    match kind {
        DataKind::Node if !b.nodes_read => {
            return Err(c.err_at(start, "$NodeData before the $Nodes section"))
        }
        DataKind::Element | DataKind::ElementNode if !b.elements_read => {
            return Err(c.err_at(start, format!("${sec} before the $Elements section")))
        }
        _ => {}
    }
    if kind == DataKind::ElementNode {
        warn(&format!(
            "{}: ${sec} view '{}' skipped (values per element node have no VTK array)",
            c.file_name(),
            h.name
        ));
        for _ in 0..h.count {
            c.int("an element tag")?;
            let at = c.pos;
            let n = c.int("the number of nodes of an element")?;
            // Gmsh's largest elements (order 10 hexahedra) have 1331 nodes.
            let n = usize::try_from(n)
                .ok()
                .filter(|&n| n <= 2000)
                .ok_or_else(|| c.err_at(at, format!("{n} nodes per element")))?;
            for _ in 0..n * h.components {
                c.real("a value")?;
            }
        }
        return c.expect_end(sec);
    }
    let on_points = kind == DataKind::Node;
    let comps = h.components;
    let name = h.name.clone();
    let vi = b.view(c, start, &name, h.step, h.time, on_points, comps)?;
    // Look-ups need the builder while values are written: take the values out meanwhile.
    let mut values = std::mem::take(&mut b.views[vi].values);
    let result = (|| {
        for _ in 0..h.count {
            let at = c.pos;
            let tag = c.int(if on_points {
                "a node tag"
            } else {
                "an element tag"
            })?;
            let index = if on_points {
                b.node_index.get(&tag)
            } else {
                b.element_index().get(&tag)
            };
            let Some(&i) = index else {
                return Err(c.err_at(
                    at,
                    format!(
                        "${sec} view '{name}' gives a value for {} {tag}, which the mesh does not have",
                        if on_points { "node" } else { "element" }
                    ),
                ));
            };
            let i = i as usize;
            for k in 0..comps {
                values[i * comps + k] = c.real("a value")?;
            }
        }
        Ok(())
    })();
    b.views[vi].values = values;
    result?;
    c.expect_end(sec)
}
