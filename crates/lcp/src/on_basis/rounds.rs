//! The exchange rounds: one violated index at a time toggled, until an
//! answer is accepted or the rounds run out.
//!
//! An answer is returned only if the acceptance rule of [`crate::accept`]
//! accepts it — the rule every solver's `ok` answer meets, read through the
//! operator: a row's diagonal entry ([`LcpOperator::diag`]) for the cheap
//! bound that clears nearly every row, a few entries kept from the row's
//! last full read for most of the others, the row itself
//! ([`LcpOperator::row`]) for the few left — and its natural residual is within
//! `accept_tol·(1 + ‖q‖∞)`, on the problem as given and, when the caller
//! passes one, on a second operator in other units (the simulator's
//! unscaled, physical LCP). No regularization. A row the rule rejects is
//! exchanged like any violated index. The caller may ask for a tighter
//! normwise bound ([`BasisTolerances::tight`]); a violation above a tenth of
//! it is exchanged even when the answer is within it: a resting stack's
//! nonbasic corner at `w_n = −5e-12` m/s, kept step after step, sinks past
//! the contact gap floor, whose stabilization term then moves `q` by 2e-10
//! and costs hundreds of pivots (measured on the 10-box stack: 31 of 2,000
//! steps pivoting before, 7 after); a contact LCP's normal rows, above a
//! ten-thousandth ([`EAGER_REPAIR_FRACTION`]: left below the tenth, a
//! stack's boxes rock). The answer within the bound is returned when the
//! exchanges find no cleaner one.

use super::answer::{answer, Also, BasisAnswer, BasisTolerances};
use super::check::{rule_rejects, within_both};
use super::factors::solve_fresh;
use super::refine::refine_on_factor;
use super::workspace::BasisWorkspace;
use crate::kernels::most_violated;
use crate::operator::LcpOperator;

