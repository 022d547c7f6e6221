//! Diagonal scaling of an LCP: `(M, q) ↦ (D_r M D_c, D_r q)`.
//!
//! For positive diagonal `D_r`, `D_c` the scaled LCP has exactly the solutions
//! `z' = D_c⁻¹ z`, `w' = D_r w` of the original one: `z' ≥ 0 ⇔ z ≥ 0`,
//! `w' = D_r (M D_c z' + q) = D_r w ≥ 0 ⇔ w ≥ 0`, and `z'_i w'_i = (r_i / c_i) z_i w_i`
//! vanishes exactly when `z_i w_i` does. So a solver may work on the scaled
//! problem and map its answer back with [`Scaling::z_back`] and
//! [`Scaling::w_back`]; only tolerances change meaning (a residual of ε in
//! scaled units is `ε / r_i` in `w` and `ε · c_i` in `z`).
//!
//! [`Scaling::ruiz`] (Ruiz equilibration, every factor a power of two, so
//! applying and undoing it is exact in floating point, barring
//! over/underflow) is built here; the friction-cone scaling of a contact LCP
//! (`D = diag(I, I, s·I)` on both sides: `fn`, `fd` unchanged, `λ_scaled = λ / s`)
//! is [`crate::contact::ContactLayout::cone_scaling`].

mod exponents;

use exponents::{Round, ZERO_EXPONENT};

use crate::problem::{Lcp, LcpError};

/// Row and column scale factors: the scaled problem is `D_r M D_c, D_r q` with
/// `D_r = diag(row)`, `D_c = diag(col)`. All factors should be positive and finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    pub row: Vec<f64>,
    pub col: Vec<f64>,
}

/// Exponent buffers of [`Scaling::ruiz_in`]: the binary exponents of every
/// entry of `M` (rows padded to whole registers) and the factor exponents
/// with a round's row and column maxima.
#[derive(Default)]
pub(crate) struct RuizBuffers {
    entries: Vec<i16>,
    factors: Vec<i16>,
}

/// Exponents beyond this are clamped so that `2^e` stays a normal, finite number.
const MAX_EXPONENT: i16 = 1000;

impl Scaling {
    /// No scaling: all factors 1.
    pub fn identity(n: usize) -> Self {
        Scaling { row: vec![1.0; n], col: vec![1.0; n] }
    }

    /// Problem size this scaling is for.
    pub fn n(&self) -> usize {
        self.row.len()
    }

    /// Ruiz equilibration of `M` (q plays no part): `iterations` rounds of
    /// dividing every row and every column of the current scaled matrix by the
    /// square root of its largest absolute entry, rows and columns updated
    /// simultaneously from the same matrix. Every factor is a power of two, so
    /// `D_r M D_c` is exact; the rounds work on binary exponents only (the
    /// largest entry of a row is taken as `2^e` with `e` the largest exponent,
    /// and `1/√2^e` rounded to the nearest power of two in log scale), which
    /// keeps them in vectorizable integer arithmetic. A row or column that is
    /// entirely zero keeps factor 1. For symmetric `M` the result is symmetric
    /// (`row == col`). Stops early once a round changes nothing.
    pub fn ruiz(lcp: &Lcp, iterations: usize) -> Scaling {
        let mut scaling = Scaling { row: Vec::new(), col: Vec::new() };
        scaling.ruiz_in(lcp, iterations, &mut RuizBuffers::default());
        scaling
    }

    /// [`Scaling::ruiz`] into `self`'s vectors, with the exponent buffers `b`
    /// (a solver's workspace keeps both between solves).
    pub(crate) fn ruiz_in(&mut self, lcp: &Lcp, iterations: usize, b: &mut RuizBuffers) {
        let n = lcp.n();
        // Exponents as i16 (entries span ±1075, factors ±MAX_EXPONENT), rows
        // padded to whole registers (see `exponents`).
        let stride = n.next_multiple_of(exponents::LANES);
        let ex = &mut b.entries;
        ex.clear();
        ex.resize(n * stride, ZERO_EXPONENT);
        for (padded, row) in ex.chunks_exact_mut(stride).zip(lcp.m().chunks_exact(n)) {
            exponents::of_row(row, &mut padded[..n]);
        }
        // Factor exponents and the maxima of a round; the padding columns keep factor 2⁰.
        let exps = &mut b.factors;
        exps.clear();
        exps.resize(2 * n + 2 * stride, 0i16);
        let (row_exp, rest) = exps.split_at_mut(n);
        let (row_max, rest) = rest.split_at_mut(n);
        let (col_exp, col_max) = rest.split_at_mut(stride);
        for _ in 0..iterations {
            // Largest exponent of every row and column of the current D_r M D_c.
            exponents::maxima(Round { ex, row_exp, col_exp, floor: ZERO_EXPONENT }, row_max, col_max);
            let rows_moved = step_toward_one(row_exp, row_max);
            if !(step_toward_one(&mut col_exp[..n], &col_max[..n]) | rows_moved) {
                break;
            }
        }
        let pow = |e: &i16| pow2(*e as i32);
        self.row.clear();
        self.row.extend(row_exp.iter().map(pow));
        self.col.clear();
        self.col.extend(col_exp[..n].iter().map(pow));
    }

    /// No scaling of size `n`, into `self`'s vectors.
    pub(crate) fn identity_in(&mut self, n: usize) {
        for v in [&mut self.row, &mut self.col] {
            v.clear();
            v.resize(n, 1.0);
        }
    }

