//! The tile schedule: every tet set up once and binned per screen tile in the global order, then
//! the tiles drawn in parallel, each walking its tets front to back until all its pixels are opaque.

use rayon::prelude::*;

use super::clip::{clip_box, ClipSetup};
use super::setup::{scalar_range, setup_tet, setup_tet_unless, Prepared, SetUp, TetSetup};
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

    /// The clipping path's set-up and pixel box of a tet the rasterizer cannot take; with
    /// `exact`, of a tet a face of which is seen nearly edge-on (`SetUp::PerPixel`), whose
    /// pixels its exact silhouette decides. Out of line: few tets come here.
    #[inline(never)]
    fn clip(&self, pv: [&Projected; 4], s: [f64; 4], exact: bool) -> Option<(ClipSetup, PixelBox)> {
        let (w, h) = (self.view.width as usize, self.view.height as usize);
        let c = if exact {
            ClipSetup::exact(pv, s)?
        } else {
            ClipSetup::new(pv, s)?
        };
        let b = clip_box(self.view, &pv, w, h)?;
        Some((c, b))
    }

    /// Sets up tet `t` (counting its class): what its tiles draw and its pixel box.
    #[inline(always)]
    pub(crate) fn prepare(&self, t: u32, st: &mut PtStats) -> Option<(Prep, PixelBox)> {
        let (pv, s) = self.vertices(t);
        if pv.iter().any(|p| !p.ok) {
            st.clipped += 1;
            let (c, b) = self.clip(pv, s, false)?;
            return Some((Prep::Clipped(c, b), b));
        }
        let mut rec = Prepared::clipped(0);
        match setup_tet(self.view, &pv, s, st, &mut rec)? {
            SetUp::Raster(b) => Some((Prep::Tet(rec), b)),
            SetUp::PerPixel => {
                st.per_pixel += 1;
                let (c, b) = self.clip(pv, s, true)?;
                Some((Prep::Clipped(c, b), b))
            }
        }
    }

    /// [`Frame::prepare`] straight into `run`: pushes tet `t`'s record (and its clipping
    /// set-up) and returns its pixel box, or `None` with nothing pushed when it draws nothing,
    /// or when every pixel it could cover is already `opaque`.
    #[inline(always)]
    fn prepare_into<D: TileDraw>(
        &self,
        t: u32,
        run: &mut Run,
        opaque: &Opaque,
        d: &D,
    ) -> Option<PixelBox> {
        let (pv, s) = self.vertices(t);
        let range = scalar_range(&s);
        if d.draws_nothing(range.0, range.1) {
            run.stats.clear += 1;
            return None;
        }
        if pv.iter().any(|p| !p.ok) {
            run.stats.clipped += 1;
            let (c, b) = self.clip(pv, s, false)?;
            run.recs.push(Prepared::clipped(run.clipped.len() as u32));
            run.clipped.push((c, b));
            return Some(b);
        }
        // A placeholder the set-up overwrites in place (`recs` has room for the whole run).
        run.recs.push(Prepared::clipped(0));
        let n = run.recs.len();
        let b = setup_tet_unless(
            self.view,
            &pv,
            s,
            range,
            &mut run.stats,
            &mut run.recs[n - 1],
            |b| opaque.hides(b),
        );
        match b {
            Some(SetUp::Raster(b)) => Some(b),
            Some(SetUp::PerPixel) => {
                run.recs.pop();
                run.stats.per_pixel += 1;
                let (c, b) = self.clip(pv, s, true)?;
                run.recs.push(Prepared::clipped(run.clipped.len() as u32));
                run.clipped.push((c, b));
                Some(b)
            }
            None => {
                run.recs.pop();
                None
            }
        }
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
    /// Whether a tet whose vertex scalars span `[lo, hi]` draws nothing at all (every fragment
    /// exactly zero), so binning can leave it out; no by default.
    #[inline(always)]
    fn draws_nothing(&self, _lo: f32, _hi: f32) -> bool {
        false
    }

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
    fn draws_nothing(&self, lo: f32, hi: f32) -> bool {
        self.shader.draws_nothing(lo, hi)
    }
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

/// Side in pixels of the blocks whose opacity decides which tets are hidden: a tet is set up
/// unless every block under its pixel box is opaque. Tets are a few pixels across, so blocks
/// much smaller than a tile find far more of them hidden where a tile is only partly opaque
/// (a silhouette's edge, an opaque region's border).
const BLOCK: usize = 8;
/// Blocks a tile row.
const TILE_BLOCKS: usize = TILE / BLOCK;
// A tile is whole blocks, one bit each in a `u64`.
const _: () = assert!(TILE.is_multiple_of(BLOCK) && TILE_BLOCKS * TILE_BLOCKS <= 64);

/// Which [`BLOCK`]-pixel blocks of the image have every pixel opaque, as of the last wave.
struct Opaque {
    /// Per block, row by row (empty while no block is opaque).
    done: Vec<bool>,
    /// Blocks a row.
    nbx: usize,
}

impl Opaque {
    /// Whether every block under pixel box `b` is opaque.
    #[inline(always)]
    fn hides(&self, (x0, y0, x1, y1): PixelBox) -> bool {
        // A frame's first waves have nothing opaque: one test instead of the box's blocks.
        if self.done.is_empty() {
            return false;
        }
        for by in (y0 as usize / BLOCK)..=(y1 as usize / BLOCK) {
            for bx in (x0 as usize / BLOCK)..=(x1 as usize / BLOCK) {
                if !self.done.get(by * self.nbx + bx).copied().unwrap_or(false) {
                    return false;
                }
            }
        }
        true
    }
}

/// How many entries ahead the loops below ask for the memory they will read: far enough for a
/// miss to arrive, near enough that the line is not evicted first (2 to 8 measured alike).
const AHEAD: usize = 4;

/// Sets up a run of the order and bins it per tile (`ntx` tiles a row) into `run`, replacing
/// what it held but keeping its buffers. Tets whose every pixel is already `opaque` are left out
/// (what they would draw is hidden).
#[inline(always)]
fn bin<D: TileDraw>(
    frame: &Frame,
    chunk: &[u32],
    ntx: usize,
    opaque: &Opaque,
    d: &D,
    run: &mut Run,
) {
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
        let Some((x0, y0, x1, y1)) = frame.prepare_into(t, run, opaque, d) else {
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
unsafe fn bin_avx2<D: TileDraw>(
    frame: &Frame,
    chunk: &[u32],
    ntx: usize,
    opaque: &Opaque,
    d: &D,
    run: &mut Run,
) {
    bin(frame, chunk, ntx, opaque, d, run)
}

/// [`bin`] compiled for AVX-512 (F and VL): with 32 vector registers the set-up's four-lane
/// plane fits spill less. No fused multiply-add: bit for bit the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512vl")]
unsafe fn bin_avx512<D: TileDraw>(
    frame: &Frame,
    chunk: &[u32],
    ntx: usize,
    opaque: &Opaque,
    d: &D,
    run: &mut Run,
) {
    bin(frame, chunk, ntx, opaque, d, run)
}

/// [`bin`] with the widest instruction set the CPU has.
fn bin_best<D: TileDraw>(
    frame: &Frame,
    chunk: &[u32],
    ntx: usize,
    opaque: &Opaque,
    d: &D,
    run: &mut Run,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512vl")
    {
        // SAFETY: the CPU has AVX-512F and VL (and so AVX2), checked just above.
        return unsafe { bin_avx512(frame, chunk, ntx, opaque, d, run) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe { bin_avx2(frame, chunk, ntx, opaque, d, run) };
    }
    bin(frame, chunk, ntx, opaque, d, run)
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
    /// Bit `by * TILE_BLOCKS + bx` set when every pixel of that block of the tile is opaque.
    blocks: u64,
    /// `opaque` when `blocks` was last found.
    scanned: usize,
}

impl<S> TileAcc<S> {
    /// Finds which of the tile's blocks are opaque, when pixels turned opaque since last time.
    fn scan_blocks(&mut self) {
        if self.opaque == self.scanned {
            return;
        }
        self.scanned = self.opaque;
        let (x0, _, x1, _) = self.tile;
        let tw = (x1 - x0 + 1) as usize;
        // Blocks past the image's edge have no pixel, so all theirs are opaque: the tests
        // never ask for them.
        let mut clear = 0u64;
        for (r, row) in self.buf.chunks(tw).enumerate() {
            for (c, p) in row.iter().enumerate() {
                if !(p[3] >= super::OPAQUE) {
                    clear |= 1 << ((r / BLOCK) * TILE_BLOCKS + c / BLOCK);
                }
            }
        }
        self.blocks = !clear;
    }
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
    render_tiles_hiding(frame, order, d, true)
}

/// [`render_tiles`], leaving out the tets hidden behind opaque blocks only when `hide` (the
/// same image either way: the tests compare both).
fn render_tiles_hiding<D: TileDraw>(
    frame: &Frame,
    order: &[u32],
    d: &D,
    hide: bool,
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
                blocks: 0,
                scanned: 0,
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
    let (nbx, nby) = (ntx * TILE_BLOCKS, nty * TILE_BLOCKS);
    // Blocks opaque before this wave: what they would draw is hidden.
    let mut opaque = Opaque {
        done: Vec::new(),
        nbx,
    };
    for wave in order.chunks(CHUNK * WAVE) {
        let t0 = std::time::Instant::now();
        let used = wave.len().div_ceil(CHUNK);
        runs[..used]
            .par_iter_mut()
            .zip(wave.par_chunks(CHUNK))
            .for_each(|(run, chunk)| bin_best(frame, chunk, ntx, &opaque, d, run));
        for run in &runs[..used] {
            stats.add(&run.stats);
        }
        bin_s += t0.elapsed().as_secs_f64();
        let runs = &runs[..used];
        tiles
            .par_iter_mut()
            .enumerate()
            .filter(|(ti, acc)| !acc.done && runs.iter().any(|r| !r.lists[*ti].is_empty()))
            .for_each(|(ti, acc)| {
                draw_tile_best(d, runs, ti, acc);
                acc.scan_blocks();
            });
        if hide && tiles.iter().any(|acc| acc.blocks != 0) {
            opaque.done.resize(nbx * nby, false);
            for (ti, acc) in tiles.iter().enumerate() {
                let (tx, ty) = (ti % ntx, ti / ntx);
                for k in 0..TILE_BLOCKS * TILE_BLOCKS {
                    let (bx, by) = (
                        tx * TILE_BLOCKS + k % TILE_BLOCKS,
                        ty * TILE_BLOCKS + k / TILE_BLOCKS,
                    );
                    opaque.done[by * nbx + bx] = acc.blocks >> k & 1 != 0;
                }
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::mesh::generate::structured_grid;
    use crate::mesh::TetMesh;
    use crate::render::integrate::{FastTf, PreintTable};
    use crate::render::pt::{project_points, stretch_map};
    use crate::render::transfer::{named_colormap, OpacitySpec, TransferFunction};
    use crate::sort::{Direction, Method, Sorter};

    /// A 96x80 view of `m` from azimuth 30 and elevation 20, and its MPVO order front to back.
    fn view_and_order(m: &TetMesh) -> anyhow::Result<(View, Vec<u32>)> {
        let mut cam = Camera::default();
        cam.reset_to(&m.bounds());
        cam.azimuth(30.0);
        cam.elevation(20.0);
        let order = Sorter::new(m, None)?
            .order(&cam, Method::Mpvo, Direction::FrontToBack)
            .order;
        Ok((View::new(&cam, 96, 80), order))
    }

    /// A pre-integrated shader (65 x 17 table) for `opacity` over [0, 1], viridis.
    fn tf(opacity: &str, unit: f64, nodes: usize) -> anyhow::Result<TransferFunction> {
        TransferFunction::build(
            &named_colormap("viridis")?,
            Some(&OpacitySpec::parse(opacity)?),
            [0.0, 1.0],
            unit,
            nodes,
        )
    }

    fn table(opacity: &str, unit: f64, nodes: usize, lmax: f64) -> anyhow::Result<Shader> {
        let tf = tf(opacity, unit, nodes)?;
        Ok(Shader::Pre(PreintTable::build(&tf, 65, 17, lmax)))
    }

    fn bits(img: &Image) -> Vec<[u32; 4]> {
        img.pixels.iter().map(|p| p.map(f32::to_bits)).collect()
    }

    #[test]
    fn tets_behind_opaque_blocks_are_skipped_without_changing_the_image() -> anyhow::Result<()> {
        // Three waves of a grid seen at an angle, nearly opaque within a few cells where x > 1/2
        // and clear elsewhere: from the second wave on, the tets behind the opaque half are
        // hidden, and a hidden tet drawing into the clear half would show.
        let n = 28;
        let m = structured_grid([n; 3], [0.0; 3], [1.0; 3]);
        assert!(m.tets.len() > 2 * CHUNK * WAVE, "{} tets", m.tets.len());
        let s: Vec<f64> = m.points.iter().map(|p| p[0]).collect();
        let shader = table("0:0.01,0.45:0.01,0.55:1,1:1", 0.02, 9, 0.1)?;
        let (view, order) = view_and_order(&m)?;
        let field = Field::Point(s);
        let proj = project_points(&view, &m.points);
        let stretch = stretch_map(&view);
        let frame = Frame {
            view: &view,
            tets: &m.tets,
            field: &field,
            proj: &proj,
            stretch: &stretch,
        };
        let plain = PlainDraw {
            frame: &frame,
            shader: &shader,
        };
        let (a, sa, _, _) = render_tiles_hiding(&frame, &order, &plain, true);
        let (b, sb, _, _) = render_tiles_hiding(&frame, &order, &plain, false);
        assert!(bits(&a) == bits(&b), "the skipped tets changed the image");
        assert_eq!(sb.hidden, 0);
        // Every tet's class is counted, hidden or not; fragments are the drawn ones.
        assert_eq!((sa.class, sa.fragments), (sb.class, sb.fragments));
        let later = m.tets.len() - CHUNK * WAVE;
        assert!(
            sa.hidden as usize > later / 4,
            "only {} of the {later} tets after the first wave hidden",
            sa.hidden
        );
        // Some pixels are not opaque (the silhouette's edge), so not everything is hidden.
        assert!(a
            .pixels
            .iter()
            .any(|p| p[3] > 0.0 && p[3] < super::super::OPAQUE));
        Ok(())
    }

    /// The plain path, but drawing every tet.
    struct EveryTet<'a>(PlainDraw<'a>);
    impl TileDraw for EveryTet<'_> {
        type State = ();
        fn draw(
            &self,
            state: &mut (),
            ti: usize,
            run: &Run,
            k: usize,
            tile: Tile,
            buf: &mut [[f32; 4]],
        ) -> (u64, usize) {
            self.0.draw(state, ti, run, k, tile, buf)
        }
    }

    #[test]
    fn tets_drawn_as_nothing_are_left_out_without_changing_the_image() -> anyhow::Result<()> {
        // The scalar is x; the transfer function draws nothing for x below 0.45 (to 0.4375
        // after resampling to 17 nodes), in every integration mode.
        let n = 20;
        let m = structured_grid([n; 3], [0.0; 3], [1.0; 3]);
        let s: Vec<f64> = m.points.iter().map(|p| p[0]).collect();
        let opacity = "0:0,0.45:0,0.6:0.5,0.7:0.1,0.9:1,1:0.2";
        let fast = FastTf::new(&tf(opacity, 0.05, 17)?);
        let shaders = [
            table(opacity, 0.05, 17, 0.2)?,
            Shader::Average(fast.clone()),
            Shader::Linear(fast),
        ];
        let (view, order) = view_and_order(&m)?;
        for (shader, field) in shaders.iter().flat_map(|sh| {
            [
                Field::Point(s.clone()),
                Field::Cell(
                    (0..m.tets.len())
                        .map(|t| m.points[m.tets[t][0] as usize][0])
                        .collect(),
                ),
            ]
            .map(|f| (sh, f))
        }) {
            let proj = project_points(&view, &m.points);
            let stretch = stretch_map(&view);
            let frame = Frame {
                view: &view,
                tets: &m.tets,
                field: &field,
                proj: &proj,
                stretch: &stretch,
            };
            let plain = PlainDraw {
                frame: &frame,
                shader,
            };
            let (a, sa, _, _) = render_tiles(&frame, &order, &plain);
            let every = EveryTet(PlainDraw {
                frame: &frame,
                shader,
            });
            let (b, sb, _, _) = render_tiles(&frame, &order, &every);
            assert!(bits(&a) == bits(&b), "leaving tets out changed the image");
            assert_eq!(sb.clear, 0);
            // The 8 of 20 cell layers below x = 0.4 are left out; the next one's point values
            // reach past 0.4375, but its cell values (x at the first vertex, the layer's low
            // side) do not.
            let nt = m.tets.len() as u64;
            let layers = if matches!(field, Field::Point(_)) {
                8
            } else {
                9
            };
            assert_eq!(sa.clear, nt * layers / 20);
            assert_eq!(sa.class.iter().sum::<u64>() + sa.clear, nt);
            assert!(sa.fragments < sb.fragments);
            assert!(a.pixels.iter().any(|p| p[3] > 0.0), "something is drawn");
        }
        Ok(())
    }

    #[test]
    fn a_block_is_opaque_only_when_all_its_pixels_are() {
        // A tile at the image's right edge, 20 pixels wide: blocks 0-2 of each block row
        // hold pixels (the third 4 wide), block 3 none.
        let (w, h) = (20usize, TILE);
        let mut acc = TileAcc {
            tile: (32, 0, 32 + w as i64 - 1, h as i64 - 1),
            buf: vec![[0.0f32; 4]; w * h],
            frags: 0,
            opaque: 0,
            state: (),
            done: false,
            blocks: 0,
            scanned: 0,
        };
        let opaque_at = |acc: &mut TileAcc<()>, x: usize, y: usize| {
            acc.buf[y * w + x] = [1.0; 4];
            acc.opaque += 1;
        };
        // Block (0, 0) whole; block (2, 1) whole, its 4 columns; block (1, 2) all but one pixel.
        for y in 0..BLOCK {
            for x in 0..BLOCK {
                opaque_at(&mut acc, x, y);
                if !(x == 7 && y == 7) {
                    opaque_at(&mut acc, BLOCK + x, 2 * BLOCK + y);
                }
            }
            for x in 16..20 {
                opaque_at(&mut acc, x, BLOCK + y);
            }
        }
        acc.scan_blocks();
        let bit = |blocks: u64, bx: usize, by: usize| blocks >> (by * TILE_BLOCKS + bx) & 1 != 0;
        let b = acc.blocks;
        assert!(bit(b, 0, 0) && bit(b, 2, 1));
        assert!(!bit(b, 1, 2), "one clear pixel keeps a block clear");
        assert!(!bit(b, 1, 0) && !bit(b, 0, 1) && !bit(b, 2, 0));
        // Unchanged opaque count: not scanned again.
        acc.buf[0] = [0.0; 4];
        acc.scan_blocks();
        assert!(bit(acc.blocks, 0, 0));

        // A box hides only when every block under it is opaque.
        let nbx = 4;
        let mut done = vec![false; nbx * 4];
        for (bx, by) in [(0, 0), (1, 0), (1, 1)] {
            done[by * nbx + bx] = true;
        }
        let o = Opaque { done, nbx };
        assert!(o.hides((0, 0, 15, 7)), "two opaque blocks");
        assert!(o.hides((9, 9, 15, 15)), "inside one");
        assert!(!o.hides((0, 0, 16, 7)), "one column into a clear block");
        assert!(o.hides((8, 7, 15, 8)), "(1, 0) and (1, 1)");
        assert!(
            !o.hides((7, 7, 15, 8)),
            "a column into (0, 1), which is clear"
        );
        let none = Opaque {
            done: Vec::new(),
            nbx,
        };
        assert!(!none.hides((0, 0, 0, 0)));
    }
}
