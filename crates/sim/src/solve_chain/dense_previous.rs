//! The previous basis of an island solved on its dense `M` (a jointed
//! island's `J P Jᵀ`, or one holding a torsion patch), before
//! `dense_loaded` and the dense Lemke: the body-space stages assume the
//! block-diagonal `M_b⁻¹` and one cone row per normal, so such an island's
//! warm basis is solved here by `lcp::on_basis` on the dense LCP (its kept
//! factorization refined, exchanges of the indices the rule rejects),
//! judged by the same acceptance rule. Reported as the previous-basis stage.

use super::stage::Found;
use crate::pipeline::island::IslandLcp;
use lcp::on_basis::{solve_on_basis_ruled, BasisTolerances};

/// The island's `warm` basis solved on its dense LCP at `accept_tol`, or
/// `None` (no basis, a scaled cone, or no accepted answer: the caller pivots).
pub(super) fn attempt(isl: &mut IslandLcp, warm: Option<&[bool]>, accept_tol: f64) -> Option<Found> {
    // (Scaled cones would need the physical LCP's check beside it: left to the Lemke.)
    let warm = warm.filter(|_| isl.lcp.scale() == 1.0)?;
    if !isl.lcp.has_matrix() {
        isl.lcp.assemble_matrix();
    }
    let lcp = isl.lcp.take_lcp().ok()?;
    // At most REPAIR_ROUNDS exchanges: on the chain of `benchmarks/joints.py`
    // the rounds a small block gets beyond them (each a fresh factorization
    // and a dense product) answered fewer steps (2,123 against 2,228 of
    // 3,000) and left more pivots to the Lemke (383,071 against 265,839).
    let tol = BasisTolerances { accept_tol, tight: accept_tol, loose: true, polish: true, more_rounds: false };
    let found = solve_on_basis_ruled(&lcp, warm, tol, None, &mut isl.basis_ws);
    isl.lcp.restore(lcp);
    Some(Found { sol: found?.solution, physical: None })
}
