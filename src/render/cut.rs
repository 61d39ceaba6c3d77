//! Scenes in the renderer: each pixel ray's body crossings split every tet's ray segment, and
//! each piece is integrated with the transfer function its region code selects (a cut draws
//! nothing). Only a scene with bodies comes here; without bodies the plain paths run unchanged.
//!
//! Cost follows the scene: a pixel computes crossings only inside some body's screen rectangle
//! (bounding-box culling), a screen tile without such pixels runs the plain rasterizer, and within
//! a tile only tets whose depth range overlaps the tile's crossing depths are split per pixel;
//! the others take one code for the whole tet.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::BTreeMap;

use anyhow::{bail, Result};
use rayon::prelude::*;
use serde::Serialize;

use super::field::Field;
use super::image::Image;
use super::integrate::{exact_segment, Integration};
use super::prepare::{self, TableSize};
use super::pt::{self, Shader, TetSetup, View, OPAQUE, SUB, TILE};
use super::raycast::{RayCaster, RayStats};
use super::transfer::{named_colormap, read_preset, ColorSource, OpacitySpec, TransferFunction};
use crate::camera::Camera;
use crate::geom::{dot, Aabb};
use crate::scene::merge::{merge_scene, Merged};
use crate::scene::ray::{footprint, Footprint, RayRegions, View as SceneView};
use crate::scene::{code_string, Effect, Scene, TransferSpec};

/// A region code's slot when it is cut.
pub const CUT: u16 = u16::MAX;

/// What the default transfer function was built from; a body's transfer function takes what it
/// leaves unset from here.
#[derive(Clone, Debug)]
pub struct BaseLook {
    pub colors: ColorSource,
    pub range: [f64; 2],
    pub unit_distance: f64,
    pub nodes: usize,
}

/// Builds a transfer function from a scene's plain-data spec. Opacity points are in scalar units
/// (the paper's two-level `F(s) = 0.93 if s > T else 0.07` is `[[lo, 0.07], [T, 0.07], [T, 0.93],
/// [hi, 0.93]]`); a step between nodes is as sharp as the node spacing allows.
pub fn build_tf(spec: &TransferSpec, base: &BaseLook) -> Result<TransferFunction> {
    let colors = match (&spec.colormap, &spec.preset) {
        (Some(name), _) => named_colormap(name)?,
        (None, Some(p)) => read_preset(p)?,
        (None, None) => base.colors.clone(),
    };
    let range = spec.range.unwrap_or(base.range);
    let opacity = if spec.opacity.is_empty() {
        None
    } else {
        let span = range[1] - range[0];
        if !(span > 0.0) {
            bail!(
                "scalar range [{}, {}] is empty: opacity points cannot be placed",
                range[0],
                range[1]
            );
        }
        Some(OpacitySpec::Points(
            spec.opacity
                .iter()
                .map(|p| ((p[0] - range[0]) / span, p[1]))
                .collect(),
        ))
    };
    let unit = spec.unit_distance.unwrap_or(base.unit_distance);
    TransferFunction::build(&colors, opacity.as_ref(), range, unit, base.nodes)
}

/// A scene's bodies resolved for rendering: the transfer function of every drawn effect.
pub struct SceneLook<'s> {
    pub scene: &'s Scene,
    /// Distinct transfer functions (the default first): bodies with equal functions share one,
    /// so they share a table and a crossing between them splits nothing.
    tfs: Vec<TransferFunction>,
    /// Per region code: index into `tfs`, or [`CUT`].
    slot: [u16; 256],
    effect: [Effect; 256],
    /// Screen rectangles and depth ranges of the bodies bound where they cost anything.
    pub culling: bool,
}