/// The rounds of [`solve_on_basis_ruled`](super::solve_on_basis_ruled) (`rounds` exchanges at most) from
/// `ws.mask`; `repair`: the violations above which an index is exchanged, and `op`'s `‖q‖∞`.
pub(super) fn solve_rounds(
    op: &dyn LcpOperator,
    basis: &[bool],
    tol: BasisTolerances,
    also: Option<Also<'_>>,
    ws: &mut BasisWorkspace,
    rounds: usize,
    repair: Repair,
) -> Option<BasisAnswer> {
    let Repair { q_norm, .. } = repair;
    // The operator is this call's: no block of an earlier call is reused.
    ws.blocked = false;
    ws.q_norm = q_norm;
    // The index the last exchange made basic.
    let mut entered = None;
    // The index the last exchange toggled.
    let mut last = None;
    ws.toggled.clear();
    // The first answer within the tight bound (a violation above `repair`
    // left), and the first within the loose one while there is none, each
    // with its largest violation.
    let (mut held, mut ruled) = (None, None);
    for round in 0..=rounds {
        let reused = round == 0 && ws.f.factored == ws.mask && refine_on_factor(op, ws, tol.polish);
        if !reused && !solve_fresh(op, ws, entered) {
            break;
        }
        let (m, rank) = (ws.f.support.len(), ws.f.rank);
        // Dependent indices carry z = 0: they leave the support.
        for &p in &ws.f.order[rank..m] {
            ws.mask[ws.f.support[p]] = false;
        }
        // The most violated index (basic z < 0 leaves, nonbasic w < 0 enters),
        // and the round-off negatives of z, clipped below.
        let (worst, negative) = repair.most_violated(&ws.mask, &ws.z, &ws.w);
        ws.clipped.clear();
        if negative {
            ws.clipped.extend(ws.z.iter().enumerate().filter(|&(_, &zi)| zi < 0.0).map(|(i, &zi)| (i, zi)));
        }
        // Clipped, they move w for the check: by their columns while they
        // are few (a resting 10-box stack clips a few friction values a step:
        // a product cost 10 % of its step), else by a product.
        if !ws.clipped.is_empty() {
            ws.z.iter_mut().for_each(|v| *v = v.max(0.0));
            if ws.clipped.len() <= CLIPPED_BY_COLUMNS {
                ws.moved.clear();
                ws.moved.extend(ws.clipped.iter().map(|&(j, v)| (j, -v)));
                op.add_columns(&ws.moved, &mut ws.w);
            } else {
                op.w_of(&ws.z, &mut ws.w);
            }
        }
        let dropped = if reused { 0 } else { m - rank };
        // Within the normwise bounds, and whether the answer may be returned at all.
        let tight = within_both(also, tol.tight, ws);
        let loose = !tight && tol.loose && held.is_none() && ruled.is_none() && within_both(also, tol.accept_tol, ws);
        // The row the acceptance rule rejects, read only for an answer that
        // could be returned or held (an exchange round after one is held
        // needs no verdict unless it is clean).
        let usable = (tight && (worst.1.is_none() || held.is_none())) || loose;
        let rejected = if usable { rule_rejects(op, also, tol.accept_tol, worst.1.is_some(), ws) } else { None };
        let accepted = usable && rejected.is_none();
        if accepted && tight && worst.1.is_none() {
            discard(ws, [held, ruled]);
            return Some(answer(ws, dropped, reused, also.is_some(), true));
        }
        // Exchanges from this basis found nothing better at the last call,
        // and its violation has not grown much since: keep its answer.
        let known = ws.retry.as_ref().is_some_and(|(b, level)| round == 0 && b == basis && worst.0 < *level);
        if accepted && (tight && held.is_none() || loose) && known {
            discard(ws, [held, ruled]);
            return Some(answer(ws, dropped, reused, also.is_some(), true));
        }
        if accepted && tight && held.is_none() {
            held = Some((answer(ws, dropped, reused, also.is_some(), false), worst.0));
            ws.hold_factors();
        }
        if accepted && loose {
            // (`loose` implies no answer is held: the factors are free to keep.)
            ruled = Some((answer(ws, dropped, reused, also.is_some(), false), worst.0));
            ws.hold_factors();
        }
        // One exchange at a time (all at once wanders on these degenerate
        // problems): the most violated index, else, for a row the rule
        // rejects, the clipped z that made it so (see [`clipped_cause`]), else
        // that row's index (a nonbasic w_i < 0 below the repair threshold but
        // above the row's own bound enters).
        let rejected = rejected.map(|r| clipped_cause(op, r, ws).unwrap_or(r));
        let Some(i) = worst.1.or(rejected) else { break };
        // Toggling back the index just exchanged would only cycle; so would
        // toggling again, for a row only the rule rejects, an index already
        // exchanged in this call.
        if last == Some(i) || (worst.1.is_none() && ws.toggled.contains(&i)) {
            break;
        }
        last = Some(i);
        ws.toggled.push(i);
        ws.mask[i] = !ws.mask[i];
        entered = ws.mask[i].then_some(i);
    }
    // The held answer, else the ruled one: its factorization is kept for the
    // next call, which starts from its basis.
    let (answer, violation) = match (held, ruled) {
        (Some(h), r) => {
            discard(ws, [r, None]);
            h
        }
        (None, r) => r?,
    };
    ws.restore_factors();
    // (The retry's mask buffer is reused.)
    let mut mask = ws.retry.take().map(|(b, _)| b).unwrap_or_default();
    mask.clone_from(&ws.f.factored);
    ws.retry = Some((mask, RETRY_GROWTH * violation));
    Some(answer)
}

/// The vectors of answers not returned, back to `ws`'s spares.
fn discard(ws: &mut BasisWorkspace, answers: [Option<(BasisAnswer, f64)>; 2]) {
    for (a, _) in answers.into_iter().flatten() {
        ws.recycle_answer(a);
    }
}

