//! fixtures/tetgen/ (made by scripts/make_tetgen_fixtures.sh with Debian's tetgen): counts agree
//! with what tetgen printed, quadratic nodes sit on edge midpoints in VTK's order, region
//! attributes and neighbours come through, and an independent python read of the sphere agrees.

mod legacy_common;

use formats::{cell_type, ArrayData, Grid};
use legacy_common::*;
use std::process::Command;

/// `Mesh points`, `Mesh tetrahedra`, `Mesh faces on facets` from the tetgen log.
fn logged(name: &str) -> (usize, usize, usize) {
    let text = std::fs::read_to_string(root().join(format!("fixtures/tetgen/{name}.log"))).unwrap();
    let get = |key: &str| -> usize {
        text.lines()
            .find_map(|l| l.trim().strip_prefix(key))
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or_else(|| panic!("{name}.log has no '{key}'"))
    };
    (
        get("Mesh points:"),
        get("Mesh tetrahedra:"),
        get("Mesh faces on facets:"),
    )
}

fn read(name: &str) -> Grid {
    formats::read(&root().join(format!("fixtures/tetgen/{name}.1.ele")))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn count(g: &Grid, t: u8) -> usize {
    g.cells.types.iter().filter(|&&x| x == t).count()
}

fn signed_volume(g: &Grid, c: &[i64]) -> f64 {
    let p: Vec<[f64; 3]> = c.iter().take(4).map(|&i| g.point(i as usize)).collect();
    let d = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let (u, v, w) = (d(p[1], p[0]), d(p[2], p[0]), d(p[3], p[0]));
    (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]))
        / 6.0
}

#[test]
fn counts_agree_with_tetgen() {
    for (name, tet, tri) in [
        ("sphere", cell_type::TETRA, cell_type::TRIANGLE),
        ("torus", cell_type::TETRA, cell_type::TRIANGLE),
        ("regions", cell_type::TETRA, cell_type::TRIANGLE),
        (
            "quadratic",
            cell_type::QUADRATIC_TETRA,
            cell_type::QUADRATIC_TRIANGLE,
        ),
    ] {
        let g = read(name);
        let (np, nt, nf) = logged(name);
        assert_eq!(g.num_points(), np, "{name} points");
        assert_eq!(count(&g, tet), nt, "{name} tets");
        assert_eq!(count(&g, tri), nf, "{name} faces");
        assert_eq!(
            g.num_cells(),
            nt + nf,
            "{name}: only tets and boundary faces"
        );
        // Tets first, then faces, as the module documents.
        assert!(g.cells.types[..nt].iter().all(|&t| t == tet));
        let markers = g.cell_data.get("boundary_marker").expect("face markers");
        assert_eq!(markers.tuples(), nt + nf);
    }
}

#[test]
fn tets_are_consistently_oriented_and_fill_the_solid() {
    for (name, volume, tol) in [
        ("sphere", 4.0 / 3.0 * std::f64::consts::PI, 0.05),
        // The torus surface is a 24 x 12 polygonal approximation of R = 1, r = 0.4.
        ("torus", 2.0 * std::f64::consts::PI.powi(2) * 0.16, 0.08),
    ] {
        let g = read(name);
        let tets: Vec<usize> = (0..g.num_cells())
            .filter(|&i| g.cells.types[i] == cell_type::TETRA)
            .collect();
        let vols: Vec<f64> = tets
            .iter()
            .map(|&i| signed_volume(&g, g.cells.cell(i)))
            .collect();
        let sign = vols[0].signum();
        assert!(
            vols.iter().all(|v| v.signum() == sign && *v != 0.0),
            "{name}: mixed orientation"
        );
        let total: f64 = vols.iter().map(|v| v.abs()).sum();
        assert!(
            (total - volume).abs() < tol * volume,
            "{name}: volume {total} vs {volume}"
        );
    }
    // The torus is not convex: its hole's axis point lies inside the bounding box but in no tet.
    let g = read("torus");
    let b = g.bounds().unwrap();
    assert!(b[0] < 0.0 && b[1] > 0.0 && b[2] < 0.0 && b[3] > 0.0);
}

