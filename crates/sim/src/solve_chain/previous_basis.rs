//! Stage 1: the previous step's basis solved on this step's LCP in body
//! space (`lcp::on_basis`), without pivoting and without forming `M`. On
//! most steps of a resting scene it still solves.

use super::stage::{Attempt, Found, PhysicalZw};
use crate::contact::{BodySpaceLcp, ContactLcp};
use crate::pipeline::island::IslandLcp;
use lcp::on_basis::{BasisTolerances, BasisWorkspace};
use lcp::operator::LcpOperator;
use lcp::Solution;

/// The stage: the island's warm basis, if it has one.
pub(super) fn attempt(isl: &mut IslandLcp, a: &Attempt<'_>) -> Option<Found> {
    let basis = a.warm?;
    // The island's last physical z and w are its buffers for this answer's.
    let mut spare = (std::mem::take(&mut isl.z), std::mem::take(&mut isl.w));
    match solve_into(&isl.lcp, basis, a.accept_tol, a.mixed, &mut isl.basis_ws, &mut spare) {
        Some((sol, zw)) => Some(Found { sol, physical: Some(zw) }),
        None => {
            (isl.z, isl.w) = spare;
            None
        }
    }
}

/// The body-space check accepts a previous basis only if its residual is this
/// fraction of Lemke's acceptance bound: pivoting ends on answers refined to
/// round-off, and a resting stack must not creep at the bound's 1e-9 m/s
/// (at 1e-2 a 3-box stack keeps its velocities below 1e-9 m/s over 500 steps;
/// at 1e-4 most stack steps went back to pivoting).
const BASIS_CHECK_TOL: f64 = 1e-2;

/// The previous step's basis solved on this step's LCP in body space. Every
/// answer is accepted by the acceptance rule (`lcp::accept`, rows read
/// through the body-space operator) at `accept_tol` on the LCP as scaled and
/// in physical units, as the dense Lemke's answers are; its natural residual
/// is within [`BASIS_CHECK_TOL`] of Lemke's bound if some exchange round gets
/// there, else within the bound itself (what the dense Lemke's warm start
/// would accept at 0 pivots) — the same answer without forming `M`.
/// With it the physical `z` and `w` it was checked with. `mixed`: the
/// body-space check will judge the answer ([`BodyCheck::applies`]).
pub(super) fn solve_in_body_space(
    lcp: &ContactLcp,
    basis: &[bool],
    accept_tol: f64,
    mixed: bool,
    ws: &mut BasisWorkspace,
) -> Option<(Solution, PhysicalZw)> {
    solve_into(lcp, basis, accept_tol, mixed, ws, &mut Default::default())
}

/// [`solve_in_body_space`], the physical `z` and `w` at scale 1 copied into
/// `spare`'s buffers (a steady step then allocates no new ones).
fn solve_into(
    lcp: &ContactLcp,
    basis: &[bool],
    accept_tol: f64,
    mixed: bool,
    ws: &mut BasisWorkspace,
    spare: &mut PhysicalZw,
) -> Option<(Solution, PhysicalZw)> {
    let scaled = BodySpaceLcp::new(lcp);
    // At scale 1 the physical LCP is the one solved: one check does (and
    // no second operator is made).
    let physical = (lcp.scale() != 1.0).then(|| BodySpaceLcp::at_scale(lcp, 1.0));
    let to_physical = |z: &[f64], out: &mut Vec<f64>| lcp.unscale_z(z, out);
    let also = physical.as_ref().map(|p| (p as &dyn LcpOperator, &to_physical as &dyn Fn(&[f64], &mut Vec<f64>)));
    // Exchanges within the bound and the loose last resort for every coupled
    // island. (They were once kept from islands of two dynamic bodies: before
    // the body-space check, a 1e8 kg box sliding on a 1 kg one met a step no
    // Lemke rung solved with them. With the check, `mass_ratio_failures`
    // (12 heavy-on-light cases, 2,000 steps): 0 failures with and without
    // them; answers left outside the body-space rule 11 → 7, the largest
    // energy a step created 2.2e-8 → 1.3e-12 of E₀ on the box–box cases; the
    // run took 90 s → 12 s.)
    let tol = BasisTolerances {
        accept_tol,
        tight: accept_tol * BASIS_CHECK_TOL,
        loose: true,
        // The last digits only where the body-space check will judge them.
        polish: mixed,
        // Not there either the extra exchange rounds of a small block: on a
        // 1e8 kg box sliding on a 1 kg one (`mass_ratio_failures`) the answers
        // they found were left outside the body-space rule on 10 of 2,000
        // steps (η_body up to 3.8e-8), against 1 (1.5e-8) with 8 rounds.
        more_rounds: !mixed,
        // Normal rows: held from round-off up (`lcp::on_basis::EAGER_REPAIR_FRACTION`).
        eager_rows: lcp.layout().nc,
    };
    let a = lcp::on_basis::solve_on_basis_ruled(&scaled, basis, tol, also, ws)?;
    // At scale 1, z and w are the physical ones (λ·1 and the same products).
    let (mut z, mut w) = std::mem::take(spare);
    let zw = match a.other {
        Some(zw) => {
            ws.recycle([z, w], []);
            zw
        }
        None => {
            z.clone_from(&a.solution.z);
            w.clone_from(&a.solution.w);
            (z, w)
        }
    };
    Some((a.solution, zw))
}
