//! The reference ray caster: per pixel, the exact integral of the piecewise-linear field along the
//! ray. Rays enter through boundary faces found with the O(N) grid, walk tet to tet through shared
//! faces, and re-enter through the grid where a non-convex mesh has gaps; an eye inside the mesh
//! starts in the tet the grid locates.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::field::Field;
use super::image::Image;
use super::integrate::ExactTf;
use super::transfer::TransferFunction;
use super::walk::{self, TetPlanes};
use crate::camera::Camera;
use crate::geom::{dot, sub, Aabb};
use crate::locate::{BoundaryIndex, GridParams, TetLocator, Topology, NONE};
use rayon::prelude::*;

/// Zero-length steps in a row after which a walk is taken to be going round slivers that meet
/// where the ray passes (more than any honest vertex or edge crossing takes).
const STALLED: usize = 64;

/// Everything the ray caster reuses between frames.
pub struct RayCaster<'a> {
    pub points: &'a [[f64; 3]],
    pub tets: &'a [[u32; 4]],
    pub field: &'a Field,
    pub topo: &'a Topology,
    pub entry: BoundaryIndex,
    pub locator: TetLocator,
    /// Per-tet barycentric planes and scalars, relative to `reference`.
    planes: Vec<TetPlanes>,
    reference: [f64; 3],
    /// The mesh's bounding-box diagonal: the scale of the re-entry slack.
    diagonal: f64,
}

/// Counts of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayStats {
    pub segments: u64,
    /// Times a ray left the mesh and found another entry further on.
    pub reentries: u64,
    /// Walks stopped because no exit face was found (degenerate tets), resumed through the grid.
    pub lost: u64,
}

