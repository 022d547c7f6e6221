//! What a solve on a basis returns ([`BasisAnswer`]) and when it accepts
//! one ([`BasisTolerances`]).

use super::workspace::BasisWorkspace;
use crate::operator::LcpOperator;
use crate::solution::{Solution, Status};

/// The answer of [`solve_on_basis`](super::solve_on_basis) when it is accepted.
#[derive(Clone, Debug, PartialEq)]
pub struct BasisAnswer {
    /// `z`, `w = M z + q` and residuals on the operator given.
    pub solution: Solution,
    /// Columns of the guess dropped as linearly dependent.
    pub dropped: usize,
    /// Whether the kept factorization served (no `M_SS` formed).
    pub reused: bool,
    /// With a second problem (`also`): `z` mapped into its units and its
    /// `w`, as checked there (a caller needs not form them again).
    pub other: Option<(Vec<f64>, Vec<f64>)>,
}

/// The second problem an answer must also solve: its operator and the map
/// of `z` into its units.
pub type Also<'a> = (&'a dyn LcpOperator, &'a dyn Fn(&[f64], &mut Vec<f64>));

/// When [`solve_on_basis_ruled`](super::solve_on_basis_ruled) accepts an answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasisTolerances {
    /// The acceptance rule's tolerance: every answer returned is accepted by
    /// [`crate::accept`] at it, on `op` and on the other units (`Solution::accepted`).
    pub accept_tol: f64,
    /// An answer the rule accepts whose natural residual is within
    /// `tight·(1 + ‖q‖∞)` (on `op` and on the other units, `tight ≤
    /// accept_tol`) is returned at once, or, with a violation above
    /// [`REPAIR_FRACTION`](super::REPAIR_FRACTION) of that bound, after exchanges find no cleaner one.
    pub tight: f64,
    /// When no round gives such an answer: the first (in round order) the
    /// rule accepts whose natural residual is within `accept_tol·(1 + ‖q‖∞)`
    /// — what the dense Lemke's warm start accepts at 0 pivots (its ladder's
    /// "tight" answer). `false`: `None` then.
    pub loose: bool,
    /// Whether refinement on a kept factorization applies its last,
    /// negligible correction too (and forms `w` for it): one product more,
    /// for answers that need their last digits (a heavy body on a light one:
    /// skipping it moved a 1e7 kg box-on-box test's energy rise past its
    /// bound). Without it the answer is the one before that correction.
    pub polish: bool,
    /// Whether a small basic block gets more exchange rounds than
    /// [`REPAIR_ROUNDS`](super::REPAIR_ROUNDS) ([`repair_rounds`](super::rounds::repair_rounds)); `false`: that many.
    pub more_rounds: bool,
    /// The first `eager_rows` indices (a contact LCP's normal rows,
    /// [`ContactLayout::fn_range`](crate::contact::ContactLayout::fn_range); 0: none) are exchanged
    /// from a violation of [`EAGER_REPAIR_FRACTION`](super::EAGER_REPAIR_FRACTION) of the bound, not
    /// [`REPAIR_FRACTION`](super::REPAIR_FRACTION): see there.
    pub eager_rows: usize,
}

/// The accepted answer in `ws`, on the basis `β` factored, with `z`, `w` in
/// the other units if `other`; the vectors are moved out of `ws` if `take`
/// (its last use in this call), else copied — into spare vectors the caller
/// handed back ([`BasisWorkspace::recycle`]) when there are some.
pub(super) fn answer(ws: &mut BasisWorkspace, dropped: usize, reused: bool, other: bool, take: bool) -> BasisAnswer {
    let spare = &mut ws.spare;
    let mut out = |v: &mut Vec<f64>| if take { spare.take(v) } else { spare.copy(v) };
    // (`within_both` formed the residuals of this z and w.)
    let solution = Solution {
        z: out(&mut ws.z),
        w: out(&mut ws.w),
        status: Status::Solved,
        pivots: 0,
        residuals: ws.residuals,
        basis: None,
        accepted: true,
    };
    let other = other.then(|| (out(&mut ws.z2), out(&mut ws.w2)));
    let solution = Solution { basis: Some(ws.spare.copy_mask(&ws.f.factored)), ..solution };
    BasisAnswer { solution, dropped, reused, other }
}
