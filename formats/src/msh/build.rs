//! What the section readers collect (nodes by tag, elements, names, views), made into a Grid.

use super::cursor::Cursor;
use super::types::ElementType;
use super::{names, warn};
use crate::{ArrayData, Cells, DataArray, Grid, Result};
use std::collections::HashMap;

/// Node or element tag to point or cell index. Std's hasher: a file's tags may be chosen to
/// collide under a simple one, and hashing is a small part of reading.
pub(crate) type TagMap = HashMap<i64, u32>;

/// One data view (`$NodeData` or `$ElementData`) of one time step, over all nodes (elements).
pub(crate) struct View {
    pub name: String,
    pub step: i64,
    pub time: f64,
    pub on_points: bool,
    pub components: usize,
    /// NaN where the view gives no value.
    pub values: Vec<f64>,
}

#[derive(Default)]
pub(crate) struct Builder {
    pub node_tags: Vec<i64>,
    pub coords: Vec<f64>,
    /// u, v, w per node (NaN where absent); created at the first parametric node block.
    pub parametric: Option<Vec<f64>>,
    pub node_index: TagMap,
    pub nodes_read: bool,
    pub cells: Cells,
    pub element_tags: Vec<i64>,
    pub physical: Vec<i32>,
    pub geometrical: Vec<i32>,
    /// First partition of each element's entity, filled in partitioned MSH 4.1 files only.
    pub partition: Vec<i32>,
    /// Elements on entities shared by several partitions (interfaces).
    pub shared_partition_cells: usize,
    pub elements_read: bool,
    /// Element tag to cell index, built when element data first needs it.
    element_index: Option<TagMap>,
    pub physical_names: Vec<(i32, i32, String)>,
    pub views: Vec<View>,
    dropped_pyramid_centres: usize,
}

impl Builder {
    pub fn new() -> Builder {
        Builder {
            cells: Cells::new(),
            ..Builder::default()
        }
    }

    /// Adds a node; `at` (its place in the file) names it in errors.
    pub fn add_node(
        &mut self,
        c: &Cursor<'_>,
        at: usize,
        tag: i64,
        xyz: [f64; 3],
        uvw: Option<[f64; 3]>,
    ) -> Result<()> {
        let index = u32::try_from(self.node_tags.len())
            .map_err(|_| c.err_at(at, "more than 2^32 nodes"))?;
        if self.node_index.insert(tag, index).is_some() {
            return Err(c.err_at(at, format!("node tag {tag} appears twice")));
        }
        if let Some(bad) = xyz.iter().find(|v| !v.is_finite()) {
            return Err(c.err_at(at, format!("node {tag} has a non-finite coordinate {bad}")));
        }
        self.node_tags.push(tag);
        self.coords.extend_from_slice(&xyz);
        if let Some(uvw) = uvw {
            let n = self.node_tags.len() - 1;
            let p = self.parametric.get_or_insert_with(|| vec![f64::NAN; 3 * n]);
            p.extend_from_slice(&uvw);
        } else if let Some(p) = &mut self.parametric {
            p.extend_from_slice(&[f64::NAN; 3]);
        }
        Ok(())
    }

    /// The point index of node `tag`, or an error naming element `element` at `at`.
    pub fn node(&self, c: &Cursor<'_>, at: usize, element: i64, tag: i64) -> Result<i64> {
        match self.node_index.get(&tag) {
            Some(&i) => Ok(i64::from(i)),
            None => Err(c.err_at(
                at,
                format!("element {element} refers to node {tag}, which the $Nodes section does not have"),
            )),
        }
    }

    /// Adds an element given its node tags in Gmsh's order.
    #[allow(clippy::too_many_arguments)]
    pub fn add_element(
        &mut self,
        c: &Cursor<'_>,
        at: usize,
        ty: &ElementType,
        tag: i64,
        node_tags: &[i64],
        physical: i32,
        geometrical: i32,
    ) -> Result<()> {
        let mut ids = [0i64; 27];
        for (k, &t) in node_tags.iter().enumerate() {
            ids[k] = self.node(c, at, tag, t)?;
        }
        let mut vtk = [0i64; 27];
        for (k, &g) in ty.from_gmsh.iter().enumerate() {
            vtk[k] = ids[g];
        }
        if ty.from_gmsh.len() < ty.nodes {
            self.dropped_pyramid_centres += 1;
        }
        self.cells.push(ty.vtk, &vtk[..ty.from_gmsh.len()]);
        self.element_tags.push(tag);
        self.physical.push(physical);
        self.geometrical.push(geometrical);
        Ok(())
    }

    /// Cell index of each element tag (the first element with a tag, if several share it).
    pub fn element_index(&mut self) -> &TagMap {
        let tags = &self.element_tags;
        self.element_index.get_or_insert_with(|| {
            let mut m = TagMap::default();
            m.reserve(tags.len());
            for (i, &t) in tags.iter().enumerate().rev() {
                m.insert(t, i as u32);
            }
            m
        })
    }

