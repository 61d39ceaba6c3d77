//! Scene bodies on the GPU: each pixel's body crossings (view depth and the region code after
//! each, computed on the CPU exactly as the CPU path computes them) uploaded as a 2-D array
//! texture, and the map from region code to the stacked transfer-function table it selects.

use std::collections::BTreeMap;

use anyhow::{bail, Result};
use rayon::prelude::*;

use crate::camera::Camera;
use crate::geom::{dot, Aabb};
use crate::render::cut::{mesh_depths, SceneLook, CUT};
use crate::render::integrate::Integration;
use crate::render::prepare::{self, TableSize};
use crate::render::pt::{Shader, View};
use crate::scene::ray::{footprint, RayRegions, View as SceneView};

/// A region code's slot on the GPU when it draws nothing.
pub const GPU_CUT: u32 = u32::MAX;

/// One frame's crossings, layer-major: layer 0 holds (count, start code) per pixel, layer
/// `i >= 1` the `i`-th crossing's (view depth, code after it).
pub struct Crossings {
    pub layers: u32,
    pub texels: Vec<[f32; 2]>,
    /// Region codes present where the mesh is.
    pub seen: [bool; 256],
    /// Pixels whose rays were tested against the bodies.
    pub traced: u64,
}

/// Per-pixel crossings: bodies are tested only inside their screen rectangles when culling is
/// on, parallel rays start behind the mesh, depths are view depths (as `render::cut`).
pub fn crossings(view: &View, cam: &Camera, look: &SceneLook, mesh_box: &Aabb) -> Crossings {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut sv = SceneView::new(look.scene, *cam, view.width, view.height);
    sv.culling = look.culling;
    let mesh_fp = footprint(mesh_box, cam, view.width, view.height);
    let (mz0, mz1, back) = mesh_depths(view, mesh_box);
    type Row = (Vec<(u8, Vec<(f32, u8)>)>, [bool; 256], u64);
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut seen = [false; 256];
            let mut traced = 0;
            let mut rr = RayRegions::default();
            let py = y as f64 + 0.5;
            let row = (0..w)
                .map(|x| {
                    let px = x as f64 + 0.5;
                    if sv.culling && !sv.footprints.iter().any(|f| f.covers(px, py)) {
                        if mesh_fp.covers(px, py) {
                            seen[0] = true;
                        }
                        return (0, Vec::new());
                    }
                    traced += 1;
                    let (mut o, d) = sv.pixel_ray(px, py);
                    if back > 0.0 {
                        o = [0, 1, 2].map(|k| o[k] - back * d[k]);
                    }
                    sv.ray_at(&o, &d, Some((px, py)), &mut rr);
                    let dz = dot(&d, &view.f);
                    let oz = view.to_view(&o)[2];
                    if mesh_fp.covers(px, py) {
                        let (t0, t1) = ((mz0 - oz) / dz, (mz1 - oz) / dz);
                        rr.pieces(t0.max(0.0), t1.max(0.0), |_, _, c| seen[c as usize] = true);
                    }
                    let list = rr
                        .depths
                        .iter()
                        .zip(&rr.codes)
                        .map(|(&t, &c)| ((oz + t * dz) as f32, c))
                        .collect();
                    (rr.start, list)
                })
                .collect();
            (row, seen, traced)
        })
        .collect();
    let mut seen = [false; 256];
    let mut traced = 0;
    let mut most = 0;
    for (row, s, t) in &rows {
        for c in 0..256 {
            seen[c] |= s[c];
        }
        traced += t;
        most = row.iter().map(|p| p.1.len()).max().unwrap_or(0).max(most);
    }
    if !seen.iter().any(|&s| s) {
        seen[0] = true;
    }
    let layers = 1 + most as u32;
    let n = w * h;
    let mut texels = vec![[0f32; 2]; n * layers as usize];
    for (y, (row, _, _)) in rows.iter().enumerate() {
        for (x, (start, list)) in row.iter().enumerate() {
            let p = y * w + x;
            texels[p] = [list.len() as f32, *start as f32];
            for (i, &(z, c)) in list.iter().enumerate() {
                texels[(i + 1) * n + p] = [z, c as f32];
            }
        }
    }
    Crossings {
        layers,
        texels,
        seen,
        traced,
    }
}

/// Pre-integration tables (or transfer-function nodes) of a scene's distinct transfer functions,
/// built when a frame first needs one.
pub struct SceneTables {
    pub mode: Integration,
    pub size: TableSize,
    pub lmax: f64,
    shaders: BTreeMap<u16, Shader>,
}

impl SceneTables {
    pub fn new(mode: Integration, size: TableSize, lmax: f64) -> SceneTables {
        SceneTables {
            mode,
            size,
            lmax,
            shaders: BTreeMap::new(),
        }
    }

    /// The transfer-function slots the codes present need (in order), the GPU slot of every code
    /// ([`GPU_CUT`] where nothing is drawn), and the shaders of the needed slots.
    pub fn resolve(
        &mut self,
        look: &SceneLook,
        seen: &[bool; 256],
    ) -> Result<(Vec<u16>, Vec<u32>, Vec<&Shader>)> {
        let mut need: Vec<u16> = (0..256)
            .filter(|&c| seen[c])
            .map(|c| look.slot(c as u8))
            .filter(|&k| k != CUT)
            .collect();
        need.sort_unstable();
        need.dedup();
        for &k in &need {
            if self.shaders.contains_key(&k) {
                continue;
            }
            let Some(tf) = (0..=255u8)
                .find(|&c| look.slot(c) == k)
                .and_then(|c| look.tf(c))
            else {
                bail!("scene: no transfer function for table {k}");
            };
            let s = prepare::shader(tf, self.mode, self.size, self.lmax);
            self.shaders.insert(k, s);
        }
        let slots = (0..256)
            .map(|c| {
                let k = look.slot(c as u8);
                need.iter()
                    .position(|&x| x == k)
                    .map_or(GPU_CUT, |i| i as u32)
            })
            .collect();
        let shaders = need.iter().filter_map(|k| self.shaders.get(k)).collect();
        Ok((need, slots, shaders))
    }
}
