//! Projected Gauss–Seidel (PGS) with relaxation (projected SOR).
//!
//! One sweep visits the rows in order and sets
//! `z_i ← max(0, z_i − ω (M z + q)_i / M_ii)` using the freshest `z`.
//! PGS converges for symmetric positive (semi)definite `M` with a solution and
//! `0 < ω < 2`, and for H-matrices with positive diagonal; on anything else it
//! may stall or diverge, which the status reports.
//!
//! Rows with `M_ii ≤ 0` cannot be updated (there is nothing to divide by, and a
//! negative pivot would push the wrong way): they are skipped and their `z_i`
//! stays 0. This is why PGS cannot solve the contact LCP (its λ rows have a
//! zero diagonal) unless no contact slides — it then ends with `MaxIterations`.

use crate::problem::{dot, Lcp};
use crate::solution::{Solution, Status};

/// Options of projected Gauss–Seidel.
#[derive(Clone, Debug, PartialEq)]
pub struct PgsOptions {
    /// Relaxation factor ω in (0, 2). Default 1.0.
    pub omega: f64,
    /// Sweep limit. Default 10 000.
    pub max_iterations: usize,
    /// Stop when the natural residual ‖min(z, w)‖∞ ≤ tol. Default 1e-10.
    pub tol: f64,
}

impl Default for PgsOptions {
    fn default() -> Self {
        PgsOptions { omega: 1.0, max_iterations: 10_000, tol: 1e-10 }
    }
}

/// Solves `lcp` by projected Gauss–Seidel from `z = 0`. Never panics; `z` is always finite.
///
/// Status: `Solved` when the natural residual is ≤ `o.tol` (checked before the
/// first sweep and after each one; `pivots` counts sweeps) and the
/// iterate passes the acceptance rule ([`crate::accept`]; sweeps go on
/// until both hold); `Numerical` when a sweep produced a non-finite value (divergence, or a non-finite ω) —
/// `z` is then the last finite iterate; otherwise `MaxIterations`.
pub fn solve(lcp: &Lcp, o: &PgsOptions) -> Solution {
    let n = lcp.n();
    let q = lcp.q();
    let mut z = vec![0.0; n];
    let mut z_prev = vec![0.0; n];
    // Rows we can update, with the reciprocal of their pivot.
    let inv_diag: Vec<Option<f64>> = (0..n)
        .map(|i| {
            let d = lcp.at(i, i);
            (d > 0.0 && (1.0 / d).is_finite()).then(|| 1.0 / d)
        })
        .collect();

    for sweep in 0..=o.max_iterations {
        let w = lcp.w_of(&z);
        let natural = z.iter().zip(&w).fold(0.0f64, |r, (&a, &b)| r.max(a.min(b).abs()));
        if natural <= o.tol && crate::accept::accepts(lcp, &z, &w, crate::accept::DEFAULT_TOL) {
            return Solution::from_z(lcp, z, Status::Solved, sweep);
        }
        if sweep == o.max_iterations {
            break;
        }

        z_prev.copy_from_slice(&z);
        let mut finite = true;
        for i in 0..n {
            let Some(inv) = inv_diag[i] else { continue };
            let r = dot(lcp.row(i), &z) + q[i];
            let update = z[i] - o.omega * r * inv;
            // Test before projecting: `f64::max` would turn NaN into 0 silently.
            finite &= update.is_finite();
            z[i] = update.max(0.0);
        }
        if !finite {
            return Solution::from_z(lcp, z_prev, Status::Numerical, sweep);
        }
    }
    Solution::from_z(lcp, z, Status::MaxIterations, o.max_iterations)
}
