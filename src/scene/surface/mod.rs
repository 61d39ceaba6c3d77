//! Closed triangle surfaces as cutting bodies: reading them (.stl, .obj, .vtk, .vtp), checking
//! that they are closed and consistently oriented, and exact ray crossings.

mod grid;
mod obj;
mod polydata;
mod stl;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use formats::FormatError;

use super::exact::{det3_sign, ZERO};
use crate::geom::Aabb;

/// A closed, consistently oriented triangle surface (possibly several components).
#[derive(Clone, Debug, PartialEq)]
pub struct TriSurface {
    pub file: PathBuf,
    pub points: Vec<[f64; 3]>,
    pub tris: Vec<[u32; 3]>,
    pub bounds: Aabb,
    grid: grid::TriGrid,
}

/// Polygons as read from a file, before welding and checking.
#[derive(Debug)]
pub(crate) struct RawSurface {
    pub points: Vec<[f64; 3]>,
    /// Polygons with at least 3 point ids; larger ones are fanned into triangles.
    pub polys: Vec<Vec<u32>>,
}

/// Reads a surface by extension and checks it is closed. Errors name the file and the place.
pub fn read(path: &Path) -> Result<TriSurface, FormatError> {
    let bytes = std::fs::read(path).map_err(|e| FormatError::io(path, e))?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let raw = match ext.as_str() {
        "stl" => stl::read(&bytes),
        "obj" => obj::read(&bytes),
        "vtk" => polydata::read_legacy(&bytes),
        "vtp" => polydata::read_xml(&bytes),
        _ => Err(FormatError::whole(format!(
            "unknown surface extension '.{ext}'; expected .stl, .obj, .vtk or .vtp"
        ))),
    }
    .map_err(|e| e.with_file(path))?;
    TriSurface::from_raw(path, raw).map_err(|e| e.with_file(path))
}

