//! VTK collections: `.vtm` multiblocks (nested, with .pvtu, legacy, polydata and image blocks)
//! and `.pvd` time series read as one merged grid, the .pvtu rule for undeclared arrays, and
//! broken collections refused with the file, the block and what was wrong. Fixtures come from
//! scripts/make_collection_fixtures.py (VTK 9.1's writers).

mod common;

use common::{fixture, require_vtk, tempdir, tetkit, tetkit_stdin};
use std::path::Path;
use tetkit::formats::{self, collection, ArrayData, Grid};

fn read(rel: &str) -> Grid {
    formats::read(&fixture(&format!("collections/{rel}"))).unwrap()
}

fn names(a: &formats::Attributes) -> Vec<&str> {
    a.arrays.iter().map(|x| x.name.as_str()).collect()
}

fn block_ids(g: &Grid) -> Vec<i32> {
    match &g.cell_data.get(collection::BLOCK_ID_ARRAY).unwrap().data {
        ArrayData::Int32(v) => v.clone(),
        other => panic!("block ids are {}", other.type_name()),
    }
}

fn block_names(g: &Grid) -> Vec<String> {
    let a = g
        .field_data
        .iter()
        .find(|a| a.name == collection::BLOCK_NAMES_ARRAY)
        .unwrap();
    match &a.data {
        ArrayData::String(v) => v.clone(),
        other => panic!("block names are {}", other.type_name()),
    }
}

/// `merged` holds `parts` one after the other: points, cells (ids shifted) and every array
/// `merged` has, bit for bit.
fn assert_concatenation(merged: &Grid, parts: &[Grid]) {
    let (mut p0, mut c0) = (0usize, 0usize);
    for part in parts {
        for i in 0..part.num_points() {
            assert_eq!(merged.point(p0 + i), part.point(i));
        }
        for c in 0..part.num_cells() {
            assert_eq!(merged.cells.types[c0 + c], part.cells.types[c]);
            let want: Vec<i64> = part.cells.cell(c).iter().map(|&v| v + p0 as i64).collect();
            assert_eq!(merged.cells.cell(c0 + c), &want[..]);
        }
        for (attrs, own, base, n) in [
            (&merged.point_data, &part.point_data, p0, part.num_points()),
            (&merged.cell_data, &part.cell_data, c0, part.num_cells()),
        ] {
            for a in &attrs.arrays {
                if a.name == collection::BLOCK_ID_ARRAY {
                    continue;
                }
                let b = own.get(&a.name).unwrap();
                let k = a.components;
                let idx: Vec<usize> = (base..base + n).collect();
                assert!(a.data.gather(k, &idx).bit_eq(&b.data), "{}", a.name);
            }
        }
        p0 += part.num_points();
        c0 += part.num_cells();
    }
    assert_eq!((p0, c0), (merged.num_points(), merged.num_cells()));
}

#[test]
fn a_multiblock_is_its_blocks_in_order_with_their_index() {
    let g = read("multiblock.vtm");
    let parts: Vec<Grid> = (0..3)
        .map(|i| read(&format!("multiblock/multiblock_{i}.vtu")))
        .collect();
    assert_concatenation(&g, &parts);
    assert_eq!(names(&g.point_data), ["temperature", "velocity"]);
    assert_eq!(
        names(&g.cell_data),
        ["material", "pressure", collection::BLOCK_ID_ARRAY]
    );
    let want: Vec<i32> = (0..3)
        .flat_map(|b| vec![b; parts[b as usize].num_cells()])
        .collect();
    assert_eq!(block_ids(&g), want);
    assert_eq!(block_names(&g), ["solid", "shell/inner", "shell/outer"]);
}

