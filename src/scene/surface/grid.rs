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
    /// Triangle ids per (x, y) column, each once: what a ray along +z may cross.
    columns: Vec<Vec<u32>>,
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
            columns: vec![Vec::new(); n[0] * n[1]],
        };
        for (i, t) in tris.iter().enumerate() {
            let b = Aabb::of_points(t.iter().map(|&v| &points[v as usize]));
            let (lo, hi) = g.range(&b);
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    g.columns[x + n[0] * y].push(i as u32);
                }
            }
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

    /// Cells a box overlaps, widened by a millionth of a cell against rounding at cell borders
    /// (the same widening at insertion and at query keeps it conservative).
    fn range(&self, b: &Aabb) -> ([usize; 3], [usize; 3]) {
        let at = |k: usize, v: f64| {
            let f = ((v - self.min[k]) / self.cell[k]).floor();
            if f.is_nan() || f < 0.0 {
                0
            } else {
                (f as usize).min(self.n[k] - 1)
            }
        };
        let pad = |k: usize| 1e-6 * self.cell[k];
        let lo = [0, 1, 2].map(|k| at(k, b.min[k] - pad(k)));
        let hi = [0, 1, 2].map(|k| at(k, b.max[k] + pad(k)));
        (lo, hi)
    }

    /// Triangles whose boxes may overlap `b` (a triangle may come more than once).
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
    }

    /// Triangles that a ray from `p` along +z may cross, each once.
    pub fn column(&self, p: &[f64; 3]) -> &[u32] {
        let b = Aabb { min: *p, max: *p };
        let (lo, hi) = self.range(&b);
        if lo[0] != hi[0] || lo[1] != hi[1] {
            // On a column border (within rounding): no single column is safe.
            return &[];
        }
        &self.columns[lo[0] + self.n[0] * lo[1]]
    }

    /// Whether `p` lies on a column border, where [`TriGrid::column`] cannot answer.
    pub fn on_column_border(&self, p: &[f64; 3]) -> bool {
        let (lo, hi) = self.range(&Aabb { min: *p, max: *p });
        lo[0] != hi[0] || lo[1] != hi[1]
    }
}
