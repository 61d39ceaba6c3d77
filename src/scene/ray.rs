//! Region codes along pixel rays: each body's crossing depths flip its bit (the paper's INVERT
//! trick, no front/back test), and bounding-box culling gives each body the screen rectangle and
//! depth range outside which it costs nothing.

use super::Scene;
use crate::camera::Camera;
use crate::geom::{dot, sub, Aabb};

/// Where a body can matter on screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Pixel rectangle `[x0, y0, x1, y1]` (pixel coordinates as [`Camera::pixel_ray`] takes
    /// them) that holds every ray meeting the body's bounding box; `None`: the whole image.
    pub rect: Option<[f64; 4]>,
    /// Ray parameters (distance along a pixel ray) the body's box spans.
    pub t_range: (f64, f64),
}

impl Footprint {
    pub fn covers(&self, px: f64, py: f64) -> bool {
        match self.rect {
            None => true,
            Some(r) => px >= r[0] && px <= r[2] && py >= r[1] && py <= r[3],
        }
    }

    /// Pixels (of a `width x height` image, centres at half-integers) the rectangle touches.
    pub fn pixel_count(&self, width: u32, height: u32) -> u64 {
        match self.rect {
            None => width as u64 * height as u64,
            Some(r) => {
                let span = |a: f64, b: f64, n: u32| {
                    let lo = (a - 0.5).ceil().max(0.0);
                    let hi = (b - 0.5).floor().min(n as f64 - 1.0);
                    if hi >= lo {
                        (hi - lo + 1.0) as u64
                    } else {
                        0
                    }
                };
                span(r[0], r[2], width) * span(r[1], r[3], height)
            }
        }
    }
}

/// The footprint of a box seen by `cam`.
pub fn footprint(b: &Aabb, cam: &Camera, width: u32, height: u32) -> Footprint {
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { b.min[0] } else { b.max[0] },
                if i & 2 == 0 { b.min[1] } else { b.max[1] },
                if i & 4 == 0 { b.min[2] } else { b.max[2] },
            ]
        })
        .collect();
    let proj: Vec<[f64; 3]> = corners
        .iter()
        .map(|c| cam.project(c, width, height))
        .collect();
    let (zmin, zmax) = proj
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), p| {
            (a.min(p[2]), c.max(p[2]))
        });
    let t_range = if cam.parallel {
        (zmin, zmax)
    } else {
        // Distance from the eye to the box, and to its farthest corner.
        let e = cam.position;
        let near: f64 = (0..3)
            .map(|k| {
                let d = (b.min[k] - e[k]).max(0.0).max(e[k] - b.max[k]);
                d * d
            })
            .sum::<f64>()
            .sqrt();
        let far = corners
            .iter()
            .map(|c| {
                let v = sub(c, &e);
                dot(&v, &v).sqrt()
            })
            .fold(0.0f64, f64::max);
        (near, far)
    };
    // Rounding of the projection: a pixel's worth of margin keeps the rectangle conservative.
    let min_depth = 1e-9 * (1.0 + zmax.abs());
    let rect = if !cam.parallel && zmin <= min_depth {
        None
    } else {
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        for p in &proj {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            y0 = y0.min(p[1]);
            y1 = y1.max(p[1]);
        }
        Some([x0 - 1.0, y0 - 1.0, x1 + 1.0, y1 + 1.0])
    };
    let pad = 1e-9 * (1.0 + t_range.1.abs());
    Footprint {
        rect,
        t_range: (t_range.0 - pad, t_range.1 + pad),
    }
}

/// The scene as one camera sees it: the footprints of its bodies.
pub struct View<'a> {
    pub scene: &'a Scene,
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub footprints: Vec<Footprint>,
    /// When false every body is tested at every pixel (to measure what culling saves).
    pub culling: bool,
    frame: ([f64; 3], [f64; 3], [f64; 3]),
    /// Per body: for surfaces, the triangles each screen tile may see.
    bins: Vec<Option<TriBins>>,
}

/// Triangles of a surface binned by their screen rectangles (conservative), so a pixel's ray is
/// tested only against the triangles of its tile.
struct TriBins {
    ntx: usize,
    lists: Vec<Vec<u32>>,
}

const BIN: f64 = 16.0;