impl<'s> SceneLook<'s> {
    /// `default_tf` applies where no body's effect does.
    pub fn new(
        scene: &'s Scene,
        default_tf: &TransferFunction,
        base: &BaseLook,
    ) -> Result<SceneLook<'s>> {
        let mut tfs = vec![default_tf.clone()];
        let mut of_effect = BTreeMap::new();
        of_effect.insert(Effect::Default, 0u16);
        for (i, b) in scene.bodies.iter().enumerate() {
            if let crate::scene::Action::Transfer(spec) = &b.action {
                let tf = build_tf(spec, base).map_err(|e| {
                    anyhow::anyhow!(
                        "{}: line {}: body {i} ({}): {e}",
                        scene.file.display(),
                        b.line,
                        b.name
                    )
                })?;
                let k = match tfs.iter().position(|t| *t == tf) {
                    Some(k) => k,
                    None => {
                        tfs.push(tf);
                        tfs.len() - 1
                    }
                };
                of_effect.insert(Effect::Transfer(i), k as u16);
            }
        }
        let effect: [Effect; 256] = std::array::from_fn(|c| scene.effect(c as u8));
        let slot = effect.map(|e| of_effect.get(&e).copied().unwrap_or(CUT));
        Ok(SceneLook {
            scene,
            tfs,
            slot,
            effect,
            culling: true,
        })
    }

    /// The transfer function for a region code; `None`: cut.
    #[inline]
    pub fn tf(&self, code: u8) -> Option<&TransferFunction> {
        self.tfs.get(self.slot[code as usize] as usize)
    }

    /// The index of a code's transfer function among the distinct ones ([`CUT`]: cut).
    #[inline]
    pub fn slot(&self, code: u8) -> u16 {
        self.slot[code as usize]
    }

    pub fn effect(&self, code: u8) -> Effect {
        self.effect[code as usize]
    }

    fn effect_name(&self, e: Effect) -> String {
        match e {
            Effect::Default => "default".into(),
            Effect::Cut => "cut".into(),
            Effect::Transfer(i) => format!("transfer of body {i} ({})", self.scene.bodies[i].name),
        }
    }
}

/// Region codes seen in a frame, before and after merging, for `--json`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RegionReport {
    /// Codes present where the mesh is, body 0 rightmost (the paper's notation).
    pub codes: Vec<String>,
    /// Merged classes: pattern (X = either) and what is drawn there.
    pub classes: Vec<ClassReport>,
    /// Classes that are drawn (cut classes need no pass).
    pub drawn_classes: usize,
    /// Transfer-function tables in use: one per distinct drawn transfer function.
    pub tables: usize,
    /// Pixels whose rays computed body crossings (the rest are outside every body's rectangle).
    pub pixels_with_crossings: u64,
    /// Tet fragments split per pixel at body crossings, and the pieces they gave.
    pub split_fragments: u64,
    pub pieces: u64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ClassReport {
    pub pattern: String,
    pub effect: String,
}

fn report(look: &SceneLook, seen: &[bool; 256], merged: &Merged, tables: usize) -> RegionReport {
    let bits = look.scene.bodies.len();
    let mut classes = Vec::new();
    for (e, cs) in &merged.groups {
        for c in cs {
            classes.push(ClassReport {
                pattern: c.pattern(bits),
                effect: look.effect_name(*e),
            });
        }
    }
    RegionReport {
        codes: (0..256)
            .filter(|&c| seen[c])
            .map(|c| code_string(c as u8, bits))
            .collect(),
        classes,
        drawn_classes: merged.drawn_classes(),
        tables,
        ..RegionReport::default()
    }
}

fn seen_codes(seen: &[bool; 256]) -> Vec<u8> {
    (0..256).filter(|&c| seen[c]).map(|c| c as u8).collect()
}

