//! Exact certification of a complementary basis.
//!
//! Every finite `f64` is a dyadic rational `m·2^e`, so the LCP given by the
//! floats `(M, q)` has an exact meaning. For a complementary basis
//! `α = {j : basis[j]}` this module solves `M_αα z_α = −q_α` in exact integer
//! arithmetic (fraction-free Bareiss elimination on `BigInt`), sets `z_ᾱ = 0`,
//! computes `w = M z + q` exactly and checks `z ≥ 0`, `w ≥ 0`, `z_i w_i = 0`
//! with no tolerance at all. A [`CertStatus::Certified`] answer is a proof that
//! this basis solves the LCP *of the floats as given*; a float solver's `z` is
//! then at most its own round-off away from an exact solution, and
//! [`Certificate::z`] (the exact `z` rounded to nearest) measures how far.
//!
//! Degenerate problems need more than a yes or no. A contact LCP's
//! `A = J M_b⁻¹ Jᵀ` is rank-deficient in real arithmetic, so at a sticking or
//! resting contact several nonbasic `w_i` (or basic `z_i`) are exactly 0 *for
//! the exact data*; the rounded floats make them ±1e-17 instead, and about half
//! of those come out negative. No basis fixes that (adding such an index makes
//! `M_αα` nearly singular and `z` meaningless). So the certificate also reports
//! the exact natural residual and a componentwise backward error
//! ([`Certificate::backward_error`]): a nonnegative rational `z̃` near the
//! exact `z` solves *exactly* an LCP whose every entry of `M` and `q` differs
//! from the given float by at most that relative amount. A value of a few
//! 2⁻⁵³ means "exact up to the rounding already in the data".
//!
//! Power-of-two row and column scalings (exact) turn the system into integers
//! with few bits, so `n = 40` takes milliseconds (see the `certify` tests).
//!
//! Why a nearby basis does not help (measured, not assumed): at a sticking
//! contact the `k` friction columns span only a 2-D tangent space, so the
//! Schur complement of `M_αα` on the degenerate indices is exactly 0 for the
//! exact data and rounding noise (~1e-17, either sign) for the floats; a
//! basis that differs there solves a tiny LCP of noise over noise and moves
//! `z` by about its own size. A bounded search (all violators flipped, each
//! alone, each with one other degenerate index; each candidate checked
//! exactly and kept only if its exact `z`, `w` lie within 1e-9 of the given
//! basis's) certified 3 more of the cube corpus's 8,913 answers (4,802 →
//! 4,805) at 2.7× the certification time; exhaustive enumeration of all flips
//! on a 600-LCP sample found no certifying basis for 107 of 119 failing
//! 1-contact LCPs, and the others were 1–100 % away. Those are exact solutions
//! of the rounded LCP, not certificates of the answer, so no search is done
//! and η and the exact residual are the honest statement for the rest.

use std::cmp::Ordering;

use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::{ToPrimitive, Zero};

use crate::problem::Lcp;

/// Outcome of an exact check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CertStatus {
    /// `z ≥ 0`, `w ≥ 0` and `z_i w_i = 0` hold exactly for the floats as given.
    Certified,
    /// The basis is nonsingular but its solution is not one of the LCP; the
    /// first offending index (by index, `z` before `w`).
    Violated(Violation),
    /// `M_αα` is exactly singular: the basis determines no unique `z`.
    Singular,
}

/// Which condition an exact solution breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViolationKind {
    /// `z_i < 0` (only basic `z_i` can be).
    NegativeZ,
    /// `w_i < 0` (only nonbasic `w_i` can be).
    NegativeW,
    /// `z_i w_i ≠ 0`: cannot happen for an exact basis solve; reported rather
    /// than asserted so that a defect here can never pass as a certificate.
    Complementarity,
}

/// One violated condition of an exact basis solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Violation {
    /// Index `i` of `z_i` / `w_i`.
    pub index: usize,
    pub kind: ViolationKind,
    /// The exact offending value (`z_i`, `w_i` or `z_i w_i`) rounded to nearest.
    pub value: f64,
}