#[test]
fn arrays_some_blocks_lack_are_dropped_and_named() {
    let r = tetkit([
        "info",
        "--json",
        fixture("collections/differing.vtm").to_str().unwrap(),
    ]);
    r.assert_success();
    for (array, block) in [
        ("velocity", "block 'b'"),
        ("b_only", "block 'a'"),
        ("a_only", "block 'b'"),
    ] {
        let line = r
            .stderr
            .lines()
            .find(|l| l.contains(&format!("'{array}'")))
            .unwrap_or_else(|| panic!("no warning for {array}:\n{}", r.stderr));
        assert!(
            line.contains("warning") && line.contains("differing.vtm") && line.contains(block),
            "{line}"
        );
    }
    let g = read("differing.vtm");
    assert_eq!(names(&g.point_data), ["temperature"]);
    assert_eq!(
        names(&g.cell_data),
        ["material", "pressure", collection::BLOCK_ID_ARRAY]
    );
}

#[test]
fn polydata_and_image_blocks_merge() {
    let r = tetkit(["info", fixture("collections/kinds.vtm").to_str().unwrap()]);
    r.assert_success();
    let g = read("kinds.vtm");
    let vol = read("kinds/kinds_0.vtu");
    let surf = formats::vtu::read_path(&fixture("collections/kinds/kinds_1.vtp")).unwrap();
    // The image block is read as voxels, as VTK's Merge Blocks gives it.
    let image = formats::read(&fixture("collections/kinds/kinds_2.vti")).unwrap();
    assert!(image.num_cells() > 0);
    assert!(image
        .cells
        .types
        .iter()
        .all(|&t| t == formats::cell_type::VOXEL));
    assert_concatenation(&g, &[vol.clone(), surf.clone(), image.clone()]);
    assert_eq!(block_names(&g), ["volume", "surface", "image"]);
    assert_eq!(*block_ids(&g).last().unwrap(), 2);
    assert_eq!(
        g.num_cells(),
        vol.num_cells() + surf.num_cells() + image.num_cells()
    );
}

#[test]
fn nested_collections_pvtu_and_legacy_blocks_are_read() {
    let g = read("refs.vtm");
    let parts = [
        read("parallel.pvtu"),
        read("refs/legacy_block.vtk"),
        read("multiblock/multiblock_0.vtu"),
        read("multiblock/multiblock_1.vtu"),
        read("multiblock/multiblock_2.vtu"),
    ];
    assert_concatenation(&g, &parts);
    assert_eq!(
        block_names(&g),
        [
            "parallel",
            "more/legacy",
            "more/nested/solid",
            "more/nested/shell/inner",
            "more/nested/shell/outer"
        ]
    );
}

#[test]
fn a_pvd_opens_at_its_first_step_and_any_step_can_be_picked() {
    let pvd = fixture("collections/series.pvd");
    let steps = formats::pvd::steps(&pvd).unwrap();
    let times: Vec<Option<f64>> = steps.iter().map(|s| s.time).collect();
    assert_eq!(times, [Some(0.0), Some(0.5), Some(1.0)]);
    for (k, sel) in [
        (0, "series.pvd"),
        (0, "series.pvd@0"),
        (1, "series.pvd@1"),
        (2, "series.pvd@last"),
    ] {
        let g = read(sel);
        let parts: Vec<Grid> = (0..2)
            .map(|p| read(&format!("series/series_{k}_{p}.vtu")))
            .collect();
        assert_concatenation(&g, &parts);
        let t = g.field_data.iter().find(|a| a.name == "TimeValue").unwrap();
        assert_eq!(t.data, ArrayData::Float64(vec![times[k].unwrap()]), "{sel}");
    }
    let r = tetkit(["info", pvd.to_str().unwrap()]);
    r.assert_success();
    let out = r.stdout_str();
    assert!(
        out.contains("time steps: 3") && out.contains("t = 0.5") && out.contains("@K"),
        "{out}"
    );
    let r = tetkit(["info", "--json", &format!("{}@2", pvd.display())]);
    let v: serde_json::Value = serde_json::from_str(&r.assert_success().stdout_str()).unwrap();
    assert_eq!(v["time_steps"]["read"], 2);
    assert_eq!(v["time_steps"]["steps"].as_array().unwrap().len(), 3);
    tetkit(["info", &format!("{}@3", pvd.display())]).assert_failure(&[
        "series.pvd",
        "no time step 3",
        "0 to 2",
    ]);
    // A step that is not a number is the step's fault, not the extension's.
    for bad in ["-1", "abc", "1.5", ""] {
        tetkit(["info", &format!("{}@{bad}", pvd.display())])
            .assert_failure(&[&format!("bad time step '{bad}'"), "'last'"]);
    }
}

