//! A uniform grid over a surface's triangles, so a tet or a vertical ray meets only the
//! triangles near it (candidates only: every decision is still made by the exact tests).

use crate::geom::Aabb;

#[derive(Clone, Debug, PartialEq)]
pub struct TriGrid {
    min: [f64; 3],
    cell: [f64; 3],
    n: [usize; 3],
    /// Triangle ids per cell, x fastest.
    cells: Vec<Vec<u32>>,
}

impl TriGrid {
    /// About two triangles per cell, at most 64 cells a side.
    pub fn build(points: &[[f64; 3]], tris: &[[u32; 3]], bounds: &Aabb) -> TriGrid {
        let side = ((tris.len() as f64 / 2.0).cbrt().ceil() as usize).clamp(1, 64);
        let ext = bounds.extent();
        let n = [0, 1, 2].map(|k| if ext[k] > 0.0 { side } else { 1 });
        let cell = [0, 1, 2].map(|k| {
            if ext[k] > 0.0 {
                ext[k] / n[k] as f64
            } else {
                1.0
            }
        });
        let mut g = TriGrid {
            min: bounds.min,
            cell,
            n,
            cells: vec![Vec::new(); n[0] * n[1] * n[2]],
        };
        for (i, t) in tris.iter().enumerate() {
            let b = Aabb::of_points(t.iter().map(|&v| &points[v as usize]));
            let (lo, hi) = g.range(&b);
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let c = g.index(x, y, z);
                        g.cells[c].push(i as u32);
                    }
                }
            }
        }
        g
    }

    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        x + self.n[0] * (y + self.n[1] * z)
    }

    /// Cells a box overlaps, widened by one cell each way against rounding at cell borders.
    fn range(&self, b: &Aabb) -> ([usize; 3], [usize; 3]) {
        let at = |k: usize, v: f64| {
            let f = ((v - self.min[k]) / self.cell[k]).floor();
            if f.is_nan() || f < 0.0 {
                0
            } else {
                (f as usize).min(self.n[k] - 1)
            }
        };
        let lo = [0, 1, 2].map(|k| at(k, b.min[k]).saturating_sub(1));
        let hi = [0, 1, 2].map(|k| (at(k, b.max[k]) + 1).min(self.n[k] - 1));
        (lo, hi)
    }

    /// Triangles whose boxes may overlap `b`, each once, in increasing order.
    pub fn candidates(&self, b: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        let (lo, hi) = self.range(b);
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    out.extend_from_slice(&self.cells[self.index(x, y, z)]);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// Triangles that a ray from `p` along +z may cross.
    pub fn column_up(&self, p: &[f64; 3], out: &mut Vec<u32>) {
        let b = Aabb {
            min: *p,
            max: [p[0], p[1], self.min[2] + self.cell[2] * self.n[2] as f64],
        };
        self.candidates(&b, out);
    }
}
