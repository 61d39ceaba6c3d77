//! Gmsh `.msh` fixtures (scripts/make_msh_fixtures.sh) through the real binary: `info` and
//! `convert` on each, ASCII and binary alike, the same mesh as Gmsh's own VTK export (up to that
//! export's known bugs), and VTK measuring every converted 3-D cell as positive with its
//! mid-edge and mid-face nodes where VTK's cell puts them.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use tetkit::formats::{self, cell_type as ct, ArrayData, Grid};

fn msh_fixtures() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(fixture("msh"))
        .expect("fixtures/msh")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "msh"))
        .collect();
    v.sort();
    assert!(v.len() >= 11, "{v:?}");
    v
}

fn read(p: &Path) -> Grid {
    formats::read(p).unwrap_or_else(|e| panic!("{e}"))
}

fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

#[test]
fn info_and_convert_every_fixture() {
    let dir = tempdir();
    for f in msh_fixtures() {
        let info = tetkit(["info".as_ref(), f.as_os_str()]);
        info.assert_success();
        let out = info.stdout_str();
        for name in ["gmsh:node_tag", "gmsh:physical", "gmsh:element_tag"] {
            assert!(
                out.contains(name),
                "{}: info lacks {name}:\n{out}",
                f.display()
            );
        }
        let vtu = dir.path().join(format!("{}.vtu", stem(&f)));
        tetkit(["convert".as_ref(), f.as_os_str(), vtu.as_os_str()]).assert_success();
        // The .vtu keeps everything the reader gave, bit for bit.
        let (a, b) = (read(&f), read(&vtu));
        grids_bit_equal(&a, &b).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let json = tetkit(["info".as_ref(), "--json".as_ref(), f.as_os_str()]);
        json.assert_success();
    }
}

/// Bit-identical grids, except that Gmsh prints ASCII reals with 16 significant digits, which
/// does not always give back the double its binary files hold: points and parametric
/// coordinates agree to 1e-15 (NaN where the other has NaN).
fn same_grid_but_ascii_rounding(a: &Grid, b: &Grid) -> Result<(), String> {
    let close = |what: &str, x: &ArrayData, y: &ArrayData| -> Result<(), String> {
        let (x, y) = (x.to_f64_vec(), y.to_f64_vec());
        if x.len() != y.len() {
            return Err(format!("{what}: {} values vs {}", x.len(), y.len()));
        }
        for (i, (p, q)) in x.iter().zip(&y).enumerate() {
            let same = (p.is_nan() && q.is_nan()) || (p - q).abs() <= 1e-15 * p.abs().max(1.0);
            if !same {
                return Err(format!("{what} value {i}: {p} vs {q}"));
            }
        }
        Ok(())
    };
    let mut b = b.clone();
    close("points", &a.points.data, &b.points.data)?;
    b.points = a.points.clone();
    if let (Some(x), Some(y)) = (
        a.point_data.get("gmsh:parametric"),
        b.point_data.get_mut("gmsh:parametric"),
    ) {
        close("gmsh:parametric", &x.data, &y.data)?;
        y.data = x.data.clone();
    }
    grids_bit_equal(a, &b)
}

#[test]
fn ascii_and_binary_give_identical_grids() {
    let g = |n: &str| read(&fixture(&format!("msh/{n}.msh")));
    for (a, b) in [
        ("block_hole_41", "block_hole_41_bin"),
        ("block_hole_22", "block_hole_22_bin"),
        ("params_41", "params_41_bin"),
    ] {
        same_grid_but_ascii_rounding(&g(a), &g(b)).unwrap_or_else(|e| panic!("{a} vs {b}: {e}"));
    }
    // 4.1 and 2.2 hold the same mesh; 2.2 has no entities, so the data must agree too.
    let (v4, v2) = (g("block_hole_41_bin"), g("block_hole_22_bin"));
    grids_bit_equal(&v4, &v2).unwrap();
}

