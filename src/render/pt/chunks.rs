//! The chunk schedule: runs of the order rendered in parallel into their own buffers over their screen boxes, then composited front to back.

use rayon::prelude::*;

use super::classify::count_class;
use super::clip::clip_box;
use super::shade::Shader;
use super::tiles::Frame;
use super::{PixelBox, Projected, PtStats, View, CHUNKS, SUB};
use crate::render::image::Image;

/// [`Schedule::Chunks`]: image, counts, seconds spent finding the chunks' screen boxes.
pub(crate) fn render_chunks(
    frame: &Frame,
    shader: &Shader,
    order: &[u32],
) -> (Image, PtStats, f64) {
    let t1 = std::time::Instant::now();
    let (w, h) = (frame.view.width as usize, frame.view.height as usize);
    let per = order.len().div_ceil(CHUNKS).max(1);
    let runs: Vec<&[u32]> = order.chunks(per).collect();
    // Each run's screen box, so a buffer covers only what its run can touch.
    let boxed: Vec<(Option<PixelBox>, PtStats)> = runs
        .par_iter()
        .map(|run| {
            let mut bb: Option<PixelBox> = None;
            let mut st = PtStats::default();
            for &t in run.iter() {
                let p = frame.tets[t as usize].map(|v| &frame.proj[v as usize]);
                count_class(&mut st, &p);
                if let Some(b) = pixel_box(frame.view, &p, w, h) {
                    bb = Some(match bb {
                        None => b,
                        Some(a) => (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)),
                    });
                }
            }
            (bb, st)
        })
        .collect();
    let mut stats = PtStats::default();
    for (_, st) in &boxed {
        stats.add(st);
    }
    let boxes: Vec<Option<PixelBox>> = boxed.iter().map(|b| b.0).collect();
    let box_s = t1.elapsed().as_secs_f64();
    let bufs: Vec<(Vec<[f32; 4]>, u64)> = runs
        .par_iter()
        .zip(&boxes)
        .map(|(run, bb)| {
            let Some(tile) = *bb else {
                return (Vec::new(), 0);
            };
            let npix = ((tile.2 - tile.0 + 1) * (tile.3 - tile.1 + 1)) as usize;
            let mut buf = vec![[0f32; 4]; npix];
            let mut frags = 0;
            // The classes were counted with the boxes.
            let mut counted = PtStats::default();
            for &t in run.iter() {
                if let Some((p, _)) = frame.prepare(t, &mut counted) {
                    frags += frame.draw_prep(&p, tile, &mut buf, shader).0;
                }
            }
            (buf, frags)
        })
        .collect();
    // Front to back: out += (1 - out.a) * run, rows in parallel.
    let mut img = Image::new(frame.view.width, frame.view.height);
    img.pixels
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as i64;
            for ((buf, _), bb) in bufs.iter().zip(&boxes) {
                let Some((x0, y0, x1, y1)) = *bb else {
                    continue;
                };
                if y < y0 || y > y1 {
                    continue;
                }
                let bw = (x1 - x0 + 1) as usize;
                let src = &buf[(y - y0) as usize * bw..][..bw];
                for (d, s) in row[x0 as usize..=x1 as usize].iter_mut().zip(src) {
                    let k = 1.0 - d[3];
                    for c in 0..4 {
                        d[c] += k * s[c];
                    }
                }
            }
        });
    stats.fragments = bufs.iter().map(|b| b.1).sum();
    (img, stats, box_s)
}

/// Pixel box (inclusive) of a tet's projection clipped to the image, if it is drawable.
#[inline]
fn pixel_box(view: &View, p: &[&Projected; 4], w: usize, h: usize) -> Option<PixelBox> {
    if p.iter().any(|q| !q.ok) {
        return clip_box(view, p, w, h);
    }
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (p[0].fx, p[0].fx, p[0].fy, p[0].fy);
    for q in &p[1..] {
        xmin = xmin.min(q.fx);
        xmax = xmax.max(q.fx);
        ymin = ymin.min(q.fy);
        ymax = ymax.max(q.fy);
    }
    let lo = |v: i64| (v - SUB / 2 + SUB - 1).div_euclid(SUB);
    let hi = |v: i64| (v - SUB / 2).div_euclid(SUB);
    let (x0, x1) = (lo(xmin).max(0), hi(xmax).min(w as i64 - 1));
    let (y0, y1) = (lo(ymin).max(0), hi(ymax).min(h as i64 - 1));
    (x0 <= x1 && y0 <= y1).then_some((x0, y0, x1, y1))
}
