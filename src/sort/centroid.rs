//! The approximate order of VTK's vtkCellCenterDepthSort: tet centroids sorted by their depth
//! along the camera's direction of projection (kept for comparison; not exact).

use rayon::prelude::*;

use super::{Direction, Order};
use crate::camera::Camera;

pub fn order(centroids: &[[f64; 3]], cam: &Camera, dir: Direction) -> Order {
    let d = cam.direction();
    let mut keyed: Vec<(f64, u32)> = centroids
        .par_iter()
        .enumerate()
        .map(|(t, c)| (c[0] * d[0] + c[1] * d[1] + c[2] * d[2], t as u32))
        .collect();
    match dir {
        Direction::FrontToBack => {
            keyed.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        }
        Direction::BackToFront => {
            keyed.par_sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)))
        }
    }
    let n = centroids.len();
    let mut stats = super::SortStats {
        leaves: 1,
        layers: n.min(1) as u32,
        layers_total: n.min(1) as u64,
        ..Default::default()
    };
    stats.tets = n;
    Order {
        order: keyed.into_iter().map(|k| k.1).collect(),
        layer: vec![0; n],
        leaf: vec![0; n],
        stats,
    }
}