fn bin_surface(s: &super::TriSurface, cam: &Camera, width: u32, height: u32) -> TriBins {
    let ntx = (width as f64 / BIN).ceil() as usize;
    let nty = (height as f64 / BIN).ceil() as usize;
    let mut lists = vec![Vec::new(); ntx * nty];
    let proj: Vec<[f64; 3]> = s
        .points
        .iter()
        .map(|p| cam.project(p, width, height))
        .collect();
    let far = s
        .points
        .iter()
        .map(|p| cam.project(p, width, height)[2].abs())
        .fold(0.0f64, f64::max);
    for (i, t) in s.tris.iter().enumerate() {
        let q = t.map(|v| proj[v as usize]);
        let (x0, x1, y0, y1) = if !cam.parallel && q.iter().any(|p| p[2] <= 1e-9 * (1.0 + far)) {
            (0, ntx - 1, 0, nty - 1)
        } else {
            let b = |f: fn(f64, f64) -> f64, k: usize, init: f64| {
                q.iter().fold(init, |m, p| f(m, p[k]))
            };
            // A pixel of margin for rounding in the projection.
            let cell = |v: f64, n: usize| ((v / BIN).floor().max(0.0) as usize).min(n - 1);
            (
                cell(b(f64::min, 0, f64::INFINITY) - 1.0, ntx),
                cell(b(f64::max, 0, f64::NEG_INFINITY) + 1.0, ntx),
                cell(b(f64::min, 1, f64::INFINITY) - 1.0, nty),
                cell(b(f64::max, 1, f64::NEG_INFINITY) + 1.0, nty),
            )
        };
        for ty in y0..=y1 {
            for tx in x0..=x1 {
                lists[ty * ntx + tx].push(i as u32);
            }
        }
    }
    TriBins { ntx, lists }
}

/// Region codes along one ray: `start` at the ray origin, then each crossing (sorted by depth)
/// flips its body's bit; `codes[i]` holds from `depths[i]` to the next depth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayRegions {
    pub start: u8,
    pub depths: Vec<f64>,
    pub codes: Vec<u8>,
    scratch: Vec<(f64, u8)>,
    hits: Vec<f64>,
}

impl RayRegions {
    /// The code at depth `t` (a crossing's own depth takes the code after it).
    pub fn code_at(&self, t: f64) -> u8 {
        let i = self.depths.partition_point(|&d| d <= t);
        if i == 0 {
            self.start
        } else {
            self.codes[i - 1]
        }
    }

    /// Calls `f(t0, t1, code)` for the pieces of `[ta, tb]` between crossings (one piece when
    /// no body surface crosses it).
    pub fn pieces(&self, ta: f64, tb: f64, mut f: impl FnMut(f64, f64, u8)) {
        let mut i = self.depths.partition_point(|&d| d <= ta);
        let mut t = ta;
        let mut code = if i == 0 {
            self.start
        } else {
            self.codes[i - 1]
        };
        while i < self.depths.len() && self.depths[i] < tb {
            if self.depths[i] > t {
                f(t, self.depths[i], code);
                t = self.depths[i];
            }
            code = self.codes[i];
            i += 1;
        }
        if tb > t {
            f(t, tb, code);
        }
    }

    /// Whether no body surface crosses the ray at all.
    pub fn is_uniform(&self) -> bool {
        self.depths.is_empty()
    }
}