/// The parameter interval where the line `o + t d` is in the box (`None`: it misses).
fn box_span(b: &Aabb, o: &[f64; 3], d: &[f64; 3]) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < b.min[k] || o[k] > b.max[k] {
                return None;
            }
        } else {
            let a = (b.min[k] - o[k]) / d[k];
            let c = (b.max[k] - o[k]) / d[k];
            t0 = t0.max(a.min(c));
            t1 = t1.min(a.max(c));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// The ray-cast reference with the scene: the same walk as [`RayCaster::render`], each segment
/// split at the pixel ray's body crossings and each piece integrated exactly with its region's
/// transfer function.
pub fn raycast(
    rc: &RayCaster,
    look: &SceneLook,
    cam: &Camera,
    width: u32,
    height: u32,
) -> (Image, RayStats, RegionReport) {
    let mut sv = SceneView::new(look.scene, *cam, width, height);
    sv.culling = look.culling;
    let w = width as usize;
    let mesh_box = rc.entry.grid.bounds();
    let default_tf = look.tf(0);
    type Row = (Vec<[f32; 4]>, RayStats, [bool; 256], u64, u64, u64);
    let rows: Vec<Row> = (0..height as usize)
        .into_par_iter()
        .map(|y| {
            let mut st = RayStats::default();
            let mut seen = [false; 256];
            let (mut traced, mut split, mut pieces) = (0u64, 0u64, 0u64);
            let mut rr = RayRegions::default();
            let py = y as f64 + 0.5;
            let row = (0..w)
                .map(|x| {
                    let px = x as f64 + 0.5;
                    let (o, d) = rc.pixel_ray(cam, px, py, width, height);
                    let Some((ta, tb)) = box_span(&mesh_box, &o, &d) else {
                        return [0.0; 4];
                    };
                    let covered = !sv.culling || sv.footprints.iter().any(|f| f.covers(px, py));
                    if covered {
                        sv.ray_at(&o, &d, Some((px, py)), &mut rr);
                        traced += 1;
                        rr.pieces(ta.max(0.0), tb.max(0.0), |_, _, c| seen[c as usize] = true);
                    } else {
                        seen[0] = true;
                    }
                    let px_rgba = if !covered || rr.is_uniform() {
                        let code = if covered { rr.start } else { 0 };
                        seen[code as usize] = true;
                        match if covered { look.tf(code) } else { default_tf } {
                            Some(tf) => rc.trace(tf, &o, &d, &mut st),
                            None => [0.0; 4],
                        }
                    } else {
                        rc.trace_with(&o, &d, &mut st, |tin, tout, sin, sout| {
                            let len = tout - tin;
                            let s_at = |t: f64| {
                                if len > 0.0 {
                                    sin + (sout - sin) * ((t - tin) / len)
                                } else {
                                    sin
                                }
                            };
                            let (mut c, mut tr) = ([0.0f64; 3], 1.0f64);
                            let mut n = 0u64;
                            let mut piece = |a: f64, b: f64, k: u16| {
                                n += 1;
                                if let Some(tf) = look.tfs.get(k as usize) {
                                    let s = exact_segment(tf, s_at(a), s_at(b), b - a);
                                    for k in 0..3 {
                                        c[k] += tr * s[k];
                                    }
                                    tr *= 1.0 - s[3];
                                }
                            };
                            // Runs of one transfer function are one piece (touching bodies
                            // leave no seam).
                            let mut run: Option<(f64, f64, u16)> = None;
                            rr.pieces(tin, tout, |a, b, code| {
                                let e = look.slot(code);
                                match run {
                                    Some((ra, _, re)) if re == e => run = Some((ra, b, e)),
                                    Some((ra, rb, re)) => {
                                        piece(ra, rb, re);
                                        run = Some((a, b, e));
                                    }
                                    None => run = Some((a, b, e)),
                                }
                            });
                            if let Some((ra, rb, re)) = run {
                                piece(ra, rb, re);
                            }
                            if n > 1 {
                                split += 1;
                                pieces += n;
                            }
                            [c[0], c[1], c[2], 1.0 - tr]
                        })
                    };
                    px_rgba.map(|v| v as f32)
                })
                .collect();
            (row, st, seen, traced, split, pieces)
        })
        .collect();
    let mut img = Image::new(width, height);
    let mut stats = RayStats::default();
    let mut seen = [false; 256];
    let (mut traced, mut split, mut pieces) = (0, 0, 0);
    for (y, (row, st, s, t, sp, pc)) in rows.into_iter().enumerate() {
        img.pixels[y * w..(y + 1) * w].copy_from_slice(&row);
        stats.segments += st.segments;
        stats.reentries += st.reentries;
        stats.lost += st.lost;
        for c in 0..256 {
            seen[c] |= s[c];
        }
        traced += t;
        split += sp;
        pieces += pc;
    }
    let present = seen_codes(&seen);
    let merged = merge_scene(look.scene, &present);
    let mut tables: Vec<u16> = present
        .iter()
        .map(|&c| look.slot(c))
        .filter(|&k| k != CUT)
        .collect();
    tables.sort_unstable();
    tables.dedup();
    let tables = tables.len();
    let mut rep = report(look, &seen, &merged, tables);
    rep.pixels_with_crossings = traced;
    rep.split_fragments = split;
    rep.pieces = pieces;
    (img, stats, rep)
}

/// PT shaders of a scene's distinct transfer functions (by their index in [`SceneLook`]), built
/// when a frame first needs one and reused by every later frame.
pub struct ShaderCache {
    pub mode: Integration,
    pub size: TableSize,
    pub lmax: f64,
    shaders: BTreeMap<u16, Shader>,
    /// Seconds spent building tables.
    pub build_s: f64,
}

impl ShaderCache {
    pub fn new(mode: Integration, size: TableSize, lmax: f64) -> ShaderCache {
        ShaderCache {
            mode,
            size,
            lmax,
            shaders: BTreeMap::new(),
            build_s: 0.0,
        }
    }

    /// Starts with an already built shader of the default transfer function (the plain path's).
    pub fn with_default(mut self, s: Shader) -> ShaderCache {
        self.shaders.insert(0, s);
        self
    }

    /// The default transfer function's shader, once built.
    pub fn default_shader(&self) -> Option<&Shader> {
        self.shaders.get(&0)
    }

    fn ensure(&mut self, look: &SceneLook, k: u16) {
        if self.shaders.contains_key(&k) {
            return;
        }
        if let Some(tf) = look.tfs.get(k as usize) {
            let t = std::time::Instant::now();
            let s = prepare::shader(tf, self.mode, self.size, self.lmax);
            self.build_s += t.elapsed().as_secs_f64();
            self.shaders.insert(k, s);
        }
    }
}

/// Per-pixel body crossings of one screen tile, as view depths.
struct TileRegions {
    start: Vec<u8>,
    off: Vec<u32>,
    z: Vec<f64>,
    codes: Vec<u8>,
    /// Crossing depths of the tile lie in `[zlo, zhi]`.
    zlo: f64,
    zhi: f64,
    /// The code every pixel of the tile starts with, when they agree.
    start_all: Option<u8>,
}

/// Counts of the split rasterizer.
#[derive(Clone, Copy, Debug, Default)]
struct SplitStats {
    fragments: u64,
    split: u64,
    pieces: u64,
}

/// Walks one pixel's segment `[zf, zb]` through its crossings (`depth(i)` and code `cs[i]`,
/// front to back; `start` the code where the ray starts) and calls `emit(a, b, shader)` for
/// each piece that is drawn: pieces run between changes of shader, so a crossing between two
/// codes with the same transfer function splits nothing and touching bodies leave no seam.
/// Returns the number of pieces, cut ones included.
#[inline(always)]
fn pieces<T: Copy + PartialOrd>(
    zf: T,
    zb: T,
    start: u8,
    cs: &[u8],
    depth: impl Fn(usize) -> T,
    slots: &[u16; 256],
    mut emit: impl FnMut(T, T, u16),
) -> u64 {
    let mut i = 0;
    while i < cs.len() && depth(i) <= zf {
        i += 1;
    }
    let code = if i == 0 { start } else { cs[i - 1] };
    let mut cur = slots[code as usize];
    let (mut a, mut n) = (zf, 0u64);
    let mut piece = |a: T, b: T, k: u16| {
        n += 1;
        if k != CUT {
            emit(a, b, k);
        }
    };
    while i < cs.len() && depth(i) < zb {
        let zc = depth(i);
        let next = slots[cs[i] as usize];
        if next != cur {
            if zc > a {
                piece(a, zc, cur);
                a = zc;
            }
            cur = next;
        }
        i += 1;
    }
    piece(a, zb, cur);
    n
}

/// Front-to-back "over" of a premultiplied colour onto a pixel.
#[inline(always)]
fn composite(slot: &mut [f32; 4], c: [f32; 4]) {
    let k = 1.0 - slot[3];
    for ch in 0..4 {
        slot[ch] += k * c[ch];
    }
}

/// Rasterizes one tet, splitting each pixel's fragment at that pixel's crossings; `z0` is the
/// view depth of the tet's vertex 0 (fragment depths are relative to it, in units of `zunit`,
/// the view's [`View::zunit`]).
#[allow(clippy::too_many_arguments)]
fn raster_split(
    t: &TetSetup,
    z0: f64,
    zunit: f64,
    parallel: bool,
    tile: (i64, i64, i64, i64),
    buf: &mut [[f32; 4]],
    stretch: &[f32],
    width: usize,
    reg: &TileRegions,
    slots: &[u16; 256],
    shaders: &[&Shader],
    st: &mut SplitStats,
) -> usize {
    let (tx0, ty0, tx1, _) = tile;
    let Some((x0, x1, y0, y1)) = t.clip(tile) else {
        return 0;
    };
    let tw = (tx1 - tx0 + 1) as usize;
    let mut newly_opaque = 0usize;
    let ne = t.nedges as usize;
    let edges = t.edges();
    for y in y0..=y1 {
        let fy = y * SUB + SUB / 2;
        let fx0 = x0 * SUB + SUB / 2;
        let mut e = [0i64; 4];
        for (ek, ed) in e.iter_mut().zip(&edges[..ne]) {
            *ek = ed.a * fx0 + ed.b * fy + ed.c + ed.bias;
        }
        let row = (y - ty0) as usize * tw;
        for x in x0..=x1 {
            let mut inside = true;
            for (ek, ed) in e.iter_mut().zip(&edges[..ne]) {
                inside &= *ek >= 0;
                *ek += ed.a * SUB;
            }
            if !inside {
                continue;
            }
            let p = row + (x - tx0) as usize;
            let slot = &mut buf[p];
            if slot[3] >= OPAQUE {
                continue;
            }
            let (zf, zb, sref, h) = pt::fragment_span(t, parallel, x, y);
            if !(zb > zf) || !zf.is_finite() || !zb.is_finite() {
                continue;
            }
            st.fragments += 1;
            let stl = stretch[y as usize * width + x as usize];
            let (lo, hi) = (reg.off[p] as usize, reg.off[p + 1] as usize);
            let zs = &reg.z[lo..hi];
            let cs = &reg.codes[lo..hi];
            let n = pieces(
                zf,
                zb,
                reg.start[p],
                cs,
                // In the rasterizer's depth unit, as `zf` and `zb` are (exact: a power of two).
                |i| ((zs[i] - z0) / zunit) as f32,
                slots,
                |a, b, k| {
                    let sa = (sref + a * h).clamp(t.smin, t.smax);
                    let sb = (sref + b * h).clamp(t.smin, t.smax);
                    composite(slot, shaders[k as usize].shade(sa, sb, (b - a) * stl));
                },
            );
            if n > 1 {
                st.split += 1;
                st.pieces += n;
            }
            if slot[3] >= OPAQUE {
                newly_opaque += 1;
            }
        }
    }
    newly_opaque
}

/// The per-pixel clipping path (a tet with a vertex behind the eye, or beyond the guard band)
/// with each pixel's ray segment split at its body crossings, as [`raster_split`] does for
/// rasterized tets: newly opaque pixels (fragments go to `st`).
#[allow(clippy::too_many_arguments)]
fn clip_split(
    c: &pt::ClipSetup,
    view: &View,
    b: pt::PixelBox,
    tile: pt::Tile,
    buf: &mut [[f32; 4]],
    reg: &TileRegions,
    slots: &[u16; 256],
    shaders: &[&Shader],
    st: &mut SplitStats,
) -> (u64, usize) {
    let (tx0, ty0, tx1, _) = tile;
    let tw = (tx1 - tx0 + 1) as usize;
    let (mut frags, mut newly) = (0u64, 0usize);
    for y in tile.1.max(b.1)..=tile.3.min(b.3) {
        for x in tile.0.max(b.0)..=tile.2.min(b.2) {
            let p = (y - ty0) as usize * tw + (x - tx0) as usize;
            let slot = &mut buf[p];
            if slot[3] >= OPAQUE {
                continue;
            }
            let (ra, rb, zmin) = pt::pixel_ray(view, x, y);
            let Some((zf, zb)) = c.span((x, y), ra, rb, zmin) else {
                continue;
            };
            frags += 1;
            let len = dot(&rb, &rb).sqrt();
            let (lo, hi) = (reg.off[p] as usize, reg.off[p + 1] as usize);
            let (zs, cs) = (&reg.z[lo..hi], &reg.codes[lo..hi]);
            let n = pieces(
                zf,
                zb,
                reg.start[p],
                cs,
                |i| zs[i],
                slots,
                |a, z, k| {
                    let (sa, sb) = (c.scalar(ra, rb, a), c.scalar(ra, rb, z));
                    let l = ((z - a) * len) as f32;
                    composite(slot, shaders[k as usize].shade(sa as f32, sb as f32, l));
                },
            );
            if n > 1 {
                st.split += 1;
                st.pieces += n;
            }
            if slot[3] >= OPAQUE {
                newly += 1;
            }
        }
    }
    // Counted in the split stats, as raster_split's fragments are.
    st.fragments += frags;
    (0, newly)
}

/// Projected tetrahedra with the scene: crossings per pixel (inside body rectangles only), the
/// codes present merged into classes, a table per drawn transfer function (cached), then the
/// tiles rasterized in the global order with each fragment split where its pixel's ray crosses a
/// body.
#[allow(clippy::too_many_arguments)]
pub fn pt_render(
    view: &View,
    cam: &Camera,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    field: &Field,
    order: &[u32],
    look: &SceneLook,
    cache: &mut ShaderCache,
) -> (Image, pt::PtStats, RegionReport) {
    let proj = pt::project_points(view, points);
    let (w, h) = (view.width as usize, view.height as usize);
    let stretch = pt::stretch_map(view);
    let mut sv = SceneView::new(look.scene, *cam, view.width, view.height);
    sv.culling = look.culling;
    let mesh_box = Aabb::of_points(points.iter());
    let mesh_fp: Footprint = footprint(&mesh_box, cam, view.width, view.height);
    let (mz0, mz1, back) = mesh_depths(view, &mesh_box);
    let fwd = view.f;
    let (ntx, nty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let ntiles = ntx * nty;

    // Crossings per tile, and the codes present where the mesh is.
    let regions: Vec<TileOut> = (0..ntiles)
        .into_par_iter()
        .map(|ti| {
            let (tx, ty) = (ti % ntx, ti / ntx);
            let (px0, py0) = (tx * TILE, ty * TILE);
            let (px1, py1) = (((tx + 1) * TILE).min(w), ((ty + 1) * TILE).min(h));
            let mut seen = [false; 256];
            let touches = |f: &Footprint| match f.rect {
                None => true,
                Some(r) => {
                    r[0] <= px1 as f64 - 0.5
                        && r[2] >= px0 as f64 + 0.5
                        && r[1] <= py1 as f64 - 0.5
                        && r[3] >= py0 as f64 + 0.5
                }
            };
            let mesh_here = touches(&mesh_fp);
            if sv.culling && !sv.footprints.iter().any(touches) {
                seen[0] = mesh_here;
                return (None, seen, 0);
            }
            let npix = (px1 - px0) * (py1 - py0);
            let mut reg = TileRegions {
                start: vec![0; npix],
                off: Vec::with_capacity(npix + 1),
                z: Vec::new(),
                codes: Vec::new(),
                zlo: f64::INFINITY,
                zhi: f64::NEG_INFINITY,
                start_all: None,
            };
            reg.off.push(0);
            let mut rr = RayRegions::default();
            let mut traced = 0u64;
            for y in py0..py1 {
                for x in px0..px1 {
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    let p = (y - py0) * (px1 - px0) + (x - px0);
                    if sv.culling && !sv.footprints.iter().any(|f| f.covers(px, py)) {
                        if mesh_fp.covers(px, py) {
                            seen[0] = true;
                        }
                        reg.off.push(reg.z.len() as u32);
                        continue;
                    }
                    traced += 1;
                    let (mut o, d) = sv.pixel_ray(px, py);
                    if back > 0.0 {
                        o = [0, 1, 2].map(|k| o[k] - back * d[k]);
                    }
                    sv.ray_at(&o, &d, Some((px, py)), &mut rr);
                    // View depth of o + t d.
                    let dz = dot(&d, &fwd);
                    let oz = view.to_view(&o)[2];
                    reg.start[p] = rr.start;
                    if mesh_fp.covers(px, py) {
                        let (t0, t1) = ((mz0 - oz) / dz, (mz1 - oz) / dz);
                        rr.pieces(t0.max(0.0), t1.max(0.0), |_, _, c| seen[c as usize] = true);
                    }
                    for (&t, &c) in rr.depths.iter().zip(&rr.codes) {
                        let z = oz + t * dz;
                        reg.zlo = reg.zlo.min(z);
                        reg.zhi = reg.zhi.max(z);
                        reg.z.push(z);
                        reg.codes.push(c);
                    }
                    reg.off.push(reg.z.len() as u32);
                }
            }
            let s0 = reg.start[0];
            reg.start_all = reg.start.iter().all(|&s| s == s0).then_some(s0);
            (Some(reg), seen, traced)
        })
        .collect();
    let mut seen = [false; 256];
    let mut traced = 0;
    for (_, s, t) in &regions {
        for c in 0..256 {
            seen[c] |= s[c];
        }
        traced += t;
    }
    // Nothing of the mesh on screen: still give the default class a shader.
    if !seen.iter().any(|&s| s) {
        seen[0] = true;
    }
    let present = seen_codes(&seen);
    let merged = merge_scene(look.scene, &present);
    // Tables for the transfer functions of the codes present only.
    let mut need: Vec<u16> = present
        .iter()
        .map(|&c| look.slot(c))
        .filter(|&k| k != CUT)
        .collect();
    need.sort_unstable();
    need.dedup();
    let tables = need.len();
    for &k in &need {
        cache.ensure(look, k);
    }
    // Code -> index into `shader_list`, or cut. A code outside the census (not where the mesh
    // is, so no fragment can carry it) has no table and is not drawn.
    let shader_list: Vec<&Shader> = need.iter().filter_map(|k| cache.shaders.get(k)).collect();
    let mut slots = [CUT; 256];
    for (c, s) in slots.iter_mut().enumerate() {
        let k = look.slot(c as u8);
        if let Some(i) = need.iter().position(|&x| x == k) {
            *s = i as u16;
        }
    }
    let mut rep = report(look, &seen, &merged, tables);
    rep.pixels_with_crossings = traced;

    // The plain path's tiles: tets set up once and binned in the global order; each tile then
    // draws a tet with one code where its depths miss the tile's crossings, else split per pixel.
    let frame = pt::Frame {
        view,
        tets,
        field,
        proj: &proj,
        stretch: &stretch,
    };
    let drawer = SceneDraw {
        frame: &frame,
        regions: &regions,
        slots: &slots,
        shaders: &shader_list,
    };
    let (img, mut stats, _, tiles) = pt::render_tiles(&frame, order, &drawer);
    for sst in &tiles {
        stats.fragments += sst.fragments;
        rep.split_fragments += sst.split;
        rep.pieces += sst.pieces;
    }
    (img, stats, rep)
}

/// Body crossings per tile, the codes the tile's pixels see, pixels traced.
type TileOut = (Option<TileRegions>, [bool; 256], u64);

/// How a scene's tiles draw a tet.
struct SceneDraw<'a> {
    frame: &'a pt::Frame<'a>,
    regions: &'a [TileOut],
    /// Region code -> index into `shaders`, or [`CUT`].
    slots: &'a [u16; 256],
    shaders: &'a [&'a Shader],
}

