//! Small geometric helpers shared by every stage: boxes, tet volume, exact orientation.

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    pub fn of_points<'a>(pts: impl IntoIterator<Item = &'a [f64; 3]>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in pts {
            b.grow(p);
        }
        b
    }

    pub fn grow(&mut self, p: &[f64; 3]) {
        for (k, &x) in p.iter().enumerate() {
            self.min[k] = self.min[k].min(x);
            self.max[k] = self.max[k].max(x);
        }
    }

    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// Whether `p` lies in the closed box (exact comparisons).
    pub fn contains(&self, p: &[f64; 3]) -> bool {
        (0..3).all(|k| self.min[k] <= p[k] && p[k] <= self.max[k])
    }

    pub fn center(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| 0.5 * (self.min[k] + self.max[k]))
    }

    pub fn extent(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.max[k] - self.min[k])
    }

    /// Bounds as VTK orders them: `[xmin, xmax, ymin, ymax, zmin, zmax]`.
    pub fn to_vtk(&self) -> [f64; 6] {
        [
            self.min[0],
            self.max[0],
            self.min[1],
            self.max[1],
            self.min[2],
            self.max[2],
        ]
    }
}

/// Exact orientation of `c` against the line `a -> b` (Shewchuk's adaptive predicate, as the
/// `robust` crate has it): positive when `a`, `b`, `c` are counter-clockwise (`c` left of
/// `a -> b` with y up), zero exactly when they are collinear.
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let p = |v: [f64; 2]| robust::Coord { x: v[0], y: v[1] };
    robust::orient2d(p(a), p(b), p(c))
}

/// Exact orientation of `d` against the plane through `a`, `b`, `c` (Shewchuk's adaptive
/// predicate): positive when `d` is below the plane, i.e. `a`, `b`, `c` appear counter-clockwise
/// seen from above, as in the `robust` crate; zero exactly when the four points are coplanar.
pub fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let c3 = |p: &[f64; 3]| robust::Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// Signed volume of a tet, `(b - a) . ((c - a) x (d - a)) / 6` in floating point (not exact;
/// use [`orient3d`] for signs).
pub fn tet_volume(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let u = sub(b, a);
    let v = sub(c, a);
    let w = sub(d, a);
    dot(&u, &cross(&v, &w)) / 6.0
}

pub fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
