//! Per-tet barycentric planes and vertex scalars, precomputed once for the ray caster's walk: a
//! step through a tet is two dot products per face (no cross products, no vertex or scalar
//! gathers), with the faces' coefficients laid out so the four faces go through together.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::field::Field;
use super::pt::FACES;
use crate::geom::{cross, dot, sub};
use rayon::prelude::*;

/// One tet: barycentric coordinate of face `f`'s opposite vertex is
/// `lambda_f(p) = gx[f] (p - r)_x + gy[f] (p - r)_y + gz[f] (p - r)_z + c[f]` with `r` the
/// mesh's reference point (the bounds' centre, so far-off meshes keep their digits), and `s` the
/// scalar at vertex `f`. A flat tet has no barycentric coordinates: its planes are the faces'
/// unscaled inward normals (the exit is still the nearest plane) and all four scalars are its
/// mean, as the per-ray computation did before.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct TetPlanes {
    pub gx: [f64; 4],
    pub gy: [f64; 4],
    pub gz: [f64; 4],
    pub c: [f64; 4],
    pub s: [f64; 4],
}

/// A face's rate along a unit ray at most this fraction of its gradient's size (the cosine of
/// the angle between them) is taken as zero: the ray runs along the face's plane.
const PARALLEL: f64 = 1e-12;

/// A ray's way through a tet it was walked into at `tin`: where it is first inside (`tin`, or
/// later where another face's plane says the ray only enters there), the exit parameter, the
/// exit face, and the scalar at the start and at the exit.
pub type Exit = (f64, f64, u8, f64, f64);

impl TetPlanes {
    fn build(v: &[[f64; 3]; 4], s: [f64; 4], r: &[f64; 3]) -> TetPlanes {
        let mut p = TetPlanes {
            s,
            ..TetPlanes::default()
        };
        let mut flat = false;
        for (f, fv) in FACES.iter().enumerate() {
            let a = v[fv[0]];
            let mut n = cross(&sub(&v[fv[1]], &a), &sub(&v[fv[2]], &a));
            // Inward normal: lambda_f grows towards vertex f. Which way that is comes from the
            // exact sign: in a sliver the float `h` is rounding noise, and a normal flipped by it
            // sent walks back across the face they came in by.
            let side = crate::geom::orient3d(&a, &v[fv[1]], &v[fv[2]], &v[f]);
            if side > 0.0 {
                n = [-n[0], -n[1], -n[2]];
            }
            let h = dot(&n, &sub(&v[f], &a)).abs();
            let inv = 1.0 / h;
            let scale = if inv.is_finite() {
                inv
            } else {
                flat = true;
                1.0
            };
            let g = n.map(|x| x * scale);
            p.gx[f] = g[0];
            p.gy[f] = g[1];
            p.gz[f] = g[2];
            // lambda_f(a) = 0, with a taken relative to r.
            p.c[f] = -dot(&g, &sub(&a, r));
        }
        if flat {
            p.s = [0.25 * (s[0] + s[1] + s[2] + s[3]); 4];
        }
        p
    }

