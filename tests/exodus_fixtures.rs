//! Exodus II fixtures (scripts/make_exodus_fixtures.py, written by VTK's vtkExodusIIWriter)
//! through the real binary: `info`, `convert` and `render` on each; the same cells, node
//! coordinates and arrays as VTK's vtkExodusIIReader gives (its output saved beside each file
//! as X_vtk.vtu); time steps by `FILE.exo@K`; VTK reading the converted files back with every
//! 3-D cell of positive volume.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use tetkit::formats::{self, cell_type as ct, ArrayData, DataArray, Grid};

fn exodus_fixtures() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(fixture("exodus"))
        .expect("fixtures/exodus")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "exo"))
        .collect();
    v.sort();
    assert!(v.len() >= 6, "{v:?}");
    v
}

fn read(p: &Path) -> Grid {
    formats::read(p).unwrap_or_else(|e| panic!("{e}"))
}

fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

fn vtk_reading(p: &Path) -> Grid {
    read(&p.with_file_name(format!("{}_vtk.vtu", stem(p))))
}

fn field(g: &Grid, name: &str) -> Vec<f64> {
    g.field_data
        .iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("no field array {name}"))
        .data
        .to_f64_vec()
}

#[test]
fn info_convert_and_render_every_fixture() {
    let dir = tempdir();
    for f in exodus_fixtures() {
        let info = tetkit(["info".as_ref(), f.as_os_str()]);
        info.assert_success();
        let out = info.stdout_str();
        for needle in ["ObjectId", "exodus:time", "time steps:"] {
            assert!(
                out.contains(needle),
                "{}: info lacks {needle}:\n{out}",
                f.display()
            );
        }
        let json = tetkit(["info".as_ref(), "--json".as_ref(), f.as_os_str()]);
        json.assert_success();
        let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
        assert!(v["time_steps"]["steps"].is_array(), "{v}");
        let vtu = dir.path().join(format!("{}.vtu", stem(&f)));
        tetkit(["convert".as_ref(), f.as_os_str(), vtu.as_os_str()]).assert_success();
        // The .vtu keeps everything the reader gave, bit for bit.
        grids_bit_equal(&read(&f), &read(&vtu)).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        // The view commands cut 3-D cells into tets, which they cannot yet do for 20-node
        // hexahedra, 15-node wedges and 13-node pyramids (any format's).
        if matches!(stem(&f).as_str(), "quadratic" | "hand" | "hand5") {
            continue;
        }
        let png = dir.path().join(format!("{}.png", stem(&f)));
        tetkit([
            "render".as_ref(),
            f.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--size".as_ref(),
            "64x64".as_ref(),
        ])
        .assert_success();
        assert!(std::fs::metadata(&png).unwrap().len() > 0);
    }
}

fn close(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-6 * a.abs().max(1.0)
}

/// Our array and VTK's agree: `ours_at(i)` / `theirs_at(i)` give the values to compare.
fn same_values(
    what: &str,
    n: usize,
    ours: &DataArray,
    theirs: &DataArray,
    index: impl Fn(usize) -> (usize, usize),
) {
    assert_eq!(ours.components, theirs.components, "{what}");
    let c = ours.components;
    for i in 0..n {
        let (o, t) = index(i);
        for k in 0..c {
            let (x, y) = (ours.data.get_f64(o * c + k), theirs.data.get_f64(t * c + k));
            assert!(close(x, y), "{what}: value {i}.{k}: tetkit {x}, VTK {y}");
        }
    }
}