impl<'a> RayCaster<'a> {
    pub fn new(
        points: &'a [[f64; 3]],
        tets: &'a [[u32; 4]],
        field: &'a Field,
        topo: &'a Topology,
        params: GridParams,
    ) -> RayCaster<'a> {
        let bounds = Aabb::of_points(points.iter());
        let reference = bounds.center();
        let e = bounds.extent();
        let diagonal = dot(&e, &e).sqrt();
        let ((entry, locator), planes) = rayon::join(
            || {
                rayon::join(
                    || BoundaryIndex::build(points, tets, topo, params),
                    || TetLocator::build(points, tets, params),
                )
            },
            || walk::build(points, tets, field, &reference),
        );
        RayCaster {
            points,
            tets,
            field,
            topo,
            entry,
            locator,
            planes,
            reference,
            diagonal: if diagonal.is_finite() { diagonal } else { 0.0 },
        }
    }

    /// Premultiplied RGBA of one ray from `o` along unit `d`, starting at `t = 0`.
    pub fn trace(
        &self,
        tf: &TransferFunction,
        o: &[f64; 3],
        d: &[f64; 3],
        stats: &mut RayStats,
    ) -> [f64; 4] {
        let ex = ExactTf::new(tf);
        self.trace_with(o, d, stats, |tin, tout, sin, sout| {
            ex.segment(sin, sout, tout - tin)
        })
    }

    /// [`RayCaster::trace`] with each tet's segment `[tin, tout]` (scalar `sin` to `sout`,
    /// linear in between) integrated by `seg` (premultiplied RGB, alpha): a scene splits it at
    /// body crossings.
    pub fn trace_with(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        stats: &mut RayStats,
        mut seg: impl FnMut(f64, f64, f64, f64) -> [f64; 4],
    ) -> [f64; 4] {
        let mut color = [0.0f64; 3];
        let mut trans = 1.0f64;
        // Start inside the mesh when the ray origin is.
        let mut cur: Option<(u32, Option<u8>, f64)> = None;
        if self.locator.grid.bounds().contains(o) {
            if let Some((t, _)) = self.locator.locate(self.points, self.tets, o) {
                cur = Some((t, None, 0.0));
            }
        }
        let mut after = 0.0f64;
        // Faces already used at parameter `after` (so a zero-length walk cannot loop).
        let mut used: Vec<(u32, u8)> = Vec::new();
        let budget = 4 * self.tets.len() + 16;
        let orel = sub(o, &self.reference);
        let mut steps = 0usize;
        'rays: loop {
            let (mut tet, mut face, mut tin) = match cur.take() {
                Some(c) => c,
                None => {
                    // Where the ray left the mesh through a face that another piece's face
                    // covers (pieces merged without welding their points: a .pvtu, an append),
                    // that face's entry is computed another way and may land a few ulps before
                    // the exit: look that far back, or the next piece's first tet is skipped.
                    let slack = if steps > 0 {
                        1e-9 * (after.abs() + self.diagonal)
                    } else {
                        0.0
                    };
                    let hit = self.first_entry(o, d, after - slack, &used);
                    match hit {
                        Some(h) => {
                            if h.t > after {
                                used.clear();
                                after = h.t;
                            }
                            used.push((h.tet, h.face));
                            if steps > 0 {
                                stats.reentries += 1;
                            }
                            (h.tet, Some(h.face), h.t)
                        }
                        None => break,
                    }
                }
            };
            // Steps in a row that did not move along the ray.
            let mut stalled = 0usize;
            loop {
                steps += 1;
                if steps > budget {
                    break 'rays;
                }
                if stalled > STALLED {
                    // Slivers meeting where the ray passes can hand the walk round a cycle of
                    // zero-length steps (a new user's clipped grid: 4 tets round and round until
                    // the step budget ran out, the rest of the ray lost: up to 0.69 off). Step a
                    // hair past the point and carry on in the tet that holds it.
                    let ahead = tin + 1e-9 * (tin.abs() + self.diagonal);
                    let p = [0, 1, 2].map(|k| o[k] + ahead * d[k]);
                    stats.reentries += 1;
                    match self.locator.locate(self.points, self.tets, &p) {
                        Some((t, _)) => {
                            (tet, face, tin) = (t, None, ahead);
                            stalled = 0;
                        }
                        None => {
                            after = after.max(ahead);
                            used.clear();
                            break;
                        }
                    }
                }
                let Some((start, tout, ef, sin, sout)) =
                    self.planes[tet as usize].exit(face, &orel, d, tin)
                else {
                    stats.lost += 1;
                    break;
                };
                stalled = if tout > tin { 0 } else { stalled + 1 };
                let seg = seg(start, tout, sin, sout);
                stats.segments += 1;
                for k in 0..3 {
                    color[k] += trans * seg[k];
                }
                trans *= 1.0 - seg[3];
                if trans < 1e-9 {
                    break 'rays;
                }
                let nb = self.topo.neighbor[tet as usize][ef as usize];
                if nb == NONE {
                    if tout > after {
                        used.clear();
                        after = tout;
                    }
                    // A line leaves a tet once: none of its faces is an entry from here on. Next
                    // to a sliver the grid's slack (above) found another face of the tet just
                    // left, and the walk went from there back into the tet before it, drawing a
                    // chord the ray does not have (a new user's clipped grid: up to 0.69 off).
                    used.extend((0..4).map(|k| (tet, k)));
                    break;
                }
                let back = self.topo.neighbor[nb as usize]
                    .iter()
                    .position(|&x| x == tet)
                    .map(|i| i as u8);
                face = back;
                tet = nb;
                tin = tout;
            }
        }
        [color[0], color[1], color[2], 1.0 - trans]
    }

    fn first_entry(
        &self,
        o: &[f64; 3],
        d: &[f64; 3],
        after: f64,
        used: &[(u32, u8)],
    ) -> Option<crate::locate::Hit> {
        self.entry
            .first_entry(self.points, self.tets, o, d, after, used)
    }

    /// The ray the caster follows through pixel position `(px, py)`: the camera's, except that
    /// parallel rays start behind the mesh's box so nothing in front of the camera is lost.
    pub fn pixel_ray(
        &self,
        cam: &Camera,
        px: f64,
        py: f64,
        width: u32,
        height: u32,
    ) -> ([f64; 3], [f64; 3]) {
        let (mut o, d) = cam.pixel_ray(px, py, width, height);
        if cam.parallel {
            let b = self.entry.grid.bounds();
            let c = b.center();
            let r = 0.5 * dot(&b.extent(), &b.extent()).sqrt() + 1.0;
            let tc = dot(&sub(&c, &o), &d) - 2.0 * r;
            o = [0, 1, 2].map(|k| o[k] + tc * d[k]);
        }
        (o, d)
    }

    /// Renders the camera's view (tiles in parallel; each pixel is independent, so the image does
    /// not depend on the thread count).
    pub fn render(
        &self,
        tf: &TransferFunction,
        cam: &Camera,
        width: u32,
        height: u32,
    ) -> (Image, RayStats) {
        let ex = ExactTf::new(tf);
        self.render_with(&|a, b, l| ex.segment(a, b, l), cam, width, height)
    }

    /// [`Self::render`] with another integration of each segment, e.g. the pre-integration
    /// table's lookup (what VTK's ray caster does): faster, no longer exact.
    pub fn render_with<F: Fn(f64, f64, f64) -> [f64; 4] + Sync>(
        &self,
        segment: &F,
        cam: &Camera,
        width: u32,
        height: u32,
    ) -> (Image, RayStats) {
        let (w, h) = (width as usize, height as usize);
        // Square tiles, not rows: the rays of a tile walk nearly the same tets, and a tile's
        // tets stay in the core's cache where a row's whole slab of the mesh would not.
        const TILE: usize = 16;
        let (tx, ty) = (w.div_ceil(TILE), h.div_ceil(TILE));
        let tiles: Vec<(Vec<[f32; 4]>, RayStats)> = (0..tx * ty)
            .into_par_iter()
            .map(|i| {
                let (x0, y0) = ((i % tx) * TILE, (i / tx) * TILE);
                let mut st = RayStats::default();
                let mut px = Vec::with_capacity(TILE * TILE);
                for y in y0..(y0 + TILE).min(h) {
                    for x in x0..(x0 + TILE).min(w) {
                        let (o, d) =
                            self.pixel_ray(cam, x as f64 + 0.5, y as f64 + 0.5, width, height);
                        let c = self.trace_with(&o, &d, &mut st, |tin, tout, a, b| {
                            segment(a, b, tout - tin)
                        });
                        px.push(c.map(|v| v as f32));
                    }
                }
                (px, st)
            })
            .collect();
        let mut img = Image::new(width, height);
        let mut stats = RayStats::default();
        for (i, (px, st)) in tiles.into_iter().enumerate() {
            let (x0, y0) = ((i % tx) * TILE, (i / tx) * TILE);
            let tw = (x0 + TILE).min(w) - x0;
            for (r, row) in px.chunks(tw).enumerate() {
                let at = (y0 + r) * w + x0;
                img.pixels[at..at + tw].copy_from_slice(row);
            }
            stats.segments += st.segments;
            stats.reentries += st.reentries;
            stats.lost += st.lost;
        }
        (img, stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::cross;
    use crate::locate::barycentric;
    use crate::mesh::generate::{jitter, structured_grid};
    use crate::render::pt::FACES;
    use crate::render::transfer::{named_colormap, OpacitySpec};

    fn tf(range: [f64; 2]) -> TransferFunction {
        TransferFunction::build(
            &named_colormap("viridis").unwrap(),
            Some(&OpacitySpec::parse("0:0.05,0.3:0.6,0.7:0.2,1:0.9").unwrap()),
            range,
            0.7,
            17,
        )
        .unwrap()
    }

    /// Independent reference: clip the ray against every tet's four planes, sort the pieces by
    /// entry, and integrate each with a midpoint sum whose steps attenuate exactly.
    fn brute(
        points: &[[f64; 3]],
        tets: &[[u32; 4]],
        s: &[f64],
        tf: &TransferFunction,
        o: &[f64; 3],
        d: &[f64; 3],
    ) -> [f64; 4] {
        let mut pieces = Vec::new();
        for t in tets {
            let v = t.map(|i| points[i as usize]);
            let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
            for (f, fv) in FACES.iter().enumerate() {
                let a = v[fv[0]];
                let mut n = cross(&sub(&v[fv[1]], &a), &sub(&v[fv[2]], &a));
                if dot(&n, &sub(&v[f], &a)) > 0.0 {
                    n = [-n[0], -n[1], -n[2]];
                }
                // Inside: n.(p - a) <= 0.
                let dn = dot(&n, d);
                let num = dot(&n, &sub(&a, o));
                if dn == 0.0 {
                    if num < 0.0 {
                        t1 = -1.0;
                    }
                } else if dn > 0.0 {
                    t1 = t1.min(num / dn);
                } else {
                    t0 = t0.max(num / dn);
                }
            }
            if t1 > t0 {
                let grad_s = |p: &[f64; 3]| {
                    let b = barycentric(&v, p);
                    (0..4).map(|k| b[k] * s[t[k] as usize]).sum::<f64>()
                };
                pieces.push((
                    t0,
                    t1,
                    grad_s(&[0, 1, 2].map(|k| o[k] + t0 * d[k])),
                    grad_s(&[0, 1, 2].map(|k| o[k] + t1 * d[k])),
                ));
            }
        }
        pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut c, mut tr) = ([0.0f64; 3], 1.0f64);
        for (t0, t1, sf, sb) in pieces {
            let n = 4000;
            let h = (t1 - t0) / n as f64;
            for i in 0..n {
                let u = (i as f64 + 0.5) / n as f64;
                let (rgb, tau) = tf.eval(sf + (sb - sf) * u);
                let a = 1.0 - (-tau * h).exp();
                for k in 0..3 {
                    c[k] += tr * a * rgb[k];
                }
                tr *= 1.0 - a;
            }
        }
        [c[0], c[1], c[2], 1.0 - tr]
    }

    fn check_against_brute(mesh: &crate::mesh::TetMesh, cam: &Camera, n: u32) {
        let s = match mesh.point_data.get("scalar") {
            Some(a) => a.data.to_f64_vec(),
            None => panic!("no scalar"),
        };
        let field = Field::Point(s.clone());
        let topo = Topology::build(&mesh.tets);
        let rc = RayCaster::new(
            &mesh.points,
            &mesh.tets,
            &field,
            &topo,
            GridParams::default(),
        );
        let tf = tf([0.0, 1.0]);
        let mut st = RayStats::default();
        let mut worst = 0.0f64;
        let mut hit = 0;
        for y in 0..n {
            for x in 0..n {
                let (o, d) = cam.pixel_ray(x as f64 + 0.37, y as f64 + 0.61, n, n);
                let a = rc.trace(&tf, &o, &d, &mut st);
                let b = brute(&mesh.points, &mesh.tets, &s, &tf, &o, &d);
                hit += (b[3] > 0.0) as usize;
                for k in 0..4 {
                    worst = worst.max((a[k] - b[k]).abs());
                }
            }
        }
        assert!(
            hit > (n * n / 6) as usize,
            "only {hit} of {} rays hit",
            n * n
        );
        assert!(worst < 1e-5, "ray caster vs brute force: {worst}");
    }

    #[test]
    fn agrees_with_brute_force_on_tiny_meshes() {
        let mut m = structured_grid([2, 2, 1], [0.0; 3], [1.0, 1.0, 0.6]);
        jitter(&mut m, [2, 2, 1], 0.2, 3);
        let mut cam = Camera::default();
        cam.reset_to(&m.bounds());
        cam.azimuth(33.0);
        cam.elevation(21.0);
        cam.zoom(1.8);
        check_against_brute(&m, &cam, 12);

        // Non-convex: a 3x1x1 bar with its middle cube removed from the top half (an L/U), seen
        // so rays leave and re-enter.
        let mut u = structured_grid([3, 1, 2], [0.0; 3], [1.5, 0.5, 1.0]);
        let keep: Vec<usize> = (0..u.tets.len())
            .filter(|&t| {
                let c = [0, 1, 2].map(|k| u.tet_points(t).iter().map(|p| p[k]).sum::<f64>() / 4.0);
                !(c[0] > 0.5 && c[0] < 1.0 && c[2] > 0.5)
            })
            .collect();
        u.tets = keep.iter().map(|&t| u.tets[t]).collect();
        let mut cam = Camera::default();
        cam.reset_to(&u.bounds());
        cam.azimuth(90.0);
        cam.elevation(10.0);
        cam.zoom(1.5);
        check_against_brute(&u, &cam, 12);
        let mut par = cam;
        par.parallel = true;
        check_against_brute(&u, &par, 12);
    }

    #[test]
    fn rays_through_vertices_and_edges_are_not_lost() {
        // A 2x2x2 grid on the unit cube: rays along grid lines (through vertices and edges of
        // many tets, in faces shared by several), along face diagonals through interior
        // vertices, and the main diagonal entering at a corner. Each must walk through (no lost
        // walk, no re-entry) and give what a ray 1e-9 beside it gives (the integral is
        // continuous in the ray), which the brute force checks (the brute force itself would
        // count a ray lying in a shared face once per tet).
        let m = structured_grid([2, 2, 2], [0.0; 3], [1.0; 3]);
        let s = m.point_data.get("scalar").unwrap().data.to_f64_vec();
        let field = Field::Point(s.clone());
        let topo = Topology::build(&m.tets);
        let rc = RayCaster::new(&m.points, &m.tets, &field, &topo, GridParams::default());
        let tf = tf([0.0, 1.0]);
        let r2 = 0.5f64.sqrt();
        let r3 = (1.0f64 / 3.0).sqrt();
        for (o, d) in [
            ([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]),
            ([0.5, -1.0, 0.5], [0.0, 1.0, 0.0]),
            ([0.5, 0.5, 2.0], [0.0, 0.0, -1.0]),
            ([-1.0, 0.0, 0.5], [1.0, 0.0, 0.0]),
            ([-0.5, -0.5, 0.5], [r2, r2, 0.0]),
            ([0.5, -0.5, -0.5], [0.0, r2, r2]),
            ([-1.0, -1.0, -1.0], [r3, r3, r3]),
            ([2.0, 2.0, 2.0], [-r3, -r3, -r3]),
        ] {
            let mut st = RayStats::default();
            let a = rc.trace(&tf, &o, &d, &mut st);
            assert_eq!((st.lost, st.reentries), (0, 0), "{o:?} {d:?}: {st:?}");
            // Beside it, inside the mesh's side of the corner and edge rays.
            let ob = [o[0] + 1.3e-9, o[1] + 0.7e-9, o[2] + 1.1e-9];
            let mut st = RayStats::default();
            let b = rc.trace(&tf, &ob, &d, &mut st);
            let c = brute(&m.points, &m.tets, &s, &tf, &ob, &d);
            assert!(c[3] > 0.1, "{o:?} {d:?} misses the mesh");
            for k in 0..4 {
                assert!((a[k] - b[k]).abs() < 1e-6, "{o:?} {d:?}: {a:?} vs {b:?}");
                assert!((b[k] - c[k]).abs() < 1e-5, "{o:?} {d:?}: {b:?} vs {c:?}");
            }
        }
    }

    #[test]
    fn eye_inside_the_mesh() {
        let m = structured_grid([2, 2, 2], [0.0; 3], [1.0; 3]);
        let cam = Camera {
            position: [0.5, 0.45, 0.4],
            focal: [0.5, 0.45, -1.0],
            ..Camera::default()
        };
        check_against_brute(&m, &cam, 8);
    }
}