#[test]
fn parametric_coordinates_as_gmsh_saves_them() {
    let g = read(&fixture("msh/params_41_bin.msh"));
    let p = g.point_data.get("gmsh:parametric").unwrap();
    assert_eq!(p.components, 3);
    let v = p.data.to_f64_vec();
    // Corner nodes and volume nodes have none; curve nodes u; surface nodes u and v.
    let count = |k: usize| {
        (0..g.num_points())
            .filter(|&i| !v[3 * i + k].is_nan())
            .count()
    };
    let (u, vv, w) = (count(0), count(1), count(2));
    assert!(u > vv && vv > 0 && w == 0, "u {u}, v {vv}, w {w}");
    assert!(u < g.num_points());
    // The same mesh without them has the same points and cells.
    let plain = read(&fixture("msh/mixed_41.msh"));
    assert!(plain.point_data.get("gmsh:parametric").is_none());
    assert_eq!(plain.cells, g.cells);
}

/// MSH 2.2 keeps parametric coordinates in `$ParametricNodes` instead of `$Nodes`; it was
/// skipped as unknown and the file refused ("$Elements before the $Nodes section"). It reads
/// as the MSH 4.1 file of the same mesh does.
#[test]
fn parametric_nodes_of_msh_2_2() {
    let (v2, v4) = (
        read(&fixture("msh/params_22.msh")),
        read(&fixture("msh/params_41.msh")),
    );
    assert_eq!(v2.num_points(), v4.num_points());
    assert_eq!(v2.points.data.to_f64_vec(), v4.points.data.to_f64_vec());
    let p = |g: &Grid| {
        g.point_data
            .get("gmsh:parametric")
            .unwrap()
            .data
            .to_f64_vec()
    };
    let (a, b) = (p(&v2), p(&v4));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(x == y || (x.is_nan() && y.is_nan()), "{x} vs {y}");
    }
    assert_eq!(v2.cells.types, v4.cells.types);
}

#[test]
fn physical_groups_and_names() {
    let g = read(&fixture("msh/block_hole_41_bin.msh"));
    let names = g
        .field_data
        .iter()
        .find(|a| a.name == "gmsh:physical_names")
        .unwrap();
    let ArrayData::String(n) = &names.data else {
        panic!("physical names are strings")
    };
    assert_eq!(n, &["hole", "outside", "solid"]);
    let tags = g
        .field_data
        .iter()
        .find(|a| a.name == "gmsh:physical_tags")
        .unwrap();
    let tag = |k: usize| tags.data.get_f64(k) as i32;
    let (hole, outside, solid) = (tag(0), tag(1), tag(2));
    let ArrayData::Int32(phys) = &g.cell_data.get("gmsh:physical").unwrap().data else {
        panic!()
    };
    // Tets are in "solid", boundary triangles in "hole" or "outside", and both get some.
    for (i, &t) in g.cells.types.iter().enumerate() {
        match t {
            ct::TETRA => assert_eq!(phys[i], solid),
            ct::TRIANGLE => assert!(phys[i] == hole || phys[i] == outside),
            _ => panic!("cell type {t}"),
        }
    }
    assert!(phys.contains(&hole) && phys.contains(&outside));
}

#[test]
fn views_become_arrays() {
    let f = fixture("msh/views_41.msh");
    let run = tetkit(["info".as_ref(), f.as_os_str()]);
    run.assert_success();
    assert!(
        run.stderr.contains("$ElementNodeData view 'slope' skipped"),
        "{}",
        run.stderr
    );
    let g = read(&f);
    let level = g.point_data.get("level").unwrap();
    let ArrayData::Float64(v) = &level.data else {
        panic!()
    };
    assert!(
        v.iter().all(|&x| x == 2.5),
        "Plugin(NewView) wrote 2.5 everywhere"
    );
    let step = g.point_data.get("level@1").unwrap();
    for (i, &x) in step.data.to_f64_vec().iter().enumerate() {
        let p = g.point(i);
        assert_eq!(x, p[0] - p[2], "node {i}");
    }
    let times = g
        .field_data
        .iter()
        .find(|a| a.name == "gmsh:time:level")
        .unwrap();
    assert_eq!(times.data.to_f64_vec().len(), 2);
    assert_eq!(times.data.get_f64(1), 0.5);
    let vel = g.cell_data.get("velocity").unwrap();
    assert_eq!(vel.components, 3);
    let vals = vel.data.to_f64_vec();
    assert_eq!(vals.iter().filter(|x| !x.is_nan()).count(), 9);
    assert!(g.point_data.get("slope").is_none() && g.cell_data.get("slope").is_none());
}

