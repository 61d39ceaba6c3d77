//! Files VTK writes the way ParaView does (bit, string, id-type and ghost arrays, an information
//! key, a triangle and a vertex beside the tets: scripts/newuser_paraview_like.py), in every XML
//! data mode and compressor and both legacy versions: tetkit reads every one as VTK reads the
//! VTU, and what `convert` writes from it reads back in VTK with every array and value. Also:
//! a written .pvtu names its active scalars, `info` counts NaN/inf values and names active arrays,
//! an ascii legacy output holding NaN is warned about,
//! and an empty ascii array is placed at its tag (it said "byte 0").

mod common;

use common::*;
use std::path::PathBuf;

/// The files the script writes into a fresh folder.
fn paraview_like() -> (tempfile::TempDir, Vec<PathBuf>) {
    let dir = tempdir();
    let script = root().join("scripts/newuser_paraview_like.py");
    let out = std::process::Command::new(VTK_PYTHON)
        .arg(&script)
        .arg(dir.path())
        .output()
        .expect("running the script");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files: Vec<PathBuf> = dir_listing(dir.path())
        .into_iter()
        .map(|n| dir.path().join(n))
        .collect();
    files.sort();
    assert_eq!(files.len(), 12, "{files:?}");
    (dir, files)
}

#[test]
fn bit_string_and_id_arrays_in_every_mode_are_read_and_converted_without_loss() {
    if !require_vtk("bit_string_and_id_arrays_in_every_mode") {
        return;
    }
    let (dir, inputs) = paraview_like();
    // VTK 9.1 reads binary legacy bit arrays back as zeros (its own files): VTK's reading of
    // the raw binary VTU is the reference every input is held to.
    let reference = vtk_check(&dir.path().join("pv_binary_none.vtu"), false);
    let mut outputs = Vec::new();
    for input in &inputs {
        let grid = tetkit::formats::read(input)
            .unwrap_or_else(|e| panic!("{}: tetkit cannot read it: {e}", input.display()));
        if let Err(e) = compare_with_vtk(&grid, &reference) {
            panic!(
                "{}: tetkit's reading differs from VTK's:\n{e}",
                input.display()
            );
        }
        // The bit arrays are kept as UInt8 0/1, with their values.
        let flag = grid.point_data.get("flag").expect("point array 'flag'");
        assert_eq!(flag.data.type_name(), "UInt8");
        let want: Vec<f64> = (0..10).map(|i| ((i * 5 + 1) % 3 % 2) as f64).collect();
        assert_eq!(flag.data.to_f64_vec(), want, "{}", input.display());
        let stem = input.file_stem().unwrap().to_string_lossy().into_owned();
        for ext in ["vtu", "vtk"] {
            let out = dir.path().join(format!("out_{stem}.{ext}"));
            tetkit(["convert".as_ref(), input.as_os_str(), out.as_os_str()]).assert_success();
            outputs.push((out, grid.clone()));
        }
    }
    let paths: Vec<PathBuf> = outputs.iter().map(|o| o.0.clone()).collect();
    for ((path, grid), vtk) in outputs.iter().zip(vtk_check_many(&paths, false)) {
        let vtk = vtk.unwrap_or_else(|e| panic!("{e}"));
        if let Err(e) = compare_with_vtk(grid, &vtk) {
            panic!(
                "{}: VTK reads tetkit's output differently:\n{e}",
                path.display()
            );
        }
    }
}

#[test]
fn a_binary_bit_array_with_the_wrong_byte_count_is_refused_by_name() {
    // 10 bits need 2 bytes; a header declaring 3 is refused, naming the array.
    let tet = "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>\
        <Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\
        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4</DataArray>\
        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>";
    let b64 = |bytes: &[u8]| {
        use base64::Engine;
        base64::engine::general_purpose::STANDARD.encode(bytes)
    };
    let file = |bits: &str| {
        format!(
            "<?xml version=\"1.0\"?><VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\
             <UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\
             <PointData>{bits}</PointData>{tet}</Piece></UnstructuredGrid></VTKFile>"
        )
    };
    let dir = tempdir();
    let cases = [
        (
            format!(
                "<DataArray type=\"Bit\" Name=\"b\" format=\"binary\">{}</DataArray>",
                b64(&[3, 0, 0, 0, 0xa0, 0, 0])
            ),
            "declares 3 bytes of data, but 4 bits need 1 bytes",
        ),
        (
            "<DataArray type=\"Bit\" Name=\"b\" format=\"ascii\">0 1 2 1</DataArray>".to_string(),
            "value 2 (2) of a Bit array is not 0 or 1",
        ),
    ];
    for (i, (bits, want)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("bad{i}.vtu"));
        std::fs::write(&path, file(bits)).unwrap();
        tetkit(["info".as_ref(), path.as_os_str()]).assert_failure(&[
            &format!("bad{i}.vtu"),
            "array 'b'",
            want,
        ]);
    }
    // The good one: 4 bits 1010 packed in one byte, most significant bit first.
    let path = dir.path().join("good.vtu");
    std::fs::write(
        &path,
        file(&format!(
            "<DataArray type=\"Bit\" Name=\"b\" format=\"binary\">{}</DataArray>",
            b64(&[1, 0, 0, 0, 0xa0])
        )),
    )
    .unwrap();
    let g = tetkit::formats::read(&path).unwrap();
    assert_eq!(
        g.point_data.get("b").unwrap().data.to_f64_vec(),
        vec![1.0, 0.0, 1.0, 0.0]
    );
}

