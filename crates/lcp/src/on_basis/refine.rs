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
use crate::kernels::{max_abs_finite, LANES};
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
/// ([`negligible_by_inverse`]): a single body's (a box on a plane, 12
/// indices at most). Forming it costs `k` solves; a resting 10-box stack's
/// kept factors (30–62 indices) served ~20 calls each, and with inverses at
/// every size its run (`step_budget run stack 2000`) took 957M instructions
/// instead of 872M (93 inverses formed, 82M).
pub(super) const INVERSE_MAX_RANK: usize = 16;

/// `z` on `β` of the kept factorization, for the new `op`: the old factors
/// precondition iterative refinement against the new block (each step one
/// product `M z`). Leaves `ws.z`, `ws.w` and returns `true` once the
/// correction is negligible (applied, and `w` formed for it, only if
/// `polish`: see [`BasisTolerances::polish`](super::BasisTolerances::polish)); `false` (factor afresh) otherwise.
///
/// Without `polish` the last correction only decides: from the step the
/// last call ended at on, it is first judged by the kept inverse
/// ([`negligible_by_inverse`]), which avoids its triangular solves whenever
/// it can tell. A cube sliding on a slope ends at its first step while its
/// speed is low, at its second later on (`q` grows with the speed, and its
/// round-off with it).
pub(super) fn refine_on_factor(op: &dyn LcpOperator, ws: &mut BasisWorkspace, polish: bool) -> bool {
    if ws.f.factored.len() != op.n() {
        return false;
    }
    first_solve(op, ws);
    let mut previous = f64::INFINITY;
    let last = if polish { None } else { ws.last_step.take() };
    // The first step reads w on β alone (its correction is seldom the last,
    // whose w the answer keeps): on a resting 10-box stack, 30 rows of 400.
    // Where the last call ended at its first step, w is formed whole at
    // once: the same values, and the answer's.
    let whole = last == Some(0);
    if whole {
        op.w_of(&ws.z, &mut ws.w);
    } else {
        ws.rows.clear();
        ws.rows.extend(ws.f.order[..ws.f.rank].iter().map(|&p| ws.f.support[p]));
        op.w_rows(&ws.z, &ws.rows, &mut ws.w);
    }
    for step in 0..=REFINE_STEPS {
        if step > 0 {
            op.w_of(&ws.z, &mut ws.w);
        }
        // (At step 0 only when `w` is whole: `last` is then 0.)
        let small = (1..=INVERSE_MAX_RANK).contains(&ws.f.rank);
        if small && last.is_some_and(|l| step >= l) && negligible_by_inverse(ws) {
            ws.last_step = Some(step);
            return true;
        }
        let (dmax, zmax) = correction(ws);
        if !(dmax.is_finite() && zmax.is_finite()) {
            return false;
        }
        // Converged, or at the accuracy this block attains: a correction at
        // round-off that no longer halves (an ill-conditioned block stalls
        // at a few 1e-15 of ‖z‖, where a fresh factorization, refined once,
        // ends no closer).
        let converged = dmax <= REFINE_STOP * zmax;
        let stalled = dmax <= REFINE_STALL * zmax && dmax > 0.5 * previous;
        let negligible = converged || stalled;
        previous = dmax;
        if negligible && !polish {
            if step == 0 && !whole {
                op.w_after_rows(&ws.z, &mut ws.w);
            }
            // (A stalled block, a resting stack's, would not be judged
            // negligible by the inverse either: it is not formed for it.)
            ws.last_step = converged.then_some(step);
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

/// Whether the refinement step's correction `M_ββ⁻¹ (−w_β)` would be
/// negligible, judged by a product with the kept factors' inverse (formed
/// once per factorization) instead of two triangular solves: `true` only
/// when that product plus its bound on the distance to the solves' answer
/// ([`principal::inverse`]) is within [`REFINE_STOP`], so that the solves'
/// correction would be negligible too (the step then ends with the same `z`
/// and `w`: a correction judged negligible is not applied); `false` when that
/// is not known (the solves decide). The solves' rows wait on one another
/// (a sliding cube's 11 × 11 block: a fifth of its step in wall time), the
/// product's do not.
fn negligible_by_inverse(ws: &mut BasisWorkspace) -> bool {
    let (m, r) = (ws.f.support.len(), ws.f.rank);
    let BasisWorkspace { f, y: b, w, z, .. } = ws;
    let err = *f.inverse.get_or_insert_with(|| principal::inverse(&f.lu, m, r, &mut f.inv, b));
    let beta = &f.order[..r];
    b.clear();
    b.extend(beta.iter().map(|&p| -w[f.support[p]]));
    // (A `w` not finite is left to the solves, whose verdict then stands.)
    let (bmax, finite) = max_abs_finite(b, 0.0);
    // X b row by row over whole lanes (the rows' padding meets b's).
    let stride = principal::inverse_stride(r);
    b.resize(stride, 0.0);
    let lanes = b.as_chunks::<LANES>().0;
    let dmax = f.inv.chunks_exact(stride).fold(0.0f64, |d, row| {
        let mut acc = [0.0; LANES];
        for (c, v) in row.as_chunks::<LANES>().0.iter().zip(lanes) {
            for k in 0..LANES {
                acc[k] += c[k] * v[k];
            }
        }
        d.max(((acc[0] + acc[1]) + (acc[2] + acc[3])).abs())
    });
    let zmax = beta.iter().fold(0.0f64, |a, &p| a.max(z[f.support[p]].abs()));
    let reach = dmax + err * bmax;
    finite && reach.is_finite() && zmax.is_finite() && reach <= REFINE_STOP * zmax
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