#[test]
fn convert_and_render_take_collections() {
    let dir = tempdir();
    let out = dir.path().join("merged.vtu");
    let png = dir.path().join("m.png");
    let vtm = fixture("collections/multiblock.vtm");
    tetkit(["convert", vtm.to_str().unwrap(), out.to_str().unwrap()]).assert_success();
    let back = formats::read(&out).unwrap();
    assert_eq!(back, read("multiblock.vtm"));
    tetkit([
        "render",
        vtm.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--size",
        "48x32",
        "--quiet",
    ])
    .assert_success();
    assert!(png.is_file());
    let step = dir.path().join("step1.vtu");
    let sel = format!("{}@1", fixture("collections/series.pvd").display());
    tetkit(["convert", sel.as_str(), step.to_str().unwrap()]).assert_success();
    assert_eq!(formats::read(&step).unwrap(), read("series.pvd@1"));
    // Collections are read, not written.
    let bad = dir.path().join("out.vtm");
    tetkit(["convert", out.to_str().unwrap(), bad.to_str().unwrap()])
        .assert_failure(&["out.vtm", "does not write"]);
    assert!(!bad.exists());
}

#[test]
fn pvtu_reads_the_arrays_it_declares() {
    let r = tetkit([
        "info",
        "--json",
        fixture("collections/extra_arrays.pvtu").to_str().unwrap(),
    ]);
    r.assert_success();
    assert!(
        r.stderr.contains("'rank_debug'")
            && r.stderr.contains("piece 1")
            && r.stderr.contains("not declared"),
        "{}",
        r.stderr
    );
    let g = read("extra_arrays.pvtu");
    assert_eq!(names(&g.cell_data), ["material", "pressure"]);

    // A declared array a piece lacks: VTK fills it with garbage; tetkit refuses.
    let dir = tempdir();
    let src = fixture("collections");
    for i in 0..3 {
        let f = format!("parallel_{i}.vtu");
        std::fs::copy(src.join(&f), dir.path().join(&f)).unwrap();
    }
    let text = std::fs::read_to_string(src.join("parallel.pvtu"))
        .unwrap()
        .replace(
            "<PCellData>",
            "<PCellData>\n      <PDataArray type=\"Float32\" Name=\"stress\"/>",
        );
    let p = dir.path().join("p.pvtu");
    std::fs::write(&p, text).unwrap();
    let out = dir.path().join("out.vtu");
    tetkit(["convert", p.to_str().unwrap(), out.to_str().unwrap()]).assert_failure(&[
        "p.pvtu",
        "piece 0",
        "parallel_0.vtu",
        "'stress'",
        "declares",
    ]);
    assert!(!out.exists());
}

/// Writes `text` as `name` in `dir`, with the fixture blocks beside it.
fn collection(dir: &Path, name: &str, body: &str) -> std::path::PathBuf {
    let src = fixture("collections/multiblock");
    std::fs::create_dir_all(dir.join("b")).unwrap();
    for i in 0..3 {
        let f = format!("multiblock_{i}.vtu");
        std::fs::copy(src.join(&f), dir.join("b").join(&f)).unwrap();
    }
    let p = dir.join(name);
    std::fs::write(
        &p,
        format!("<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\"><vtkMultiBlockDataSet>\n{body}\n</vtkMultiBlockDataSet></VTKFile>\n"),
    )
    .unwrap();
    p
}