    /// The index in `views` of the view for (`name`, `step`) on points or cells, created NaN-filled when new. Gmsh writes
    /// one data section per partition of the same step; they fill the same view.
    #[allow(clippy::too_many_arguments)]
    pub fn view(
        &mut self,
        c: &Cursor<'_>,
        at: usize,
        name: &str,
        step: i64,
        time: f64,
        on_points: bool,
        components: usize,
    ) -> Result<usize> {
        let n = if on_points {
            self.node_tags.len()
        } else {
            self.element_tags.len()
        };
        let found = self
            .views
            .iter()
            .position(|v| v.name == name && v.step == step && v.on_points == on_points);
        let i = match found {
            Some(i) => {
                if self.views[i].components != components {
                    return Err(c.err_at(
                        at,
                        format!(
                            "view '{name}' step {step} has {components} components here and {} before",
                            self.views[i].components
                        ),
                    ));
                }
                i
            }
            None => {
                let len = n
                    .checked_mul(components)
                    .filter(|&l| l <= isize::MAX as usize / 8)
                    .ok_or_else(|| c.err_at(at, format!("view '{name}' is too large")))?;
                self.views.push(View {
                    name: name.to_string(),
                    step,
                    time,
                    on_points,
                    components,
                    values: vec![f64::NAN; len],
                });
                self.views.len() - 1
            }
        };
        Ok(i)
    }

    pub fn finish(self, path_for_warnings: &str) -> Result<Grid> {
        if self.dropped_pyramid_centres > 0 {
            warn(&format!(
                "{path_for_warnings}: {} 14-node pyramids read as VTK's 13-node quadratic pyramid: the node at the centre of the base is dropped",
                self.dropped_pyramid_centres
            ));
        }
        let mut g = Grid {
            points: DataArray::new("Points", 3, ArrayData::Float64(self.coords)),
            cells: self.cells,
            ..Grid::default()
        };
        g.point_data.arrays.push(DataArray::new(
            names::NODE_TAG,
            1,
            ArrayData::Int64(self.node_tags),
        ));
        if let Some(p) = self.parametric {
            let mut a = DataArray::new(names::PARAMETRIC, 3, ArrayData::Float64(p));
            a.component_names = vec!["u".into(), "v".into(), "w".into()];
            g.point_data.arrays.push(a);
        }
        g.cell_data.arrays.push(DataArray::new(
            names::PHYSICAL,
            1,
            ArrayData::Int32(self.physical),
        ));
        g.cell_data.arrays.push(DataArray::new(
            names::GEOMETRICAL,
            1,
            ArrayData::Int32(self.geometrical),
        ));
        if !self.partition.is_empty() {
            if self.shared_partition_cells > 0 {
                warn(&format!(
                    "{path_for_warnings}: {} cells lie on entities shared by several partitions; gmsh:partition keeps the first partition of each",
                    self.shared_partition_cells
                ));
            }
            g.cell_data.arrays.push(DataArray::new(
                names::PARTITION,
                1,
                ArrayData::Int32(self.partition),
            ));
        }
        g.cell_data.arrays.push(DataArray::new(
            names::ELEMENT_TAG,
            1,
            ArrayData::Int64(self.element_tags),
        ));
        if !self.physical_names.is_empty() {
            let (dims, rest): (Vec<i32>, Vec<(i32, String)>) = self
                .physical_names
                .into_iter()
                .map(|(d, t, n)| (d, (t, n)))
                .unzip();
            let (tags, names_): (Vec<i32>, Vec<String>) = rest.into_iter().unzip();
            g.field_data.push(DataArray::new(
                names::PHYSICAL_NAMES,
                1,
                ArrayData::String(names_),
            ));
            g.field_data.push(DataArray::new(
                names::PHYSICAL_DIMS,
                1,
                ArrayData::Int32(dims),
            ));
            g.field_data.push(DataArray::new(
                names::PHYSICAL_TAGS,
                1,
                ArrayData::Int32(tags),
            ));
        }
        // The first step of a view met in the file takes the plain name; later steps NAME@STEP.
        let mut times: Vec<(String, Vec<f64>)> = Vec::new();
        for v in self.views {
            let key = format!("{}{}", if v.on_points { "p" } else { "c" }, v.name);
            let array_name = match times.iter_mut().find(|(k, _)| *k == key) {
                Some((_, t)) => {
                    t.push(v.time);
                    format!("{}@{}", v.name, v.step)
                }
                None => {
                    times.push((key, vec![v.time]));
                    v.name.clone()
                }
            };
            let a = DataArray::new(array_name, v.components, ArrayData::Float64(v.values));
            let set = if v.on_points {
                &mut g.point_data
            } else {
                &mut g.cell_data
            };
            // A view named like another array (gmsh:physical, say) is kept beside it; the
            // common read path renames it, with a warning.
            set.arrays.push(a);
        }
        for (key, t) in times {
            let name = format!("{}{}", names::TIME_PREFIX, &key[1..]);
            if g.field_data.iter().any(|a| a.name == name) {
                // A view on points and one on cells with the same name: keep the first times.
                continue;
            }
            g.field_data
                .push(DataArray::new(name, 1, ArrayData::Float64(t)));
        }
        Ok(g)
    }
}

/// Converts a 4.1 `size_t` tag (or 2.2 int) to i64.
pub(crate) fn tag_i64(c: &Cursor<'_>, at: usize, v: u64, what: &str) -> Result<i64> {
    i64::try_from(v).map_err(|_| c.err_at(at, format!("{what} {v} is too large")))
}

pub(crate) fn to_i32(c: &Cursor<'_>, at: usize, v: i64, what: &str) -> Result<i32> {
    i32::try_from(v).map_err(|_| c.err_at(at, format!("{what} {v} does not fit 32 bits")))
}
