//! Brute-force enumeration of complementary bases, the ground truth for small
//! problems in tests and experiments.
//!
//! For every index set `α ⊆ {0, …, n−1}` (2ⁿ of them) solve
//! `M_αα z_α = −q_α`, set `z_ᾱ = 0`, and keep `z` if it solves the LCP within
//! `tol` ([`is_solution`]). This finds every solution that is a *basic*
//! (vertex) solution, i.e. whose support can be extended to an `α` with
//! nonsingular `M_αα`. Principal submatrices that are numerically singular are
//! skipped, so a continuum of solutions (possible when `M` is not a P-matrix) is
//! represented only by its vertices, and a solution with no nonsingular basis
//! is not found. For a P-matrix every `M_αα` is nonsingular and the result is
//! the unique solution.

use crate::newton_fb::lu_solve;
use crate::problem::Lcp;
use crate::solution::Residuals;

/// Largest `n` [`all_solutions`] enumerates (2¹⁶ = 65 536 bases).
pub const MAX_N: usize = 16;

/// All distinct basic solutions of `lcp` (see the module docs), in the order
/// of their index set as a bit mask (`z = 0` first when it is a solution).
///
/// Two candidates count as the same solution when they differ by at most
/// `tol · max(1, ‖z‖∞)` in every entry (degenerate problems reach one solution
/// from several bases). Returns an empty `Vec` when `n > MAX_N`; callers that
/// need to tell that apart from "no solution" check `lcp.n()` first.
pub fn all_solutions(lcp: &Lcp, tol: f64) -> Vec<Vec<f64>> {
    let n = lcp.n();
    if n > MAX_N {
        return Vec::new();
    }
    let q = lcp.q();
    let mut found: Vec<Vec<f64>> = Vec::new();
    let mut sub = Vec::with_capacity(n * n);
    let mut rhs = Vec::with_capacity(n);
    for mask in 0u32..(1u32 << n) {
        let alpha: Vec<usize> = (0..n).filter(|&i| mask & (1 << i) != 0).collect();
        let mut z = vec![0.0; n];
        if !alpha.is_empty() {
            // M_αα z_α = −q_α
            sub.clear();
            for &i in &alpha {
                sub.extend(alpha.iter().map(|&j| lcp.at(i, j)));
            }
            rhs.clear();
            rhs.extend(alpha.iter().map(|&i| -q[i]));
            let Some(z_alpha) = lu_solve(&sub, alpha.len(), &rhs) else { continue };
            for (&i, zi) in alpha.iter().zip(z_alpha) {
                z[i] = zi;
            }
        }
        if is_solution(lcp, &z, tol) && !found.iter().any(|s| same(s, &z, tol)) {
            found.push(z);
        }
    }
    found
}

/// `true` when `z` has length `n`, is finite and its natural residual
/// `‖min(z, M z + q)‖∞` is ≤ `tol` — equivalently `z ≥ −tol`, `w ≥ −tol` and
/// in every pair at least one of `z_i`, `w_i` is within `tol` of zero.
pub fn is_solution(lcp: &Lcp, z: &[f64], tol: f64) -> bool {
    if z.len() != lcp.n() || !z.iter().all(|v| v.is_finite()) {
        return false;
    }
    let (_, r) = Residuals::compute(lcp, z);
    r.residual <= tol
}

fn same(a: &[f64], b: &[f64], tol: f64) -> bool {
    let scale = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol * scale)
}