#[test]
fn quadratic_edge_nodes_are_midpoints_in_vtk_order() {
    let g = read("quadratic");
    let edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)];
    let mut checked = 0;
    for i in 0..g.num_cells() {
        if g.cells.types[i] != cell_type::QUADRATIC_TETRA {
            continue;
        }
        let c = g.cells.cell(i);
        for (k, (a, b)) in edges.iter().enumerate() {
            let (pa, pb, m) = (
                g.point(c[*a] as usize),
                g.point(c[*b] as usize),
                g.point(c[4 + k] as usize),
            );
            for d in 0..3 {
                assert!(
                    ((pa[d] + pb[d]) / 2.0 - m[d]).abs() < 1e-12,
                    "cell {i} node {}",
                    4 + k
                );
            }
        }
        checked += 1;
    }
    assert_eq!(checked, 12);
}

#[test]
fn region_attributes_and_neighbours() {
    let g = read("regions");
    let (_, nt, _) = logged("regions");
    let ArrayData::Float64(r) = &g.cell_data.get("region").expect("region array").data else {
        panic!("region is Float64")
    };
    let ones = r[..nt].iter().filter(|&&x| x == 1.0).count();
    let twos = r[..nt].iter().filter(|&&x| x == 2.0).count();
    assert_eq!(ones + twos, nt);
    assert!(ones > 0 && twos > 0);
    assert!(r[nt..].iter().all(|x| x.is_nan()), "faces carry no region");

    let g = read("sphere");
    let (_, nt, _) = logged("sphere");
    let ArrayData::Int64(n) = &g.cell_data.get("neighbors").expect("neighbors").data else {
        panic!("neighbors is Int64")
    };
    // Neighbourhood is symmetric, and each tet's boundary faces (-1) are boundary triangles.
    let mut boundary = 0;
    for t in 0..nt {
        for k in 0..4 {
            let u = n[4 * t + k];
            if u < 0 {
                boundary += 1;
            } else {
                assert!(n[4 * u as usize..4 * u as usize + 4].contains(&(t as i64)));
            }
        }
    }
    assert_eq!(boundary, count(&g, cell_type::TRIANGLE));
}

#[test]
fn a_python_read_of_the_sphere_agrees() {
    let script = r#"
import sys
def rows(p):
    out = []
    for line in open(p):
        line = line.split('#')[0].split()
        if line:
            out.append(line)
    return out
node = rows(sys.argv[1] + '.node')
ele = rows(sys.argv[1] + '.ele')
first = int(node[1][0])
xyz = {int(r[0]) - first: [float(x) for x in r[1:4]] for r in node[1:]}
ids = [int(x) - first for r in ele[1:] for x in r[1:5]]
print(len(xyz), len(ele) - 1, sum(ids), repr(sum(sum(p) for p in xyz.values())))
"#;
    let out = Command::new("/usr/bin/python3")
        .args(["-c", script])
        .arg(root().join("fixtures/tetgen/sphere.1"))
        .output()
        .expect("python3");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let f: Vec<&str> = text.split_whitespace().collect();
    let g = read("sphere");
    let (_, nt, _) = logged("sphere");
    assert_eq!(f[0].parse::<usize>().unwrap(), g.num_points());
    assert_eq!(f[1].parse::<usize>().unwrap(), nt);
    let conn: i64 = g.cells.connectivity[..4 * nt].iter().sum();
    assert_eq!(f[2].parse::<i64>().unwrap(), conn);
    // Same parse of the same decimal text, summed in the same order: identical bits.
    let sum: f64 = (0..g.num_points())
        .map(|i| g.point(i).iter().sum::<f64>())
        .sum();
    let py: f64 = f[3].parse().unwrap();
    assert!(
        (py - sum).abs() <= 1e-12 * g.num_points() as f64,
        "{py} vs {sum}"
    );
}

