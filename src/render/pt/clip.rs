//! The per-pixel path for tets the rasterizer cannot take (a vertex behind the eye or beyond the guard band): rays clipped against the four face planes.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::exact::Silhouette;
use super::shade::Shader;
use super::tiles::Tile;
use super::{PixelBox, Projected, View, FACES, OPAQUE};
use crate::geom;

/// The per-pixel path for tets the rasterizer cannot take: a vertex behind the eye (the eye
/// inside or beside the tet, in perspective) or projected beyond the guard band. Each pixel's
/// ray is clipped against the tet's four face planes in view coordinates, and, in perspective,
/// starts at the eye, as the ray-cast reference's rays do.
pub(crate) struct ClipSetup {
    /// Inside where `n . P <= c`, per face.
    planes: [([f64; 3], f64); 4],
    /// Scalar at vertex 0 and its gradient, in view coordinates.
    v0: [f64; 3],
    s0: f64,
    g: [f64; 3],
    smin: f64,
    smax: f64,
    /// For a tet the rasterizer could take but a face of which is seen nearly edge-on: its
    /// exact silhouette, which decides the pixels (the planes alone would give a ray in a
    /// face's plane to both tets that share the face), and the faces seen exactly edge-on,
    /// which bound no chord.
    sil: Option<Box<(Silhouette, [bool; 4])>>,
    /// Per face: the length of its normal, its first corner's distance from the view origin,
    /// and whether a ray lying in its plane counts as inside (see [`ClipSetup::span`]).
    norm: [f64; 4],
    reach: [f64; 4],
    tie: [bool; 4],
}

impl ClipSetup {
    pub(crate) fn new(pv: [&Projected; 4], s: [f64; 4]) -> Option<ClipSetup> {
        let v = pv.map(|p| p.view);
        let sub = |a: [f64; 3], b: [f64; 3]| geom::sub(&a, &b);
        let cr = |a: [f64; 3], b: [f64; 3]| geom::cross(&a, &b);
        let dt = |a: [f64; 3], b: [f64; 3]| geom::dot(&a, &b);
        let e = [1, 2, 3].map(|k| sub(v[k], v[0]));
        let det = dt(e[0], cr(e[1], e[2]));
        if !(det != 0.0 && det.is_finite()) {
            return None;
        }
        let mut planes = [([0.0; 3], 0.0); 4];
        let (mut norm, mut reach, mut tie) = ([0.0; 4], [0.0; 4], [false; 4]);
        for (f, fv) in FACES.iter().enumerate() {
            let a = v[fv[0]];
            let mut n = cr(sub(v[fv[1]], a), sub(v[fv[2]], a));
            if dt(n, sub(v[f], a)) > 0.0 {
                n = [-n[0], -n[1], -n[2]];
            }
            planes[f] = (n, dt(n, a));
            norm[f] = dt(n, n).sqrt();
            reach[f] = dt(a, a).sqrt();
            // The first component of the outward normal that is not rounding: the two tets
            // that share the face see it with opposite signs.
            let lead = n
                .into_iter()
                .find(|x| x.abs() > 1e-9 * norm[f])
                .unwrap_or(0.0);
            tie[f] = lead < 0.0;
        }
        let ds = [1, 2, 3].map(|k| s[k] - s[0]);
        let (c0, c1, c2) = (cr(e[1], e[2]), cr(e[2], e[0]), cr(e[0], e[1]));
        let g = [0, 1, 2].map(|a| (ds[0] * c0[a] + ds[1] * c1[a] + ds[2] * c2[a]) / det);
        Some(ClipSetup {
            planes,
            v0: v[0],
            s0: s[0],
            g,
            smin: s.iter().copied().fold(f64::INFINITY, f64::min),
            smax: s.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            sil: None,
            norm,
            reach,
            tie,
        })
    }

