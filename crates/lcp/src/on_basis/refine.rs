//! A kept factorization serving the next call.
//!
//! The factorization is kept: when the next call starts from the basis it
//! factored (the previous answer's), `M_SS` is not formed again — the old
//! factors precondition iterative refinement against the new `M` (products
//! only, O(contacts) in body space), and a fresh factorization is made only
//! when that does not converge in a few steps. Refinement converges to the
//! solution of the new block itself; nothing about the problem is changed.

use super::principal;
use super::workspace::BasisWorkspace;
use crate::operator::LcpOperator;

/// Refinement steps with a kept factorization before a fresh one is made.
pub(super) const REFINE_STEPS: usize = 4;

/// Refinement has converged when its correction is below this fraction of `‖z_β‖∞`.
pub(super) const REFINE_STOP: f64 = 1e-15;

/// Refinement has also converged when its correction, below this fraction
/// of `‖z_β‖∞`, did not halve the previous one (it stalls at round-off).
/// Measured on `stack_steps 2000 10`: from step ~1,100 the stack's basis
/// (78 basic indices) stalls at 1e-15–7e-15 and was factored afresh on
/// every step.
pub(super) const REFINE_STALL: f64 = 1e-13;

/// `z` on `β` of the kept factorization, for the new `op`: the old factors
/// precondition iterative refinement against the new block (each step one
/// product `M z`). Leaves `ws.z`, `ws.w` and returns `true` once the
/// correction is negligible (applied, and `w` formed for it, only if
/// `polish`: see [`BasisTolerances::polish`](super::BasisTolerances::polish)); `false` (factor afresh) otherwise.
pub(super) fn refine_on_factor(op: &dyn LcpOperator, ws: &mut BasisWorkspace, polish: bool) -> bool {
    if ws.f.factored.len() != op.n() {
        return false;
    }
    first_solve(op, ws);
    let mut previous = f64::INFINITY;
    // The first step reads w on β alone (its correction is seldom the last,
    // whose w the answer keeps): on a resting 10-box stack, 30 rows of 400.
    ws.rows.clear();
    ws.rows.extend(ws.f.order[..ws.f.rank].iter().map(|&p| ws.f.support[p]));
    op.w_rows(&ws.z, &ws.rows, &mut ws.w);
    for step in 0..=REFINE_STEPS {
        if step > 0 {
            op.w_of(&ws.z, &mut ws.w);
        }
        let (dmax, zmax) = correction(ws);
        if !(dmax.is_finite() && zmax.is_finite()) {
            return false;
        }
        // Converged, or at the accuracy this block attains: a correction at
        // round-off that no longer halves (an ill-conditioned block stalls
        // at a few 1e-15 of ‖z‖, where a fresh factorization, refined once,
        // ends no closer).
        let stalled = dmax <= REFINE_STALL * zmax && dmax > 0.5 * previous;
        let negligible = dmax <= REFINE_STOP * zmax || stalled;
        previous = dmax;
        if negligible && !polish {
            if step == 0 {
                op.w_after_rows(&ws.z, &mut ws.w);
            }
            return true;
        }
        if step == REFINE_STEPS {
            break;
        }
        apply_correction(ws);
        if negligible {
            op.w_of(&ws.z, &mut ws.w);
            return true;
        }
    }
    false
}

/// `z_β = M_ββ⁻¹ (−q_β)` with the factors in `ws`, `z = 0` elsewhere (`w`
/// sized `n`, its values left for the caller's `w = M z + q`).
pub(super) fn first_solve(op: &dyn LcpOperator, ws: &mut BasisWorkspace) {
    let (n, m, q) = (op.n(), ws.f.support.len(), op.q());
    ws.x.clear();
    ws.x.resize(m, 0.0);
    for &p in &ws.f.order[..ws.f.rank] {
        ws.x[p] = -q[ws.f.support[p]];
    }
    principal::solve(&ws.f.lu, m, &ws.f.order, ws.f.rank, &mut ws.x, &mut ws.y);
    ws.z.clear();
    ws.z.resize(n, 0.0);
    ws.w.resize(n, 0.0);
    scatter_add(&ws.x, &ws.f.order[..ws.f.rank], &ws.f.support, &mut ws.z);
}

/// One refinement step: `z_β += M_ββ⁻¹ (−w_β)` with the kept factors;
/// returns `(‖correction‖∞, ‖z_β‖∞)` (of `z_β` before the step).
pub(super) fn correct(ws: &mut BasisWorkspace) -> (f64, f64) {
    let sizes = correction(ws);
    apply_correction(ws);
    sizes
}

/// The correction `x_β = M_ββ⁻¹ (−w_β)` into `ws.x` (not applied);
/// returns `(‖x_β‖∞, ‖z_β‖∞)`.
pub(super) fn correction(ws: &mut BasisWorkspace) -> (f64, f64) {
    let m = ws.f.support.len();
    for &p in &ws.f.order[..ws.f.rank] {
        ws.x[p] = -ws.w[ws.f.support[p]];
    }
    principal::solve(&ws.f.lu, m, &ws.f.order, ws.f.rank, &mut ws.x, &mut ws.y);
    let beta = &ws.f.order[..ws.f.rank];
    let dmax = beta.iter().fold(0.0f64, |a, &p| a.max(ws.x[p].abs()));
    let zmax = beta.iter().fold(0.0f64, |a, &p| a.max(ws.z[ws.f.support[p]].abs()));
    (dmax, zmax)
}

/// `z_β += x_β` (the correction in `ws.x`).
pub(super) fn apply_correction(ws: &mut BasisWorkspace) {
    scatter_add(&ws.x, &ws.f.order[..ws.f.rank], &ws.f.support, &mut ws.z);
}

/// `z[S[p]] += x[p]` for the positions `p` given.
pub(super) fn scatter_add(x: &[f64], positions: &[usize], support: &[usize], z: &mut [f64]) {
    for &p in positions {
        z[support[p]] += x[p];
    }
}