/// Gmsh's VTK export numbers a 2nd-order prism's nodes as VTK does but without mirroring it
/// (VTK measures those cells negative); tetkit mirrors it as it mirrors linear prisms, which
/// Gmsh's export does too. Entry k: the Gmsh-export node that is tetkit's node k.
const MIRROR_PRISM: [usize; 18] = [0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13, 17, 16, 15];
/// Gmsh's VTK export writes 2nd-order pyramids as VTK_PYRAMID (type 14) with 13 or 14 nodes in
/// Gmsh's own order (edges 01 03 04 12 14 23 24 34); VTK's quadratic pyramid wants 01 12 23 30 04
/// 14 24 34.
const PYRAMID_FROM_GMSH: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];

#[test]
fn same_mesh_as_gmsh_vtk_export() {
    for (msh, vtk) in [
        ("block_hole_41", "block_hole"),
        ("mixed_41", "mixed"),
        ("mixed_o2_41", "mixed_o2"),
        ("mixed_o2i_22_bin", "mixed_o2i"),
        ("tet_o2_41_bin", "tet_o2"),
    ] {
        let ours = read(&fixture(&format!("msh/{msh}.msh")));
        // Gmsh writes a 2nd-order pyramid as a linear one with 13 or 14 points, which tetkit's
        // legacy reader refuses; compare with the file's cells as Gmsh wrote them.
        let theirs = gmsh_vtk_cells(&fixture(&format!("msh/gmsh_vtk/{vtk}.vtk")));
        assert_eq!(ours.num_points(), theirs.points.len(), "{msh}");
        for (i, p) in theirs.points.iter().enumerate() {
            let q = ours.point(i);
            for k in 0..3 {
                assert!(
                    (p[k] - q[k]).abs() <= 1e-12,
                    "{msh}: point {i}: {p:?} vs {q:?}"
                );
            }
        }
        assert_eq!(ours.num_cells(), theirs.cells.len(), "{msh}");
        for (i, (t, ids)) in theirs.cells.iter().enumerate() {
            let (ot, oids) = (ours.cells.types[i], ours.cells.cell(i));
            let expect: Vec<i64> = match (*t, ot) {
                (a, b)
                    if a == b
                        && !matches!(a, ct::QUADRATIC_WEDGE | ct::BIQUADRATIC_QUADRATIC_WEDGE) =>
                {
                    ids.clone()
                }
                (a, b) if a == b => MIRROR_PRISM[..ids.len()].iter().map(|&k| ids[k]).collect(),
                (ct::PYRAMID, ct::QUADRATIC_PYRAMID) if ids.len() >= 13 => {
                    PYRAMID_FROM_GMSH.iter().map(|&k| ids[k]).collect()
                }
                _ => panic!("{msh}: cell {i}: Gmsh exports type {t}, tetkit reads {ot}"),
            };
            assert_eq!(oids, &expect[..], "{msh}: cell {i} (type {ot})");
        }
    }
}

struct VtkCells {
    points: Vec<[f64; 3]>,
    cells: Vec<(u8, Vec<i64>)>,
}

/// The points and cells of a legacy ASCII VTK 2.0 file as Gmsh writes it (POINTS, CELLS,
/// CELL_TYPES), read without validation.
fn gmsh_vtk_cells(path: &Path) -> VtkCells {
    let text = std::fs::read_to_string(path).unwrap();
    let mut toks = text.split_whitespace();
    let mut points = Vec::new();
    let mut cells = Vec::new();
    let mut sizes = Vec::new();
    while let Some(t) = toks.next() {
        match t {
            "POINTS" => {
                let n: usize = toks.next().unwrap().parse().unwrap();
                toks.next();
                for _ in 0..n {
                    let mut p = [0.0; 3];
                    for x in &mut p {
                        *x = toks.next().unwrap().parse().unwrap();
                    }
                    points.push(p);
                }
            }
            "CELLS" => {
                let n: usize = toks.next().unwrap().parse().unwrap();
                toks.next();
                for _ in 0..n {
                    let k: usize = toks.next().unwrap().parse().unwrap();
                    let ids: Vec<i64> = (0..k)
                        .map(|_| toks.next().unwrap().parse().unwrap())
                        .collect();
                    sizes.push(ids);
                }
            }
            "CELL_TYPES" => {
                let n: usize = toks.next().unwrap().parse().unwrap();
                for ids in sizes.drain(..).take(n) {
                    let t: u8 = toks.next().unwrap().parse().unwrap();
                    cells.push((t, ids));
                }
            }
            _ => {}
        }
    }
    VtkCells { points, cells }
}