/// VTK's reader gives each block the points its cells use (shared nodes once per block), so
/// cells are compared by their nodes' coordinates and point arrays through the cells.
#[test]
fn same_cells_and_arrays_as_vtk_reader() {
    for f in exodus_fixtures() {
        let name = f.display().to_string();
        let (ours, theirs) = (read(&f), vtk_reading(&f));
        assert_eq!(ours.num_cells(), theirs.num_cells(), "{name}: cells");
        for c in 0..ours.num_cells() {
            let (mut a, b) = (ours.cells.cell(c), theirs.cells.cell(c));
            let (ta, tb) = (ours.cells.types[c], theirs.cells.types[c]);
            // VTK 9.1's reader makes a 9-node quadrilateral an 8-node one, dropping the centre;
            // tetkit keeps it.
            if (ta, tb) == (ct::BIQUADRATIC_QUAD, ct::QUADRATIC_QUAD) {
                a = &a[..8];
            } else {
                assert_eq!(ta, tb, "{name}: cell {c}'s type");
            }
            assert_eq!(a.len(), b.len(), "{name}: cell {c}");
            for (k, (&p, &q)) in a.iter().zip(b).enumerate() {
                let (x, y) = (ours.point(p as usize), theirs.point(q as usize));
                assert!(
                    (0..3).all(|i| close(x[i], y[i])),
                    "{name}: cell {c} node {k}: tetkit {x:?}, VTK {y:?}"
                );
            }
        }
        // Every array VTK's reader makes, other than its pedigree ids (copies of the global
        // ids), tetkit makes too, under the same name.
        for t in &theirs.cell_data.arrays {
            if t.name.starts_with("Pedigree") {
                continue;
            }
            let o = ours
                .cell_data
                .get(&t.name)
                .unwrap_or_else(|| panic!("{name}: no cell array {}", t.name));
            same_values(
                &format!("{name} cell {}", t.name),
                ours.num_cells(),
                o,
                t,
                |i| (i, i),
            );
        }
        for t in &theirs.point_data.arrays {
            if t.name.starts_with("Pedigree") {
                continue;
            }
            let o = ours
                .point_data
                .get(&t.name)
                .unwrap_or_else(|| panic!("{name}: no point array {}", t.name));
            let pairs: Vec<(usize, usize)> = (0..ours.num_cells())
                .flat_map(|c| {
                    let (a, b) = (ours.cells.cell(c), theirs.cells.cell(c));
                    // zip stops at VTK's 8 nodes of a 9-node quadrilateral.
                    a.iter()
                        .zip(b)
                        .map(|(&p, &q)| (p as usize, q as usize))
                        .collect::<Vec<_>>()
                })
                .collect();
            same_values(
                &format!("{name} point {}", t.name),
                pairs.len(),
                o,
                t,
                |i| pairs[i],
            );
        }
        // Types as VTK's reader gives them.
        assert!(matches!(
            ours.cell_data.get("ObjectId").unwrap().data,
            ArrayData::Int32(_)
        ));
        for (attrs, id) in [
            (&ours.cell_data, "GlobalElementId"),
            (&ours.point_data, "GlobalNodeId"),
        ] {
            if let Some(a) = attrs.get(id) {
                assert!(matches!(a.data, ArrayData::Int64(_)), "{name}: {id}");
            }
        }
    }
}

#[test]
fn block_ids_names_and_global_ids() {
    let g = read(&fixture("exodus/tets.exo"));
    let ids = g.cell_data.get("ObjectId").unwrap().data.to_f64_vec();
    assert!(ids.iter().all(|&i| i == 10.0 || i == 20.0), "{ids:?}");
    // Block by block, as VTK's reader numbers cells.
    assert!(ids.windows(2).all(|w| w[0] <= w[1]), "{ids:?}");
    let gid = g.point_data.get("GlobalNodeId").unwrap();
    assert_eq!(
        gid.data,
        ArrayData::Int64((0..g.num_points() as i64).map(|i| 3 * i + 7).collect())
    );
    let names = g
        .field_data
        .iter()
        .find(|a| a.name == "exodus:block_names")
        .unwrap();
    assert_eq!(names.tuples(), 2);
}

#[test]
fn time_steps_by_selector() {
    let f = fixture("exodus/steps.exo");
    let dir = tempdir();
    for (sel, t) in [
        ("", 0.0),
        ("@0", 0.0),
        ("@1", 0.5),
        ("@2", 1.25),
        ("@last", 1.25),
    ] {
        let input = format!("{}{sel}", f.display());
        let out = dir.path().join("step.vtu");
        tetkit(["convert", input.as_str(), out.to_str().unwrap()]).assert_success();
        let g = read(&out);
        assert_eq!(field(&g, "exodus:time"), vec![0.0, 0.5, 1.25]);
        let energy = g.cell_data.get("energy").unwrap().data.to_f64_vec();
        assert!(energy.iter().all(|&e| e == t * t), "{sel}: {energy:?}");
        let phi = g.point_data.get("phi").unwrap().data.to_f64_vec();
        for (i, v) in phi.iter().enumerate() {
            let x = g.point(i)[0];
            // The fixture script computes phi in single precision.
            assert!((v - (3.0 * x + t).sin()).abs() < 1e-6, "{sel}: point {i}");
        }
        let info = tetkit(["info", input.as_str()]);
        info.assert_success();
        assert!(info.stdout_str().contains("time steps: 3"));
    }
    let input = format!("{}@3", f.display());
    tetkit(["info", input.as_str()])
        .assert_failure(&["steps.exo: there is no time step 3: the file has 3 (0 to 2)"]);
}

