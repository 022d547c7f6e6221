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
//! Two scalings are built here:
//! - [`Scaling::ruiz`]: Ruiz equilibration, every factor a power of two, so
//!   applying and undoing it is exact in floating point (barring over/underflow);
//! - [`Scaling::cone`]: the seed's friction-cone scaling `D = diag(I, I, s·I)`
//!   on both sides (DESIGN §1): `fn`, `fd` unchanged, `λ_scaled = λ / s`.

use crate::problem::{Lcp, LcpError};

/// Row and column scale factors: the scaled problem is `D_r M D_c, D_r q` with
/// `D_r = diag(row)`, `D_c = diag(col)`. All factors should be positive and finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    pub row: Vec<f64>,
    pub col: Vec<f64>,
}

/// Exponents beyond this are clamped so that `2^e` stays a normal, finite number.
const MAX_EXPONENT: i32 = 1000;

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
    /// simultaneously from the same matrix. Every factor is rounded to a power
    /// of two (nearest in log scale), so `D_r M D_c` is exact. A row or column
    /// that is entirely zero keeps factor 1. For symmetric `M` the result is
    /// symmetric (`row == col`). Stops early once a round changes nothing.
    pub fn ruiz(lcp: &Lcp, iterations: usize) -> Scaling {
        let n = lcp.n();
        let mut row_exp = vec![0i32; n];
        let mut col_exp = vec![0i32; n];
        let mut row_max = vec![0.0f64; n];
        let mut col_max = vec![0.0f64; n];
        for _ in 0..iterations {
            // Max-abs of every row and column of the current D_r M D_c.
            row_max.iter_mut().for_each(|v| *v = 0.0);
            col_max.iter_mut().for_each(|v| *v = 0.0);
            for i in 0..n {
                let ri = pow2(row_exp[i]);
                for (j, &mij) in lcp.row(i).iter().enumerate() {
                    let a = (ri * mij * pow2(col_exp[j])).abs();
                    row_max[i] = row_max[i].max(a);
                    col_max[j] = col_max[j].max(a);
                }
            }
            let mut changed = false;
            for (e, &m) in row_exp.iter_mut().zip(&row_max).chain(col_exp.iter_mut().zip(&col_max)) {
                let step = inv_sqrt_exponent(m);
                if step != 0 {
                    *e = (*e + step).clamp(-MAX_EXPONENT, MAX_EXPONENT);
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        Scaling { row: row_exp.into_iter().map(pow2).collect(), col: col_exp.into_iter().map(pow2).collect() }
    }

    /// The seed's friction-cone scaling for `nc` contacts with `k` directions
    /// (z ordered `[fn (nc); fd (nc·k); λ (nc)]`): `D = diag(I_nc, I_{nc·k}, s·I_nc)`
    /// on both sides. Applied to the unscaled contact LCP it yields the blocks
    /// `s·E`, `s·μ`, `−s·Eᵀ` of DESIGN §1.
    pub fn cone(nc: usize, k: usize, s: f64) -> Scaling {
        let mut d = vec![1.0; nc + nc * k];
        d.resize(nc + nc * k + nc, s);
        Scaling { row: d.clone(), col: d }
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
    let e = e.clamp(-MAX_EXPONENT, MAX_EXPONENT);
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// The exponent `e` with `2^e` nearest (in log scale) to `1 / √m`; 0 for a
/// zero (or non-finite) `m`, so empty rows and columns keep their factor.
fn inv_sqrt_exponent(m: f64) -> i32 {
    if m <= 0.0 || !m.is_finite() {
        return 0;
    }
    let e = (-0.5 * m.log2()).round();
    e.clamp(-(MAX_EXPONENT as f64), MAX_EXPONENT as f64) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inv_sqrt_exponent_rounds_in_log_scale() {
        assert_eq!(inv_sqrt_exponent(1.0), 0);
        assert_eq!(inv_sqrt_exponent(16.0), -2);
        assert_eq!(inv_sqrt_exponent(1.0 / 64.0), 3);
        assert_eq!(inv_sqrt_exponent(0.0), 0);
    }
}