impl TriSurface {
    pub(crate) fn from_raw(path: &Path, raw: RawSurface) -> Result<TriSurface, FormatError> {
        let n = raw.points.len();
        for (i, p) in raw.points.iter().enumerate() {
            if !p.iter().all(|x| x.is_finite()) {
                return Err(FormatError::whole(format!(
                    "point {i} is not finite: {p:?}"
                )));
            }
        }
        // Weld coincident points (STL repeats every vertex) so edges can be matched.
        let mut id_of: HashMap<[u64; 3], u32> = HashMap::new();
        let mut points = Vec::new();
        let mut remap = Vec::with_capacity(n);
        for p in &raw.points {
            let key = p.map(|x| if x == 0.0 { 0u64 } else { x.to_bits() });
            let id = *id_of.entry(key).or_insert_with(|| {
                points.push(*p);
                (points.len() - 1) as u32
            });
            remap.push(id);
        }
        let mut tris = Vec::new();
        for (pi, poly) in raw.polys.iter().enumerate() {
            if poly.len() < 3 {
                return Err(FormatError::whole(format!(
                    "polygon {pi} has {} points; a closed surface needs triangles",
                    poly.len()
                )));
            }
            for &v in poly {
                if v as usize >= n {
                    return Err(FormatError::whole(format!(
                        "polygon {pi} refers to point {v}, but there are {n} points"
                    )));
                }
            }
            let ids: Vec<u32> = poly.iter().map(|&v| remap[v as usize]).collect();
            for k in 1..ids.len() - 1 {
                let t = [ids[0], ids[k], ids[k + 1]];
                if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                    return Err(FormatError::whole(format!(
                        "polygon {pi} has a repeated point ({}, {}, {})",
                        fmt_point(&points[t[0] as usize]),
                        fmt_point(&points[t[1] as usize]),
                        fmt_point(&points[t[2] as usize])
                    )));
                }
                tris.push(t);
            }
        }
        if tris.is_empty() {
            return Err(FormatError::whole(
                "no triangles: a body needs a closed surface",
            ));
        }
        check_closed(&points, &tris)?;
        let bounds = Aabb::of_points(points.iter());
        let grid = grid::TriGrid::build(&points, &tris, &bounds);
        Ok(TriSurface {
            file: path.to_path_buf(),
            points,
            tris,
            bounds,
            grid,
        })
    }

    /// Depths `t > 0` (or `t >= 0`: a surface through the origin counts as just in front) where
    /// the ray `o + t d` crosses the surface, counting each crossing once however the ray meets
    /// edges and vertices: the ray is treated as if its origin were moved by an infinitesimal
    /// `eps u + eps^2 w` (simulation of simplicity), with `u`, `w` the two coordinate axes other
    /// than `d`'s largest. Triangles seen edge-on never count (the moved line misses them).
    pub fn crossings(&self, o: &[f64; 3], d: &[f64; 3], out: &mut Vec<f64>) {
        self.crossings_among(o, d, None, out)
    }

    /// [`TriSurface::crossings`] restricted to the triangles `among` (all when `None`); the
    /// caller guarantees the others cannot be crossed.
    pub fn crossings_among(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        among: Option<&[u32]>,
        out: &mut Vec<f64>,
    ) {
        let k = (0..3)
            .max_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
            .unwrap_or(2);
        let mut u = [0.0; 3];
        u[(k + 1) % 3] = 1.0;
        let mut w = [0.0; 3];
        w[(k + 2) % 3] = 1.0;
        // The side of the moved line relative to the directed edge a -> b: antisymmetric in
        // (a, b), so a shared edge counts for exactly one of its two triangles.
        let side = |a: &[f64; 3], b: &[f64; 3]| -> i32 {
            let s = det3_sign((*d, ZERO), (*a, *o), (*b, *o));
            if s != 0 {
                return s;
            }
            let s = -det3_sign((*d, ZERO), (u, ZERO), (*b, *a));
            if s != 0 {
                return s;
            }
            -det3_sign((*d, ZERO), (w, ZERO), (*b, *a))
        };
        let (bmin, bmax) = (self.bounds.min, self.bounds.max);
        // Quick reject with the box (the slab test is only a filter: it is widened).
        if let Some((t0, t1)) = (super::shapes::Primitive::Box {
            min: bmin.map(|x| x - 1e-9 * (1.0 + x.abs())),
            max: bmax.map(|x| x + 1e-9 * (1.0 + x.abs())),
        })
        .line_span(o, d)
        {
            if t1 < 0.0 && t0 < 0.0 {
                return;
            }
        } else {
            return;
        }
        // A float filter first: shear along d onto the plane x_k = o_k, where the ray is the
        // point (o_i, o_j); triangles whose sheared box misses it by more than any rounding are
        // skipped before the exact signs.
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (si, sj) = (d[i] / d[k], d[j] / d[k]);
        let mag = [bmin, bmax, *o]
            .iter()
            .flat_map(|p| p.iter())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let eps = 1e-12 * mag * (2.0 + si.abs() + sj.abs()) + f64::MIN_POSITIVE;
        let shear = |p: &[f64; 3]| {
            let dk = p[k] - o[k];
            (p[i] - si * dk - o[i], p[j] - sj * dk - o[j])
        };
        let all = 0..self.tris.len() as u32;
        let ids: Box<dyn Iterator<Item = u32>> = match among {
            Some(ids) => Box::new(ids.iter().copied()),
            None => Box::new(all),
        };
        for ti in ids {
            let t = &self.tris[ti as usize];
            let [a, b, c] = t.map(|v| self.points[v as usize]);
            let (sa, sb, sc) = (shear(&a), shear(&b), shear(&c));
            if (sa.0 > eps && sb.0 > eps && sc.0 > eps)
                || (sa.0 < -eps && sb.0 < -eps && sc.0 < -eps)
                || (sa.1 > eps && sb.1 > eps && sc.1 > eps)
                || (sa.1 < -eps && sb.1 < -eps && sc.1 < -eps)
            {
                continue;
            }
            let s0 = side(&a, &b);
            let s1 = side(&b, &c);
            if s0 != s1 {
                continue;
            }
            let s2 = side(&c, &a);
            if s0 != s2 {
                continue;
            }
            // Edge-on triangles: the three sides can agree only by the tie-breaking terms.
            if det3_sign((*d, ZERO), (b, a), (c, a)) == 0 {
                continue;
            }
            // Is the plane in front of the origin? sign of (a - o) . n against d . n.
            let front = det3_sign((b, a), (c, a), (a, *o));
            let facing = det3_sign((b, a), (c, a), (*d, ZERO));
            if front != 0 && front != facing {
                continue;
            }
            let n = crate::geom::cross(&crate::geom::sub(&b, &a), &crate::geom::sub(&c, &a));
            let denom = crate::geom::dot(d, &n);
            let tt = crate::geom::dot(&crate::geom::sub(&a, o), &n) / denom;
            out.push(tt.max(0.0));
        }
    }

    /// Whether `p` is inside: the parity of crossings of a ray from `p` (exact, same rule).
    pub fn contains(&self, p: &[f64; 3]) -> bool {
        if !self.bounds.contains(p) {
            return false;
        }
        let mut v = Vec::new();
        let among = if self.grid.on_column_border(p) {
            None
        } else {
            Some(self.grid.column(p))
        };
        self.crossings_among(p, &[0.0, 0.0, 1.0], among, &mut v);
        v.len() % 2 == 1
    }

    /// Triangles whose boxes may overlap `b` (a superset; a triangle may repeat).
    pub fn candidates(&self, b: &Aabb, out: &mut Vec<u32>) {
        self.grid.candidates(b, out)
    }
}

/// The next three words of a text record as finite coordinates; `what` names the record in the
/// error (e.g. `'v'` in OBJ, `'vertex'` in ASCII STL).
pub(super) fn parse_xyz<'a>(
    words: &mut impl Iterator<Item = &'a str>,
    line_no: usize,
    what: &str,
) -> Result<[f64; 3], FormatError> {
    let mut p = [0.0; 3];
    for x in p.iter_mut() {
        let w = words.next().ok_or_else(|| {
            FormatError::at_line(line_no, format!("{what} needs three coordinates"))
        })?;
        *x = w
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                FormatError::at_line(line_no, format!("'{w}' is not a finite number"))
            })?;
    }
    Ok(p)
}