/// The hand-written CDF-1 and CDF-5 files: an element variable, a node set, a global variable, and step 1
/// by selector.
#[test]
fn hand_written_cdf1_variables_and_sets() {
    let f = fixture("exodus/hand.exo");
    let g = read(Path::new(&format!("{}@1", f.display())));
    let heat = g.cell_data.get("heat").unwrap().data.to_f64_vec();
    assert_eq!(heat, vec![2.0, 4.0]);
    assert_eq!(field(&g, "work"), vec![1.0, 2.0]);
    assert_eq!(field(&g, "exodus:time"), vec![0.0, 0.75]);
    let bottom = g
        .point_data
        .get("nodeset:bottom")
        .unwrap()
        .data
        .to_f64_vec();
    assert_eq!(bottom.iter().sum::<f64>(), 4.0);
    assert!(bottom[..4].iter().all(|&b| b == 1.0));
    let step0 = read(&f);
    let (d0, d1) = (
        step0.point_data.get("dist").unwrap().data.to_f64_vec(),
        g.point_data.get("dist").unwrap().data.to_f64_vec(),
    );
    assert!(d0.iter().zip(&d1).all(|(a, b)| *b == 2.0 * a));
    assert_eq!(
        g.cells.types,
        vec![ct::TRIQUADRATIC_HEXAHEDRON, ct::BIQUADRATIC_QUAD]
    );
    // The same file as CDF-5 (64-bit counts and offsets) reads the same.
    grids_bit_equal(&step0, &read(&fixture("exodus/hand5.exo"))).unwrap();
}

#[test]
fn refusals_name_file_and_place() {
    let dir = tempdir();
    let bytes = std::fs::read(fixture("exodus/tets.exo")).unwrap();
    let hdf = dir.path().join("new.exo");
    let mut h = b"\x89HDF\r\n\x1a\n".to_vec();
    h.resize(512, 0);
    std::fs::write(&hdf, h).unwrap();
    tetkit(["info".as_ref(), hdf.as_os_str()]).assert_failure(&["new.exo: NetCDF-4 (HDF5): "]);
    let cut = dir.path().join("cut.e");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    tetkit(["info".as_ref(), cut.as_os_str()]).assert_failure(&["cut.e: byte "]);
    let wrong = dir.path().join("wrong.vtu");
    std::fs::write(&wrong, &bytes).unwrap();
    tetkit(["info".as_ref(), wrong.as_os_str()])
        .assert_failure(&["the extension says VTU but the content is Exodus II"]);
    let out = dir.path().join("out.exo");
    tetkit([
        "convert".as_ref(),
        fixture("exodus/tets.exo").as_os_str(),
        out.as_os_str(),
    ])
    .assert_failure(&["tetkit reads Exodus II but does not write it"]);
}

/// The grid with each 27-node hexahedron cut to the 20-node one its first nodes form: VTK
/// measures its own 27-node hexahedron as 0.
fn measurable(g: &Grid) -> Grid {
    let mut out = g.clone();
    out.cells = formats::Cells::new();
    for c in 0..g.num_cells() {
        match g.cells.types[c] {
            ct::TRIQUADRATIC_HEXAHEDRON => out
                .cells
                .push(ct::QUADRATIC_HEXAHEDRON, &g.cells.cell(c)[..20]),
            t => out.cells.push(t, g.cells.cell(c)),
        }
    }
    out
}

