//! A distributed dataset as ParaView saves it with ghost levels: a .pvtu whose pieces each repeat
//! a layer of their neighbour's cells, marked `vtkGhostType` = 1 (DUPLICATECELL). Merged as they
//! are, those duplicates were drawn, sorted and partitioned twice (a brighter image, a mesh
//! that overlaps itself); the view commands drop them as ParaView does, and say so. Pieces
//! merged without welding their points also lost the ray caster a tet at every piece boundary
//! it crossed (the next piece's entry face computed a few ulps before the exit).

mod common;

use common::{tempdir, tetkit};
use std::path::Path;
use tetkit::formats::{self, ArrayData, Cells, DataArray, Grid};
use tetkit::mesh::generate::structured_grid;

/// The cells of `g` at `idx`, with their cell data and every point.
fn subset(g: &Grid, idx: &[usize], ghost: &[u8]) -> Grid {
    let mut out = g.clone();
    let mut cells = Cells::new();
    for &i in idx {
        cells.push(g.cells.types[i], g.cells.cell(i));
    }
    out.cells = cells;
    out.cell_data = g.cell_data.gather(idx);
    out.cell_data.insert(DataArray::new(
        "vtkGhostType",
        1,
        ArrayData::UInt8(ghost.to_vec()),
    ));
    out
}

fn lit_rgba(png: &Path) -> Vec<u8> {
    image::open(png).unwrap().to_rgba8().into_raw()
}

#[test]
fn ghost_cells_of_a_pvtu_are_not_drawn_twice() {
    let dir = tempdir();
    let whole = structured_grid([6, 4, 4], [0.0; 3], [1.5, 1.0, 1.0]).to_grid();
    let whole_path = dir.path().join("whole.vtu");
    formats::write(&whole_path, &whole, &Default::default()).unwrap();
    // Cube column of each cell (cube_id = i + 6 (j + 4 k)): piece 0 owns columns 0-2 and has
    // column 3 as ghosts, piece 1 owns 3-5 and has column 2 as ghosts.
    let column: Vec<i64> = whole
        .cell_data
        .get("cube_id")
        .unwrap()
        .data
        .to_f64_vec()
        .iter()
        .map(|&c| c as i64 % 6)
        .collect();
    std::fs::create_dir(dir.path().join("p")).unwrap();
    for (k, (own, ghost)) in [(0..3, 3), (3..6, 2)].into_iter().enumerate() {
        let idx: Vec<usize> = (0..whole.num_cells())
            .filter(|&i| own.contains(&column[i]) || column[i] == ghost)
            .collect();
        let flags: Vec<u8> = idx.iter().map(|&i| (column[i] == ghost) as u8).collect();
        let piece = subset(&whole, &idx, &flags);
        formats::write(
            &dir.path().join(format!("p/p_{k}.vtu")),
            &piece,
            &Default::default(),
        )
        .unwrap();
    }
    let pvtu = dir.path().join("p.pvtu");
    std::fs::write(
        &pvtu,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">\n\
         <PUnstructuredGrid GhostLevel=\"1\">\n<PPointData Scalars=\"scalar\">\
         <PDataArray type=\"Float64\" Name=\"scalar\"/></PPointData>\n\
         <PCellData><PDataArray type=\"UInt8\" Name=\"vtkGhostType\"/></PCellData>\n\
         <PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n\
         <Piece Source=\"p/p_0.vtu\"/>\n<Piece Source=\"p/p_1.vtu\"/>\n\
         </PUnstructuredGrid>\n</VTKFile>\n",
    )
    .unwrap();
    let merged = formats::read(&pvtu).unwrap();
    let ghosts = whole.num_cells() / 3;
    assert_eq!(merged.num_cells(), whole.num_cells() + ghosts);

    // The same image as the mesh without pieces, with PT and with the ray caster.
    for method in ["pt", "raycast"] {
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        let args = |input: &Path, out: &Path| {
            tetkit([
                "render".as_ref(),
                input.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
                "--size".as_ref(),
                "40x40".as_ref(),
                "--method".as_ref(),
                method.as_ref(),
                "--elevation".as_ref(),
                "20".as_ref(),
                "--azimuth".as_ref(),
                "30".as_ref(),
            ])
        };
        let run = args(&pvtu, &a);
        run.assert_success();
        assert!(
            run.stderr
                .contains(&format!("dropped {ghosts} ghost cells")),
            "{}",
            run.stderr
        );
        args(&whole_path, &b).assert_success();
        let worst = lit_rgba(&a)
            .iter()
            .zip(lit_rgba(&b))
            .map(|(x, y)| x.abs_diff(y))
            .max()
            .unwrap();
        assert!(
            worst <= 1,
            "{method}: differs from the whole mesh by {worst}/255"
        );
    }
    // Sorting and partitioning see each cell once.
    let sorted = dir.path().join("sorted.vtu");
    tetkit([
        "sort".as_ref(),
        pvtu.as_os_str(),
        "-o".as_ref(),
        sorted.as_os_str(),
    ])
    .assert_success();
    assert_eq!(
        formats::read(&sorted).unwrap().num_cells(),
        whole.num_cells()
    );
    let (split, tree) = (dir.path().join("split.vtu"), dir.path().join("tree.vtu"));
    let run = tetkit([
        "partition".as_ref(),
        pvtu.as_os_str(),
        "-o".as_ref(),
        split.as_os_str(),
        "--tree".as_ref(),
        tree.as_os_str(),
        "--json".as_ref(),
    ]);
    run.assert_success();
    let split = formats::read(&split).unwrap();
    // original_cell_id points at the cells of the .pvtu as read (ghosts included), none a ghost.
    let ghost_flag = merged.cell_data.get("vtkGhostType").unwrap();
    for id in split
        .cell_data
        .get("original_cell_id")
        .unwrap()
        .data
        .to_f64_vec()
    {
        assert_eq!(ghost_flag.data.get_f64(id as usize), 0.0);
    }
    // Converting keeps every cell, ghosts included (nothing is lost on the way to a file).
    let conv = dir.path().join("conv.vtu");
    tetkit(["convert".as_ref(), pvtu.as_os_str(), conv.as_os_str()]).assert_success();
    assert_eq!(
        formats::read(&conv).unwrap().num_cells(),
        merged.num_cells()
    );
}