    /// `(D_r M D_c, D_r q)`, or an error when the sizes do not match `lcp` or
    /// a scaled entry is not finite (overflow, or a non-finite factor).
    pub fn try_apply(&self, lcp: &Lcp) -> Result<Lcp, LcpError> {
        let n = lcp.n();
        if self.row.len() != n || self.col.len() != n {
            let wrong = if self.row.len() != n { self.row.len() } else { self.col.len() };
            return Err(LcpError::LengthMismatch { q_len: wrong, n });
        }
        let mut m = Vec::with_capacity(n * n);
        for i in 0..n {
            let ri = self.row[i];
            m.extend(lcp.row(i).iter().zip(&self.col).map(|(&mij, &cj)| ri * mij * cj));
        }
        let q = lcp.q().iter().zip(&self.row).map(|(&qi, &ri)| ri * qi).collect();
        Lcp::new(m, q)
    }

    /// `(D_r M D_c, D_r q)`.
    ///
    /// # Panics
    /// If the scaling has the wrong size for `lcp` or produces a non-finite
    /// entry; scalings from [`Scaling::ruiz`] of the same problem never do.
    /// Use [`Scaling::try_apply`] for untrusted factors.
    pub fn apply(&self, lcp: &Lcp) -> Lcp {
        match self.try_apply(lcp) {
            Ok(scaled) => scaled,
            Err(e) => panic!("Scaling::apply: {e}"),
        }
    }

    /// `(D_r M D_c, qf·D_r q)` in one pass without re-validation, for factors
    /// that are powers of two (Ruiz): the result is then exact. An overflow
    /// shows up as non-finite entries, which solvers report as `Numerical`.
    /// Written into `out`, whose buffers are reused.
    pub(crate) fn apply_pow2_into(&self, lcp: &Lcp, qf: f64, out: &mut Lcp) {
        let n = lcp.n();
        let (mut m, mut q) = std::mem::replace(out, Lcp::from_parts_unchecked(Vec::new(), Vec::new())).into_parts();
        m.clear();
        for (row, &ri) in lcp.m().chunks_exact(n).zip(&self.row) {
            m.extend(row.iter().zip(&self.col).map(|(&mij, &cj)| ri * mij * cj));
        }
        q.clear();
        q.extend(lcp.q().iter().zip(&self.row).map(|(&qi, &ri)| qf * ri * qi));
        *out = Lcp::from_parts_unchecked(m, q);
    }

    /// Original unknowns from scaled ones: `z = D_c z'`.
    pub fn z_back(&self, z_scaled: &[f64]) -> Vec<f64> {
        z_scaled.iter().zip(&self.col).map(|(z, c)| c * z).collect()
    }

    /// Original `w` from the scaled one: `w = D_r⁻¹ w'`.
    pub fn w_back(&self, w_scaled: &[f64]) -> Vec<f64> {
        w_scaled.iter().zip(&self.row).map(|(w, r)| w / r).collect()
    }

    /// Scaled unknowns from original ones: `z' = D_c⁻¹ z` (inverse of [`Scaling::z_back`]).
    pub fn z_forward(&self, z: &[f64]) -> Vec<f64> {
        z.iter().zip(&self.col).map(|(z, c)| z / c).collect()
    }

    /// Scaled `w` from the original one: `w' = D_r w` (inverse of [`Scaling::w_back`]).
    pub fn w_forward(&self, w: &[f64]) -> Vec<f64> {
        w.iter().zip(&self.row).map(|(w, r)| r * w).collect()
    }

    /// `true` when every factor is 1.
    pub fn is_identity(&self) -> bool {
        self.row.iter().chain(&self.col).all(|&f| f == 1.0)
    }
}

/// `2^e` built from its bit pattern (exact; |e| ≤ MAX_EXPONENT keeps it normal).
#[inline]
fn pow2(e: i32) -> f64 {
    let e = e.clamp(-(MAX_EXPONENT as i32), MAX_EXPONENT as i32);
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// One Ruiz step of every factor exponent `e` from its row's (column's)
/// largest exponent `m`, branch-free (which factors move is data-dependent);
/// `true` if any moved.
fn step_toward_one(e: &mut [i16], m: &[i16]) -> bool {
    let mut moved = 0i16;
    for (e, &m) in e.iter_mut().zip(m) {
        let step = inv_sqrt_step(m);
        *e = (*e + step).clamp(-MAX_EXPONENT, MAX_EXPONENT);
        moved |= step;
    }
    moved != 0
}

/// For a largest entry in `[2^e, 2^(e+1))`, the exponent step nearest (in log
/// scale, taking the interval's midpoint) to `1/√(2^(e+½))`; 0 for an empty
/// row or column so it keeps its factor.
#[inline]
fn inv_sqrt_step(e: i16) -> i16 {
    if e < -4 * MAX_EXPONENT {
        return 0;
    }
    -(e + 1).div_euclid(2)
}

#[cfg(test)]
mod tests {
    use super::exponents::exponent;
    use super::*;

    #[test]
    fn inv_sqrt_step_rounds_in_log_scale() {
        let step = |v: f64| inv_sqrt_step(exponent(v));
        assert_eq!(step(1.0), 0);
        assert_eq!(step(16.0), -2);
        assert_eq!(step(1.0 / 64.0), 3);
        assert_eq!(step(0.0), 0);
        assert_eq!(step(-8.0), -2);
    }
}