/// VTK's view of each converted fixture: per 3-D cell type the smallest volume
/// vtkCellSizeFilter measures, and how many mid-edge and mid-face nodes are not where VTK's own
/// edges and faces of the cell say (VTK's GetEdge/GetFace give each edge's end and middle
/// nodes, each face's corners and centre).
const VTK_GEOMETRY: &str = r#"
import json, sys, vtk
import numpy as np
from vtk.util import numpy_support as ns
vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_OFF)
out = {}
# VTK measures its 18-node wedge and 27-node hexahedron wrongly (0 for the hexahedron, a
# volume of the wrong sign and size for the wedge even on its own reference cell), so those are
# measured through the 15-node wedge and 20-node hexahedron their first nodes form.
SUB = {32: (26, 15), 29: (25, 20)}
for path in sys.argv[1:]:
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pts = ns.vtk_to_numpy(g.GetPoints().GetData())
    h = vtk.vtkUnstructuredGrid()
    h.SetPoints(g.GetPoints())
    types = []
    bad_mid = 0
    for i in range(g.GetNumberOfCells()):
        c = g.GetCell(i)
        if c.GetCellDimension() != 3:
            continue
        t = c.GetCellType()
        ids = [c.GetPointId(k) for k in range(c.GetNumberOfPoints())]
        st, n = SUB.get(t, (t, len(ids)))
        h.InsertNextCell(st, n, ids[:n])
        types.append(t)
        for e in range(c.GetNumberOfEdges()):
            ed = c.GetEdge(e)
            if ed.GetNumberOfPoints() == 3:
                a, b, m = (pts[ed.GetPointId(k)] for k in range(3))
                # Where the swept fixture's cells collapse onto the sweep axis (x = y = 0), Gmsh
                # puts some middle nodes of the edges leaving the axis off the edge (its own
                # export has the same nodes); those edges are not judged.
                if min(np.hypot(a[0], a[1]), np.hypot(b[0], b[1])) < 1e-9:
                    continue
                if np.linalg.norm(m - (a + b) / 2) > 0.25 * np.linalg.norm(a - b):
                    bad_mid += 1
        for f in range(c.GetNumberOfFaces()):
            fa = c.GetFace(f)
            if fa.GetNumberOfPoints() == 9:
                corners = np.array([pts[fa.GetPointId(k)] for k in range(4)])
                m = pts[fa.GetPointId(8)]
                if np.linalg.norm(m - corners.mean(0)) > 0.25 * np.linalg.norm(corners[0] - corners[2]):
                    bad_mid += 1
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(h)
    f.Update()
    vol = ns.vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume"))
    types = np.array(types)
    out[path] = {
        "min_volume": {str(t): float(vol[types == t].min()) for t in np.unique(types)},
        "bad_mid_nodes": bad_mid,
    }
json.dump(out, sys.stdout)
"#;

