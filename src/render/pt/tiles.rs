//! The tile schedule: every tet set up once and binned per screen tile in the global order, then
//! the tiles drawn in parallel, each walking its tets front to back until all its pixels are opaque.

use rayon::prelude::*;

use super::clip::{clip_box, ClipSetup};
use super::setup::{setup_tet, Prepared, TetSetup};
use super::shade::Shader;
use super::{huge_pages, prefetch, PixelBox, Projected, PtStats, View, TILE};
use crate::render::field::Field;
use crate::render::image::Image;

/// A screen tile's pixel box (x0, y0, x1, y1), inclusive.
pub(crate) type Tile = (i64, i64, i64, i64);

/// What setting up and drawing the tets of one frame read.
pub(crate) struct Frame<'a> {
    pub(crate) view: &'a View,
    pub(crate) tets: &'a [[u32; 4]],
    pub(crate) field: &'a Field,
    pub(crate) proj: &'a [Projected],
    /// Per pixel: world length of the view ray per unit of depth.
    pub(crate) stretch: &'a [f32],
}

/// What a tile draws a set-up tet from.
pub(crate) enum PrepKind<'a> {
    Tet(TetSetup),
    /// Drawn by the per-pixel clipping path, over its pixel box.
    Clipped(&'a ClipSetup, PixelBox),
}

/// A tet of one frame, set up once for all the tiles it touches.
pub(crate) enum Prep {
    Tet(Prepared),
    Clipped(ClipSetup, PixelBox),
}

impl Frame<'_> {
    /// Tet `t`'s projected vertices and field values.
    #[inline(always)]
    fn vertices(&self, t: u32) -> ([&Projected; 4], [f64; 4]) {
        let tet = &self.tets[t as usize];
        let pr = self.proj;
        let pv = [
            &pr[tet[0] as usize],
            &pr[tet[1] as usize],
            &pr[tet[2] as usize],
            &pr[tet[3] as usize],
        ];
        (pv, self.field.at(t as usize, tet))
    }

    /// The clipping path's set-up and pixel box of a tet the rasterizer cannot take.
    #[inline(always)]
    fn clip(&self, pv: [&Projected; 4], s: [f64; 4]) -> Option<(ClipSetup, PixelBox)> {
        let (w, h) = (self.view.width as usize, self.view.height as usize);
        let c = ClipSetup::new(pv, s)?;
        let b = clip_box(self.view, &pv, w, h)?;
        Some((c, b))
    }

    /// Sets up tet `t` (counting its class): what its tiles draw and its pixel box.
    #[inline(always)]
    pub(crate) fn prepare(&self, t: u32, st: &mut PtStats) -> Option<(Prep, PixelBox)> {
        let (pv, s) = self.vertices(t);
        if pv.iter().any(|p| !p.ok) {
            st.clipped += 1;
            let (c, b) = self.clip(pv, s)?;
            Some((Prep::Clipped(c, b), b))
        } else {
            let mut rec = Prepared::clipped(0);
            let b = setup_tet(self.view, &pv, s, st, &mut rec)?;
            Some((Prep::Tet(rec), b))
        }
    }

    /// [`Frame::prepare`] straight into `run`: pushes tet `t`'s record (and its clipping
    /// set-up) and returns its pixel box, or `None` with nothing pushed when it draws nothing.
    #[inline(always)]
    fn prepare_into(&self, t: u32, run: &mut Run) -> Option<PixelBox> {
        let (pv, s) = self.vertices(t);
        if pv.iter().any(|p| !p.ok) {
            run.stats.clipped += 1;
            let (c, b) = self.clip(pv, s)?;
            run.recs.push(Prepared::clipped(run.clipped.len() as u32));
            run.clipped.push((c, b));
            return Some(b);
        }
        // A placeholder the set-up overwrites in place (`recs` has room for the whole run).
        run.recs.push(Prepared::clipped(0));
        let n = run.recs.len();
        let b = setup_tet(self.view, &pv, s, &mut run.stats, &mut run.recs[n - 1]);
        if b.is_none() {
            run.recs.pop();
        }
        b
    }

    /// What record `k` of `run` is drawn from.
    #[inline(always)]
    pub(crate) fn kind<'a>(&self, run: &'a Run, k: usize) -> PrepKind<'a> {
        let p = &run.recs[k];
        match p.clip_index() {
            None => PrepKind::Tet(p.setup(self.view.width as i64, self.view.height as i64)),
            Some(i) => {
                let (c, b) = &run.clipped[i];
                PrepKind::Clipped(c, *b)
            }
        }
    }

    /// Draws a set-up tet with one shader into `buf` covering `tile`: fragments and newly
    /// opaque pixels.
    #[inline(always)]
    pub(crate) fn draw(
        &self,
        p: &PrepKind,
        tile: Tile,
        buf: &mut [[f32; 4]],
        shader: &Shader,
    ) -> (u64, usize) {
        match p {
            PrepKind::Tet(su) => shader.draw(
                su,
                self.view.parallel,
                tile,
                buf,
                self.stretch,
                self.view.width as usize,
            ),
            PrepKind::Clipped(c, b) => c.draw(self.view, *b, tile, buf, shader),
        }
    }

    /// [`Frame::draw`] of a tet as [`Frame::prepare`] gave it.
    #[inline(always)]
    pub(crate) fn draw_prep(
        &self,
        p: &Prep,
        tile: Tile,
        buf: &mut [[f32; 4]],
        shader: &Shader,
    ) -> (u64, usize) {
        let kind = match p {
            Prep::Tet(r) => PrepKind::Tet(r.setup(self.view.width as i64, self.view.height as i64)),
            Prep::Clipped(c, b) => PrepKind::Clipped(c, *b),
        };
        self.draw(&kind, tile, buf, shader)
    }
}