/// The result of [`certify`], [`certify_against`] or [`certify_z`].
#[derive(Clone, Debug, PartialEq)]
pub struct Certificate {
    pub status: CertStatus,
    /// The basis that was checked (`basis[j]`: `z_j` basic).
    pub basis: Vec<bool>,
    /// The exact solution of the basis, each entry rounded to the nearest
    /// `f64` (0 exactly off the basis). Empty when [`CertStatus::Singular`].
    pub z: Vec<f64>,
    /// The exact `w = M z + q`, rounded to nearest (0 exactly on the basis).
    /// Empty when [`CertStatus::Singular`].
    pub w: Vec<f64>,
    /// How many indices violate `z_i ≥ 0`, `w_i ≥ 0` or `z_i w_i = 0` (0 unless `Violated`).
    pub violations: usize,
    /// Bit length of the exact (scaled, integer) determinant of `M_αα`: the
    /// size of the arithmetic, a rough measure of how ill-posed the basis is.
    pub det_bits: u64,
    /// `‖min(z, w)‖∞` of the exact solution (the largest negative part of
    /// `z` or `w`), rounded: 0 exactly when certified; infinite when singular.
    pub natural_residual: f64,
    /// Componentwise (Oettli–Prager) backward error: the smallest `η` found
    /// such that some `z̃ ≥ 0` solves the LCP of `(M + ΔM, q + Δq)` exactly
    /// with `|ΔM| ≤ η|M|`, `|Δq| ≤ η|q|` entrywise. `z̃` is the exact `z` with
    /// its negative entries, and then its entries below 1e-15, 1e-12 or 1e-9
    /// of `‖z‖∞`, set to 0 (the smallest `η` of these candidates; the residual
    /// of each is exact, the ratio evaluated in floating point). 0 when
    /// certified; ~2⁻⁵³ when only the rounding of degenerate data stands in
    /// the way; order 1 for a wrong basis; infinite when `M_αα` is singular.
    pub backward_error: f64,
    /// [`certify_against`], [`certify_z`]: `max_j |z_j − z_given_j|` between
    /// the rounded exact `z` and the float `z` given (NaN if it holds a NaN).
    pub z_error: Option<f64>,
}

impl Certificate {
    /// `true` only for [`CertStatus::Certified`].
    pub fn certified(&self) -> bool {
        self.status == CertStatus::Certified
    }

    /// Certified, or an exact solution of data within a relative `eta` of the
    /// floats given (see [`Certificate::backward_error`]).
    pub fn certified_within(&self, eta: f64) -> bool {
        self.backward_error <= eta
    }
}

/// Checks the complementary basis `α = {j : basis[j]}` exactly (see the module docs).
///
/// # Panics
/// If `basis.len() != lcp.n()` (a caller error, not a numerical one).
pub fn certify(lcp: &Lcp, basis: &[bool]) -> Certificate {
    assert_eq!(basis.len(), lcp.n(), "certify: basis has {} entries for an LCP of size {}", basis.len(), lcp.n());
    let alpha: Vec<usize> = (0..lcp.n()).filter(|&j| basis[j]).collect();
    match solve_exact(lcp, &alpha) {
        None => Certificate {
            status: CertStatus::Singular,
            basis: basis.to_vec(),
            z: Vec::new(),
            w: Vec::new(),
            violations: 0,
            det_bits: 0,
            natural_residual: f64::INFINITY,
            backward_error: f64::INFINITY,
            z_error: None,
        },
        Some(exact) => check(lcp, basis, &alpha, &exact),
    }
}

/// [`certify`], and also compares the exact solution with a float `z`
/// (`Certificate::z_error`).
///
/// # Panics
/// If `basis` or `z` do not have `lcp.n()` entries.
pub fn certify_against(lcp: &Lcp, basis: &[bool], z: &[f64]) -> Certificate {
    assert_eq!(z.len(), lcp.n(), "certify_against: z has {} entries for an LCP of size {}", z.len(), lcp.n());
    let mut c = certify(lcp, basis);
    if c.status != CertStatus::Singular {
        c.z_error =
            Some(
                c.z.iter()
                    .zip(z)
                    .fold(0.0f64, |e, (a, b)| if (a - b).is_nan() { f64::NAN } else { e.max((a - b).abs()) }),
            );
    }
    c
}

