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
use crate::kernels::{max_abs_finite, pick_max};
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

/// The largest block whose kept factors get an inverse
/// ([`refine_by_inverse`]): a single body's (a box on a plane, 12
/// indices at most). Forming it costs `k` solves; a resting 10-box stack's
/// kept factors (30–62 indices) served ~20 calls each, and with inverses at
/// every size its run (`step_budget run stack 2000`) took 957M instructions
/// instead of 872M (93 inverses formed, 82M).
pub(super) const INVERSE_MAX_RANK: usize = principal::INVERSE_TIMES_MAX;

/// [`refine_by_inverse`] reads `w` on `β`'s rows alone only when `n` is
/// above this many times their count (body space: the sliding cube's
/// `w_rows` on 11 rows of 40 took 1.9k instructions, `w_of` 1.7k).
const ROWS_PER_PRODUCT: usize = 4;

/// `z` on `β` of the kept factorization, for the new `op`: the old factors
/// precondition iterative refinement against the new block (each step one
/// product `M z`). Leaves `ws.z`, `ws.w` and returns `true` once the
/// correction is negligible (applied, and `w` formed for it, only if
/// `polish`: see [`BasisTolerances::polish`](super::BasisTolerances::polish)); `false` (factor afresh) otherwise.
///
/// Without `polish`, a block of at most [`INVERSE_MAX_RANK`] indices whose
/// kept factors have an inverse with a finite error bound is refined by
/// products with that inverse alone ([`refine_by_inverse`]).
pub(super) fn refine_on_factor(op: &dyn LcpOperator, ws: &mut BasisWorkspace, polish: bool) -> bool {
    if ws.f.factored.len() != op.n() {
        return false;
    }
    if !polish && (1..=INVERSE_MAX_RANK).contains(&ws.f.rank) {
        let (m, r) = (ws.f.support.len(), ws.f.rank);
        let f = &mut ws.f;
        let err = *f.inverse.get_or_insert_with(|| principal::inverse(&f.lu, m, r, &mut f.inv, &mut ws.y));
        if err.is_finite() {
            return refine_by_inverse(op, ws, err);
        }
    }
    first_solve(op, ws);
    let mut previous = f64::INFINITY;
    // The first step reads w on β alone (its correction is seldom the last,
    // whose w the answer keeps): on a resting 10-box stack, 30 rows of 400.
    ws.basic_rows();
    op.w_rows(&ws.z, &ws.rows, &mut ws.w);
    for step in 0..=REFINE_STEPS {
        if step > 0 {
            op.w_of(&ws.z, &mut ws.w);
        }
        let (dmax, zmax) = correction(ws);
        if !(dmax.is_finite() && zmax.is_finite()) {
            return false;
        }
        let negligible = settled(dmax, zmax, previous);
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

/// [`refine_on_factor`] on a small block by its kept factors' inverse `X`
/// (formed once per factorization, [`principal::inverse`], `err` its bound):
/// `z_β = X (−q_β)`, then corrections `X (−w_β)` until one is negligible —
/// the product plus `err·‖w_β‖∞`, its distance to what the triangular solves
/// would give, within [`REFINE_STOP`] of `‖z_β‖∞` (or stalled below
/// [`REFINE_STALL`]); that last correction only decides (`z` and `w` are the
/// ones before it). The solves' rows wait on one another (each backward
/// row on a division), the product's rows do not: on a sliding cube (an
/// 11 × 11 block) two triangular solves a step were a fifth of its step in
/// wall time. The answer is the same to round-off, not bit for bit, and is
/// judged by the same rule.
fn refine_by_inverse(op: &dyn LcpOperator, ws: &mut BasisWorkspace, err: f64) -> bool {
    let (n, r) = (op.n(), ws.f.rank);
    ws.basic_rows();
    let q = op.q();
    ws.x.clear();
    ws.x.extend(ws.rows.iter().map(|&i| -q[i]));
    ws.z.clear();
    ws.z.resize(n, 0.0);
    ws.w.resize(n, 0.0);
    let BasisWorkspace { f, rows, x, y, .. } = ws;
    principal::inverse_times(&f.inv, r, x, y);
    for (&i, &v) in rows.iter().zip(y.iter()) {
        ws.z[i] = v;
    }
    // The first step reads w on β alone (its correction is seldom the last)
    // where β is a small part of the rows: in body space a row costs about
    // three indices' share of the whole product (a sliding cube's 11 rows of
    // 40 cost more than the product).
    let by_rows = ROWS_PER_PRODUCT * r < n;
    if by_rows {
        op.w_rows(&ws.z, &ws.rows, &mut ws.w);
    }
    let mut previous = f64::INFINITY;
    for step in 0..=REFINE_STEPS {
        if step > 0 || !by_rows {
            op.w_of(&ws.z, &mut ws.w);
        }
        let BasisWorkspace { rows, x, y, z, w, f, .. } = ws;
        x.clear();
        x.extend(rows.iter().map(|&i| -w[i]));
        let (bmax, finite) = max_abs_finite(x, 0.0);
        let dmax = principal::inverse_times(&f.inv, r, x, y);
        let zmax = rows.iter().fold(0.0f64, |a, &i| pick_max(a, z[i].abs()));
        let reach = dmax + err * bmax;
        if !(finite && reach.is_finite() && zmax.is_finite()) {
            return false;
        }
        let negligible = settled(reach, zmax, previous);
        previous = reach;
        if negligible {
            if step == 0 && by_rows {
                op.w_after_rows(&ws.z, &mut ws.w);
            }
            return true;
        }
        if step == REFINE_STEPS {
            break;
        }
        for (&i, &d) in rows.iter().zip(y.iter()) {
            z[i] += d;
        }
    }
    false
}

/// Whether refinement has settled with a correction of size `d` (or its
/// bound) on `‖z_β‖∞ = zmax`, after one of size `previous`: converged
/// (below [`REFINE_STOP`] of `zmax`), or at the accuracy this block attains
/// — a correction at round-off ([`REFINE_STALL`]) that no longer halves (an
/// ill-conditioned block stalls at a few 1e-15 of `‖z‖`, where a fresh
/// factorization, refined once, ends no closer).
fn settled(d: f64, zmax: f64, previous: f64) -> bool {
    let converged = d <= REFINE_STOP * zmax;
    let stalled = d <= REFINE_STALL * zmax && d > 0.5 * previous;
    converged || stalled
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