impl<'a> View<'a> {
    pub fn new(scene: &'a Scene, camera: Camera, width: u32, height: u32) -> View<'a> {
        let footprints = scene
            .bodies
            .iter()
            .map(|b| footprint(&b.bounds(), &camera, width, height))
            .collect();
        View {
            scene,
            camera,
            width,
            height,
            footprints,
            culling: true,
            frame: camera.frame(),
            bins: scene
                .bodies
                .iter()
                .map(|b| match &b.shape {
                    super::Shape::Surface(s) => Some(bin_surface(s, &camera, width, height)),
                    _ => None,
                })
                .collect(),
        }
    }

    /// The ray through pixel coordinates `(px, py)`: bit for bit [`Camera::pixel_ray`], with
    /// the camera frame computed once.
    pub fn pixel_ray(&self, px: f64, py: f64) -> ([f64; 3], [f64; 3]) {
        self.camera
            .pixel_ray_in_frame(&self.frame, px, py, self.width, self.height)
    }

    /// Region codes along the ray through pixel coordinates `(px, py)`.
    pub fn pixel(&self, px: f64, py: f64, out: &mut RayRegions) {
        let (o, d) = self.pixel_ray(px, py);
        self.ray_at(&o, &d, Some((px, py)), out);
    }

    /// Region codes along a ray that passes through pixel `(px, py)` (any origin on it), with
    /// culling when on; `None`: a ray of no pixel, tested against every body and triangle.
    pub fn ray_at(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        pixel: Option<(f64, f64)>,
        out: &mut RayRegions,
    ) {
        let active = |i: usize| match pixel {
            Some((px, py)) => !self.culling || self.footprints[i].covers(px, py),
            None => true,
        };
        let tris = |i: usize| -> Option<&[u32]> {
            let (px, py) = pixel?;
            if !self.culling {
                return None;
            }
            let b = self.bins[i].as_ref()?;
            let nty = b.lists.len() / b.ntx;
            let tx = ((px / BIN).floor().max(0.0) as usize).min(b.ntx - 1);
            let ty = ((py / BIN).floor().max(0.0) as usize).min(nty - 1);
            Some(&b.lists[ty * b.ntx + tx])
        };
        self.ray_with(o, d, active, tris, out)
    }

    /// Region codes along any ray `o + t d`, `t >= 0`, testing the bodies `active` accepts.
    pub fn ray(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        active: impl Fn(usize) -> bool,
        out: &mut RayRegions,
    ) {
        self.ray_with(o, d, active, |_| None, out)
    }

    fn ray_with<'b>(
        &'b self,
        o: &[f64; 3],
        d: &[f64; 3],
        active: impl Fn(usize) -> bool,
        tris: impl Fn(usize) -> Option<&'b [u32]>,
        out: &mut RayRegions,
    ) {
        out.start = 0;
        out.depths.clear();
        out.codes.clear();
        out.scratch.clear();
        for (i, b) in self.scene.bodies.iter().enumerate() {
            if !active(i) {
                continue;
            }
            out.hits.clear();
            match (&b.shape, tris(i)) {
                (super::Shape::Surface(s), Some(ids)) => {
                    s.crossings_among(o, d, Some(ids), &mut out.hits)
                }
                _ => b.crossings(o, d, &mut out.hits),
            }
            if out.hits.len() % 2 == 1 {
                // An odd number of crossings ahead: the origin is inside.
                out.start |= 1 << i;
            }
            for &t in &out.hits {
                out.scratch.push((t, i as u8));
            }
        }
        out.scratch
            .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut code = out.start;
        for &(t, i) in &out.scratch {
            code ^= 1 << i;
            out.depths.push(t);
            out.codes.push(code);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{parse, Effect};
    use std::path::Path;

    fn cam() -> Camera {
        Camera {
            position: [0.5, 0.5, 5.0],
            focal: [0.5, 0.5, 0.0],
            up: [0.0, 1.0, 0.0],
            view_angle: 30.0,
            parallel: false,
            parallel_scale: 1.0,
        }
    }

    #[test]
    fn crossings_flip_bits_and_the_eye_state_is_right() {
        let s = parse(
            "[[body]]\nshape = \"sphere\"\ncenter = [0.5, 0.5, 0.0]\nradius = 0.5\n\
             [[body]]\nshape = \"box\"\nmin = [-10.0, -10.0, -1.0]\nmax = [10.0, 10.0, 10.0]\n",
            Path::new("t.toml"),
        )
        .unwrap();
        let v = View::new(&s, cam(), 64, 64);
        let mut r = RayRegions::default();
        v.pixel(32.0, 32.0, &mut r);
        // The eye is inside the box (bit 1); the central ray meets the sphere at z = 0.5 and
        // z = -0.5, then leaves the box at z = -1.
        assert_eq!(r.start, 0b10);
        assert_eq!(r.codes, vec![0b11, 0b10, 0b00]);
        assert!((r.depths[0] - 4.5).abs() < 1e-12 && (r.depths[1] - 5.5).abs() < 1e-12);
        assert_eq!(r.code_at(5.0), 0b11);
        let mut pieces = Vec::new();
        r.pieces(4.0, 5.0, |a, b, c| pieces.push((a, b, c)));
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[1].2, 0b11);
        assert_eq!(s.effect(0b11), Effect::Cut);
        // A corner pixel misses the sphere; culling skips it without changing the codes.
        let mut a = RayRegions::default();
        v.pixel(0.5, 0.5, &mut a);
        let mut v2 = View::new(&s, cam(), 64, 64);
        v2.culling = false;
        let mut b = RayRegions::default();
        v2.pixel(0.5, 0.5, &mut b);
        assert_eq!((a.start, &a.codes), (b.start, &b.codes));
        assert!(v.footprints[0].pixel_count(64, 64) < 64 * 64);
        assert_eq!(v.footprints[1].rect, None);
    }
}