/// Certifies the support of a float `z`: the basis `{j : z_j > 0}`, compared with `z`.
///
/// # Panics
/// If `z.len() != lcp.n()`.
pub fn certify_z(lcp: &Lcp, z: &[f64]) -> Certificate {
    let basis: Vec<bool> = z.iter().map(|&v| v > 0.0).collect();
    certify_against(lcp, &basis, z)
}

/// A finite `f64` as `m·2^e` with `m` odd (or 0).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dyadic {
    pub(crate) m: i64,
    pub(crate) e: i64,
}

impl Dyadic {
    pub(crate) fn of(x: f64) -> Dyadic {
        let bits = x.to_bits();
        let field = ((bits >> 52) & 0x7ff) as i64;
        let frac = (bits & ((1u64 << 52) - 1)) as i64;
        // Subnormals have no hidden bit and the exponent of the smallest normal.
        let (m, e) = if field == 0 { (frac, -1074) } else { (frac | (1i64 << 52), field - 1075) };
        if m == 0 {
            return Dyadic { m: 0, e: 0 };
        }
        let tz = m.trailing_zeros() as i64;
        let m = m >> tz;
        Dyadic { m: if x < 0.0 { -m } else { m }, e: e + tz }
    }

    pub(crate) fn is_zero(self) -> bool {
        self.m == 0
    }

    /// Exponent of the leading bit plus one: `|x| < 2^top`.
    fn top(self) -> i64 {
        self.e + (64 - self.m.unsigned_abs().leading_zeros()) as i64
    }
}

/// The exact solution of a basis: `z_α[r] = x[r] · 2^(col_exp[r]) / det` with `det > 0`.
struct Exact {
    x: Vec<BigInt>,
    col_exp: Vec<i64>,
    det: BigInt,
}

/// Solves `M_αα z_α = −q_α` exactly; `None` if `M_αα` is singular.
fn solve_exact(lcp: &Lcp, alpha: &[usize]) -> Option<Exact> {
    let m = alpha.len();
    if m == 0 {
        return Some(Exact { x: Vec::new(), col_exp: Vec::new(), det: BigInt::from(1) });
    }
    let width = m + 1;
    // Scaled system A C y = 2^β b with C = diag(2^γ_j): every column's (and the
    // right side's) largest entry below 1, so the integer rows need few bits.
    let entry = |r: usize, c: usize| -> Dyadic {
        if c < m {
            Dyadic::of(lcp.at(alpha[r], alpha[c]))
        } else {
            Dyadic::of(-lcp.q()[alpha[r]])
        }
    };
    let mut shift = vec![0i64; width];
    for (c, s) in shift.iter_mut().enumerate() {
        let top = (0..m).map(|r| entry(r, c)).filter(|d| !d.is_zero()).map(Dyadic::top).max();
        match top {
            Some(t) => *s = -t,
            None if c < m => return None, // a zero column
            None => {}
        }
    }
    // Integer rows: each row times 2^(−its smallest exponent).
    let mut a: Vec<BigInt> = Vec::with_capacity(m * width);
    for r in 0..m {
        let row: Vec<(Dyadic, i64)> = (0..width).map(|c| (entry(r, c), shift[c])).collect();
        let emin = row.iter().filter(|(d, _)| !d.is_zero()).map(|(d, s)| d.e + s).min().unwrap_or(0);
        a.extend(row.iter().map(|&(d, s)| {
            if d.is_zero() {
                BigInt::zero()
            } else {
                BigInt::from(d.m) << (d.e + s - emin) as usize
            }
        }));
    }

    // Fraction-free (Bareiss) elimination: every entry stays an integer minor.
    let mut prev = BigInt::from(1);
    for k in 0..m {
        // Pivot: the nonzero entry with the fewest bits keeps the products small.
        let p = (k..m).filter(|&r| !a[r * width + k].is_zero()).min_by_key(|&r| a[r * width + k].bits())?;
        if p != k {
            for c in 0..width {
                a.swap(p * width + c, k * width + c);
            }
        }
        let akk = a[k * width + k].clone();
        for r in k + 1..m {
            let ark = std::mem::take(&mut a[r * width + k]);
            let (top, rest) = a.split_at_mut(r * width);
            let pivot_row = &top[k * width..(k + 1) * width];
            for (v, akc) in rest[k + 1..width].iter_mut().zip(&pivot_row[k + 1..]) {
                *v *= &akk;
                if !ark.is_zero() && !akc.is_zero() {
                    *v -= &ark * akc;
                }
                if k > 0 {
                    *v /= &prev;
                }
            }
        }
        prev = akk;
    }
    let mut det = prev;

    // Back substitution on x = det · y (Cramer's numerators, integers).
    let mut x = vec![BigInt::zero(); m];
    for r in (0..m).rev() {
        let mut t = &det * &a[r * width + m];
        for c in r + 1..m {
            let arc = &a[r * width + c];
            if !arc.is_zero() && !x[c].is_zero() {
                t -= arc * &x[c];
            }
        }
        x[r] = t / &a[r * width + r];
    }
    if det.sign() == Sign::Minus {
        det = -det;
        x.iter_mut().for_each(|v| *v = -std::mem::take(v));
    }
    // z_α[c] = 2^(γ_c − β) y_c.
    let col_exp = (0..m).map(|c| shift[c] - shift[m]).collect();
    Some(Exact { x, col_exp, det })
}

