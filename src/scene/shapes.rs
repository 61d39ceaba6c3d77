//! The analytic bodies (box, sphere, capped cylinder, cone frustum): where a line enters and
//! leaves them, whether they contain a point, and their bounds.

use crate::geom::{dot, sub, Aabb};

/// An analytic convex body. A cylinder is a frustum with equal radii.
#[derive(Clone, Debug, PartialEq)]
pub enum Primitive {
    Box {
        min: [f64; 3],
        max: [f64; 3],
    },
    Sphere {
        center: [f64; 3],
        radius: f64,
    },
    /// The convex hull of the disc of radius `r0` centred at `start` and the disc of radius `r1`
    /// centred at `end`, both perpendicular to `end - start`.
    Frustum {
        start: [f64; 3],
        end: [f64; 3],
        r0: f64,
        r1: f64,
    },
}

/// The closed parameter interval `[t0, t1]` where the line `o + t d` lies in the body, if any.
pub type Span = Option<(f64, f64)>;

impl Primitive {
    /// Where the whole line `o + t d` (t over all reals) is inside the closed body: one interval,
    /// since every body is convex. Lines that only graze the surface give a zero-length interval,
    /// i.e. two crossings at the same depth, so they never change a region code.
    pub fn line_span(&self, o: &[f64; 3], d: &[f64; 3]) -> Span {
        match self {
            Primitive::Box { min, max } => {
                let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
                for k in 0..3 {
                    if d[k] == 0.0 {
                        if o[k] < min[k] || o[k] > max[k] {
                            return None;
                        }
                    } else {
                        let a = (min[k] - o[k]) / d[k];
                        let b = (max[k] - o[k]) / d[k];
                        t0 = t0.max(a.min(b));
                        t1 = t1.min(a.max(b));
                    }
                }
                (t0 <= t1).then_some((t0, t1))
            }
            Primitive::Sphere { center, radius } => {
                let oc = sub(o, center);
                let a = dot(d, d);
                let b = dot(&oc, d);
                let c = dot(&oc, &oc) - radius * radius;
                let disc = b * b - a * c;
                if disc < 0.0 || a == 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                // The numerically stable pair of roots.
                let q = -(b + b.signum() * s);
                if q == 0.0 {
                    return Some((0.0, 0.0));
                }
                let (r1, r2) = (q / a, c / q);
                Some((r1.min(r2), r1.max(r2)))
            }
            Primitive::Frustum { start, end, r0, r1 } => frustum_span(start, end, *r0, *r1, o, d),
        }
    }

    /// Whether `p` is in the closed body.
    pub fn contains(&self, p: &[f64; 3]) -> bool {
        match self {
            Primitive::Box { min, max } => (0..3).all(|k| min[k] <= p[k] && p[k] <= max[k]),
            Primitive::Sphere { center, radius } => {
                let v = sub(p, center);
                dot(&v, &v) <= radius * radius
            }
            Primitive::Frustum { start, end, r0, r1 } => {
                let axis = sub(end, start);
                let len2 = dot(&axis, &axis);
                let s = dot(&sub(p, start), &axis) / len2;
                if !(0.0..=1.0).contains(&s) {
                    return false;
                }
                let foot = [0, 1, 2].map(|k| start[k] + s * axis[k]);
                let v = sub(p, &foot);
                let r = r0 + (r1 - r0) * s;
                dot(&v, &v) <= r * r
            }
        }
    }

    /// A box containing the body (exact for boxes and spheres up to rounding, which is rounded
    /// outwards).
    pub fn bounds(&self) -> Aabb {
        // The corners are each one rounded sum away from the exact ones; 4 eps of the largest
        // magnitude covers that, and the smallest normal number any underflow.
        let grow = |b: Aabb| {
            let pad = b
                .min
                .iter()
                .chain(b.max.iter())
                .fold(0.0f64, |m, x| m.max(x.abs()))
                * 4.0
                * f64::EPSILON
                + f64::MIN_POSITIVE;
            Aabb {
                min: b.min.map(|x| x - pad),
                max: b.max.map(|x| x + pad),
            }
        };
        match self {
            Primitive::Box { min, max } => Aabb {
                min: *min,
                max: *max,
            },
            Primitive::Sphere { center, radius } => grow(Aabb {
                min: center.map(|c| c - radius),
                max: center.map(|c| c + radius),
            }),
            Primitive::Frustum { start, end, r0, r1 } => {
                let axis = sub(end, start);
                let len = dot(&axis, &axis).sqrt();
                let mut b = Aabb::EMPTY;
                for (c, r) in [(start, r0), (end, r1)] {
                    for (k, &ck) in c.iter().enumerate() {
                        // A rim reaches r sqrt(1 - a_k^2 / L^2) = r |a with a_k dropped| / L
                        // along axis k; written without the cancellation in 1 - a_k^2 / L^2
                        // (which near an axis-aligned body could lose half the digits), each
                        // step is off by at most an ulp, and 1 + 2^-40 covers them all.
                        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                        let across = (axis[i] * axis[i] + axis[j] * axis[j]).sqrt();
                        let ext = r * (across / len).min(1.0) * (1.0 + 1.0 / (1u64 << 40) as f64);
                        b.min[k] = b.min[k].min(ck - ext);
                        b.max[k] = b.max[k].max(ck + ext);
                    }
                }
                grow(b)
            }
        }
    }