#[test]
fn broken_collections_name_the_file_block_and_fault() {
    let dir = tempdir();
    let d = dir.path();
    let out = d.join("out.vtu");
    let fails = |input: &Path, needles: &[&str]| {
        tetkit(["convert", input.to_str().unwrap(), out.to_str().unwrap()]).assert_failure(needles);
        assert!(!out.exists(), "{} wrote output", input.display());
    };
    let p = collection(
        d,
        "self.vtm",
        r#"<DataSet index="0" name="me" file="self.vtm"/>"#,
    );
    fails(&p, &["self.vtm", "block 'me'", "cycle"]);
    let p = collection(
        d,
        "missing.vtm",
        r#"<DataSet index="0" name="ok" file="b/multiblock_0.vtu"/><DataSet index="1" name="gone" file="b/nope.vtu"/>"#,
    );
    fails(
        &p,
        &["missing.vtm", "block 'gone'", "nope.vtu", "does not exist"],
    );
    let p = collection(
        d,
        "bad_xml.vtm",
        r#"<DataSet index="0" file="b/multiblock_0.vtu"><Block>"#,
    );
    fails(&p, &["bad_xml.vtm", "malformed XML"]);
    let p = collection(
        d,
        "odd.vtm",
        r#"<DataSet index="0" name="x" file="b/notes.txt"/>"#,
    );
    std::fs::write(d.join("b/notes.txt"), "hello").unwrap();
    fails(
        &p,
        &["odd.vtm", "block 'x'", "notes.txt", "not a VTK data file"],
    );
    // A block with Float64 points beside Float32 ones: they meet in Float64, exactly.
    let mut g = formats::read(&d.join("b/multiblock_1.vtu")).unwrap();
    let narrow = formats::read(&d.join("b/multiblock_0.vtu")).unwrap();
    g.points.data = ArrayData::Float64(g.points.data.to_f64_vec());
    formats::write(&d.join("b/f64.vtu"), &g, &Default::default()).unwrap();
    let p = collection(
        d,
        "types.vtm",
        r#"<DataSet index="0" name="a" file="b/multiblock_0.vtu"/><DataSet index="1" name="wide" file="b/f64.vtu"/>"#,
    );
    let merged = formats::read(&p).unwrap();
    assert_eq!(merged.points.data.type_name(), "Float64");
    assert_eq!(merged.point(0), narrow.point(0));
    // 64-bit integer points would not survive Float64: refused, naming the block.
    g.points.data = ArrayData::Int64(vec![1 << 60; g.points.data.len()]);
    formats::write(&d.join("b/i64.vtu"), &g, &Default::default()).unwrap();
    let p = collection(
        d,
        "ints.vtm",
        r#"<DataSet index="0" name="a" file="b/multiblock_0.vtu"/><DataSet index="1" name="huge" file="b/i64.vtu"/>"#,
    );
    fails(&p, &["ints.vtm", "block 'huge'", "Int64", "Float32"]);
    // An inner file's own fault is named with the outer file and block in front.
    std::fs::write(
        d.join("b/broken.vtu"),
        "<VTKFile type=\"UnstructuredGrid\"><Unstr",
    )
    .unwrap();
    let p = collection(
        d,
        "inner.vtm",
        r#"<DataSet index="0" name="br" file="b/broken.vtu"/>"#,
    );
    fails(&p, &["inner.vtm", "block 'br'", "broken.vtu"]);
    // An empty <DataSet/> is an empty block: it keeps its name and index.
    let p = collection(
        d,
        "empty.vtm",
        r#"<DataSet index="0" name="none"/><DataSet index="1" name="a" file="b/multiblock_0.vtu"/>"#,
    );
    let g = formats::read(&p).unwrap();
    assert_eq!(block_names(&g), ["none", "a"]);
    assert!(block_ids(&g).iter().all(|&b| b == 1));
    // .pvd faults.
    let pvd = d.join("s.pvd");
    std::fs::write(
        &pvd,
        r#"<VTKFile type="Collection"><Collection><DataSet timestep="x" file="b/multiblock_0.vtu"/></Collection></VTKFile>"#,
    )
    .unwrap();
    fails(&pvd, &["s.pvd", "timestep 'x' is not a number"]);
    std::fs::write(
        &pvd,
        r#"<VTKFile type="Collection"><Collection><DataSet timestep="0" file="s.pvd"/></Collection></VTKFile>"#,
    )
    .unwrap();
    fails(&pvd, &["s.pvd", "cycle"]);
    // Collections need their sibling files: stdin is refused.
    let bytes = std::fs::read(fixture("collections/multiblock.vtm")).unwrap();
    tetkit_stdin(["info", "-"], &bytes)
        .assert_failure(&["<stdin>", "cannot be read from a stream"]);
}

