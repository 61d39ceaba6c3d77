//! The camera reduced to what projection needs, and mesh points projected to fixed-point screen positions.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{GUARD, SUB};
use crate::camera::Camera;
use rayon::prelude::*;

/// The camera reduced to what projection needs.
#[derive(Clone, Copy, Debug)]
pub struct View {
    pub width: u32,
    pub height: u32,
    pub eye: [f64; 3],
    pub r: [f64; 3],
    pub u: [f64; 3],
    pub f: [f64; 3],
    pub parallel: bool,
    /// tan(half view angle) (perspective) or parallel scale.
    pub scale: f64,
    pub aspect: f64,
    /// Depth below which a point counts as at or behind the eye (perspective): 1e-9, or 1e-9 of
    /// the camera's distance when that is below 1, so a mesh 1e-10 across (nanometres in
    /// metres) is not all "behind the eye".
    pub near: f64,
    /// The depth unit of the rasterizer's perspective planes, a power of two near the camera's
    /// distance (1 in parallel): depths go to f32 as `w = zunit / z` and depth offsets come out
    /// in units of `zunit`. With `w = 1 / z` the products `w0 (w0 + d)` overflowed f32 for a
    /// mesh 1e-20 across and underflowed at 1e25 across, leaving the image blank; scaling by a
    /// power of two is exact, so ordinary views keep every bit.
    pub zunit: f64,
}

/// The power of two nearest `d` (within 2^-1000..2^1000), or 1 when `d` is not a positive
/// finite number.
fn pow2_near(d: f64) -> f64 {
    if !(d.is_finite() && d > 0.0) {
        return 1.0;
    }
    let e = d.log2().round().clamp(-1000.0, 1000.0) as i64;
    // The exponent field of an f64 holds e + 1023 for a normal power of two.
    f64::from_bits(((e + 1023) as u64) << 52)
}

impl View {
    pub fn new(cam: &Camera, width: u32, height: u32) -> View {
        let (r, u, f) = cam.frame();
        View {
            width,
            height,
            eye: cam.position,
            r,
            u,
            f,
            parallel: cam.parallel,
            scale: if cam.parallel {
                cam.parallel_scale
            } else {
                (0.5 * cam.view_angle).to_radians().tan()
            },
            aspect: width as f64 / height as f64,
            near: 1e-9 * cam.distance().min(1.0),
            zunit: if cam.parallel {
                1.0
            } else {
                pow2_near(cam.distance())
            },
        }
    }

    /// View coordinates (right, up, forward depth) of a world point.
    #[inline]
    pub fn to_view(&self, p: &[f64; 3]) -> [f64; 3] {
        let d = [p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]];
        let dot = |a: &[f64; 3]| d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
        [dot(&self.r), dot(&self.u), dot(&self.f)]
    }

    /// Screen x of view coordinates (pixels, y down).
    #[inline]
    pub(crate) fn screen(&self, v: &[f64; 3]) -> (f64, f64) {
        let (sx, sy) = if self.parallel {
            (v[0] / self.scale, v[1] / self.scale)
        } else {
            (v[0] / (v[2] * self.scale), v[1] / (v[2] * self.scale))
        };
        (
            (sx / self.aspect + 1.0) * 0.5 * self.width as f64,
            (1.0 - sy) * 0.5 * self.height as f64,
        )
    }

    /// Screen-plane coordinates (xs, ys) of a pixel position, in units of `scale`: the view ray
    /// is (scale xs, scale ys, 1) (perspective) or starts at (scale xs, scale ys, 0) (parallel).
    #[inline]
    pub fn screen_plane(&self, px: f64, py: f64) -> (f64, f64) {
        (
            (2.0 * px / self.width as f64 - 1.0) * self.aspect,
            1.0 - 2.0 * py / self.height as f64,
        )
    }

    /// World length of the view ray per unit of depth through a pixel position.
    pub fn stretch(&self, px: f64, py: f64) -> f64 {
        if self.parallel {
            1.0
        } else {
            let (xs, ys) = self.screen_plane(px, py);
            (1.0 + (self.scale * xs).powi(2) + (self.scale * ys).powi(2)).sqrt()
        }
    }
}

/// A mesh point after projection: one cache line each, since the tets of a frame read their
/// points in visibility order, out of the points' order.
#[derive(Clone, Copy, Debug, Default)]
#[repr(align(64))]
pub struct Projected {
    pub view: [f64; 3],
    pub px: f64,
    pub py: f64,
    /// Fixed-point screen position (1/256 pixel).
    pub fx: i64,
    pub fy: i64,
    /// Usable: in front of the eye and inside the guard band.
    pub ok: bool,
}

/// Projects every point (in parallel).
pub fn project_points(view: &View, points: &[[f64; 3]]) -> Vec<Projected> {
    let near = view.near;
    let mut out = Vec::with_capacity(points.len());
    super::huge_pages(&mut out);
    points
        .par_iter()
        .map(|p| {
            let v = view.to_view(p);
            if !view.parallel && !(v[2] > near) {
                return Projected {
                    view: v,
                    ..Default::default()
                };
            }
            let (px, py) = view.screen(&v);
            let (sx, sy) = (px * SUB as f64, py * SUB as f64);
            let ok = sx.abs() < GUARD && sy.abs() < GUARD && v.iter().all(|c| c.is_finite());
            Projected {
                view: v,
                px,
                py,
                fx: if ok { sx.round() as i64 } else { 0 },
                fy: if ok { sy.round() as i64 } else { 0 },
                ok,
            }
        })
        .collect_into_vec(&mut out);
    out
}

/// Each pixel centre's world length of the view ray per [`View::zunit`] of depth (the unit of
/// the rasterizer's depth offsets), row by row.
pub(crate) fn stretch_map(view: &View) -> Vec<f32> {
    let (w, h) = (view.width as usize, view.height as usize);
    (0..w * h)
        .into_par_iter()
        .map(|i| (view.stretch((i % w) as f64 + 0.5, (i / w) as f64 + 0.5) * view.zunit) as f32)
        .collect()
}