    /// The set-up of a tet whose vertices all project inside the guard band, but a face of
    /// which is seen nearly edge-on (see `setup::snapped_sliver`): pixels decided by its exact
    /// silhouette. `None` when it draws nothing.
    pub(crate) fn exact(pv: [&Projected; 4], s: [f64; 4]) -> Option<ClipSetup> {
        let sil = Silhouette::new(&pv)?;
        Some(ClipSetup {
            sil: Some(Box::new(sil)),
            ..ClipSetup::new(pv, s)?
        })
    }

    /// Whether pixel `(x, y)` is the tet's to draw: always for a tet with a vertex behind the
    /// eye or beyond the guard band (its planes decide), else by its exact silhouette.
    #[inline]
    fn covers(&self, x: i64, y: i64) -> bool {
        self.sil.as_ref().is_none_or(|s| s.0.covers(x, y))
    }

    /// The view depths `(z0, z1)` where the ray `A + z B` (z the view depth) of pixel `(x, y)`
    /// is inside the tet, from `zmin` on.
    #[inline]
    pub(crate) fn span(
        &self,
        (x, y): (i64, i64),
        a: [f64; 3],
        b: [f64; 3],
        zmin: f64,
    ) -> Option<(f64, f64)> {
        let (mut z0, mut z1) = (zmin, f64::INFINITY);
        let mut in_plane = false;
        let edge_on = self.sil.as_ref().map_or([false; 4], |s| s.1);
        let (al, bl) = (dot3(a, a).sqrt(), dot3(b, b).sqrt());
        for (f, (n, c)) in self.planes.iter().enumerate() {
            if edge_on[f] {
                continue;
            }
            let na = dot3(*n, a);
            let nb = dot3(*n, b);
            // A ray in the face's plane, to rounding (an eye on a grid node or grid plane: the
            // rays through the pixel centres on that plane's line). It lies on the boundary of
            // both tets that share the face, so the clipped planes alone gave it to both (57/255
            // too bright) or to neither; it goes to one, as if its origin moved off the plane
            // along a fixed direction whose side the normal's leading component tells. That
            // decides it for a tet with an exact silhouette too: the pixel centre lies within
            // rounding of the face's line there, and the screen positions' rounding is not the
            // view coordinates' (a ray down an edge seen end-on: the tets around the edge all
            // touched it, and two took the whole edge).
            let tol = 1e-12 * self.norm[f];
            if nb.abs() <= tol * bl && (c - na).abs() <= tol * (self.reach[f] + al) {
                if self.tie[f] {
                    in_plane = true;
                    continue;
                }
                return None;
            }
            // n.A + z n.B <= c.
            if nb > 0.0 {
                z1 = z1.min((c - na) / nb);
            } else if nb < 0.0 {
                z0 = z0.max((c - na) / nb);
            } else if na > *c {
                return None;
            }
        }
        let inside = in_plane || self.covers(x, y);
        (inside && z1 > z0 && z0.is_finite() && z1.is_finite()).then_some((z0, z1))
    }

    /// The scalar at depth `z` of the ray `A + z B`, clamped to the tet's range.
    #[inline]
    pub(crate) fn scalar(&self, a: [f64; 3], b: [f64; 3], z: f64) -> f64 {
        let p = [a[0] + z * b[0], a[1] + z * b[1], a[2] + z * b[2]];
        (self.s0
            + dot3(
                self.g,
                [p[0] - self.v0[0], p[1] - self.v0[1], p[2] - self.v0[2]],
            ))
        .clamp(self.smin, self.smax)
    }

    /// (Sf, Sb, l) of the ray `A + z B` (z the view depth), from `zmin` on.
    #[inline]
    fn segment(
        &self,
        px: (i64, i64),
        a: [f64; 3],
        b: [f64; 3],
        zmin: f64,
    ) -> Option<(f64, f64, f64)> {
        let (z0, z1) = self.span(px, a, b, zmin)?;
        Some((
            self.scalar(a, b, z0),
            self.scalar(a, b, z1),
            (z1 - z0) * dot3(b, b).sqrt(),
        ))
    }
}

