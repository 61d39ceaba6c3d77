//! Outward-rounded f64 intervals: the proven floating-point filter in front of the exact dyadic
//! predicates (a sign the interval cannot settle sends the caller to exact arithmetic).

use super::exact::Arith;

/// A closed interval `[lo, hi]` that contains the exact value of the expression that built it.
/// An overflow or an undefined operation leaves `lo = hi = NaN`, whose sign is unknown.
#[derive(Clone, Copy, Debug)]
pub struct Interval {
    lo: f64,
    hi: f64,
}

const UNKNOWN: Interval = Interval {
    lo: f64::NAN,
    hi: f64::NAN,
};

impl Interval {
    /// Round-to-nearest is off by at most half a unit in the last place, so one step outwards
    /// on each side bounds the exact result (subnormals included).
    fn widen(lo: f64, hi: f64) -> Interval {
        let (lo, hi) = (lo.next_down(), hi.next_up());
        if lo.is_finite() && hi.is_finite() {
            Interval { lo, hi }
        } else {
            UNKNOWN
        }
    }

    #[cfg(test)]
    fn of(x: f64) -> Interval {
        Interval::diff(x, 0.0)
    }

    #[cfg(test)]
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }
}

impl Arith for Interval {
    /// `x - y` of two floats: the rounding error is known exactly (Knuth's two-sum), so an exact
    /// difference (the common case for nearby coordinates) stays a point.
    fn diff(x: f64, y: f64) -> Interval {
        let s = x - y;
        if !s.is_finite() {
            return UNKNOWN;
        }
        let yy = -y;
        let bv = s - x;
        let av = s - bv;
        let err = (x - av) + (yy - bv);
        if err > 0.0 {
            Interval::widen(s, s).max_lo(s)
        } else if err < 0.0 {
            Interval::widen(s, s).min_hi(s)
        } else {
            Interval { lo: s, hi: s }
        }
    }

    fn add(&self, o: &Interval) -> Interval {
        Interval::widen(self.lo + o.lo, self.hi + o.hi)
    }

    fn sub(&self, o: &Interval) -> Interval {
        Interval::widen(self.lo - o.hi, self.hi - o.lo)
    }

    fn mul(&self, o: &Interval) -> Interval {
        // An interval is either finite at both ends or NaN at both, so the products are all
        // finite or all NaN, and min/max cannot drop a NaN.
        let (a, b, c, d) = (
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        );
        let lo = a.min(b).min(c.min(d));
        let hi = a.max(b).max(c.max(d));
        if lo == hi && is_exact_product(self, o, lo) {
            return Interval { lo, hi };
        }
        Interval::widen(lo, hi)
    }

    fn neg(&self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }

    fn sign(&self) -> Option<i32> {
        if self.lo > 0.0 {
            Some(1)
        } else if self.hi < 0.0 {
            Some(-1)
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Some(0)
        } else {
            None
        }
    }
}

impl Interval {
    fn max_lo(self, lo: f64) -> Interval {
        Interval {
            lo: self.lo.max(lo),
            hi: self.hi,
        }
    }

    fn min_hi(self, hi: f64) -> Interval {
        Interval {
            lo: self.lo,
            hi: self.hi.min(hi),
        }
    }
}

/// A product of two points that is exactly zero (a zero factor) needs no widening, so exact
/// zeros (coordinates on an axis, a vertex on a cap plane) keep a known sign.
fn is_exact_product(a: &Interval, b: &Interval, p: f64) -> bool {
    p == 0.0 && ((a.lo == 0.0 && a.hi == 0.0) || (b.lo == 0.0 && b.hi == 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encloses_exact_results() {
        // 0.1 + 0.2 is inexact; the interval holds both neighbours of the rounded sum.
        let s = Interval::of(0.1).add(&Interval::of(0.2));
        assert!(s.lo < 0.30000000000000004 && s.hi >= 0.30000000000000004);
        assert_eq!(s.sign(), Some(1));
        // An exact difference stays a point; an inexact one brackets the true value.
        let d = Interval::diff(8_388_608.25, 8_388_605.25);
        assert_eq!((d.lo, d.hi), (3.0, 3.0));
        let e = Interval::diff(1.0, 1e-20);
        assert!(e.lo < 1.0 && e.hi == 1.0);
        let f = Interval::diff(1e-20, 1.0);
        assert!(f.lo == -1.0 && f.hi > -1.0);
        // Exact zeros keep their sign; a cancellation that is not exact stays unknown.
        let z = Interval::of(0.0).mul(&Interval::of(3.5));
        assert_eq!(z.sign(), Some(0));
        let c = Interval::of(0.1)
            .mul(&Interval::of(3.0))
            .sub(&Interval::of(0.3));
        assert_eq!(c.sign(), None);
        // Overflow is unknown, never a wrong sign.
        let big = Interval::of(1e200).mul(&Interval::of(1e200));
        assert_eq!(big.sign(), None);
        assert_eq!(big.mul(&Interval::of(0.0)).sign(), None);
        assert_eq!(Interval::of(f64::INFINITY).sign(), None);
        // Subnormal products are bracketed too.
        let t = Interval::of(1e-200).mul(&Interval::of(1e-200));
        assert!(t.contains(0.0) || t.lo > 0.0);
        assert_ne!(t.sign(), Some(-1));
    }
}