/// How the tiles draw a prepared tet: one shader for the plain path, the scene's per-pixel body
/// crossings for scenes.
pub(crate) trait TileDraw: Sync {
    /// What a tile counts besides fragments.
    type State: Default + Send;
    /// Draws record `k` of `run` into `buf` covering tile `ti` (pixel box `tile`): fragments
    /// and newly opaque pixels.
    fn draw(
        &self,
        state: &mut Self::State,
        ti: usize,
        run: &Run,
        k: usize,
        tile: Tile,
        buf: &mut [[f32; 4]],
    ) -> (u64, usize);
}

/// The plain path: every tet with one shader.
pub(crate) struct PlainDraw<'a> {
    pub(crate) frame: &'a Frame<'a>,
    pub(crate) shader: &'a Shader,
}

impl TileDraw for PlainDraw<'_> {
    type State = ();
    #[inline(always)]
    fn draw(
        &self,
        _: &mut (),
        _: usize,
        run: &Run,
        k: usize,
        tile: Tile,
        buf: &mut [[f32; 4]],
    ) -> (u64, usize) {
        let f = self.frame;
        let p = &run.recs[k];
        match p.clip_index() {
            // The set-up is built where the rasterizer reads it: wrapped in a [`PrepKind`] it
            // would be built once and copied.
            None => {
                let su = p.setup(f.view.width as i64, f.view.height as i64);
                self.shader.draw(
                    &su,
                    f.view.parallel,
                    tile,
                    buf,
                    f.stretch,
                    f.view.width as usize,
                )
            }
            Some(i) => {
                let (c, b) = &run.clipped[i];
                c.draw(f.view, *b, tile, buf, self.shader)
            }
        }
    }
}

/// A run of the order set up and binned per tile.
pub(crate) struct Run {
    /// The drawn tets' records, in the order.
    recs: Vec<Prepared>,
    /// Mesh index of each record's tet.
    pub(crate) tets: Vec<u32>,
    /// The tets the clipping path draws, and their pixel boxes.
    clipped: Vec<(ClipSetup, PixelBox)>,
    /// Per tile, its records in order.
    lists: Vec<Vec<u32>>,
    stats: PtStats,
}

impl Run {
    /// An empty run with room for `cap` tets over `ntiles` tiles.
    fn new(cap: usize, ntiles: usize) -> Run {
        let mut run = Run {
            recs: Vec::with_capacity(cap),
            tets: Vec::with_capacity(cap),
            clipped: Vec::new(),
            lists: vec![Vec::new(); ntiles],
            stats: PtStats::default(),
        };
        huge_pages(&mut run.recs);
        run
    }
}

/// How many entries ahead the loops below ask for the memory they will read: far enough for a
/// miss to arrive, near enough that the line is not evicted first (2 to 8 measured alike).
const AHEAD: usize = 4;

