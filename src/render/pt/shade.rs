//! Fragment shading: the three integration modes behind one [`Shader`], and the lane-wise [`Shade`] the rasterizer calls.

use super::raster::raster;
use super::setup::TetSetup;
use super::tiles::Tile;
use crate::render::integrate::{FastTf, Integration, PreintTable};

/// Per-pixel shading of a fragment.
pub enum Shader {
    Average(FastTf),
    Linear(FastTf),
    Pre(PreintTable),
}

impl Shader {
    pub fn mode(&self) -> Integration {
        match self {
            Shader::Average(_) => Integration::Average,
            Shader::Linear(_) => Integration::Linear,
            Shader::Pre(_) => Integration::Preintegrated,
        }
    }

    /// Colour and opacity of one fragment.
    #[inline(always)]
    pub fn shade(&self, sf: f32, sb: f32, l: f32) -> [f32; 4] {
        match self {
            Shader::Pre(tab) => tab.lookup(sf, sb, l),
            Shader::Average(tf) => tf.average(sf, sb, l),
            Shader::Linear(tf) => tf.linear(sf, sb, l),
        }
    }

    /// Rasterizes one set-up tet into `buf` covering `tile` (front to back) with this
    /// integration: fragments and newly opaque pixels.
    #[inline(always)]
    pub(crate) fn draw(
        &self,
        setup: &TetSetup,
        parallel: bool,
        tile: Tile,
        buf: &mut [[f32; 4]],
        stretch: &[f32],
        w: usize,
    ) -> (u64, usize) {
        match self {
            Shader::Pre(tab) => raster(setup, parallel, tile, buf, stretch, w, tab),
            Shader::Average(tf) => raster(
                setup,
                parallel,
                tile,
                buf,
                stretch,
                w,
                &TfShade::<false>(tf),
            ),
            Shader::Linear(tf) => {
                raster(setup, parallel, tile, buf, stretch, w, &TfShade::<true>(tf))
            }
        }
    }
}

/// Pixels of the batched fragment math: fixed-size loops over them vectorize (one AVX2
/// register; the rasterizer fills the lanes from several rows of a tet, so few stay idle).
pub(crate) const LANES: usize = 8;

/// (Sf, Sb, l) of [`LANES`] fragments.
pub(crate) type Lanes = [[f32; LANES]; 3];

/// Colour and opacity of fragments for the rasterizer: per-lane arithmetic for [`LANES`]
/// fragments at once (it vectorizes), then per-pixel reads for the lanes that are drawn.
pub(crate) trait Shade {
    type Prep;
    fn prep(&self, f: &Lanes) -> Self::Prep;
    fn at(&self, p: &Self::Prep, i: usize) -> [f32; 4];
}

/// Table corners and weights of [`LANES`] lookups.
pub(crate) struct TableLanes {
    base: [usize; LANES],
    w: [[f32; LANES]; 3],
}

impl Shade for PreintTable {
    type Prep = TableLanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> TableLanes {
        let top = (self.ns - 1) as f32;
        let ltop = (self.nl - 1) as f32;
        let (mut base, mut w) = ([0usize; LANES], [[0f32; LANES]; 3]);
        let (ns, nl) = (self.ns as i32, self.nl as i32);
        for i in 0..LANES {
            // max then min (not clamp): NaN becomes 0, so every value is in [0, top].
            let xf = ((f[0][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let xb = ((f[1][i] - self.s0) * self.inv_ds).max(0.0).min(top);
            let xl = (f[2][i] * self.inv_dl).max(0.0).min(ltop);
            // SAFETY: each value is finite and in [0, ns - 1] or [0, nl - 1] (table sizes are
            // far below i32::MAX), where truncation to i32 is defined; the checked cast would
            // not vectorize.
            let (a, b, c) = unsafe {
                (
                    xf.to_int_unchecked::<i32>().min(ns - 2),
                    xb.to_int_unchecked::<i32>().min(ns - 2),
                    xl.to_int_unchecked::<i32>().min(nl - 2),
                )
            };
            w[0][i] = xf - a as f32;
            w[1][i] = xb - b as f32;
            w[2][i] = xl - c as f32;
            base[i] = ((c * ns + b) * ns + a) as usize;
        }
        TableLanes { base, w }
    }
    #[inline(always)]
    fn at(&self, p: &TableLanes, i: usize) -> [f32; 4] {
        self.corners(p.base[i], p.w[0][i], p.w[1][i], p.w[2][i])
    }
}

/// A transfer function evaluated at both ends of each fragment as a [`Shade`]: VTK's averaged
/// integration ([`FastTf::average`]), or linear integration ([`FastTf::linear`]) when `LINEAR`.
struct TfShade<'a, const LINEAR: bool>(&'a FastTf);

impl<const LINEAR: bool> Shade for TfShade<'_, LINEAR> {
    type Prep = Lanes;
    #[inline(always)]
    fn prep(&self, f: &Lanes) -> Lanes {
        *f
    }
    #[inline(always)]
    fn at(&self, f: &Lanes, i: usize) -> [f32; 4] {
        if LINEAR {
            self.0.linear(f[0][i], f[1][i], f[2][i])
        } else {
            self.0.average(f[0][i], f[1][i], f[2][i])
        }
    }
}