#[test]
fn the_ray_caster_crosses_unwelded_piece_boundaries() {
    // The same mesh as two pieces with their own copies of the shared points (what vtkAppendFilter
    // and a .pvtu give): the exact ray caster must see the same tets along every ray.
    let dir = tempdir();
    let whole = structured_grid([6, 4, 4], [0.0; 3], [1.5, 1.0, 1.0]).to_grid();
    let n = whole.num_points() as i64;
    let mut pieces = whole.clone();
    let pts = whole.points.data.to_f64_vec();
    let mut both = pts.clone();
    both.extend_from_slice(&pts);
    pieces.points = DataArray::new("Points", 3, ArrayData::Float64(both));
    pieces.point_data = whole.point_data.gather(
        &(0..2 * n as usize)
            .map(|i| i % n as usize)
            .collect::<Vec<_>>(),
    );
    // Cells of the right half (cube column >= 3) use the second copy of the points.
    let column = whole.cell_data.get("cube_id").unwrap().data.to_f64_vec();
    let mut cells = Cells::new();
    for (i, c) in column.iter().enumerate() {
        let shift = if *c as i64 % 6 >= 3 { n } else { 0 };
        let ids: Vec<i64> = whole.cells.cell(i).iter().map(|&p| p + shift).collect();
        cells.push(whole.cells.types[i], &ids);
    }
    pieces.cells = cells;
    let (a, b) = (dir.path().join("pieces.vtu"), dir.path().join("whole.vtu"));
    formats::write(&a, &pieces, &Default::default()).unwrap();
    formats::write(&b, &whole, &Default::default()).unwrap();
    let mut images = Vec::new();
    for (k, input) in [&a, &b].into_iter().enumerate() {
        let png = dir.path().join(format!("{k}.png"));
        let run = tetkit([
            "render".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--size".as_ref(),
            "48x48".as_ref(),
            "--method".as_ref(),
            "raycast".as_ref(),
            "--azimuth".as_ref(),
            "30".as_ref(),
            "--elevation".as_ref(),
            "20".as_ref(),
        ]);
        run.assert_success();
        let segments = run
            .stderr
            .split("segments ")
            .nth(1)
            .and_then(|r| r.split(',').next())
            .map(str::to_string);
        images.push((lit_rgba(&png), segments));
    }
    assert!(images[1].1.is_some(), "no segment count on stderr");
    assert_eq!(images[0].1, images[1].1, "segments walked");
    let worst = images[0]
        .0
        .iter()
        .zip(&images[1].0)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap();
    assert!(
        worst <= 1,
        "the pieces differ from the whole mesh by {worst}/255"
    );
}