#[test]
fn a_pvtu_names_its_active_scalars_for_paraview() {
    if !require_vtk("a_pvtu_names_its_active_scalars_for_paraview") {
        return;
    }
    // ParaView takes the active attributes of a .pvtu from its <PPointData>/<PCellData>, not
    // from the pieces: without them the colouring array was lost on the way through a .pvtu.
    let (dir, _) = paraview_like();
    let out = dir.path().join("out.pvtu");
    tetkit([
        "convert".as_ref(),
        dir.path().join("pv_binary_none.vtu").as_os_str(),
        out.as_os_str(),
    ])
    .assert_success();
    let name = vtk_python(
        "import sys, vtk\nr = vtk.vtkXMLPUnstructuredGridReader()\nr.SetFileName(sys.argv[1])\nr.Update()\ns = r.GetOutput().GetPointData().GetScalars()\nprint(s.GetName() if s else None)",
        &[out.to_str().unwrap()],
    );
    assert_eq!(name.trim(), "temp");
}

#[test]
fn nan_in_an_ascii_legacy_output_is_warned_about() {
    // VTK 9.1 stops reading an ascii legacy file at its first `nan`: say so when writing one.
    let dir = tempdir();
    let mut grid = tetkit::formats::read(&fixture("scenes/cube_mesh.vtk")).unwrap();
    if let tetkit::formats::ArrayData::Float64(v) =
        &mut grid.point_data.get_mut("scalar").unwrap().data
    {
        v[3] = f64::NAN;
        v[4] = f64::INFINITY;
    }
    grid.point_data
        .active
        .push((tetkit::formats::Attribute::Scalars, "scalar".to_string()));
    let input = dir.path().join("in.vtu");
    tetkit::formats::write(&input, &grid, &Default::default()).unwrap();
    // `info` counts them apart from the range (which leaves them out) and names the active array.
    let run = tetkit(["info".as_ref(), input.as_os_str(), "--json".as_ref()]);
    run.assert_success();
    let info: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let a = &info["point_data"][0];
    assert_eq!(a["name"], "scalar");
    assert_eq!(
        (a["nan"].as_u64(), a["inf"].as_u64()),
        (Some(1), Some(1)),
        "{a}"
    );
    assert_eq!(a["active"], serde_json::json!(["Scalars"]));
    let text = tetkit(["info".as_ref(), input.as_os_str()]).stdout_str();
    assert!(
        text.contains("(1 NaN, 1 infinite)  active Scalars"),
        "{text}"
    );
    for (enc, warned) in [("ascii", true), ("binary", false)] {
        let out = dir.path().join(format!("{enc}.vtk"));
        let run = tetkit([
            "convert".as_ref(),
            input.as_os_str(),
            out.as_os_str(),
            "--encoding".as_ref(),
            enc.as_ref(),
        ]);
        run.assert_success();
        assert_eq!(
            run.stderr.contains("warning") && run.stderr.contains("'scalar'"),
            warned,
            "{enc}: {}",
            run.stderr
        );
        // tetkit reads both back with the values.
        let back = tetkit::formats::read(&out).unwrap();
        let v = back.point_data.get("scalar").unwrap().data.to_f64_vec();
        assert!(v[3].is_nan() && v[4] == f64::INFINITY, "{enc}");
    }
}

#[test]
fn an_empty_ascii_array_is_placed_at_its_tag() {
    let dir = tempdir();
    let path = dir.path().join("empty_offsets.vtu");
    std::fs::write(
        &path,
        "<?xml version=\"1.0\"?><VTKFile type=\"UnstructuredGrid\" version=\"0.1\"><UnstructuredGrid>\
         <Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>\
         <Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\
         <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\"></DataArray>\
         <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>",
    )
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let tag = text
        .find("<DataArray type=\"Int32\" Name=\"offsets\"")
        .unwrap();
    tetkit(["info".as_ref(), path.as_os_str()]).assert_failure(&[
        "empty_offsets.vtu",
        &format!("byte {tag}: array 'offsets': has 0 ascii values, expected 1"),
    ]);
}