#[test]
fn vtk_reads_the_converted_files_with_positive_volumes() {
    if !require_vtk("vtk_reads_the_converted_files_with_positive_volumes") {
        return;
    }
    let dir = tempdir();
    let mut outs = Vec::new();
    let mut grids = Vec::new();
    for f in exodus_fixtures() {
        let vtu = dir.path().join(format!("{}.vtu", stem(&f)));
        tetkit(["convert".as_ref(), f.as_os_str(), vtu.as_os_str()]).assert_success();
        grids.push(read(&f));
        outs.push(vtu);
    }
    // VTK reads what tetkit wrote, bit for bit.
    for ((vtu, grid), r) in outs.iter().zip(&grids).zip(vtk_check_many(&outs, false)) {
        let r = r.unwrap_or_else(|e| panic!("{e}"));
        compare_with_vtk(grid, &r).unwrap_or_else(|e| panic!("{}: {e}", vtu.display()));
    }
    let measured: Vec<PathBuf> = grids
        .iter()
        .zip(&outs)
        .map(|(g, vtu)| {
            let p = vtu.with_extension("measured.vtu");
            formats::write(&p, &measurable(g), &Default::default()).unwrap();
            p
        })
        .collect();
    for (p, r) in measured.iter().zip(vtk_check_many(&measured, true)) {
        let r = r.unwrap_or_else(|e| panic!("{e}"));
        let min = r["min_cell_volume"].as_f64().unwrap();
        assert!(min > 0.0, "{}: a cell of volume {min}", p.display());
    }
}

/// The NetCDF-4 (HDF5) copies (scripts/make_exodus_nc4_fixtures.sh) and the classic files they
/// were made from: `nccopy -k nc4 -d 1 -s` (chunked, deflate + shuffle), `-k nc7` (netCDF-4
/// classic model), and a file written as meshio writes Exodus (int64 connectivity; NC_STRING
/// names in meshio_strings.exo) beside its CDF-5 copy.
const NC4_COPIES: [(&str, &str); 10] = [
    ("nc4/hand.exo", "hand.exo"),
    ("nc4/hand.exo", "hand5.exo"),
    ("nc4/mixed.exo", "mixed.exo"),
    ("nc4/quadratic.exo", "quadratic.exo"),
    ("nc4/steps.exo", "steps.exo"),
    ("nc4/steps_nc7.exo", "steps.exo"),
    ("nc4/tets.exo", "tets.exo"),
    ("nc4/tets_nc7.exo", "tets.exo"),
    ("nc4/meshio.exo", "nc4/meshio_cdf5.exo"),
    ("nc4/meshio_strings.exo", "nc4/meshio_cdf5.exo"),
];

fn exodus(rel: &str) -> PathBuf {
    fixture(&format!("exodus/{rel}"))
}

fn at_step(p: &Path, k: usize) -> PathBuf {
    PathBuf::from(format!("{}@{k}", p.display()))
}

/// Every step of every NetCDF-4 copy reads to the same grid as its classic original, bit for
/// bit; `info` lists the same steps; `convert` to .vtu keeps it all.
#[test]
fn netcdf4_copies_read_as_their_classic_originals() {
    let dir = tempdir();
    for (nc4, classic) in NC4_COPIES {
        let (a, b) = (exodus(nc4), exodus(classic));
        let json = |p: &Path| {
            let run = tetkit(["info".as_ref(), "--json".as_ref(), p.as_os_str()]);
            run.assert_success();
            let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
            v["time_steps"].clone()
        };
        let steps = json(&a);
        assert_eq!(steps, json(&b), "{nc4}: time steps");
        let n = steps["steps"].as_array().unwrap().len();
        assert!(n >= 1, "{nc4}: {steps}");
        let info = tetkit(["info".as_ref(), a.as_os_str()]);
        info.assert_success();
        assert!(
            info.stdout_str().contains(&format!("time steps: {n}")),
            "{nc4}:\n{}",
            info.stdout_str()
        );
        for k in 0..n {
            let (ga, gb) = (read(&at_step(&a, k)), read(&at_step(&b, k)));
            grids_bit_equal(&ga, &gb).unwrap_or_else(|e| panic!("{nc4}@{k}: {e}"));
        }
        let vtu = dir.path().join("copy.vtu");
        tetkit(["convert".as_ref(), a.as_os_str(), vtu.as_os_str()]).assert_success();
        grids_bit_equal(&read(&vtu), &read(&b)).unwrap_or_else(|e| panic!("{nc4} .vtu: {e}"));
    }
    let g = read(&exodus("nc4/steps.exo@last"));
    assert_eq!(field(&g, "exodus:time"), vec![0.0, 0.5, 1.25]);
    let energy = g.cell_data.get("energy").unwrap().data.to_f64_vec();
    assert!(energy.iter().all(|&e| e == 1.25 * 1.25), "{energy:?}");
}

