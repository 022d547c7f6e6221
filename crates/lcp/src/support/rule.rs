//! The acceptance rule of [`crate::accept`] evaluated through an
//! [`LcpOperator`]: the same per-row test without the dense `M`.
//!
//! Most rows pass on lower bounds of their scale and floor that cost nothing
//! or one diagonal entry (`s_i ≥ |q_i| + |M_ii| z_i`, `f_i ≥ ρ·|M_ii|·Σ z`);
//! only the others read their row ([`LcpOperator::row_abs`], which in body
//! space costs the contacts that share a body with the row's contact).

use super::LcpOperator;
use crate::accept::{row_eta, violation, ROUND_OFF};

/// Whether `z` with `w = M z + q` (as computed) is within the rule of
/// [`crate::accept::accepts`] at `tol`, with the round-off floor taken at
/// `floor_fraction` of its value (`1` is the rule itself; less is stricter).
/// The rows outside it are added to `failing` (`(η_i, i)`); returns `false`
/// when `z` is negative or not finite (no answer at all).
pub(crate) fn check(op: &dyn LcpOperator, z: &[f64], w: &[f64], tol: f64, floor_fraction: f64, failing: &mut Vec<(f64, usize)>) -> bool {
    let q = op.q();
    if !z.iter().all(|&v| v >= 0.0 && v.is_finite()) {
        return false;
    }
    let rho = floor_fraction * ROUND_OFF;
    let mut zsum = None;
    for i in 0..q.len() {
        let v = violation(z[i], w[i]);
        // `v <= …` so that a NaN falls through to the full check (and fails it).
        if v == 0.0 || v <= tol * q[i].abs() {
            continue;
        }
        let zs = *zsum.get_or_insert_with(|| z.iter().sum::<f64>());
        let d = op.diag(i).abs();
        if v <= tol * (q[i].abs() + d * z[i]) + rho * d * zs {
            continue;
        }
        let eta = if v.is_finite() {
            let (terms, rmax) = op.row_abs(i, z);
            row_eta(v, (q[i].abs() + terms, rho * rmax * zs))
        } else {
            f64::INFINITY
        };
        // `!(eta <= tol)`: a NaN row fails.
        if !(eta <= tol) {
            failing.push((eta, i));
        }
    }
    true
}
