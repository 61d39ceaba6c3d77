//! VTK PolyData bodies (.vtp XML and legacy .vtk POLYDATA), read by the formats crate's readers
//! (every encoding, compressor, header type, version and byte order VTK writes); their polygons
//! and triangle strips are the surface.

use formats::{cell_type, FormatError, Grid};

use super::RawSurface;

pub(super) fn read_xml(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    from_grid(&formats::vtu::read(bytes)?)
}

pub(super) fn read_legacy(bytes: &[u8]) -> Result<RawSurface, FormatError> {
    from_grid(&formats::legacy::read(bytes)?)
}

/// The polygons of a surface grid: triangles, quads and polygons as they are, each triangle strip
/// as its triangles (every second one turned so the strip keeps one orientation). Vertices and
/// lines bound no volume and are left out.
pub(super) fn from_grid(grid: &Grid) -> Result<RawSurface, FormatError> {
    if grid.points.components != 3 {
        return Err(FormatError::in_array(
            &grid.points.name,
            "points need 3 components",
        ));
    }
    let np = grid.num_points();
    let points: Vec<[f64; 3]> = (0..np)
        .map(|i| {
            [
                grid.points.data.get_f64(3 * i),
                grid.points.data.get_f64(3 * i + 1),
                grid.points.data.get_f64(3 * i + 2),
            ]
        })
        .collect();
    let c = &grid.cells;
    let mut polys = Vec::new();
    for (i, &t) in c.types.iter().enumerate() {
        let (a, b) = (c.offsets[i], c.offsets[i + 1]);
        let ids = c
            .connectivity
            .get(a.max(0) as usize..b.max(0) as usize)
            .ok_or_else(|| {
                FormatError::in_array("offsets", format!("cell {i} runs past the connectivity"))
            })?;
        let mut v = Vec::with_capacity(ids.len());
        for &id in ids {
            if id < 0 || id as usize >= np {
                return Err(FormatError::in_array(
                    "connectivity",
                    format!("cell {i}: point id {id} out of range ({np} points)"),
                ));
            }
            v.push(id as u32);
        }
        match t {
            cell_type::TRIANGLE | cell_type::QUAD | cell_type::POLYGON => polys.push(v),
            cell_type::TRIANGLE_STRIP => {
                for k in 0..v.len().saturating_sub(2) {
                    let tri = if k % 2 == 0 {
                        vec![v[k], v[k + 1], v[k + 2]]
                    } else {
                        vec![v[k + 1], v[k], v[k + 2]]
                    };
                    polys.push(tri);
                }
            }
            cell_type::VERTEX | cell_type::POLY_VERTEX | cell_type::LINE | cell_type::POLY_LINE => {
            }
            other => {
                return Err(FormatError::whole(format!(
                    "cell {i} is a {} cell; a body surface is made of polygons",
                    cell_type::name(other)
                )))
            }
        }
    }
    if polys.is_empty() {
        return Err(FormatError::whole(
            "no polygons or triangle strips: a body surface needs closed polygons",
        ));
    }
    Ok(RawSurface { points, polys })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron's surface written by hand: two triangles as a strip, two as polygons, plus a
    /// line that is ignored.
    const TET: &str = r#"<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PolyData>
    <Piece NumberOfPoints="4" NumberOfVerts="0" NumberOfLines="1" NumberOfStrips="1" NumberOfPolys="2">
      <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
      <Lines>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">2</DataArray>
      </Lines>
      <Strips>
        <DataArray type="Int64" Name="connectivity" format="ascii">1 0 2 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
      </Strips>
      <Polys>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 3 1 2 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">3 6</DataArray>
      </Polys>
    </Piece>
  </PolyData>
</VTKFile>
"#;

    #[test]
    fn strips_become_triangles_and_lines_are_ignored() {
        let s = read_xml(TET.as_bytes()).unwrap();
        assert_eq!(s.points.len(), 4);
        // VTK's order: lines, polys, strips; the line is dropped, the strip gives two triangles.
        assert_eq!(
            s.polys,
            vec![vec![0, 1, 3], vec![1, 2, 3], vec![1, 0, 2], vec![2, 0, 3]]
        );
        // ... and they close the tetrahedron with one orientation.
        let t = super::super::TriSurface::from_raw(std::path::Path::new("tet.vtp"), s).unwrap();
        assert_eq!(t.tris.len(), 4);
    }

    #[test]
    fn bad_ids_and_missing_arrays_are_named() {
        let bad = TET.replace("0 1 3 1 2 3", "0 1 3 1 2 9");
        let e = read_xml(bad.as_bytes()).unwrap_err();
        assert!(e.to_string().contains("point id 9"), "{e}");
        let none = TET.replace(
            r#"Name="offsets" format="ascii">3 6"#,
            r#"Name="offs" format="ascii">3 6"#,
        );
        let e = read_xml(none.as_bytes()).unwrap_err();
        assert!(e.to_string().contains("'offsets'"), "{e}");
    }
}
