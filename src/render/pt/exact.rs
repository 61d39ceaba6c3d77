//! The exact silhouette, in the true (unsnapped) screen coordinates, of a tet the per-pixel path draws because a face of it is seen nearly edge-on.

use super::classify::silhouette;
use super::{Projected, FACES};

/// A projected tet's silhouette decided with exact predicates on the screen positions
/// themselves, not on the 1/256-pixel grid, so it agrees with the depth planes and the
/// view-space chords, which come from the same positions.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Silhouette {
    /// Corners, positively oriented: the first `n` (3 or 4).
    p: [(f64, f64); 4],
    n: usize,
}

/// `geom::orient2d` of screen points: positive when `c` lies left of `a -> b` (as in
/// `classify::orient2`), exact.
fn orient(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    crate::geom::orient2d([a.0, a.1], [b.0, b.1], [c.0, c.1])
}

impl Silhouette {
    /// The silhouette of the tet with projected vertices `pv`, and which faces project to a
    /// segment exactly (seen exactly edge-on: a ray in such a face's plane lies on the tet's
    /// boundary, so the face bounds no chord); `None` when the whole tet projects to a segment.
    pub(crate) fn new(pv: &[&Projected; 4]) -> Option<(Silhouette, [bool; 4])> {
        let q = pv.map(|p| (p.px, p.py));
        let d = FACES.map(|f| orient(q[f[0]], q[f[1]], q[f[2]]));
        let flat = d.map(|x| x == 0.0);
        let sign = d.map(|x| (x > 0.0) as i8 - (x < 0.0) as i8);
        let (c, n) = silhouette(sign, |a, b, c| orient(q[a], q[b], q[c]) > 0.0)?;
        let (p, n) = (c.map(|v| q[v]), n as usize);
        Some((Silhouette { p, n }, flat))
    }

    /// Whether the centre `(x + 0.5, y + 0.5)` of pixel `(x, y)` is inside: strictly, or on an
    /// edge the owner rule of the fixed-point silhouettes gives it (see `setup::Edge::new`), so
    /// a pixel centre on an edge two silhouettes share lies in exactly one of them.
    pub(crate) fn covers(&self, x: i64, y: i64) -> bool {
        let c = (x as f64 + 0.5, y as f64 + 0.5);
        (0..self.n).all(|e| {
            let (a, b) = (self.p[e], self.p[(e + 1) % self.n]);
            let s = orient(a, b, c);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            s > 0.0 || (s == 0.0 && (dy < 0.0 || (dy == 0.0 && dx > 0.0)))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn at(x: f64, y: f64) -> Projected {
        Projected {
            px: x,
            py: y,
            ..Default::default()
        }
    }

    proptest! {
        /// Two triangles (tets with a corner doubled) on either side of a shared edge, with
        /// corners on half pixels so pixel centres fall on the edge: each pixel centre strictly
        /// inside the edge is covered by exactly one of them.
        #[test]
        fn a_pixel_centre_on_a_shared_edge_lies_in_one_silhouette(
            e in prop::array::uniform2(prop::array::uniform2(0i32..16)),
            c in prop::array::uniform2(prop::array::uniform2(0i32..16)),
        ) {
            let h = |v: [i32; 2]| at(v[0] as f64 * 0.5, v[1] as f64 * 0.5);
            let (a, b, u, w) = (h(e[0]), h(e[1]), h(c[0]), h(c[1]));
            let o = |p: &Projected| orient((a.px, a.py), (b.px, b.py), (p.px, p.py));
            prop_assume!(o(&u) * o(&w) < 0.0);
            let s1 = Silhouette::new(&[&a, &b, &u, &u]);
            let s2 = Silhouette::new(&[&a, &b, &w, &w]);
            let (Some((s1, f1)), Some((s2, _))) = (s1, s2) else {
                return Err(TestCaseError::fail("a triangle is not flat"));
            };
            prop_assert_eq!(f1.iter().filter(|&&f| f).count(), 2);
            for y in 0..8 {
                for x in 0..8 {
                    let c = (x as f64 + 0.5, y as f64 + 0.5);
                    let t = (c.0 - a.px) * (b.px - a.px) + (c.1 - a.py) * (b.py - a.py);
                    let l = (b.px - a.px).powi(2) + (b.py - a.py).powi(2);
                    if orient((a.px, a.py), (b.px, b.py), c) == 0.0 && t > 0.0 && t < l {
                        prop_assert!(s1.covers(x, y) != s2.covers(x, y), "pixel ({}, {})", x, y);
                    }
                }
            }
        }
    }
}
