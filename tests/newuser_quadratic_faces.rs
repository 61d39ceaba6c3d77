//! `convert --tetrahedralize` of quadratic TetGen output (`tetgen -o2`: 10-node tets and 6-node
//! `.face` triangles) to TetGen files dropped every boundary face, with a note calling them
//! "vertices, lines, quads, polygons": the written `.face` was gone, and its markers with it.
//! Each quadratic triangle now becomes the 4 linear triangles its tets' pieces show there.

mod common;

use common::{fixture, tempdir, tetkit};
use std::collections::HashSet;
use tetkit::formats::{self, cell_type};

#[test]
fn quadratic_boundary_faces_survive_tetrahedralization_to_tetgen() {
    let dir = tempdir();
    let input = fixture("tetgen/quadratic.1.ele");
    let src = formats::read(&input).unwrap();
    let quad_faces = src
        .cells
        .types
        .iter()
        .filter(|&&t| t == cell_type::QUADRATIC_TRIANGLE)
        .count();
    assert!(quad_faces > 0);
    let out = dir.path().join("lin.ele");
    let r = tetkit([
        "convert".as_ref(),
        input.as_os_str(),
        out.as_os_str(),
        "--tetrahedralize".as_ref(),
    ]);
    r.assert_success();
    assert!(!r.stderr.contains("dropped"), "{}", r.stderr);
    let g = formats::read(&out).unwrap();
    let mut faces = HashSet::new();
    let mut tris = Vec::new();
    for i in 0..g.num_cells() {
        let mut c = g.cells.cell(i).to_vec();
        match g.cells.types[i] {
            cell_type::TETRA => {
                for skip in 0..4 {
                    let mut f: Vec<i64> = (0..4).filter(|&k| k != skip).map(|k| c[k]).collect();
                    f.sort();
                    faces.insert(f);
                }
            }
            cell_type::TRIANGLE => {
                c.sort();
                tris.push((i, c));
            }
            t => panic!("cell {i} has type {t}"),
        }
    }
    assert_eq!(tris.len(), 4 * quad_faces);
    for (i, t) in &tris {
        assert!(faces.contains(t), "triangle {i} {t:?} is no tet's face");
    }
    // Every marker of the input is still there, on its 4 pieces.
    let marks = |g: &formats::Grid| -> Vec<i64> {
        let a = g.cell_data.get("boundary_marker").unwrap();
        let mut v: Vec<i64> = (0..g.num_cells())
            .filter(|&i| {
                g.cells.types[i] != cell_type::TETRA
                    && g.cells.types[i] != cell_type::QUADRATIC_TETRA
            })
            .map(|i| a.data.get_f64(i) as i64)
            .collect();
        v.sort();
        v
    };
    let before: Vec<i64> = marks(&src).into_iter().flat_map(|m| [m; 4]).collect();
    assert_eq!(marks(&g), before);
}