/// For a row `r` the acceptance rule rejects: the basic index, not yet
/// exchanged in this call, whose clipped negative `z_j` moved `w_r` furthest
/// in the direction of its violation (clipping adds `−M_rj z_j` to `w_r`),
/// if any did. Such a `z_j` leaves the basis instead of `r` being exchanged.
///
/// On a resting stack the basis of an unloaded corner (normal force 0, its
/// friction degenerate) solves to friction values of ±1e-13 that should be
/// 0: clipping the negative one leaves the cone row `w_λ = μ f_n − Σ f_d`
/// at −1e-13, just above its round-off floor. Exchanging `λ` itself was
/// undone by the next solve's round-off and ended the exchanges ("the same
/// index again"). Measured on `stack_steps 2000 4 … 16` (26,000 steps):
/// steps that pivot 200 → 100, pivots 49,596 → 40,204.
pub(super) fn clipped_cause(op: &dyn LcpOperator, r: usize, ws: &mut BasisWorkspace) -> Option<usize> {
    if ws.clipped.is_empty() {
        return None;
    }
    ws.row.clear();
    ws.row.resize(op.n(), 0.0);
    op.row(r, &mut ws.row);
    let sign = if ws.w[r] < 0.0 { -1.0 } else { 1.0 };
    let BasisWorkspace { clipped, row, toggled, .. } = ws;
    clipped
        .iter()
        .filter(|(j, _)| !toggled.contains(j))
        .map(|&(j, zj)| (j, sign * -row[j] * zj))
        .filter(|&(_, share)| share > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

/// Where [`solve_rounds`] exchanges an index in an answer within the bound.
#[derive(Clone, Copy, Debug)]
pub(super) struct Repair {
    /// The violation above which an index is exchanged.
    pub floor: f64,
    /// The first `.0` indices are exchanged above `.1` instead ([`BasisTolerances::eager_rows`]).
    pub eager: (usize, f64),
    /// `op`'s `‖q‖∞`.
    pub q_norm: f64,
}

impl Repair {
    /// The most violated index (basic `z < 0`, nonbasic `w < 0`) among those
    /// above their floors, with its violation (`(floor, None)` when none is
    /// above), and whether some `z < 0`. The largest violation goes first,
    /// whichever floor it passed: ranked by their floors instead, a normal
    /// row at 1e-14 went before a friction row at 1e-12, and on 45-cube pours
    /// (4 directions, seeds 0 and 1, 2,000 steps) the rounds ended without
    /// an answer 18 % more often.
    fn most_violated(&self, basic: &[bool], z: &[f64], w: &[f64]) -> ((f64, Option<usize>), bool) {
        let (e, eager_floor) = self.eager;
        let e = e.min(basic.len()).min(z.len()).min(w.len());
        if e == 0 {
            return most_violated(basic, z, w, self.floor);
        }
        let ((top_e, at_e), neg_e) = most_violated(&basic[..e], &z[..e], &w[..e], eager_floor);
        let ((top, at), neg) = most_violated(&basic[e..], &z[e..], &w[e..], self.floor);
        let worst = match (at_e, at) {
            (Some(i), None) => (top_e, Some(i)),
            (Some(i), Some(_)) if top_e >= top => (top_e, Some(i)),
            (_, at) => (top, at.map(|j| j + e)),
        };
        (worst, neg_e || neg)
    }
}

/// Violations of the eager rows ([`BasisTolerances::eager_rows`], a contact
/// LCP's normal rows) above this fraction of `tight·(1 + ‖q‖∞)` are
/// exchanged — a thousandth of [`REPAIR_FRACTION`]: there, one left
/// violated feeds an unstable mode. A box of a resting stack carries its
/// load on two diagonal corners; the other two, a basic one at zero force
/// and a nonbasic one at zero velocity, hold its rocking about that
/// diagonal. Round-off turns the first's force a hair negative (clipped to
/// 0) and lets the second sink a hair: both are free, and the box above,
/// balanced on an edge, is an inverted pendulum. Left below
/// `REPAIR_FRACTION`, those violations on the 10-box stack doubled every
/// ~40 steps from 1e-16 m/s, the boxes tilting and sliding with them, until
/// after ~500 steps friction at round-off entered the basis, which grew
/// from 30 to ~110 indices, every step and exchange paying for the larger
/// block (`step_budget profile stack4 4000`: 150 ms; with this, the tilt
/// stays below 5e-16 rad, the basis at 28–30, 56 ms). Friction rows keep
/// `REPAIR_FRACTION`: a sliding velocity at round-off only drifts the
/// position (linearly in time).
pub const EAGER_REPAIR_FRACTION: f64 = 1e-4;

/// Clipped entries of `z` whose columns move `w` ([`LcpOperator::add_columns`]);
/// more, and `w` is formed again.
const CLIPPED_BY_COLUMNS: usize = 8;

/// Violations above this fraction of `accept_tol·(1 + ‖q‖∞)` are exchanged,
/// also in an answer within the bound. Measured on `stack_steps 2000 10`:
/// 0.1 → 7 pivoting steps, 39 steps with exchanges; 0.03 and 0.01 → 1–2
/// pivoting steps but 530–870 steps running every exchange round (slower).
pub const REPAIR_FRACTION: f64 = 0.1;

/// Exchanges that found nothing better than an answer within the bound are
/// tried again from its basis once its largest violation has grown by this
/// factor. Measured on `stack_steps 2000 10`: without it ~200 steps ran every
/// exchange round in vain, step after step (a violation 1 % above the
/// threshold, growing 1 % per step). The same holds for an answer within only
/// the rule's own bound (`loose`): from step ~5,550 of the 10-box stack every
/// step's answer was one at 0.2 of it (an unloaded corner at `w = −2e-10`
/// m/s, held there by the gap stabilization), each after every exchange round
/// failed on fresh factorizations: `stack_steps 10000 10` ran at 1,979
/// steps/s; with the exchanges skipped and the answer's factorization kept,
/// 17,373 (same pivots).
pub(super) const RETRY_GROWTH: f64 = 2.0;

/// Index exchanges tried after the guessed basis itself (block principal
/// pivoting on the violated indices), at least; the caller pivots when they
/// do not do.
pub const REPAIR_ROUNDS: usize = 8;

/// Exchanges tried at most, for a small basic block ([`repair_rounds`](super::rounds::repair_rounds)).
pub const REPAIR_ROUNDS_MAX: usize = 32;

/// The work of the exchange rounds, in `k³` of a `k`-index basic block
/// (a round factors it afresh): [`REPAIR_ROUNDS_MAX`] rounds of a block of
/// 90 indices.
pub(super) const REPAIR_WORK: f64 = REPAIR_ROUNDS_MAX as f64 * 90.0 * 90.0 * 90.0;

/// Exchange rounds for a guess with `k` basic indices: as many as
/// [`REPAIR_WORK`] pays for, between [`REPAIR_ROUNDS`](super::REPAIR_ROUNDS) and [`REPAIR_ROUNDS_MAX`].
///
/// Measured on resting stacks (`stack_steps 2000 4 … 16`, 26,000 steps, basic
/// blocks of 30–90 indices; with [`clipped_cause`]): 8 rounds → 100 steps
/// pivot (40,204 pivots, 4.3 s), 16 → 56 (17,682, 3.0 s), 32 → 39 (7,561,
/// 2.5 s), 64 → 38 (6,739, 2.7 s): a round costs one factorization, the
/// pivoting step it saves a few hundred pivots. On a forming 14-cube heap
/// (`many_bodies heap:14 400`, blocks of 100–260 indices) 32 rounds nearly
/// never found an answer 8 had not (2 of ~80 calls) and the run fell from
/// 142 to 82 steps/s; with this budget 127 (8 rounds: 134; the runs part
/// ways, 113 against 106 pivots a step).
pub(super) fn repair_rounds(basis: &[bool]) -> usize {
    let k = basis.iter().filter(|&&b| b).count().max(1) as f64;
    ((REPAIR_WORK / (k * k * k)) as usize).clamp(REPAIR_ROUNDS, REPAIR_ROUNDS_MAX)
}

#[cfg(test)]
mod tests {
    use super::Repair;

    /// Two eager rows (floor 1e-15) before three others (floor 1e-12).
    fn repair() -> Repair {
        Repair { floor: 1e-12, eager: (2, 1e-15), q_norm: 0.0 }
    }

    #[test]
    fn eager_rows_are_exchanged_from_their_own_floor_and_the_largest_violation_goes_first() {
        let basic = [true, false, false, false, true];
        // Eager: a basic z at −1e-14 (past its floor); others: a nonbasic w
        // at −5e-13 (not past 1e-12) and a basic z at −2e-12 (past).
        let (z, w) = ([-1e-14, 0.0, 0.0, 0.0, -2e-12], [0.0, 0.0, 0.0, -5e-13, 0.0]);
        assert_eq!(repair().most_violated(&basic, &z, &w), ((2e-12, Some(4)), true));
        // Without the large one the eager row's small violation is exchanged.
        let z = [-1e-14, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(repair().most_violated(&basic, &z, &w), ((1e-14, Some(0)), true));
        // The same violations past no floor: none (an eager row's below 1e-15, the rest below 1e-12).
        let (z, w) = ([-5e-16, 0.0, 0.0, 0.0, -5e-13], [0.0, -9e-16, 0.0, -5e-13, 0.0]);
        assert_eq!(repair().most_violated(&basic, &z, &w), ((1e-12, None), true));
        // A nonbasic eager w past its floor, and no eager rows at all: the plain scan.
        let (z, w) = ([0.0; 5], [0.0, -3e-15, 0.0, -5e-13, 0.0]);
        assert_eq!(repair().most_violated(&basic, &z, &w), ((3e-15, Some(1)), false));
        let plain = Repair { eager: (0, 1e-15), ..repair() };
        assert_eq!(plain.most_violated(&basic, &z, &w), ((1e-12, None), false));
    }
}