/// Sets up a run of the order and bins it per tile (`ntx` tiles a row) into `run`, replacing
/// what it held but keeping its buffers.
#[inline(always)]
fn bin(frame: &Frame, chunk: &[u32], ntx: usize, run: &mut Run) {
    run.recs.clear();
    run.tets.clear();
    run.clipped.clear();
    for l in &mut run.lists {
        l.clear();
    }
    run.stats = PtStats::default();
    let (tets, proj) = (frame.tets, frame.proj);
    for (i, &t) in chunk.iter().enumerate() {
        // The order visits the mesh's arrays out of their order: ask for the tet ahead, then
        // for the points of the one after it, which the tet's line has brought by then.
        if let Some(&u) = chunk.get(i + 4 * AHEAD) {
            prefetch(tets.as_ptr().wrapping_add(u as usize));
        }
        if let Some(tet) = chunk.get(i + 2 * AHEAD).and_then(|&u| tets.get(u as usize)) {
            for &v in tet {
                prefetch(proj.as_ptr().wrapping_add(v as usize));
                if let Field::Point(s) = frame.field {
                    prefetch(s.as_ptr().wrapping_add(v as usize));
                }
            }
        }
        let Some((x0, y0, x1, y1)) = frame.prepare_into(t, run) else {
            continue;
        };
        let k = run.tets.len() as u32;
        run.tets.push(t);
        for ty in (y0 as usize / TILE)..=(y1 as usize / TILE) {
            for tx in (x0 as usize / TILE)..=(x1 as usize / TILE) {
                run.lists[ty * ntx + tx].push(k);
            }
        }
    }
}

/// [`bin`] compiled for AVX2 (bit for bit the same, as [`draw_tile_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bin_avx2(frame: &Frame, chunk: &[u32], ntx: usize, run: &mut Run) {
    bin(frame, chunk, ntx, run)
}

/// [`bin`] with the widest instruction set the CPU has.
fn bin_best(frame: &Frame, chunk: &[u32], ntx: usize, run: &mut Run) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { bin_avx2(frame, chunk, ntx, run) };
    }
    bin(frame, chunk, ntx, run)
}

/// A tile being drawn across the waves of a frame.
struct TileAcc<S> {
    /// Pixel box (x0, y0, x1, y1), inclusive.
    tile: Tile,
    buf: Vec<[f32; 4]>,
    frags: u64,
    opaque: usize,
    state: S,
    /// Every pixel opaque: later tets are not drawn.
    done: bool,
}

/// Draws the lists of tile `ti` in the binned runs, in order, onto what the tile holds.
#[inline(always)]
fn draw_tile<D: TileDraw>(d: &D, runs: &[Run], ti: usize, acc: &mut TileAcc<D::State>) {
    let npix = acc.buf.len();
    let (tile, buf, state) = (acc.tile, &mut acc.buf[..], &mut acc.state);
    let (mut frags, mut opaque) = (acc.frags, acc.opaque);
    'outer: for run in runs {
        let list = &run.lists[ti];
        for (i, &k) in list.iter().enumerate() {
            // Each tile skips through the records: ask for the one a few entries ahead.
            if let Some(&n) = list.get(i + AHEAD) {
                let p = run.recs.as_ptr().wrapping_add(n as usize);
                prefetch(p);
                prefetch(p.cast::<u8>().wrapping_add(64));
            }
            let (f, o) = d.draw(state, ti, run, k as usize, tile, buf);
            frags += f;
            opaque += o;
            if opaque == npix {
                acc.done = true;
                break 'outer;
            }
        }
    }
    (acc.frags, acc.opaque) = (frags, opaque);
}

/// [`draw_tile`] compiled for AVX2: the per-pixel lanes vectorize far better than with the
/// baseline SSE2. No fused multiply-add is enabled, so the image is bit for bit the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn draw_tile_avx2<D: TileDraw>(d: &D, runs: &[Run], ti: usize, acc: &mut TileAcc<D::State>) {
    draw_tile(d, runs, ti, acc)
}

/// [`draw_tile`] compiled for AVX-512 (F and VL): the same 8-lane code, but with 32 vector
/// registers the lanes spill far less. Still no fused multiply-add: the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512vl")]
unsafe fn draw_tile_avx512<D: TileDraw>(
    d: &D,
    runs: &[Run],
    ti: usize,
    acc: &mut TileAcc<D::State>,
) {
    draw_tile(d, runs, ti, acc)
}