#[test]
fn info_and_convert_run_on_the_readme_fixture() {
    let out = tetkit(&["info", "--json", "fixtures/tetgen/sphere.1.ele"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (np, nt, nf) = logged("sphere");
    assert_eq!(v["points"], np);
    assert_eq!(v["cells"], nt + nf);
    let dir = tempfile::tempdir().unwrap();
    let vtk = dir.path().join("sphere.vtk");
    let out = tetkit(&["convert", "fixtures/tetgen/sphere.1.ele", path_str(&vtk)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let back = formats::read(&vtk).unwrap();
    same_grid(&back, &read("sphere")).unwrap();
}

#[test]
fn written_tetgen_files_read_back_the_same() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["sphere", "regions", "quadratic", "torus"] {
        let g = read(name);
        let out = dir.path().join(format!("{name}.2.node"));
        formats::write(&out, &g, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let back = formats::read(&out).unwrap();
        // Everything comes back, `neighbors` through `.neigh` where the mesh had one.
        same_grid(&back, &g).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            dir.path().join(format!("{name}.2.neigh")).exists(),
            g.cell_data.get("neighbors").is_some(),
            "{name}"
        );
    }
}

/// A `neighbors` array `.neigh` cannot hold (here one pointing at a boundary triangle, and one
/// of three components) is not dropped: it goes to `.ele` as attribute columns.
#[test]
fn a_neighbors_array_neigh_cannot_hold_becomes_attribute_columns() {
    let dir = tempfile::tempdir().unwrap();
    let (_, nt, _) = logged("sphere");
    for comps in [4usize, 3] {
        let mut g = read("sphere");
        let Some(a) = g
            .cell_data
            .arrays
            .iter_mut()
            .find(|a| a.name == "neighbors")
        else {
            panic!("the sphere has neighbours");
        };
        let ArrayData::Int64(v) = &mut a.data else {
            panic!("neighbors is Int64")
        };
        // Tet 0's first neighbour: the first boundary triangle (cell nt), not a tet.
        v[0] = nt as i64;
        if comps == 3 {
            let n = v.len() / 4;
            let three: Vec<i64> = (0..n * 3).map(|k| v[k / 3 * 4 + k % 3]).collect();
            *v = three;
            a.components = 3;
        }
        let out = dir.path().join(format!("n{comps}.node"));
        formats::write(&out, &g, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(!dir.path().join(format!("n{comps}.neigh")).exists());
        let back = formats::read(&out).unwrap();
        let ele = std::fs::read_to_string(dir.path().join(format!("n{comps}.ele"))).unwrap();
        let header: Vec<&str> = ele
            .lines()
            .find(|l| !l.starts_with('#'))
            .unwrap()
            .split_whitespace()
            .collect();
        // The neighbours' columns (the sphere has no region attribute).
        assert_eq!(header[2], comps.to_string(), "{header:?}");
        let attr = formats::tetgen::names::ele_attribute(comps - 1);
        assert!(back.cell_data.get(&attr).is_some(), "no {attr}");
    }
}

#[test]
fn tetgen_writer_refuses_other_cells_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let g = formats::read(&root().join("fixtures/legacy/mixed_51_binary.vtk")).unwrap();
    let out = dir.path().join("mixed.ele");
    let e = formats::write(&out, &g, &Default::default()).unwrap_err();
    assert!(e.message.contains("tetrahedralize"), "{e}");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no partial files"
    );
}

#[test]
fn rewriting_without_faces_removes_stale_face_and_neigh_files() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["node", "ele", "face", "neigh"] {
        std::fs::copy(
            root().join(format!("fixtures/tetgen/sphere.1.{ext}")),
            dir.path().join(format!("s.{ext}")),
        )
        .unwrap();
    }
    let mut g = read("sphere");
    let (_, nt, _) = logged("sphere");
    let keep: Vec<usize> = (0..nt).collect();
    g.cells.types.truncate(nt);
    g.cells.offsets.truncate(nt + 1);
    g.cells.connectivity.truncate(4 * nt);
    g.cell_data = g.cell_data.gather(&keep);
    g.cell_data.arrays.retain(|a| a.name != "neighbors");
    formats::write(&dir.path().join("s.node"), &g, &Default::default()).unwrap();
    assert!(!dir.path().join("s.face").exists() && !dir.path().join("s.neigh").exists());
    let back = formats::read(&dir.path().join("s.ele")).unwrap();
    assert_eq!(back.num_cells(), nt);
}

/// `tetgen -o2` without other switches writes 10-node tets but 3-node boundary faces; the
/// reader expected 6-node faces next to 10-node tets and refused the file ("a face line has 4
/// fields, expected 7"). The faces' node count now comes from the first face line.
#[test]
fn second_order_tets_with_three_node_faces_read() {
    let g = read("cube_o2");
    assert_eq!(count(&g, cell_type::QUADRATIC_TETRA), 6);
    assert_eq!(count(&g, cell_type::TRIANGLE), 12);
    assert_eq!(g.num_points(), 27);
}