    /// The support point of the body in direction `v` (the point maximising `v . x`), for the
    /// convex distance test.
    pub fn support(&self, v: &[f64; 3]) -> [f64; 3] {
        match self {
            Primitive::Box { min, max } => {
                [0, 1, 2].map(|k| if v[k] >= 0.0 { max[k] } else { min[k] })
            }
            Primitive::Sphere { center, radius } => {
                let n = dot(v, v).sqrt();
                if n == 0.0 {
                    return *center;
                }
                [0, 1, 2].map(|k| center[k] + radius * v[k] / n)
            }
            Primitive::Frustum { start, end, r0, r1 } => {
                let axis = sub(end, start);
                let len2 = dot(&axis, &axis);
                let along = dot(v, &axis) / len2;
                let perp = [0, 1, 2].map(|k| v[k] - along * axis[k]);
                let pn = dot(&perp, &perp).sqrt();
                let disc = |c: &[f64; 3], r: f64| {
                    if pn == 0.0 {
                        *c
                    } else {
                        [0, 1, 2].map(|k| c[k] + r * perp[k] / pn)
                    }
                };
                let a = disc(start, *r0);
                let b = disc(end, *r1);
                if dot(v, &a) >= dot(v, &b) {
                    a
                } else {
                    b
                }
            }
        }
    }
}