impl pt::TileDraw for SceneDraw<'_> {
    type State = SplitStats;

    #[inline(always)]
    fn draw(
        &self,
        sst: &mut SplitStats,
        ti: usize,
        run: &pt::Run,
        k: usize,
        tile: pt::Tile,
        buf: &mut [[f32; 4]],
    ) -> (u64, usize) {
        let f = self.frame;
        let pv = f.tets[run.tets[k] as usize].map(|v| &f.proj[v as usize]);
        let reg = self.regions[ti].0.as_ref();
        // One code for the whole tet when its depths miss the tile's crossings.
        let uniform = match reg {
            None => Some(0u8),
            Some(r) => {
                let zmin = pv.iter().map(|q| q.view[2]).fold(f64::INFINITY, f64::min);
                let zmax = pv
                    .iter()
                    .map(|q| q.view[2])
                    .fold(f64::NEG_INFINITY, f64::max);
                if zmin > r.zhi {
                    Some(0)
                } else if zmax < r.zlo {
                    r.start_all
                } else {
                    None
                }
            }
        };
        match (uniform, reg, &f.kind(run, k)) {
            (Some(c), _, kind) => match self.shaders.get(self.slots[c as usize] as usize) {
                Some(sh) => f.draw(kind, tile, buf, sh),
                None => (0, 0),
            },
            (None, Some(r), pt::PrepKind::Tet(setup)) => {
                let o = raster_split(
                    setup,
                    pv[0].view[2],
                    f.view.zunit,
                    f.view.parallel,
                    tile,
                    buf,
                    f.stretch,
                    f.view.width as usize,
                    r,
                    self.slots,
                    self.shaders,
                    sst,
                );
                (0, o)
            }
            (None, Some(r), pt::PrepKind::Clipped(c, b)) => {
                clip_split(c, f.view, *b, tile, buf, r, self.slots, self.shaders, sst)
            }
            // A tile without crossings is always uniform (code 0).
            (None, None, _) => (0, 0),
        }
    }
}

/// The depth range of the mesh's box along the view direction, and how far parallel rays start
/// behind the camera plane so they begin behind everything PT draws (it draws behind the camera
/// plane too); 0 in perspective or when the box is in front.
pub(crate) fn mesh_depths(view: &View, mesh_box: &Aabb) -> (f64, f64, f64) {
    let (mut mz0, mut mz1) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..8 {
        let c = [0, 1, 2].map(|k| {
            if i >> k & 1 == 0 {
                mesh_box.min[k]
            } else {
                mesh_box.max[k]
            }
        });
        let z = view.to_view(&c)[2];
        mz0 = mz0.min(z);
        mz1 = mz1.max(z);
    }
    let back = if view.parallel && mz0 < 0.0 {
        -mz0 + 1.0
    } else {
        0.0
    };
    (mz0, mz1, back)
}