/// Computes `w = M z + q` exactly and checks the LCP conditions.
fn check(lcp: &Lcp, basis: &[bool], alpha: &[usize], ex: &Exact) -> Certificate {
    let n = lcp.n();
    let mut z = vec![0.0; n];
    let mut z_sign = vec![Ordering::Equal; n];
    for (r, &j) in alpha.iter().enumerate() {
        z[j] = ratio_to_f64(&ex.x[r], &ex.det, ex.col_exp[r]);
        z_sign[j] = sign(&ex.x[r]);
    }
    let (w, w_sign) = exact_w(lcp, alpha, &ex.x, ex);

    let mut first: Option<Violation> = None;
    let mut violations = 0;
    for i in 0..n {
        let found = if z_sign[i] == Ordering::Less {
            Some((ViolationKind::NegativeZ, z[i]))
        } else if w_sign[i] == Ordering::Less {
            Some((ViolationKind::NegativeW, w[i]))
        } else if z_sign[i] != Ordering::Equal && w_sign[i] != Ordering::Equal {
            Some((ViolationKind::Complementarity, z[i] * w[i]))
        } else {
            None
        };
        if let Some((kind, value)) = found {
            violations += 1;
            first.get_or_insert(Violation { index: i, kind, value });
        }
    }
    let natural_residual = z.iter().chain(&w).fold(0.0f64, |a, &v| a.max(-v));
    let backward_error = if first.is_none() { 0.0 } else { backward_error(lcp, alpha, ex, &z) };
    Certificate {
        status: first.map_or(CertStatus::Certified, CertStatus::Violated),
        basis: basis.to_vec(),
        z,
        w,
        violations,
        det_bits: ex.det.bits(),
        natural_residual,
        backward_error,
        z_error: None,
    }
}

