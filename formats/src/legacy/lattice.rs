//! Legacy STRUCTURED_POINTS, STRUCTURED_GRID and RECTILINEAR_GRID: their geometry keywords, and
//! the points and cells they imply (see [`crate::structured`]).

use super::attributes::{read_metadata, read_type};
use super::cursor::{is_kw, show, Cursor};
use super::values::{read_numeric, LegacyType};
use crate::structured::{self, Image, Lattice};
use crate::{ArrayData, DataArray, Grid, Result};

/// Which structured data set the DATASET line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Points,
    Grid,
    Rectilinear,
}

impl Kind {
    pub fn from_keyword(t: &[u8]) -> Option<Kind> {
        if is_kw(t, "STRUCTURED_POINTS") {
            Some(Kind::Points)
        } else if is_kw(t, "STRUCTURED_GRID") {
            Some(Kind::Grid)
        } else if is_kw(t, "RECTILINEAR_GRID") {
            Some(Kind::Rectilinear)
        } else {
            None
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Kind::Points => "a STRUCTURED_POINTS",
            Kind::Grid => "a STRUCTURED_GRID",
            Kind::Rectilinear => "a RECTILINEAR_GRID",
        }
    }
}

/// What a structured data set's keywords have said so far.
pub(crate) struct State {
    pub kind: Kind,
    /// Where the DATASET line was.
    at: usize,
    /// DIMENSIONS (points per axis; `None` inside when a count is 0: an empty data set), and
    /// where the keyword was.
    dims: Option<(Option<[usize; 3]>, usize)>,
    image: Image,
    /// X_, Y_ and Z_COORDINATES of a rectilinear grid, with where each was.
    coords: [Option<(ArrayData, usize)>; 3],
}

fn floats<const N: usize>(cur: &mut Cursor<'_>, what: &str) -> Result<[f64; N]> {
    let mut out = [0.0; N];
    for v in &mut out {
        let (p, t) = cur.require(&format!("{N} numbers after {what}"))?;
        *v = std::str::from_utf8(&t)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|x| x.is_finite())
            .ok_or_else(|| cur.err(p, format!("{what}: '{}' is not a finite number", show(&t))))?;
    }
    Ok(out)
}

impl State {
    pub fn new(kind: Kind, at: usize) -> State {
        State {
            kind,
            at,
            dims: None,
            image: Image::default(),
            coords: [None, None, None],
        }
    }

    /// Points and cells DIMENSIONS implies; an error at `p` when it has not been given yet.
    pub fn counts(&self, cur: &Cursor<'_>, p: usize) -> Result<(usize, usize)> {
        let (d, at) = self.dims.ok_or_else(|| {
            cur.err(
                p,
                format!("{} data set needs DIMENSIONS before this", self.kind.name()),
            )
        })?;
        structured::counts(d).map_err(|m| cur.err(at, format!("DIMENSIONS: {m}")))
    }

