//! Whether an answer may be returned: its natural residual within a
//! normwise bound, and no row the acceptance rule of [`crate::accept`]
//! rejects, on the operator given and on the other units.

use super::answer::Also;
use super::workspace::BasisWorkspace;
use crate::operator::LcpOperator;
use crate::solution::Residuals;

/// The natural residual of `(z, w)` is within `accept_tol·(1 + ‖q‖∞)` of `op`.
pub(super) fn within(op: &dyn LcpOperator, z: &[f64], w: &[f64], accept_tol: f64) -> bool {
    natural_residual(z, w) <= accept_tol * (1.0 + norm_inf(op.q()))
}

/// `Residuals::of(z, w).residual` alone (infinite if an entry is not
/// finite), in one pass without the other measures: called on every round.
fn natural_residual(z: &[f64], w: &[f64]) -> f64 {
    let (mut r, mut finite) = (0.0f64, true);
    for (&a, &b) in z.iter().zip(w) {
        let m = a.min(b).abs();
        r = if m > r { m } else { r };
        finite &= a.is_finite() & b.is_finite();
    }
    if finite {
        r
    } else {
        f64::INFINITY
    }
}

/// The natural residual is within `accept_tol·(1 + ‖q‖∞)` on the call's
/// operator (its `‖q‖∞` in `ws.q_norm`) and, with `also`, on `z` mapped into
/// the other units (into `ws.z2`, `ws.w2`).
pub(super) fn within_both(also: Option<Also<'_>>, accept_tol: f64, ws: &mut BasisWorkspace) -> bool {
    // (The residuals are kept: an answer returned next reports them.)
    ws.residuals = Residuals::of(&ws.z, &ws.w);
    if !(ws.residuals.residual <= accept_tol * (1.0 + ws.q_norm)) {
        return false;
    }
    let Some((other, map)) = also else { return true };
    map(&ws.z, &mut ws.z2);
    // (Every entry is written by `w_of`.)
    ws.w2.resize(ws.z2.len(), 0.0);
    other.w_of(&ws.z2, &mut ws.w2);
    within(other, &ws.z2, &ws.w2, accept_tol)
}

/// A row the acceptance rule rejects at `accept_tol`, on `op` or on the other
/// units (`ws.z2`, `ws.w2` as [`within_both`] left them); `None` when both
/// accept. `first`: any rejected row does (the caller exchanges another
/// index), else the worst of the first operator that rejects.
pub(super) fn rule_rejects(
    op: &dyn LcpOperator,
    also: Option<Also<'_>>,
    accept_tol: f64,
    first: bool,
    ws: &mut BasisWorkspace,
) -> Option<usize> {
    let BasisWorkspace { z, w, z2, w2, kept, kept_other, row, .. } = ws;
    crate::accept::rejected_row_operator(op, z, w, accept_tol, first, kept, row).or_else(|| {
        let (other, _) = also?;
        crate::accept::rejected_row_operator(other, z2, w2, accept_tol, first, kept_other, row)
    })
}

/// `max_i |v_i|` (NaN entries skipped), over four lanes.
pub(super) fn norm_inf(v: &[f64]) -> f64 {
    crate::kernels::max_abs_finite(v, 0.0).0
}