/// `w = M z + q` for `z_α[r] = x[r]·2^(col_exp[r])/det`, rounded, with its exact signs.
fn exact_w(lcp: &Lcp, alpha: &[usize], x: &[BigInt], ex: &Exact) -> (Vec<f64>, Vec<Ordering>) {
    let n = lcp.n();
    let mut w = vec![0.0; n];
    let mut w_sign = vec![Ordering::Equal; n];
    // det·w_i = Σ_r M_{i,α_r} 2^(col_exp_r) x_r + q_i det: dyadics times integers.
    let mut terms: Vec<(i64, i64, &BigInt)> = Vec::with_capacity(alpha.len() + 1);
    for i in 0..n {
        terms.clear();
        for (r, &j) in alpha.iter().enumerate() {
            let d = Dyadic::of(lcp.at(i, j));
            if !d.is_zero() && !x[r].is_zero() {
                terms.push((d.m, d.e + ex.col_exp[r], &x[r]));
            }
        }
        let dq = Dyadic::of(lcp.q()[i]);
        if !dq.is_zero() {
            terms.push((dq.m, dq.e, &ex.det));
        }
        let Some(emin) = terms.iter().map(|t| t.1).min() else { continue };
        let mut acc = BigInt::zero();
        for &(mant, e, v) in &terms {
            acc += (v * mant) << (e - emin) as usize;
        }
        w[i] = ratio_to_f64(&acc, &ex.det, emin);
        w_sign[i] = sign(&acc);
    }
    (w, w_sign)
}

/// Relative thresholds (of `‖z‖∞`) below which [`backward_error`] tries setting `z_j` to 0.
const ZERO_CANDIDATES: [f64; 4] = [0.0, 1e-15, 1e-12, 1e-9];

/// Smallest Oettli–Prager backward error over the candidates `z̃` (see
/// [`Certificate::backward_error`]): for `z̃ ≥ 0` and `r = M z̃ + q` (exact),
/// row `i` needs `r_i = 0` if `z̃_i > 0` and `r_i ≥ 0` otherwise, which a
/// relative perturbation `η` of row `i` of `(M, q)` achieves iff
/// `|r_i − target| ≤ η·(Σ_j |M_ij| z̃_j + |q_i|)`.
fn backward_error(lcp: &Lcp, alpha: &[usize], ex: &Exact, z: &[f64]) -> f64 {
    let zmax = z.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut best = f64::INFINITY;
    let mut last: Option<Vec<bool>> = None;
    for tau in ZERO_CANDIDATES {
        let keep: Vec<bool> = alpha.iter().map(|&j| z[j] > tau * zmax).collect();
        if last.as_ref() == Some(&keep) {
            continue;
        }
        let x: Vec<BigInt> =
            ex.x.iter()
                .zip(&keep)
                .map(|(v, &k)| if k && v.sign() == Sign::Plus { v.clone() } else { BigInt::zero() })
                .collect();
        let (r, _) = exact_w(lcp, alpha, &x, ex);
        let mut zt = vec![0.0; lcp.n()];
        let mut positive = vec![false; lcp.n()];
        for (k, &j) in alpha.iter().enumerate() {
            zt[j] = ratio_to_f64(&x[k], &ex.det, ex.col_exp[k]);
            positive[j] = !x[k].is_zero();
        }
        let mut eta = 0.0f64;
        for (i, &ri) in r.iter().enumerate() {
            let need = if positive[i] { ri.abs() } else { (-ri).max(0.0) };
            if need > 0.0 {
                let size = alpha.iter().map(|&j| lcp.at(i, j).abs() * zt[j]).sum::<f64>() + lcp.q()[i].abs();
                eta = eta.max(if size > 0.0 { need / size } else { f64::INFINITY });
            }
        }
        best = best.min(eta);
        last = Some(keep);
    }
    best
}

fn sign(v: &BigInt) -> Ordering {
    match v.sign() {
        Sign::Minus => Ordering::Less,
        Sign::NoSign => Ordering::Equal,
        Sign::Plus => Ordering::Greater,
    }
}

/// `num · 2^exp2 / den` (`den > 0`) rounded to the nearest `f64`, ties to even,
/// subnormals and overflow included.
pub(crate) fn ratio_to_f64(num: &BigInt, den: &BigInt, exp2: i64) -> f64 {
    if num.is_zero() {
        return 0.0;
    }
    let neg = num.sign() == Sign::Minus;
    let v = magnitude_to_f64(num.magnitude(), den.magnitude(), exp2);
    if neg {
        -v
    } else {
        v
    }
}

