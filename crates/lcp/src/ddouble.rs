//! Double-double numbers: an unevaluated sum `hi + lo` of two `f64` with
//! `|lo| ≤ ½ ulp(hi)`, about 106 bits of significand (unit round-off
//! ~1.1e-32), built from the error-free transformations TwoSum and TwoProd
//! (`f64::mul_add`, one instruction where the CPU has FMA). The exponent
//! range is `f64`'s. Used where `f64` pivoting cannot resolve a problem but
//! exact rational arithmetic would cost too much (see `lemke::extended`).
//!
//! The operations are the "accurate" ones of Hida, Li and Bailey's QD
//! library: relative error of a few 2⁻¹⁰⁶ per operation.

use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo`, normalized (`hi` is the sum rounded to nearest).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Dd {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b = s + e` exactly (Knuth's TwoSum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly, given `|a| ≥ |b|` (Dekker's FastTwoSum).
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `a·b = p + e` exactly (barring underflow).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };

    #[inline]
    pub fn of(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    #[inline]
    fn norm(hi: f64, lo: f64) -> Dd {
        let (hi, lo) = quick_two_sum(hi, lo);
        Dd { hi, lo }
    }

    /// The nearest `f64` (to within one rounding of the sum).
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    #[inline]
    pub fn is_zero(self) -> bool {
        self.hi == 0.0
    }

    #[inline]
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// `self − a·b`, the elimination kernel.
    #[inline]
    pub fn sub_mul(self, a: Dd, b: Dd) -> Dd {
        self - a * b
    }

    /// `self·b` for an `f64` `b` (one TwoProd fewer than `Dd·Dd`).
    #[inline]
    pub fn mul_f64(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        Dd::norm(p, self.lo.mul_add(b, e))
    }
}

impl Neg for Dd {
    type Output = Dd;
    #[inline]
    fn neg(self) -> Dd {
        Dd { hi: -self.hi, lo: -self.lo }
    }
}

impl Add for Dd {
    type Output = Dd;
    #[inline]
    fn add(self, b: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let (s, e) = quick_two_sum(s, e + t);
        Dd::norm(s, e + f)
    }
}

impl Sub for Dd {
    type Output = Dd;
    #[inline]
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    #[inline]
    fn mul(self, b: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, b.hi);
        let e = self.hi.mul_add(b.lo, self.lo.mul_add(b.hi, e));
        Dd::norm(p, e)
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division in three `f64` quotient digits.
    #[inline]
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b.mul_f64(q1);
        let q2 = r.hi / b.hi;
        let r = r - b.mul_f64(q2);
        let q3 = r.hi / b.hi;
        let (q1, q2) = quick_two_sum(q1, q2);
        Dd { hi: q1, lo: q2 } + Dd::of(q3)
    }
}

impl PartialOrd for Dd {
    #[inline]
    fn partial_cmp(&self, b: &Dd) -> Option<Ordering> {
        match self.hi.partial_cmp(&b.hi)? {
            Ordering::Equal => self.lo.partial_cmp(&b.lo),
            o => Some(o),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carries_what_f64_drops() {
        // 1 + 2⁻⁸⁰ − 1 is 0 in f64, 2⁻⁸⁰ here.
        let tiny = 2f64.powi(-80);
        assert_eq!((Dd::ONE + Dd::of(tiny) - Dd::ONE).to_f64(), tiny);
        // (1 + 2⁻⁵⁰)² = 1 + 2⁻⁴⁹ + 2⁻¹⁰⁰ exactly (the last term lost in f64).
        let a = Dd::of(1.0 + 2f64.powi(-50));
        let sq = a * a - Dd::ONE - Dd::of(2f64.powi(-49));
        assert_eq!(sq.to_f64(), 2f64.powi(-100));
        // 1/3·3 = 1 to ~1e-32.
        let third = Dd::ONE / Dd::of(3.0);
        assert!((third * Dd::of(3.0) - Dd::ONE).to_f64().abs() < 1e-31);
        assert!(third.lo != 0.0 && (third.hi - 1.0 / 3.0).abs() == 0.0);
    }
}