/// Line against a cone frustum: the slab between the two cap planes intersected with the region
/// of the (double) cone through both rims; inside the slab the cone's radius is non-negative, so
/// the result is the frustum's single interval.
fn frustum_span(
    start: &[f64; 3],
    end: &[f64; 3],
    r0: f64,
    r1: f64,
    o: &[f64; 3],
    d: &[f64; 3],
) -> Span {
    let axis = sub(end, start);
    let len2 = dot(&axis, &axis);
    let w = sub(o, start);
    // Axial parameter s(t) = s0 + t ds, in [0, 1] inside the slab.
    let s0 = dot(&w, &axis) / len2;
    let ds = dot(d, &axis) / len2;
    let (mut t0, mut t1) = if ds == 0.0 {
        if !(0.0..=1.0).contains(&s0) {
            return None;
        }
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        let a = -s0 / ds;
        let b = (1.0 - s0) / ds;
        (a.min(b), a.max(b))
    };
    // Perpendicular offset x(t) = wp + t dp, radius r(s) = r0 + (r1 - r0) s.
    let wp = [0, 1, 2].map(|k| w[k] - s0 * axis[k]);
    let dp = [0, 1, 2].map(|k| d[k] - ds * axis[k]);
    let dr = r1 - r0;
    let rc = r0 + dr * s0; // radius at t = 0
    let rt = dr * ds; // radius change per unit t
                      // q(t) = |wp + t dp|^2 - (rc + t rt)^2 <= 0
    let qa = dot(&dp, &dp) - rt * rt;
    let qb = dot(&wp, &dp) - rc * rt; // half the linear coefficient
    let qc = dot(&wp, &wp) - rc * rc;
    let scale = dot(&dp, &dp) + rt * rt;
    if qa.abs() <= 1e-14 * scale {
        // Linear (a line parallel to a cone generator, or a cylinder along its axis).
        if qb == 0.0 {
            if qc > 0.0 {
                return None;
            }
        } else {
            let root = -qc / (2.0 * qb);
            if qb > 0.0 {
                t1 = t1.min(root);
            } else {
                t0 = t0.max(root);
            }
        }
        return (t0 <= t1).then_some((t0, t1));
    }
    let disc = qb * qb - qa * qc;
    if qa > 0.0 {
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let q = -(qb + qb.signum() * s);
        let (ra, rb) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            (q / qa, qc / q)
        };
        t0 = t0.max(ra.min(rb));
        t1 = t1.min(ra.max(rb));
        return (t0 <= t1).then_some((t0, t1));
    }
    // qa < 0: q <= 0 outside the roots (both nappes); the slab keeps only the frustum's nappe.
    if disc < 0.0 {
        return (t0 <= t1).then_some((t0, t1));
    }
    let s = disc.sqrt();
    let q = -(qb + qb.signum() * s);
    let (ra, rb) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / qa, qc / q)
    };
    let (lo, hi) = (ra.min(rb), ra.max(rb));
    let left = (t0, t1.min(lo));
    let right = (t0.max(hi), t1);
    let lok = left.0 <= left.1;
    let rok = right.0 <= right.1;
    match (lok, rok) {
        (true, false) => Some(left),
        (false, true) => Some(right),
        (false, false) => None,
        (true, true) => {
            // Only rounding can leave both: keep the piece whose radius is positive.
            let mid = 0.5 * (left.0.max(-1e300) + left.1.min(1e300));
            if rc + mid * rt >= 0.0 {
                Some(left)
            } else {
                Some(right)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_span(p: &Primitive, o: [f64; 3], d: [f64; 3], expect: Span) {
        let got = p.line_span(&o, &d);
        match (got, expect) {
            (None, None) => {}
            (Some(g), Some(e)) => assert!(
                (g.0 - e.0).abs() < 1e-9 && (g.1 - e.1).abs() < 1e-9,
                "{p:?}: got {g:?} expected {e:?}"
            ),
            _ => panic!("{p:?}: got {got:?} expected {expect:?}"),
        }
    }

    #[test]
    fn spans_of_each_shape() {
        let bx = Primitive::Box {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        check_span(&bx, [-1.0, 0.5, 0.5], [1.0, 0.0, 0.0], Some((1.0, 2.0)));
        check_span(&bx, [-1.0, 1.5, 0.5], [1.0, 0.0, 0.0], None);
        let sp = Primitive::Sphere {
            center: [0.0; 3],
            radius: 2.0,
        };
        check_span(&sp, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0], Some((3.0, 7.0)));
        check_span(&sp, [0.0, 3.0, -5.0], [0.0, 0.0, 1.0], None);
        let cyl = Primitive::Frustum {
            start: [0.0; 3],
            end: [0.0, 0.0, 2.0],
            r0: 1.0,
            r1: 1.0,
        };
        check_span(&cyl, [-3.0, 0.0, 1.0], [1.0, 0.0, 0.0], Some((2.0, 4.0)));
        check_span(&cyl, [0.5, 0.0, -1.0], [0.0, 0.0, 1.0], Some((1.0, 3.0)));
        let cone = Primitive::Frustum {
            start: [0.0; 3],
            end: [0.0, 0.0, 2.0],
            r0: 2.0,
            r1: 0.0,
        };
        // At height 1 the radius is 1.
        check_span(&cone, [-3.0, 0.0, 1.0], [1.0, 0.0, 0.0], Some((2.0, 4.0)));
        // Along a line through the apex region, beyond the slab nothing (other nappe excluded).
        check_span(&cone, [0.0, 0.0, -1.0], [0.0, 0.0, 1.0], Some((1.0, 3.0)));
        // radius 2 - z: at y = 1.5 inside for z <= 0.5.
        check_span(&cone, [0.0, 1.5, 3.0], [0.0, 0.0, -1.0], Some((2.5, 3.0)));
        // Slanted line through the far nappe only: nothing.
        check_span(&cone, [-5.0, 0.0, 4.0], [1.0, 0.0, 0.0], None);
    }

    #[test]
    fn spans_agree_with_contains() {
        let bodies = [
            Primitive::Box {
                min: [-0.3, 0.1, -1.0],
                max: [0.7, 0.9, 0.2],
            },
            Primitive::Sphere {
                center: [0.1, 0.2, -0.1],
                radius: 0.6,
            },
            Primitive::Frustum {
                start: [0.0, -0.5, 0.0],
                end: [0.3, 0.6, 0.2],
                r0: 0.4,
                r1: 0.1,
            },
            Primitive::Frustum {
                start: [0.2, 0.0, -0.4],
                end: [-0.2, 0.1, 0.5],
                r0: 0.3,
                r1: 0.3,
            },
        ];
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for b in &bodies {
            for _ in 0..300 {
                let o = [rnd() * 2.0, rnd() * 2.0, rnd() * 2.0];
                let d = [rnd(), rnd(), rnd()];
                let span = b.line_span(&o, &d);
                for i in 0..50 {
                    let t = -4.0 + 8.0 * i as f64 / 49.0;
                    let p = [0, 1, 2].map(|k| o[k] + t * d[k]);
                    let inside = b.contains(&p);
                    let in_span = span.is_some_and(|(a, c)| a <= t && t <= c);
                    let near =
                        span.is_some_and(|(a, c)| (t - a).abs() < 1e-9 || (t - c).abs() < 1e-9);
                    assert!(
                        inside == in_span || near,
                        "{b:?} o {o:?} d {d:?} t {t} span {span:?}"
                    );
                    if inside {
                        let bb = b.bounds();
                        assert!(bb.contains(&p));
                    }
                }
            }
        }
    }
}