#[test]
fn partition_pieces_read_back_as_the_split_mesh() {
    let dir = tempdir();
    let d = dir.path();
    let (split, tree, pieces) = (d.join("split.vtu"), d.join("tree.vtu"), d.join("pieces"));
    tetkit([
        "partition",
        fixture("collections/multiblock/multiblock_0.vtu")
            .to_str()
            .unwrap(),
        "-o",
        split.to_str().unwrap(),
        "--tree",
        tree.to_str().unwrap(),
        "--leaves",
        "4",
        "--pieces",
        pieces.to_str().unwrap(),
    ])
    .assert_success();
    let whole = formats::read(&split).unwrap();
    for file in ["split.vtm", "split.pvtu"] {
        let g = formats::read(&pieces.join(file)).unwrap();
        assert_eq!(g.num_cells(), whole.num_cells(), "{file}");
        // Pieces repeat the points leaves share, so cells are compared through coordinates.
        for c in 0..whole.num_cells() {
            let a: Vec<[f64; 3]> = whole
                .cells
                .cell(c)
                .iter()
                .map(|&v| whole.point(v as usize))
                .collect();
            let b: Vec<[f64; 3]> = g
                .cells
                .cell(c)
                .iter()
                .map(|&v| g.point(v as usize))
                .collect();
            assert_eq!(a, b, "{file} cell {c}");
            for pa in &whole.point_data.arrays {
                let pb = g.point_data.get(&pa.name).unwrap();
                let k = pa.components;
                for (&va, &vb) in whole.cells.cell(c).iter().zip(g.cells.cell(c)) {
                    let ta = pa.data.gather(k, &[va as usize]);
                    assert!(
                        ta.bit_eq(&pb.data.gather(k, &[vb as usize])),
                        "{file} {}",
                        pa.name
                    );
                }
            }
        }
        for a in &whole.cell_data.arrays {
            assert!(
                a.bit_eq(g.cell_data.get(&a.name).unwrap()),
                "{file} {}",
                a.name
            );
        }
        if file.ends_with(".vtm") {
            let leaf: Vec<i32> = whole
                .cell_data
                .get("leaf_id")
                .unwrap()
                .data
                .to_f64_vec()
                .iter()
                .map(|&v| v as i32)
                .collect();
            assert_eq!(block_ids(&g), leaf);
        }
    }
}

#[test]
fn vtk_reads_the_merged_conversion() {
    if !require_vtk("vtk_reads_the_merged_conversion") {
        return;
    }
    let dir = tempdir();
    let out = dir.path().join("merged.vtu");
    // VTK 9.1 reads only serial XML files as blocks (not refs.vtm's .pvtu, .vtk or nested .vtm).
    let vtm = fixture("collections/multiblock.vtm");
    tetkit(["convert", vtm.to_str().unwrap(), out.to_str().unwrap()]).assert_success();
    let ours = formats::read(&vtm).unwrap();
    let v = common::vtk_check(&out, false);
    assert_eq!(v["cells"].as_u64(), Some(ours.num_cells() as u64), "{v}");
    assert_eq!(v["points"].as_u64(), Some(ours.num_points() as u64), "{v}");
    let cell_names: Vec<&str> = v["cell_data"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert!(cell_names.contains(&collection::BLOCK_ID_ARRAY), "{v}");
    // VTK's own multiblock reader sees as many cells in the blocks as tetkit merged.
    let code = r#"
import sys, vtk
r = vtk.vtkXMLMultiBlockDataReader()
r.SetFileName(sys.argv[1])
r.Update()
it = r.GetOutput().NewIterator()
it.InitTraversal()
n = 0
while not it.IsDoneWithTraversal():
    n += it.GetCurrentDataObject().GetNumberOfCells()
    it.GoToNextItem()
print(n)
"#;
    let n = common::vtk_python(code, &[vtm.to_str().unwrap()]);
    assert_eq!(n.trim(), ours.num_cells().to_string());
}