pub(crate) fn fmt_point(p: &[f64; 3]) -> String {
    format!("{} {} {}", p[0], p[1], p[2])
}

/// Every edge must be used by exactly two triangles, once in each direction.
fn check_closed(points: &[[f64; 3]], tris: &[[u32; 3]]) -> Result<(), FormatError> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in tris {
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            *directed.entry(e).or_default() += 1;
        }
    }
    let edge = |a: u32, b: u32| {
        format!(
            "({}) - ({})",
            fmt_point(&points[a as usize]),
            fmt_point(&points[b as usize])
        )
    };
    let mut bad: Vec<(&(u32, u32), &u32)> = directed.iter().collect();
    bad.sort();
    for (&(a, b), &n) in bad {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        if n > 1 {
            return Err(FormatError::whole(format!(
                "edge {} is used {} times in the same direction: the triangles around it are not consistently oriented{}",
                edge(a, b),
                n,
                if n + back > 2 { " (or more than two triangles meet there)" } else { "" }
            )));
        }
        if back == 0 {
            return Err(FormatError::whole(format!(
                "the surface is open: edge {} belongs to only one triangle",
                edge(a, b)
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A unit cube [0,1]^3 as 12 outward triangles.
    pub fn cube_raw() -> RawSurface {
        let points = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        RawSurface {
            points,
            polys: quads.iter().map(|q| q.to_vec()).collect(),
        }
    }

    #[test]
    fn closed_cube_and_crossings_through_edges_and_vertices() {
        let s = TriSurface::from_raw(Path::new("cube"), cube_raw()).unwrap();
        assert_eq!(s.tris.len(), 12);
        // Every ray through the cube's diagonals, edges, vertices and face diagonals crosses
        // exactly twice.
        let mut v = Vec::new();
        for (o, d) in [
            ([0.5, 0.5, -1.0], [0.0, 0.0, 1.0]),
            ([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]),
            ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]),
            ([0.5, 0.0, -1.0], [0.0, 0.0, 1.0]),
            ([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]),
            ([-1.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
            ([-0.5, -0.5, 0.5], [1.0, 1.0, 0.0]),
        ] {
            v.clear();
            s.crossings(&o, &d, &mut v);
            v.sort_by(f64::total_cmp);
            assert!(v.len() == 2 || v.is_empty(), "{o:?} {d:?}: {v:?}");
        }
        v.clear();
        s.crossings(&[0.5, 0.5, -1.0], &[0.0, 0.0, 1.0], &mut v);
        v.sort_by(f64::total_cmp);
        assert_eq!(v, vec![1.0, 2.0]);
        assert!(s.contains(&[0.5, 0.5, 0.5]));
        assert!(!s.contains(&[1.5, 0.5, 0.5]));
    }

    #[test]
    fn open_and_misoriented_surfaces_are_refused() {
        let mut raw = cube_raw();
        raw.polys.pop();
        let e = TriSurface::from_raw(Path::new("open"), raw).unwrap_err();
        assert!(e.to_string().contains("open"), "{e}");
        let mut raw = cube_raw();
        raw.polys[0].reverse();
        let e = TriSurface::from_raw(Path::new("flip"), raw).unwrap_err();
        assert!(e.to_string().contains("orient"), "{e}");
    }
}

#[cfg(test)]
mod reader_tests {
    use super::*;

    fn read_text(name: &str, text: &str) -> Result<TriSurface, FormatError> {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        read(&p)
    }

    const TET_OBJ: &str =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    #[test]
    fn each_reader_reads_a_tetrahedron_and_names_bad_lines() {
        let s = read_text("t.obj", TET_OBJ).unwrap();
        assert_eq!(s.tris.len(), 4);
        assert!(s.contains(&[0.1, 0.1, 0.1]));
        let vtk42 = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0\n0 1 0 0 0 1\nPOLYGONS 4 16\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        assert_eq!(read_text("t.vtk", vtk42).unwrap().tris, s.tris);
        let bad = vtk42.replace("0 1 0 0 0 1", "0 1 0 0 zero 1");
        let e = read_text("t.vtk", &bad).unwrap_err().to_string();
        assert!(e.contains("line 7") && e.contains("zero"), "{e}");
        let e = read_text("t.obj", "v 0 0 0\nf 1 2 3\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2"), "{e}");
        let e = read_text(
            "t.stl",
            "solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 4"), "{e}");
        let e = read_text("t.ply", "").unwrap_err().to_string();
        assert!(e.contains("t.ply") && e.contains(".stl"), "{e}");
        // A binary STL of the same tetrahedron.
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&4u32.to_le_bytes());
        let p = [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        for t in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
            b.extend_from_slice(&[0u8; 12]);
            for v in t {
                for x in p[v] {
                    b.extend_from_slice(&x.to_le_bytes());
                }
            }
            b.extend_from_slice(&[0u8; 2]);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.stl");
        std::fs::write(&path, &b).unwrap();
        let st = read(&path).unwrap();
        assert_eq!(st.tris.len(), 4);
        assert!(st.contains(&[0.1, 0.1, 0.1]) && !st.contains(&[0.5, 0.5, 0.5]));
    }
}