    /// Reads the geometry keyword `t` (at `p`) when it is one of this data set's; `false` when it
    /// is not (POINTS, attribute sections and unknown words are the caller's).
    pub fn keyword(&mut self, cur: &mut Cursor<'_>, p: usize, t: &[u8]) -> Result<bool> {
        if is_kw(t, "DIMENSIONS") {
            if self.dims.is_some() {
                return Err(cur.err(p, "a second DIMENSIONS line"));
            }
            let mut d = [0usize; 3];
            for v in &mut d {
                *v = cur.expect_count("three point counts after DIMENSIONS")?;
            }
            let dims = if d.contains(&0) { None } else { Some(d) };
            structured::counts(dims).map_err(|m| cur.err(p, format!("DIMENSIONS: {m}")))?;
            self.dims = Some((dims, p));
            return Ok(true);
        }
        if self.kind == Kind::Points {
            if is_kw(t, "ORIGIN") {
                self.image.origin = floats(cur, "ORIGIN")?;
                return Ok(true);
            }
            // Newer VTK writes the image's direction matrix (row-major), as the XML files do.
            if is_kw(t, "DIRECTION") {
                self.image.direction = floats(cur, "DIRECTION")?;
                return Ok(true);
            }
            // ASPECT_RATIO is what files before VTK 2.0 call the spacing.
            if is_kw(t, "SPACING") || is_kw(t, "ASPECT_RATIO") {
                self.image.spacing = floats(cur, &show(t))?;
                return Ok(true);
            }
        }
        if self.kind == Kind::Rectilinear {
            let axis = ["X_COORDINATES", "Y_COORDINATES", "Z_COORDINATES"]
                .iter()
                .position(|k| is_kw(t, k));
            if let Some(a) = axis {
                let what = show(t);
                if self.coords[a].is_some() {
                    return Err(cur.err(p, format!("a second {what} section")));
                }
                let n = cur.expect_count(&format!("the number of {what}"))?;
                let ty = read_type(cur, &what)?;
                if matches!(ty, LegacyType::String | LegacyType::Bit) {
                    return Err(cur.err(p, format!("{what} must be numbers")));
                }
                let data = read_numeric(cur, ty, n, &what)?;
                if let Some(k) = (0..data.len()).find(|&k| !data.get_f64(k).is_finite()) {
                    return Err(cur.err(p, format!("{what}: value {k} is not finite")));
                }
                read_metadata(cur, 1)?;
                self.coords[a] = Some((data, p));
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Puts the lattice's points (STRUCTURED_POINTS, RECTILINEAR_GRID) and cells into `grid`,
    /// checking POINTS (STRUCTURED_GRID) and coordinate counts against DIMENSIONS.
    pub fn finish(self, cur: &Cursor<'_>, grid: &mut Grid, have_points: bool) -> Result<()> {
        let (dims, at) = self.dims.ok_or_else(|| {
            cur.err(
                self.at,
                format!("{} data set without DIMENSIONS", self.kind.name()),
            )
        })?;
        let (np, _) = structured::counts(dims).map_err(|m| cur.err(at, m))?;
        let extent = match dims {
            Some(d) => [0, d[0] as i64 - 1, 0, d[1] as i64 - 1, 0, d[2] as i64 - 1],
            None => [0, -1, 0, -1, 0, -1],
        };
        let lattice = match self.kind {
            Kind::Points => {
                grid.points = structured::image_points(&self.image, extent, dims)
                    .map_err(|m| cur.err(at, m))?;
                Lattice::Axis
            }
            Kind::Rectilinear => {
                let names = ["X_COORDINATES", "Y_COORDINATES", "Z_COORDINATES"];
                let mut axes = Vec::with_capacity(3);
                for (a, c) in self.coords.iter().enumerate() {
                    let want = dims.map_or(0, |d| d[a]);
                    match c {
                        Some((data, _)) if data.len() == want => axes.push(data),
                        Some((data, p)) => {
                            return Err(cur.err(
                                *p,
                                format!(
                                "{} has {} values but DIMENSIONS gives {want} points on that axis",
                                names[a],
                                data.len()
                            ),
                            ))
                        }
                        None if want == 0 => {}
                        None => {
                            return Err(cur
                                .err(cur.pos, format!("a RECTILINEAR_GRID without {}", names[a])))
                        }
                    }
                }
                grid.points = match axes.as_slice() {
                    [x, y, z] => {
                        structured::rectilinear_points([x, y, z]).map_err(|m| cur.err(at, m))?
                    }
                    _ => DataArray::new("Points", 3, ArrayData::Float32(Vec::new())),
                };
                Lattice::Axis
            }
            Kind::Grid => {
                if !have_points && np > 0 {
                    return Err(cur.err(self.at, "a STRUCTURED_GRID without POINTS"));
                }
                if grid.num_points() != np {
                    return Err(cur.err(
                        at,
                        format!(
                            "DIMENSIONS gives {np} points but POINTS has {}",
                            grid.num_points()
                        ),
                    ));
                }
                Lattice::Curvilinear
            }
        };
        grid.cells = structured::cells(dims, lattice).map_err(|m| cur.err(at, m))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::legacy::read;
    use crate::{cell_type, ArrayData};

    #[test]
    fn structured_points_with_direction_and_cell_data() {
        let text = b"# vtk DataFile Version 5.1\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 1\nSPACING 1 2 3\nORIGIN 10 0 0\nDIRECTION 0 -1 0 1 0 0 0 0 1\nCELL_DATA 2\nSCALARS m int 1\nLOOKUP_TABLE default\n5 6\n";
        let g = read(text).unwrap();
        assert_eq!(g.cells.types, vec![cell_type::PIXEL; 2]);
        assert_eq!(g.cells.cell(1), &[2, 3, 4, 5]);
        let ArrayData::Float64(p) = &g.points.data else {
            panic!("Float64 points");
        };
        // Point (1, 2, 0): index (1, 4, 0) turned to (-4, 1, 0).
        assert_eq!(&p[15..18], &[6.0, 1.0, 0.0]);
        assert_eq!(
            g.cell_data.get("m").unwrap().data,
            ArrayData::Int32(vec![5, 6])
        );
    }

    #[test]
    fn refusals_name_the_problem() {
        let cases: [(&str, &str); 5] = [
            (
                "DATASET STRUCTURED_GRID\nDIMENSIONS 2 2 1\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n",
                "POINTS has 3",
            ),
            (
                "DATASET STRUCTURED_GRID\nDIMENSIONS 2 2 1\n",
                "without POINTS",
            ),
            (
                "DATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 x\n",
                "point counts",
            ),
            (
                "DATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nSPACING 1 1\n",
                "3 numbers",
            ),
            (
                "DATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nCELLS 1 2\n",
                "unknown keyword 'CELLS' in a STRUCTURED_POINTS",
            ),
        ];
        for (body, needle) in cases {
            let text = format!("# vtk DataFile Version 4.2\nt\nASCII\n{body}");
            let e = read(text.as_bytes()).unwrap_err().to_string();
            assert!(e.contains(needle), "{body}: {e}");
        }
        // An empty lattice is a valid, empty data set.
        let g = read(
            b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 0 2 2\n",
        )
        .unwrap();
        assert_eq!((g.num_points(), g.num_cells()), (0, 0));
    }
}
