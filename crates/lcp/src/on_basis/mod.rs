//! Solving an LCP on a guessed complementary basis, without pivoting and
//! without forming `M`.
//!
//! A simulator's LCP changes little from one step to the next, and on most
//! steps the previous step's complementary basis (which `z_j` are basic)
//! solves the new problem as it is: `z_S = −M_SS⁻¹ q_S`, `z = 0` elsewhere,
//! with `z ≥ 0` and `w = M z + q ≥ 0`. Checking that needs only the block
//! `M_SS` and products `M z`, both of which a caller can compute from a
//! structure far smaller than the dense `n × n` matrix (the simulator keeps
//! `M = J M_b⁻¹ Jᵀ` in body space). [`LcpOperator`] is that access;
//! [`solve_on_basis`] is the check.
//!
//! The files, in the order a call meets them:
//!
//! - [`workspace`]: the buffers a caller keeps across calls, with the last
//!   factorization and the back-off of calls that found nothing;
//! - [`refine`]: the kept factorization serving the next call (iterative refinement);
//! - [`factors`]: a fresh factorization of `M_SS` (formed from the previous
//!   round's block, or bordered from its factors) on the regular block `β`;
//! - [`principal`]: the rank-revealing principal LU behind both;
//! - [`check`]: the normwise bounds and the acceptance rule of [`crate::accept`] read through the operator;
//! - [`rounds`]: the exchange rounds (one violated index at a time) and their budget;
//! - [`answer`]: what a call returns ([`BasisAnswer`]) and when it accepts one ([`BasisTolerances`]).

mod answer;
mod check;
mod factors;
pub(crate) mod principal;
mod refine;
mod rounds;
mod workspace;

pub use answer::{Also, BasisAnswer, BasisTolerances};
pub use rounds::{EAGER_REPAIR_FRACTION, REPAIR_FRACTION, REPAIR_ROUNDS, REPAIR_ROUNDS_MAX};
pub use workspace::BasisWorkspace;

use crate::operator::LcpOperator;
use rounds::{repair_rounds, solve_rounds, Repair};

/// Solves `op` on the complementary basis `basis` (`basis[j]`: `z_j` basic):
/// `M_ββ z_β = −q_β` on a regular principal block `β` of the guess (dependent
/// indices dropped), refined to convergence, `z` clipped at 0; violated
/// indices are exchanged one at a time (at most [`repair_rounds`]). Returns
/// the first answer that the acceptance rule of [`crate::accept`] accepts at
/// `accept_tol` and whose natural residual is at most `accept_tol·(1 + ‖q‖∞)`,
/// on `op` and, when given, on `also` (the same `z` mapped, e.g. to physical
/// units), with no violation above [`REPAIR_FRACTION`] of that bound; else
/// the first answer that meets the rule and the bound; `None` when there is
/// none (the caller then pivots). The returned `Solution` has status
/// `Solved`, 0 pivots and the basis `β` used.
pub fn solve_on_basis(
    op: &dyn LcpOperator,
    basis: &[bool],
    accept_tol: f64,
    also: Option<Also<'_>>,
    ws: &mut BasisWorkspace,
) -> Option<BasisAnswer> {
    solve_on_basis_ruled(
        op,
        basis,
        BasisTolerances { accept_tol, tight: accept_tol, loose: false, polish: true, more_rounds: true, eager_rows: 0 },
        also,
        ws,
    )
}

/// [`solve_on_basis`] with the tolerances apart ([`BasisTolerances`]): a
/// normwise bound `tight` below the rule's, and a looser last resort.
/// Exchanges are tried first: an answer within the tight bound is preferred
/// (a resting stack accepted at the looser bound step after step creeps).
pub fn solve_on_basis_ruled(
    op: &dyn LcpOperator,
    basis: &[bool],
    tol: BasisTolerances,
    also: Option<Also<'_>>,
    ws: &mut BasisWorkspace,
) -> Option<BasisAnswer> {
    let n = op.n();
    if basis.len() != n {
        return None;
    }
    // Violations far below the acceptance bound are exchanged too, so a
    // slowly drifting vertex is left before its values reach the bound.
    let q_norm = check::norm_inf(op.q());
    // (A fraction of `tight·(1 + ‖q‖∞)`, multiplied in this order as always.)
    let of_bound = |fraction: f64| fraction * tol.tight * (1.0 + q_norm);
    let (repair, eager) = (of_bound(REPAIR_FRACTION), (tol.eager_rows.min(n), of_bound(EAGER_REPAIR_FRACTION)));
    ws.mask.clear();
    ws.mask.extend_from_slice(basis);
    // After calls in a row that found nothing, the basis comes from the
    // caller's pivoting: exchanges are tried again only on the 1st, 2nd,
    // 4th, 8th, … such call (a resting stack's exchanges failed on 25
    // steps in a row, each ending in the pivoting anyway).
    let most = if tol.more_rounds { repair_rounds(basis) } else { REPAIR_ROUNDS };
    let rounds = if ws.failures.is_power_of_two() || ws.failures == 0 { most } else { 0 };
    let found = solve_rounds(op, basis, tol, also, ws, rounds, Repair { floor: repair, eager, q_norm });
    ws.failures = if found.is_some() { 0 } else { ws.failures.saturating_add(1) };
    found
}