    /// Leaves this tet (entered through face `entry` at `tin`) along `o + t d`, `o` relative to
    /// the reference point: the nearest face, other than the entry face, whose barycentric
    /// coordinate falls along the ray. The segment starts at `tin` or, where the coordinate of
    /// another face still rises along the ray and reaches zero only later, there: next to a
    /// sliver the walk can be handed a tet the ray meets later or not at all (the faces' planes
    /// nearly coincide, so the exit face is decided by rounding), and counting it from `tin`
    /// drew a chord through it that the ray does not have (a new user's clipped grid: up to
    /// 0.69 off in a dozen pixels, where PT was right). A tet the ray misses gets a segment of
    /// zero length. The scalar comes from the same coordinates (linear in `t`), clamped to the
    /// tet's values.
    #[inline]
    pub fn exit(&self, entry: Option<u8>, o: &[f64; 3], d: &[f64; 3], tin: f64) -> Option<Exit> {
        let mut a = [0.0f64; 4];
        let mut b = [0.0f64; 4];
        for f in 0..4 {
            a[f] = self.gx[f] * o[0] + self.gy[f] * o[1] + self.gz[f] * o[2] + self.c[f];
            b[f] = self.gx[f] * d[0] + self.gy[f] * d[1] + self.gz[f] * d[2];
            // A ray along the face's plane to rounding (down an edge or in a face of a
            // tetrahedralized grid; `d` is unit, so `b` is the gradient's size times the cosine
            // between them) has a rate of rounding noise, and its root `-a / b` lands
            // anywhere: it pushed the start of a tet's chord to the next grid node, so a ray
            // down a grid's edges lost its chords (a new user's 48-tet block at elevation 45:
            // the centre pixel 187/255 darker than PT; tests/newuser_offset_elevation.rs).
            // Treated as parallel, as an exact zero rate is.
            let m = self.gx[f].abs() + self.gy[f].abs() + self.gz[f].abs();
            if b[f].abs() <= PARALLEL * m {
                b[f] = 0.0;
            }
        }
        let skip = entry.map_or(4, usize::from);
        let mut best: Option<(f64, u8)> = None;
        for f in 0..4 {
            if f == skip || !(b[f] < 0.0) {
                continue;
            }
            let t = -a[f] / b[f];
            if t.is_finite() && best.is_none_or(|x| t < x.0) {
                best = Some((t, f as u8));
            }
        }
        let (tout, face) = best?;
        let tout = tout.max(tin);
        let mut start = tin;
        for f in 0..4 {
            if f != skip && b[f] > 0.0 {
                let t = -a[f] / b[f];
                if t > start {
                    start = t;
                }
            }
        }
        let start = start.min(tout);
        let s = &self.s;
        let va = s[0] * a[0] + s[1] * a[1] + s[2] * a[2] + s[3] * a[3];
        let vb = s[0] * b[0] + s[1] * b[1] + s[2] * b[2] + s[3] * b[3];
        let lo = s[0].min(s[1]).min(s[2].min(s[3]));
        let hi = s[0].max(s[1]).max(s[2].max(s[3]));
        // max/min (not clamp) so a NaN (a flat tet's infinite coordinates) lands on the range.
        let at = |t: f64| (va + t * vb).max(lo).min(hi);
        Some((start, tout, face, at(start), at(tout)))
    }
}

/// Planes of every tet, built in parallel.
pub fn build(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &Field,
    reference: &[f64; 3],
) -> Vec<TetPlanes> {
    tets.par_iter()
        .enumerate()
        .map(|(t, tet)| {
            let v = tet.map(|i| points[i as usize]);
            TetPlanes::build(&v, field.at(t, tet), reference)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_coordinates_and_exit() -> Result<(), &'static str> {
        let v = [
            [1e7, 1e7, 1e7],
            [1e7 + 1.0, 1e7, 1e7],
            [1e7, 1e7 + 1.0, 1e7],
            [1e7, 1e7, 1e7 + 1.0],
        ];
        let r = [1e7 + 0.5, 1e7 - 0.5, 1e7];
        let p = TetPlanes::build(&v, [0.0, 1.0, 2.0, 3.0], &r);
        // At each vertex, its own coordinate is 1 and the others 0.
        for (k, vk) in v.iter().enumerate() {
            let q = sub(vk, &r);
            for f in 0..4 {
                let l = p.gx[f] * q[0] + p.gy[f] * q[1] + p.gz[f] * q[2] + p.c[f];
                assert!((l - (f == k) as u8 as f64).abs() < 1e-12, "{k} {f} {l}");
            }
        }
        // A ray along +x entering through face 1 (x = 0) leaves through face 0 (x + y + z = 1).
        let o = sub(&[1e7 - 1.0, 1e7 + 0.2, 1e7 + 0.1], &r);
        let (start, tout, face, sin, sout) = p
            .exit(Some(1), &o, &[1.0, 0.0, 0.0], 1.0)
            .ok_or("no exit")?;
        assert_eq!((start, face), (1.0, 0));
        assert!((tout - 1.7).abs() < 1e-8, "{tout}");
        // s = x + 2 y + 3 z relative to v0 (1e7 + 0.2 is off by an ulp of 1e7, 2e-9).
        assert!((sin - (0.0 + 0.4 + 0.3)).abs() < 1e-8, "{sin}");
        assert!((sout - (0.7 + 0.4 + 0.3)).abs() < 1e-8, "{sout}");
        // A flat tet gives its mean value and still finds an exit.
        let f = TetPlanes::build(
            &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
            [0.0, 1.0, 2.0, 5.0],
            &[0.0; 3],
        );
        let (_, _, _, a, b) = f
            .exit(None, &[0.2, 0.2, -1.0], &[0.0, 0.0, 1.0], 0.0)
            .ok_or("a flat tet found no exit")?;
        assert_eq!((a, b), (2.0, 2.0));
        Ok(())
    }
}