#[test]
fn vtk_measures_every_converted_cell_positive() {
    if !require_vtk("vtk_measures_every_converted_cell_positive") {
        return;
    }
    let dir = tempdir();
    let mut outs = Vec::new();
    for f in msh_fixtures() {
        let vtu = dir.path().join(format!("{}.vtu", stem(&f)));
        tetkit(["convert".as_ref(), f.as_os_str(), vtu.as_os_str()]).assert_success();
        // VTK reads the same points, cells and arrays tetkit wrote.
        let grid = read(&f);
        compare_with_vtk(&grid, &vtk_check(&vtu, false))
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        outs.push(vtu);
    }
    let args: Vec<&str> = outs.iter().map(|p| p.to_str().unwrap()).collect();
    let report: serde_json::Value = serde_json::from_str(&vtk_python(VTK_GEOMETRY, &args)).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for p in &args {
        let r = &report[*p];
        assert_eq!(r["bad_mid_nodes"], 0, "{p}: {r}");
        for (t, v) in r["min_volume"].as_object().unwrap() {
            assert!(
                v.as_f64().unwrap() > 0.0,
                "{p}: a cell of type {t} has volume {v}"
            );
            seen.insert(t.clone());
        }
    }
    // Every 3-D type the reader makes was measured.
    for t in [10, 12, 13, 14, 24, 25, 26, 27, 29, 32] {
        assert!(
            seen.contains(&t.to_string()),
            "no cell of type {t} measured: {seen:?}"
        );
    }
}

#[test]
fn refusals_name_file_and_place() {
    let dir = tempdir();
    let text = std::fs::read_to_string(fixture("msh/block_hole_22.msh")).unwrap();
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("truncated", text[..text.len() / 2].to_string(), vec!["truncated.msh: line"]),
        (
            "v3",
            text.replacen("2.2 0 8", "3.0 0 8", 1),
            vec!["v3.msh: line 2:", "MSH version 3.0"],
        ),
        (
            "unknown_node",
            {
                // The first tet's last node becomes one the file does not have.
                let i = text.find("\n281 4 2 1 1 ").unwrap();
                let line_end = i + 1 + text[i + 1..].find('\n').unwrap();
                let mut t = text[..line_end].to_string();
                let cut = t.rfind(' ').unwrap();
                t.truncate(cut);
                t.push_str(" 99999");
                t.push_str(&text[line_end..]);
                t
            },
            vec!["unknown_node.msh: line", "refers to node 99999"],
        ),
        (
            "order3",
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n1 1 26 1\n1 1 2 3 4\n$EndElements\n".to_string(),
            vec!["order3.msh: line 9:", "element type 26 (4-node line) is of order 3"],
        ),
    ];
    for (name, body, needles) in cases {
        let p = dir.path().join(format!("{name}.msh"));
        std::fs::write(&p, body).unwrap();
        tetkit(["info".as_ref(), p.as_os_str()]).assert_failure(&needles);
        let out = dir.path().join(format!("{name}.vtu"));
        tetkit(["convert".as_ref(), p.as_os_str(), out.as_os_str()]).assert_failure(&needles);
        assert!(!out.exists());
    }
    // Writing .msh is refused.
    let out = dir.path().join("x.msh");
    let src = fixture("msh/mixed_41.msh");
    tetkit(["convert".as_ref(), src.as_os_str(), out.as_os_str()])
        .assert_failure(&["does not write"]);
}

#[test]
fn stdin_is_sniffed_as_msh() {
    let bytes = std::fs::read(fixture("msh/block_hole_22_bin.msh")).unwrap();
    let run = tetkit_stdin(["info", "--json", "-"], &bytes);
    run.assert_success();
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["points"], 141, "{v}");
    let run = tetkit_stdin(["info", "-"], b"$MeshFormat\n4.0 0 8\n$EndMeshFormat\n");
    run.assert_failure(&["<stdin>: line 2:", "MSH version 4.0"]);
}

/// MSH 2.2 writes an element once per physical group it is in: the copies stay cells, as Gmsh
/// reads them back, but the mesh then overlaps itself (a new user's volume counted 3.0 for 2.0),
/// and nothing said so where the MSH 4.1 reader warns. Now a warning counts the copies.
#[test]
fn elements_in_two_physical_groups_are_counted_as_copies() {
    let path = fixture("msh/multi_group_22.msh");
    let g = read(&path);
    assert_eq!(
        g.cells.types.iter().filter(|&&t| t == ct::TETRA).count(),
        300
    );
    let r = tetkit(["info", path.to_str().unwrap()]);
    r.assert_success();
    assert!(
        r.stderr
            .contains("100 elements repeat an earlier one's type and nodes"),
        "{}",
        r.stderr
    );
    let plain = tetkit(["info", fixture("msh/block_hole_22.msh").to_str().unwrap()]);
    assert!(!plain.stderr.contains("repeat"), "{}", plain.stderr);
}
