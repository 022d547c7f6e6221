//! Stage 2: a basis guessed from the previous step's impulses by a few
//! sweeps of body-space projected Gauss–Seidel, solved in body space as the
//! previous basis is. When the previous vertex has drifted a hair
//! infeasible, the guess usually lands on the new one at once.

use super::previous_basis::solve_in_body_space;
use super::stage::{Attempt, Found, PhysicalZw};
use crate::contact::ContactLcp;
use crate::pipeline::island::IslandLcp;
use lcp::on_basis::BasisWorkspace;
use lcp::structured::guess::GuessOptions;
use lcp::Solution;

/// The stage: the guessed basis, with every exchange round.
pub(super) fn attempt(isl: &mut IslandLcp, a: &Attempt<'_>) -> Option<Found> {
    let (sol, zw) = solve_guessed(&isl.lcp, a.z_prev, a.accept_tol, a.mixed, &mut isl.basis_ws)?;
    Some(Found { sol, physical: Some(zw) })
}

/// The stage applies to islands under this many unknowns; larger ones go
/// from a failed previous basis to the structured Lemke, which they would
/// otherwise reach after the guess failed too. On a forming pile the guess
/// answers few of them: 45-cube pour, seed 0, 3,000 steps, at ddc06d8 (the
/// stage timed per island), at n ≥ 300 it answered 15 of 1,017 islands, each
/// try costing half to all of the structured solve that followed it, 13 %
/// of the run in all; under 300 it answered 177 of 392. From 100 up a try
/// costs more than the structured solve it would spare (the same pour,
/// steps 0–2,000, every island of 100–300 unknowns solved with and without
/// the guess on copies: 1.75 s with it, 1.18 s without, docs/pours.md);
/// under 100 the two are within the measurement's noise. Resting stacks
/// (`stack_steps 2000 4 8 12 16`, n = 160–640) pivot on 1–3 of 2,000 steps
/// with it and without.
pub const GUESSED_MAX_N: usize = 100;

/// Sweeps of the guessed basis tried when the previous basis fails ([`solve_guessed`]).
/// Measured on resting stacks (`stack_steps 2000 …`, 2,000 steps each; which
/// steps pivot is chaotic in the stack's size and in the sweeps): on 4–16
/// boxes the steps that pivot fall 777 → 301; on 5, 7–12, 14 and 16 boxes
/// 550 → 218 with 60 sweeps (and, before `fresh_attempt` kept the back-off,
/// 216 with 60, 314 with 20, 326 with 120, 275 with 600 more
/// when 60 fail, 459 with 60 from zero impulses).
pub const GUESS_SWEEPS_PREVIOUS: usize = 60;

/// When the previous step's basis fails in body space (after its exchange
/// rounds, or none when the back-off of `lcp::on_basis` skips them), the
/// basis read from [`GUESS_SWEEPS_PREVIOUS`] sweeps of body-space projected
/// Gauss–Seidel (`lcp::structured::guess`) started at the previous
/// step's impulses `z_prev` (physical; from zero when it is not of this
/// size), solved and checked as the previous one is ([`solve_in_body_space`],
/// with every exchange round). On a resting stack the previous basis fails
/// when its answer has drifted to a vertex that round-off leaves a hair
/// infeasible; the dense Lemke then pivots a few hundred times from it to
/// another vertex, where the guess usually lands on one at once.
pub(super) fn solve_guessed(
    lcp: &ContactLcp,
    z_prev: &[f64],
    accept_tol: f64,
    mixed: bool,
    ws: &mut BasisWorkspace,
) -> Option<(Solution, PhysicalZw)> {
    let (lay, s) = (lcp.layout(), lcp.scale());
    let op = crate::contact::body_factors::structured_lcp(lcp, s).ok()?;
    // The sweeps work in the units solved: λ / s.
    let z0 = (z_prev.len() == lay.n()).then(|| {
        let mut z = z_prev.to_vec();
        z[lay.lambda_range()].iter_mut().for_each(|v| *v /= s);
        z
    });
    let o = GuessOptions { sweeps: GUESS_SWEEPS_PREVIOUS, ..Default::default() };
    let guess = lcp::structured::guess::guess_basis(&op, lay, &o, z0.as_deref());
    ws.fresh_attempt(|ws| solve_in_body_space(lcp, &guess, accept_tol, mixed, ws))
}
