//! Floats carrying a bound on their rounding error (a static filter in the style of Shewchuk's
//! and FPG's): the cheap first stage in front of intervals and exact dyadic arithmetic.
//!
//! Each value is the float result `v` of a straight-line program of `+`, `-`, `*` on leaves,
//! with `m`, the same program evaluated on the leaves' magnitudes with every `-` taken as `+`,
//! and `k`, the longest chain of roundings behind it (a leaf that is a rounded difference counts
//! one, a sum adds one to the larger of its operands', a product adds one to the sum of its
//! operands'). Then `|v - exact| <= k u' M` to first order, `u' = 2^-53` plus the underflow term
//! below, and `M <= m (1 + k u)`, so `(k + 2) 2^-51 m` bounds the error with room to spare.
//!
//! Underflow: every leaf is 0 or has magnitude in `[2^-45, 2]` (the caller scales its leaves by a
//! power of two, [`Fb::scaled_diff`]), and no predicate has degree over 20, so a non-zero `M` is at least
//! `2^-900` and an underflowed operation's absolute error (at most `2^-1075`) is below
//! `2^-175 M`; nothing overflows (`M < 2^60`). A leaf outside that range poisons the value (its
//! sign is unknown, the caller moves on to intervals).

use super::exact::Arith;

/// Smallest and largest magnitude of a non-zero leaf.
const LEAF_MIN: f64 = 1.0 / (1u64 << 45) as f64;
const LEAF_MAX: f64 = 2.0;

#[derive(Clone, Copy, Debug)]
pub struct Fb {
    v: f64,
    m: f64,
    k: u32,
}

const POISON: Fb = Fb {
    v: f64::NAN,
    m: f64::NAN,
    k: 0,
};

impl Fb {
    fn leaf(x: f64, k: u32) -> Fb {
        if x == 0.0 {
            Fb {
                v: 0.0,
                m: 0.0,
                k: 0,
            }
        } else if (LEAF_MIN..=LEAF_MAX).contains(&x.abs()) {
            Fb {
                v: x,
                m: x.abs(),
                k,
            }
        } else {
            POISON
        }
    }

    #[cfg(test)]
    fn of(x: f64) -> Fb {
        Fb::leaf(x, 0)
    }

    /// The leaf `(x - y) s` for a power of two `s`: the product is exact (in range, it is
    /// normal), so the only rounding is the difference's.
    pub fn scaled_diff(x: f64, y: f64, s: f64) -> Fb {
        Fb::leaf((x - y) * s, 1)
    }

    /// The power of two that brings `max` (the largest leaf magnitude of a predicate) into
    /// `[1, 2)`, or `None` for zero, subnormal or non-finite `max`.
    pub fn scale_for(max: f64) -> Option<f64> {
        if !(max.is_normal()) {
            return None;
        }
        let e = ((max.to_bits() >> 52) & 0x7ff) as i64; // biased exponent, 1..=2046
        let s = 2046 - e; // biased exponent of 2^-(e - 1023)
        (1..=2046)
            .contains(&s)
            .then(|| f64::from_bits((s as u64) << 52))
    }
}

impl Arith for Fb {
    fn diff(x: f64, y: f64) -> Fb {
        Fb::leaf(x - y, 1)
    }

    fn add(&self, o: &Fb) -> Fb {
        Fb {
            v: self.v + o.v,
            m: self.m + o.m,
            k: self.k.max(o.k) + 1,
        }
    }

    fn sub(&self, o: &Fb) -> Fb {
        Fb {
            v: self.v - o.v,
            m: self.m + o.m,
            k: self.k.max(o.k) + 1,
        }
    }

    fn mul(&self, o: &Fb) -> Fb {
        Fb {
            v: self.v * o.v,
            m: self.m * o.m,
            k: self.k + o.k + 1,
        }
    }

    fn neg(&self) -> Fb {
        Fb {
            v: -self.v,
            m: self.m,
            k: self.k,
        }
    }

    fn sign(&self) -> Option<i32> {
        // NaN (a poisoned leaf) fails every comparison: unknown.
        let err = self.m * (self.k + 2) as f64 * (1.0 / (1u64 << 51) as f64);
        if self.v > err {
            Some(1)
        } else if self.v < -err {
            Some(-1)
        } else if self.m == 0.0 {
            Some(0)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signs_are_certain_or_unknown() {
        let s = Fb::of(0.1).mul(&Fb::of(3.0)).sub(&Fb::of(0.3));
        assert_eq!(s.sign(), None); // 0.1 * 3 - 0.3 is 2^-54 in floats, not settled
        let t = Fb::of(0.5).mul(&Fb::of(1.5)).sub(&Fb::of(0.25));
        assert_eq!(t.sign(), Some(1));
        assert_eq!(Fb::of(0.0).mul(&Fb::of(1.5)).sign(), Some(0));
        assert_eq!(Fb::diff(1.5, 1.5).sign(), Some(0));
        // Leaves out of range poison.
        assert_eq!(Fb::of(1e-20).sign(), None);
        assert_eq!(Fb::of(3.0).add(&Fb::of(1.0)).sign(), None);
        assert_eq!(Fb::scale_for(3.0), Some(0.5));
        assert_eq!(Fb::scale_for(1e-300).map(|s| s * 1e-300 >= 1.0), Some(true));
        assert_eq!(Fb::scale_for(0.0), None);
        assert_eq!(Fb::scale_for(f64::INFINITY), None);
    }
}
