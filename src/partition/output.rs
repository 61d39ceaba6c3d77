//! What a partition writes besides the split mesh: the tree as hexahedra (one per node, to look at
//! in ParaView) and one piece per leaf (a .vtm multiblock of .vtu files).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use formats::{cell_type, ArrayData, Cells, DataArray, Grid, WriteOptions};

use super::tree::KdTree;
use crate::mesh::TetMesh;

/// One VTK_HEXAHEDRON per tree node with cell data node_id, parent_id, depth, is_leaf, leaf_id
/// (-1 for inner nodes), split_axis (-1 for leaves), split_position (NaN for leaves) and
/// tet_count; the tree is also kept in field data.
pub fn tree_grid(tree: &KdTree) -> Grid {
    let n = tree.nodes.len();
    let mut pts = Vec::with_capacity(24 * n);
    let mut cells = Cells::new();
    for (i, node) in tree.nodes.iter().enumerate() {
        let (lo, hi) = (node.bounds.min, node.bounds.max);
        // VTK hexahedron order: bottom face counter-clockwise, then the top face.
        for z in [lo[2], hi[2]] {
            for (x, y) in [
                (lo[0], lo[1]),
                (hi[0], lo[1]),
                (hi[0], hi[1]),
                (lo[0], hi[1]),
            ] {
                pts.extend([x, y, z]);
            }
        }
        let b = 8 * i as i64;
        cells.push(
            cell_type::HEXAHEDRON,
            &[b, b + 1, b + 2, b + 3, b + 4, b + 5, b + 6, b + 7],
        );
    }
    let i32s = |f: &dyn Fn(usize) -> i32| ArrayData::Int32((0..n).map(f).collect());
    let nodes = &tree.nodes;
    let mut grid = Grid {
        points: DataArray::new("Points", 3, ArrayData::Float64(pts)),
        cells,
        ..Grid::default()
    };
    let cd = &mut grid.cell_data;
    cd.insert(DataArray::new("node_id", 1, i32s(&|i| i as i32)));
    cd.insert(DataArray::new(
        "parent_id",
        1,
        i32s(&|i| nodes[i].parent.map_or(-1, |p| p as i32)),
    ));
    cd.insert(DataArray::new("depth", 1, i32s(&|i| nodes[i].depth as i32)));
    cd.insert(DataArray::new(
        "is_leaf",
        1,
        ArrayData::UInt8(nodes.iter().map(|x| x.leaf_id.is_some() as u8).collect()),
    ));
    cd.insert(DataArray::new(
        "leaf_id",
        1,
        i32s(&|i| nodes[i].leaf_id.map_or(-1, |l| l as i32)),
    ));
    cd.insert(DataArray::new(
        "split_axis",
        1,
        i32s(&|i| nodes[i].split.map_or(-1, |s| s.axis as i32)),
    ));
    cd.insert(DataArray::new(
        "split_position",
        1,
        ArrayData::Float64(
            nodes
                .iter()
                .map(|x| x.split.map_or(f64::NAN, |s| s.position))
                .collect(),
        ),
    ));
    cd.insert(DataArray::new(
        "tet_count",
        1,
        ArrayData::Int64(nodes.iter().map(|x| x.tet_count as i64).collect()),
    ));
    grid.field_data = tree.to_field_data();
    grid
}

/// The tets of each leaf as its own mesh (only the points it uses, all arrays gathered), given a
/// split mesh whose tets are grouped by leaf in leaf order (as [`super::partition`] makes them).
pub fn leaf_pieces(mesh: &TetMesh, tree: &KdTree) -> Vec<TetMesh> {
    let mut out = Vec::with_capacity(tree.num_leaves());
    let mut start = 0usize;
    for node in tree.leaf_nodes() {
        let count = tree.nodes[node as usize].tet_count as usize;
        let range = start..(start + count).min(mesh.tets.len());
        start = range.end;
        let mut new_id = vec![u32::MAX; mesh.points.len()];
        let mut used = Vec::new();
        let tets: Vec<[u32; 4]> = mesh.tets[range.clone()]
            .iter()
            .map(|t| {
                t.map(|v| {
                    if new_id[v as usize] == u32::MAX {
                        new_id[v as usize] = used.len() as u32;
                        used.push(v as usize);
                    }
                    new_id[v as usize]
                })
            })
            .collect();
        let cells: Vec<usize> = range.collect();
        out.push(TetMesh {
            points: used.iter().map(|&v| mesh.points[v]).collect(),
            tets,
            point_data: mesh.point_data.gather(&used),
            cell_data: mesh.cell_data.gather(&cells),
            field_data: Vec::new(),
        });
    }
    out
}

/// Writes one .vtu per leaf into `dir/<stem>/<stem>_<leaf>.vtu`, with two files naming them:
/// `dir/<stem>.pvtu` (a parallel unstructured grid: ParaView reads its pieces in parallel across
/// server processes) and `dir/<stem>.vtm` (a multiblock with one block per leaf, to colour or
/// hide leaves one by one). The .pvtu and its pieces appear together or not at all; if the .vtm
/// then fails, they are removed. Returns the two paths.
pub fn write_pieces(
    dir: &Path,
    stem: &str,
    pieces: &[TetMesh],
    opts: &WriteOptions,
) -> Result<(PathBuf, PathBuf)> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let pvtu = dir.join(format!("{stem}.pvtu"));
    let grids: Vec<Grid> = pieces.iter().map(TetMesh::to_grid).collect();
    formats::vtu::pvtu::write(&pvtu, &grids, opts)?;
    let vtm = dir.join(format!("{stem}.vtm"));
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <vtkMultiBlockDataSet>\n",
    );
    for i in 0..pieces.len() {
        xml.push_str(&format!(
            "    <DataSet index=\"{i}\" name=\"leaf_{i}\" file=\"{s}/{s}_{i}.vtu\"/>\n",
            s = xml_escape(stem)
        ));
    }
    xml.push_str("  </vtkMultiBlockDataSet>\n</VTKFile>\n");
    let written = (|| -> std::io::Result<()> {
        let mut f = formats::atomic::AtomicFile::create(&vtm)?;
        std::io::Write::write_all(&mut f, xml.as_bytes())?;
        f.commit()
    })();
    if let Err(e) = written {
        remove_pieces(dir, stem, pieces.len(), false);
        return Err(e).with_context(|| format!("writing {}", vtm.display()));
    }
    Ok((pvtu, vtm))
}

/// Takes back what [`write_pieces`] wrote for `count` pieces: the piece files, their folder
/// (when left empty), the .pvtu and, with `vtm` (it was placed), the .vtm.
pub fn remove_pieces(dir: &Path, stem: &str, count: usize, vtm: bool) {
    for i in 0..count {
        let _ = std::fs::remove_file(dir.join(stem).join(format!("{stem}_{i}.vtu")));
    }
    let _ = std::fs::remove_dir(dir.join(stem));
    let _ = std::fs::remove_file(dir.join(format!("{stem}.pvtu")));
    if vtm {
        let _ = std::fs::remove_file(dir.join(format!("{stem}.vtm")));
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