fn dot3(p: [f64; 3], q: [f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// The ray of pixel `(x, y)` as `A + z B` with `z` the view depth (from the eye in perspective,
/// from the camera plane in parallel), and the depth where it starts.
#[inline]
pub(crate) fn pixel_ray(view: &View, x: i64, y: i64) -> ([f64; 3], [f64; 3], f64) {
    let (xs, ys) = view.screen_plane(x as f64 + 0.5, y as f64 + 0.5);
    if view.parallel {
        (
            [view.scale * xs, view.scale * ys, 0.0],
            [0.0, 0.0, 1.0],
            f64::NEG_INFINITY,
        )
    } else {
        ([0.0; 3], [view.scale * xs, view.scale * ys, 1.0], 0.0)
    }
}

/// Screen box of a tet with a vertex behind the eye or beyond the guard band: the box of its
/// part in front of the view's near depth (edges cut there), clamped to the image.
pub(crate) fn clip_box(view: &View, p: &[&Projected; 4], w: usize, h: usize) -> Option<PixelBox> {
    let near = if view.parallel {
        f64::NEG_INFINITY
    } else {
        view.near
    };
    let mut pts: Vec<[f64; 3]> = Vec::with_capacity(8);
    for i in 0..4 {
        let a = p[i].view;
        if a[2] >= near {
            pts.push(a);
        }
        for q in &p[i + 1..] {
            let b = q.view;
            if (a[2] < near) != (b[2] < near) {
                let t = (near - a[2]) / (b[2] - a[2]);
                pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), near]);
            }
        }
    }
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for v in &pts {
        let (px, py) = view.screen(v);
        if !(px.is_finite() && py.is_finite()) {
            // Too close to the eye plane to place: the whole image.
            (x0, x1, y0, y1) = (
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
            );
            break;
        }
        x0 = x0.min(px);
        x1 = x1.max(px);
        y0 = y0.min(py);
        y1 = y1.max(py);
    }
    if pts.is_empty() {
        return None;
    }
    // Pixel centres i + 0.5 in [min, max], widened by a pixel against rounding.
    let lo = |v: f64| (v - 1.5).ceil().clamp(0.0, 1e9) as i64;
    let hi = |v: f64, n: usize| (v + 0.5).floor().clamp(-1.0, n as f64 - 1.0) as i64;
    let b = (lo(x0), lo(y0), hi(x1, w), hi(y1, h));
    (b.0 <= b.2 && b.1 <= b.3).then_some(b)
}

impl ClipSetup {
    /// Draws the tet pixel by pixel over the part of its pixel box `b` inside `tile`, into `buf`
    /// covering `tile` (front to back): fragments and newly opaque pixels.
    pub(crate) fn draw(
        &self,
        view: &View,
        b: PixelBox,
        tile: Tile,
        buf: &mut [[f32; 4]],
        shader: &Shader,
    ) -> (u64, usize) {
        let (tx0, ty0, tx1, _) = tile;
        let part = (
            tile.0.max(b.0),
            tile.1.max(b.1),
            tile.2.min(b.2),
            tile.3.min(b.3),
        );
        let tw = (tx1 - tx0 + 1) as usize;
        let (mut frags, mut newly) = (0u64, 0usize);
        for y in part.1..=part.3 {
            for x in part.0..=part.2 {
                let slot = &mut buf[(y - ty0) as usize * tw + (x - tx0) as usize];
                if slot[3] >= OPAQUE {
                    continue;
                }
                let (a, b, zmin) = pixel_ray(view, x, y);
                let Some((sf, sb, l)) = self.segment((x, y), a, b, zmin) else {
                    continue;
                };
                let col = shader.shade(sf as f32, sb as f32, l as f32);
                let k = 1.0 - slot[3];
                for ch in 0..4 {
                    slot[ch] += k * col[ch];
                }
                frags += 1;
                if slot[3] >= OPAQUE {
                    newly += 1;
                }
            }
        }
        (frags, newly)
    }
}