/// VTK's vtkExodusIIReader (through netCDF-C) reads the nccopy'd NetCDF-4 copies as it reads
/// their classic originals, at every step, and as many cells as tetkit gives. (VTK 9.1 cannot
/// read the meshio-style file's coordinates in either encoding, so it is left out.)
#[test]
fn vtk_reads_the_netcdf4_copies_as_the_classic_files() {
    if !require_vtk("vtk_reads_the_netcdf4_copies_as_the_classic_files") {
        return;
    }
    const CODE: &str = r#"
import sys, vtk
out = sys.argv[1]
for i, path in enumerate(sys.argv[2:]):
    r = vtk.vtkExodusIIReader()
    r.SetFileName(path)
    r.UpdateInformation()
    for ot in (r.ELEM_BLOCK, r.NODAL, r.ELEM_BLOCK_ELEM_CONN, r.GLOBAL, r.NODE_SET):
        r.SetAllArrayStatus(ot, 1)
    r.SetGenerateObjectIdCellArray(1)
    r.SetGenerateGlobalElementIdArray(1)
    r.SetGenerateGlobalNodeIdArray(1)
    for k in range(max(1, r.GetNumberOfTimeSteps())):
        r.SetTimeStep(k)
        r.Update()
        m = vtk.vtkAppendFilter()
        it = r.GetOutput().NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            m.AddInputData(it.GetCurrentDataObject())
            it.GoToNextItem()
        m.Update()
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetFileName("%s/%d_%d.vtu" % (out, i, k))
        w.SetInputData(m.GetOutput())
        w.Write()
        print(i, k)
"#;
    let dir = tempdir();
    let copies: Vec<(&str, &str)> = NC4_COPIES
        .into_iter()
        .filter(|(a, _)| !a.contains("meshio"))
        .collect();
    let mut args = vec![dir.path().to_str().unwrap().to_string()];
    for (a, b) in &copies {
        args.push(exodus(a).display().to_string());
        args.push(exodus(b).display().to_string());
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let printed = vtk_python(CODE, &args);
    for (i, (a, _)) in copies.iter().enumerate() {
        let steps = printed
            .lines()
            .filter(|l| l.starts_with(&format!("{} ", 2 * i)))
            .count();
        assert!(steps >= 1, "{a}: VTK read no step:\n{printed}");
        for k in 0..steps {
            let vtu = |j: usize| read(&dir.path().join(format!("{j}_{k}.vtu")));
            let (theirs, original) = (vtu(2 * i), vtu(2 * i + 1));
            grids_bit_equal(&theirs, &original).unwrap_or_else(|e| panic!("{a}@{k}: VTK: {e}"));
            assert_eq!(
                theirs.num_cells(),
                read(&at_step(&exodus(a), k)).num_cells(),
                "{a}@{k}"
            );
        }
    }
}

/// An HDF5 file that is not Exodus II is refused naming the file and what it lacks; a cut one
/// naming the file.
#[test]
fn netcdf4_refusals_name_the_file() {
    let dir = tempdir();
    let other = dir.path().join("data.exo");
    std::fs::copy(exodus("nc4/not_exodus.nc"), &other).unwrap();
    tetkit(["info".as_ref(), other.as_os_str()]).assert_failure(&[
        "data.exo: a NetCDF file with 1 dimensions and 1 variables but not Exodus II: it lacks the dimension num_dim, the dimension num_nodes, coordinates",
    ]);
    let bytes = std::fs::read(exodus("nc4/tets.exo")).unwrap();
    let cut = dir.path().join("cut.e");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    tetkit(["convert".as_ref(), cut.as_os_str(), "x.vtu".as_ref()])
        .assert_failure(&["cut.e: ", "NetCDF-4 (HDF5): HDF5 error"]);
}