fn magnitude_to_f64(a: &BigUint, b: &BigUint, exp2: i64) -> f64 {
    // v = a/b · 2^exp2 ∈ [2^(e−1), 2^(e+1)).
    let e = a.bits() as i64 - b.bits() as i64 + exp2;
    if e > 1025 {
        return f64::INFINITY;
    }
    if e < -1075 {
        return 0.0; // v < 2^−1075: rounds to zero
    }
    // Last kept bit at 2^ulp (53 bits, or the subnormal grid), one guard bit below.
    let ulp = (e - 1 - 52).max(-1074);
    let mut g = ulp - 1;
    let sh = exp2 - g;
    let (mut q, r) = if sh >= 0 { (a << sh as usize).div_rem(b) } else { a.div_rem(&(b << (-sh) as usize)) };
    let mut sticky = !r.is_zero();
    // v turned out to be ≥ 2^e: one bit too many.
    if q.bits() > 54 {
        sticky |= q.bit(0);
        q >>= 1u32;
        g += 1;
    }
    let round = q.bit(0);
    let mut m = (q >> 1u32).to_u64().unwrap_or(u64::MAX);
    if round && (sticky || m & 1 == 1) {
        m += 1;
    }
    ldexp(m as f64, g + 1)
}

/// `x · 2^e`, exact whenever the result is representable.
fn ldexp(mut x: f64, mut e: i64) -> f64 {
    while e > 1000 {
        x *= pow2(1000);
        e -= 1000;
        if x.is_infinite() {
            return x;
        }
    }
    while e < -1000 {
        x *= pow2(-1000);
        e += 1000;
    }
    x * pow2(e)
}

/// `2^e` for `−1022 ≤ e ≤ 1023`.
fn pow2(e: i64) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dyadic_round_trips() {
        for &x in &[1.0, -3.5, 0.1, 1e-300, 5e-324, f64::MAX, -f64::MIN_POSITIVE, 2.0f64.powi(-1074) * 3.0] {
            let d = Dyadic::of(x);
            let back = ratio_to_f64(&BigInt::from(d.m), &BigInt::from(1), d.e);
            assert_eq!(back, x, "{x:e}");
        }
        assert!(Dyadic::of(0.0).is_zero() && Dyadic::of(-0.0).is_zero());
    }

    #[test]
    fn ratio_rounds_like_ieee_division() {
        // a/b in f64 is correctly rounded for exact a, b: the reference.
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..20000 {
            let a = (next() >> (11 + next() % 40)) as i64 + 1;
            let b = (next() >> (11 + next() % 40)) as i64 + 1;
            let e = (next() % 2200) as i64 - 1100;
            let want = (a as f64 / b as f64) * 1.0; // exact a, b (< 2^53)
            let got = ratio_to_f64(&BigInt::from(a), &BigInt::from(b), 0);
            assert_eq!(got, want, "{a}/{b}");
            // Scaled by 2^e: compare against exact scaling where it stays normal.
            if (-1000..1000).contains(&e) && want * pow2(e) != 0.0 && (want * pow2(e)).is_normal() {
                assert_eq!(ratio_to_f64(&BigInt::from(a), &BigInt::from(b), e), want * pow2(e));
            }
        }
        // Subnormal ties: 2^−1075 rounds to 0 (even), 3·2^−1076 to 2^−1074.
        assert_eq!(ratio_to_f64(&BigInt::from(1), &BigInt::from(1), -1075), 0.0);
        assert_eq!(ratio_to_f64(&BigInt::from(3), &BigInt::from(1), -1076), 5e-324);
        assert_eq!(ratio_to_f64(&BigInt::from(3), &BigInt::from(1), -1075), 2.0 * 5e-324);
        assert_eq!(ratio_to_f64(&BigInt::from(1), &BigInt::from(3), 2000), f64::INFINITY);
        assert_eq!(ratio_to_f64(&BigInt::from(-7), &BigInt::from(2), 0), -3.5);
    }
}