/// [`draw_tile`] with the widest instruction set the CPU has.
fn draw_tile_best<D: TileDraw>(d: &D, runs: &[Run], ti: usize, acc: &mut TileAcc<D::State>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512vl")
    {
        // SAFETY: the CPU has AVX-512F and VL (and so AVX2), checked just above.
        return unsafe { draw_tile_avx512(d, runs, ti, acc) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { draw_tile_avx2(d, runs, ti, acc) };
    }
    draw_tile(d, runs, ti, acc)
}

/// Tets set up per run of the order.
const CHUNK: usize = 1 << 14;
/// Runs per wave: a wave's records (128 bytes a tet, 8 MiB) stay in the last-level cache
/// between binning and drawing, where a whole frame's (128 MiB at a million tets) would be
/// written out to memory and read back by every tile.
const WAVE: usize = 4;

/// The tile schedule, in waves of [`WAVE`] runs of [`CHUNK`] consecutive tets of the order:
/// each wave's runs set up and binned in parallel (each keeping its tets in order, each tet set
/// up once however many tiles it touches), then the tiles drawn in parallel with `d` from those
/// runs, each carrying on from the earlier waves. A tile that walks the runs in turn sees the
/// global order, so neither the waves nor the runs change the image. Returns the image, counts,
/// seconds spent setting up and binning, and each tile's state.
pub(crate) fn render_tiles<D: TileDraw>(
    frame: &Frame,
    order: &[u32],
    d: &D,
) -> (Image, PtStats, f64, Vec<D::State>) {
    let (w, h) = (frame.view.width as usize, frame.view.height as usize);
    let (ntx, nty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let ntiles = ntx * nty;
    let mut tiles: Vec<TileAcc<D::State>> = (0..ntiles)
        .map(|ti| {
            let (tx, ty) = (ti % ntx, ti / ntx);
            let (px0, py0) = (tx * TILE, ty * TILE);
            let (px1, py1) = (((tx + 1) * TILE).min(w), ((ty + 1) * TILE).min(h));
            TileAcc {
                tile: (px0 as i64, py0 as i64, px1 as i64 - 1, py1 as i64 - 1),
                buf: vec![[0f32; 4]; (px1 - px0) * (py1 - py0)],
                frags: 0,
                opaque: 0,
                state: D::State::default(),
                done: false,
            }
        })
        .collect();
    let nruns = order.len().div_ceil(CHUNK).clamp(1, WAVE);
    let mut runs: Vec<Run> = (0..nruns)
        .into_par_iter()
        .map(|_| Run::new(CHUNK, ntiles))
        .collect();
    let mut stats = PtStats::default();
    let mut bin_s = 0.0;
    for wave in order.chunks(CHUNK * WAVE) {
        let t0 = std::time::Instant::now();
        let used = wave.len().div_ceil(CHUNK);
        runs[..used]
            .par_iter_mut()
            .zip(wave.par_chunks(CHUNK))
            .for_each(|(run, chunk)| bin_best(frame, chunk, ntx, run));
        for run in &runs[..used] {
            stats.add(&run.stats);
        }
        bin_s += t0.elapsed().as_secs_f64();
        let runs = &runs[..used];
        tiles
            .par_iter_mut()
            .enumerate()
            .filter(|(ti, acc)| !acc.done && runs.iter().any(|r| !r.lists[*ti].is_empty()))
            .for_each(|(ti, acc)| draw_tile_best(d, runs, ti, acc));
    }
    let mut img = Image::new(frame.view.width, frame.view.height);
    let mut states = Vec::with_capacity(ntiles);
    for acc in tiles {
        stats.fragments += acc.frags;
        states.push(acc.state);
        let (px0, py0, px1, _) = acc.tile;
        let (px0, py0) = (px0 as usize, py0 as usize);
        let tw = px1 as usize + 1 - px0;
        for (r, row) in acc.buf.chunks(tw).enumerate() {
            let y = py0 + r;
            img.pixels[y * w + px0..y * w + px0 + tw].copy_from_slice(row);
        }
    }
    (img, stats, bin_s, states)
}
