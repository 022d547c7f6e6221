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
//! Statically indeterminate contact (four corners of a box on a box bear a
//! load that three constraints fix) makes a guessed basis rank-deficient. The
//! block is factored by the principal rank-revealing LU of [`principal`]
//! (shared with the dense Lemke's warm start); dependent indices leave the
//! support (`z_j = 0`, `w_j` basic instead), which keeps the previous vertex
//! of the solution set instead of jumping to another — the reason a resting
//! stack needs no pivot.
//!
//! The factorization is kept: when the next call starts from the basis it
//! factored (the previous answer's), `M_SS` is not formed again — the old
//! factors precondition iterative refinement against the new `M` (products
//! only, O(contacts) in body space), and a fresh factorization is made only
//! when that does not converge in a few steps. Refinement converges to the
//! solution of the new block itself; nothing about the problem is changed.
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
//! steps pivoting before, 7 after). The answer within the bound is returned
//! when the exchanges find no cleaner one.

pub(crate) mod principal;

use crate::operator::LcpOperator;
#[cfg(test)]
use crate::problem::Lcp;
use crate::solution::{Residuals, Solution, Status};

/// Buffers of [`solve_on_basis`], reused across calls by their owner; they
/// also keep the last factorization for the next call.
#[derive(Clone, Debug, Default)]
pub struct SupportWorkspace {
    /// Which `z_j` are basic in the basis being tried.
    mask: Vec<bool>,
    /// Support `S` (basic `z` indices) of the factorization.
    support: Vec<usize>,
    /// `M_SS`, factored in place by [`principal::factor`] (row-major).
    lu: Vec<f64>,
    /// The block `M_SS` of the last fresh factorization of this call, unfactored,
    /// and its support ([`form_block`]); `blocked` is false at a call's start.
    block: Vec<f64>,
    block_support: Vec<usize>,
    blocked: bool,
    /// Scratch of [`form_block`]: each index's position in `block_support`
    /// ([`NOT_IN_BLOCK`] between calls), the block before, the new indices' entries.
    block_pos: Vec<usize>,
    block_prev: Vec<f64>,
    block_fresh: Vec<f64>,
    /// Pivot order (positions in `S`) and rank: `β = S[order[..rank]]`.
    order: Vec<usize>,
    rank: usize,
    /// `β` as a mask when `lu` holds its factors (empty when it does not).
    factored: Vec<bool>,
    /// Right-hand side and solution, by position in `S`.
    x: Vec<f64>,
    y: Vec<f64>,
    /// `z` and `w` of a candidate in the operator's units, and in the other units.
    z: Vec<f64>,
    w: Vec<f64>,
    z2: Vec<f64>,
    w2: Vec<f64>,
    /// The factorization of the answer held while exchanges are tried.
    held: HeldFactors,
    /// The factors [`border`] grew from, their buffers kept for the next exchange.
    grown_from: HeldFactors,
    /// A basis whose exchanges found nothing better than its answer, and the
    /// violation below which they are not tried again from it.
    retry: Option<(Vec<bool>, f64)>,
    /// Columns of each row kept for the acceptance rule's bounds
    /// ([`crate::accept::rejected_row_operator`]), in `op`'s units and in the other ones.
    kept: Vec<crate::accept::KeptColumns>,
    kept_other: Vec<crate::accept::KeptColumns>,
    /// The indices exchanged in the current call.
    toggled: Vec<usize>,
    /// Basic indices whose `z` was negative before clipping, with that value.
    clipped: Vec<(usize, f64)>,
    /// One row of `M` (see [`clipped_cause`]).
    row: Vec<f64>,
    /// Calls in a row that found no answer (the caller pivoted).
    failures: usize,
}

/// A copy of [`SupportWorkspace`]'s factorization fields (also the factors
/// [`border`] grows): packed LU of `principal::factor` (row-major,
/// `support.len()` square), support, pivot order, rank, and `β` as a mask.
#[derive(Clone, Debug, Default)]
struct HeldFactors {
    support: Vec<usize>,
    lu: Vec<f64>,
    order: Vec<usize>,
    rank: usize,
    factored: Vec<bool>,
}

impl SupportWorkspace {
    /// Copies the current factorization aside.
    fn hold_factors(&mut self) {
        let h = &mut self.held;
        h.support.clone_from(&self.support);
        h.lu.clone_from(&self.lu);
        h.order.clone_from(&self.order);
        h.rank = self.rank;
        h.factored.clone_from(&self.factored);
    }

    /// Makes the factorization copied aside the current one again.
    fn restore_factors(&mut self) {
        let mut held = std::mem::take(&mut self.held);
        self.swap_factors(&mut held);
        self.held = held;
    }

    /// Exchanges the current factorization, buffers and all, with `h`.
    fn swap_factors(&mut self, h: &mut HeldFactors) {
        std::mem::swap(&mut h.support, &mut self.support);
        std::mem::swap(&mut h.lu, &mut self.lu);
        std::mem::swap(&mut h.order, &mut self.order);
        std::mem::swap(&mut h.rank, &mut self.rank);
        std::mem::swap(&mut h.factored, &mut self.factored);
    }

    /// Forgets the kept factorization (the next call factors afresh).
    pub fn forget(&mut self) {
        self.factored.clear();
    }

    /// Forgets the calls that found nothing: the next call tries every
    /// exchange round (for a caller whose other rungs failed, where time
    /// matters less than an answer).
    pub fn forget_failures(&mut self) {
        self.failures = 0;
    }

    /// Runs `attempt` (calls from a basis other than the previous answer's)
    /// with every exchange round; if it finds nothing, the count of failed
    /// calls is left as it was, so the back-off of the calls from the
    /// previous answer's basis goes on.
    pub fn fresh_attempt<R>(&mut self, attempt: impl FnOnce(&mut Self) -> Option<R>) -> Option<R> {
        let failures = self.failures;
        self.failures = 0;
        let found = attempt(self);
        if found.is_none() {
            self.failures = failures;
        }
        found
    }
}

/// The answer of [`solve_on_basis`] when it is accepted.
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
    ws: &mut SupportWorkspace,
) -> Option<BasisAnswer> {
    solve_on_basis_ruled(
        op,
        basis,
        BasisTolerances { accept_tol, tight: accept_tol, loose: false, polish: true, more_rounds: true },
        also,
        ws,
    )
}

/// When [`solve_on_basis_ruled`] accepts an answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasisTolerances {
    /// The acceptance rule's tolerance: every answer returned is accepted by
    /// [`crate::accept`] at it, on `op` and on the other units (`Solution::accepted`).
    pub accept_tol: f64,
    /// An answer the rule accepts whose natural residual is within
    /// `tight·(1 + ‖q‖∞)` (on `op` and on the other units, `tight ≤
    /// accept_tol`) is returned at once, or, with a violation above
    /// [`REPAIR_FRACTION`] of that bound, after exchanges find no cleaner one.
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
    /// [`REPAIR_ROUNDS`] ([`repair_rounds`]); `false`: that many.
    pub more_rounds: bool,
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
    ws: &mut SupportWorkspace,
) -> Option<BasisAnswer> {
    let n = op.n();
    if basis.len() != n {
        return None;
    }
    // Violations far below the acceptance bound are exchanged too, so a
    // slowly drifting vertex is left before its values reach the bound.
    let repair = REPAIR_FRACTION * tol.tight * (1.0 + norm_inf(op.q()));
    ws.mask.clear();
    ws.mask.extend_from_slice(basis);
    // After calls in a row that found nothing, the basis comes from the
    // caller's pivoting: exchanges are tried again only on the 1st, 2nd,
    // 4th, 8th, … such call (a resting stack's exchanges failed on 25
    // steps in a row, each ending in the pivoting anyway).
    let most = if tol.more_rounds { repair_rounds(basis) } else { REPAIR_ROUNDS };
    let rounds = if ws.failures.is_power_of_two() || ws.failures == 0 { most } else { 0 };
    let found = solve_rounds(op, basis, tol, also, ws, rounds, repair);
    ws.failures = if found.is_some() { 0 } else { ws.failures.saturating_add(1) };
    found
}

/// The rounds of [`solve_on_basis_ruled`] (`rounds` exchanges at most) from
/// `ws.mask`; `repair`: the violation above which an index is exchanged.
fn solve_rounds(
    op: &dyn LcpOperator,
    basis: &[bool],
    tol: BasisTolerances,
    also: Option<Also<'_>>,
    ws: &mut SupportWorkspace,
    rounds: usize,
    repair: f64,
) -> Option<BasisAnswer> {
    let n = op.n();
    // The operator is this call's: no block of an earlier call is reused.
    ws.blocked = false;
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
        let reused = round == 0 && ws.factored == ws.mask && refine_on_factor(op, ws, tol.polish);
        if !reused && !solve_fresh(op, ws, entered) {
            break;
        }
        let (m, rank) = (ws.support.len(), ws.rank);
        // Dependent indices carry z = 0: they leave the support.
        for &p in &ws.order[rank..m] {
            ws.mask[ws.support[p]] = false;
        }
        // The most violated index (basic z < 0 leaves, nonbasic w < 0 enters).
        let mut worst = (repair, None);
        for i in 0..n {
            let v = if ws.mask[i] { -ws.z[i] } else { -ws.w[i] };
            if v > worst.0 {
                worst = (v, Some(i));
            }
        }
        // Round-off negatives of z are clipped and w recomputed for the check.
        ws.clipped.clear();
        ws.clipped.extend(ws.z.iter().enumerate().filter(|&(_, &v)| v < 0.0).map(|(j, &v)| (j, v)));
        if !ws.clipped.is_empty() {
            ws.z.iter_mut().for_each(|v| *v = v.max(0.0));
            op.w_of(&ws.z, &mut ws.w);
        }
        let dropped = if reused { 0 } else { m - rank };
        // Within the normwise bounds, and whether the answer may be returned at all.
        let tight = within_both(op, also, tol.tight, ws);
        let loose =
            !tight && tol.loose && held.is_none() && ruled.is_none() && within_both(op, also, tol.accept_tol, ws);
        // The row the acceptance rule rejects, read only for an answer that
        // could be returned or held (an exchange round after one is held
        // needs no verdict unless it is clean).
        let usable = (tight && (worst.1.is_none() || held.is_none())) || loose;
        let rejected = if usable { rule_rejects(op, also, tol.accept_tol, worst.1.is_some(), ws) } else { None };
        let accepted = usable && rejected.is_none();
        if accepted && tight && worst.1.is_none() {
            return Some(answer(ws, dropped, reused, also.is_some(), true));
        }
        // Exchanges from this basis found nothing better at the last call,
        // and its violation has not grown much since: keep its answer.
        let known = ws.retry.as_ref().is_some_and(|(b, level)| round == 0 && b == basis && worst.0 < *level);
        if accepted && (tight && held.is_none() || loose) && known {
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
    let (answer, violation) = held.or(ruled)?;
    ws.restore_factors();
    ws.retry = Some((ws.factored.clone(), RETRY_GROWTH * violation));
    Some(answer)
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
fn clipped_cause(op: &dyn LcpOperator, r: usize, ws: &mut SupportWorkspace) -> Option<usize> {
    if ws.clipped.is_empty() {
        return None;
    }
    ws.row.clear();
    ws.row.resize(op.n(), 0.0);
    op.row(r, &mut ws.row);
    let sign = if ws.w[r] < 0.0 { -1.0 } else { 1.0 };
    let SupportWorkspace { clipped, row, toggled, .. } = ws;
    clipped
        .iter()
        .filter(|(j, _)| !toggled.contains(j))
        .map(|&(j, zj)| (j, sign * -row[j] * zj))
        .filter(|&(_, share)| share > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

/// The accepted answer in `ws`, on the basis `β` factored, with `z`, `w` in
/// the other units if `other`; the vectors are moved out of `ws` if `take`
/// (its last use in this call), else copied.
fn answer(ws: &mut SupportWorkspace, dropped: usize, reused: bool, other: bool, take: bool) -> BasisAnswer {
    let out = |v: &mut Vec<f64>| if take { std::mem::take(v) } else { v.clone() };
    let residuals = Residuals::of(&ws.z, &ws.w);
    let solution = Solution {
        z: out(&mut ws.z),
        w: out(&mut ws.w),
        status: Status::Solved,
        pivots: 0,
        residuals,
        basis: Some(ws.factored.clone()),
        accepted: true,
    };
    let other = other.then(|| (out(&mut ws.z2), out(&mut ws.w2)));
    BasisAnswer { solution, dropped, reused, other }
}

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
const RETRY_GROWTH: f64 = 2.0;

/// Index exchanges tried after the guessed basis itself (block principal
/// pivoting on the violated indices), at least; the caller pivots when they
/// do not do.
pub const REPAIR_ROUNDS: usize = 8;

/// Exchanges tried at most, for a small basic block ([`repair_rounds`]).
pub const REPAIR_ROUNDS_MAX: usize = 32;

/// The work of the exchange rounds, in `k³` of a `k`-index basic block
/// (a round factors it afresh): [`REPAIR_ROUNDS_MAX`] rounds of a block of
/// 90 indices.
const REPAIR_WORK: f64 = REPAIR_ROUNDS_MAX as f64 * 90.0 * 90.0 * 90.0;

/// Exchange rounds for a guess with `k` basic indices: as many as
/// [`REPAIR_WORK`] pays for, between [`REPAIR_ROUNDS`] and [`REPAIR_ROUNDS_MAX`].
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
fn repair_rounds(basis: &[bool]) -> usize {
    let k = basis.iter().filter(|&&b| b).count().max(1) as f64;
    ((REPAIR_WORK / (k * k * k)) as usize).clamp(REPAIR_ROUNDS, REPAIR_ROUNDS_MAX)
}

/// Refinement steps with a kept factorization before a fresh one is made.
const REFINE_STEPS: usize = 4;

/// Refinement has converged when its correction is below this fraction of `‖z_β‖∞`.
const REFINE_STOP: f64 = 1e-15;

/// Refinement has also converged when its correction, below this fraction
/// of `‖z_β‖∞`, did not halve the previous one (it stalls at round-off).
/// Measured on `stack_steps 2000 10`: from step ~1,100 the stack's basis
/// (78 basic indices) stalls at 1e-15–7e-15 and was factored afresh on
/// every step.
const REFINE_STALL: f64 = 1e-13;

/// `z` on `β` of the kept factorization, for the new `op`: the old factors
/// precondition iterative refinement against the new block (each step one
/// product `M z`). Leaves `ws.z`, `ws.w` and returns `true` once the
/// correction is negligible (applied, and `w` formed for it, only if
/// `polish`: see [`BasisTolerances::polish`]); `false` (factor afresh) otherwise.
fn refine_on_factor(op: &dyn LcpOperator, ws: &mut SupportWorkspace, polish: bool) -> bool {
    if ws.factored.len() != op.n() {
        return false;
    }
    first_solve(op, ws);
    let mut previous = f64::INFINITY;
    for step in 0..=REFINE_STEPS {
        op.w_of(&ws.z, &mut ws.w);
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
fn first_solve(op: &dyn LcpOperator, ws: &mut SupportWorkspace) {
    let (n, m, q) = (op.n(), ws.support.len(), op.q());
    ws.x.clear();
    ws.x.resize(m, 0.0);
    for &p in &ws.order[..ws.rank] {
        ws.x[p] = -q[ws.support[p]];
    }
    principal::solve(&ws.lu, m, &ws.order, ws.rank, &mut ws.x, &mut ws.y);
    ws.z.clear();
    ws.z.resize(n, 0.0);
    ws.w.resize(n, 0.0);
    scatter_add(&ws.x, &ws.order[..ws.rank], &ws.support, &mut ws.z);
}

/// One refinement step: `z_β += M_ββ⁻¹ (−w_β)` with the kept factors;
/// returns `(‖correction‖∞, ‖z_β‖∞)` (of `z_β` before the step).
fn correct(ws: &mut SupportWorkspace) -> (f64, f64) {
    let sizes = correction(ws);
    apply_correction(ws);
    sizes
}

/// The correction `x_β = M_ββ⁻¹ (−w_β)` into `ws.x` (not applied);
/// returns `(‖x_β‖∞, ‖z_β‖∞)`.
fn correction(ws: &mut SupportWorkspace) -> (f64, f64) {
    let m = ws.support.len();
    for &p in &ws.order[..ws.rank] {
        ws.x[p] = -ws.w[ws.support[p]];
    }
    principal::solve(&ws.lu, m, &ws.order, ws.rank, &mut ws.x, &mut ws.y);
    let beta = &ws.order[..ws.rank];
    let dmax = beta.iter().fold(0.0f64, |a, &p| a.max(ws.x[p].abs()));
    let zmax = beta.iter().fold(0.0f64, |a, &p| a.max(ws.z[ws.support[p]].abs()));
    (dmax, zmax)
}

/// `z_β += x_β` (the correction in `ws.x`).
fn apply_correction(ws: &mut SupportWorkspace) {
    scatter_add(&ws.x, &ws.order[..ws.rank], &ws.support, &mut ws.z);
}

/// `z[S[p]] += x[p]` for the positions `p` given.
fn scatter_add(x: &[f64], positions: &[usize], support: &[usize], z: &mut [f64]) {
    for &p in positions {
        z[support[p]] += x[p];
    }
}

/// Factors `M_SS` of the support `ws.mask`: when the support is the factored
/// `β` and the index `entered`, by bordering `β`'s factors ([`border`]),
/// else afresh ([`principal::factor`], `entered` pivoted first so that it
/// stays basic); then `z` on its regular block `β` with one refinement step
/// and `w = M z + q`, unclipped. `false` if the block or `z` is not finite.
///
/// Bordering, measured on resting stacks (`stack_steps 2000 4 … 16`): the
/// exchange rounds' fresh factorizations were ~11 % of the run; with it
/// steps that pivot 42 → 24, pivots 9,001 → 3,871, 26,000 steps 2.6 → 1.9 s
/// (the values differ from a fresh factorization's in their last digits, and
/// which steps pivot is chaotic: judged on the family).
fn solve_fresh(op: &dyn LcpOperator, ws: &mut SupportWorkspace, entered: Option<usize>) -> bool {
    let n = op.n();
    // The factors of β when the new support is β and the entering index.
    let grown = entered.filter(|&i| {
        ws.factored.len() == n && !ws.factored[i] && (0..n).all(|j| ws.mask[j] == (ws.factored[j] || j == i))
    });
    // β's factors move aside (into `grown_from`, whose buffers `ws` takes over).
    let old = grown.is_some().then(|| {
        let mut old = std::mem::take(&mut ws.grown_from);
        ws.swap_factors(&mut old);
        old
    });
    ws.factored.clear();
    ws.support.clear();
    ws.support.extend((0..n).filter(|&j| ws.mask[j]));
    let m = ws.support.len();
    form_block(op, ws);
    if !ws.block.iter().all(|v| v.is_finite()) {
        return false;
    }
    let bordered = matches!((grown, &old), (Some(i), Some(f)) if border(ws, i, f));
    if let Some(old) = old {
        ws.grown_from = old;
    }
    if !bordered {
        ws.lu.clone_from(&ws.block);
        let first = entered.and_then(|i| ws.support.binary_search(&i).ok());
        ws.rank = principal::factor(&mut ws.lu, m, &mut ws.order, first);
    }
    first_solve(op, ws);
    op.w_of(&ws.z, &mut ws.w);
    correct(ws);
    if !ws.z.iter().all(|v| v.is_finite()) {
        return false;
    }
    op.w_of(&ws.z, &mut ws.w);
    ws.factored.resize(n, false);
    for &p in &ws.order[..ws.rank] {
        ws.factored[ws.support[p]] = true;
    }
    true
}

/// The factors of `β ∪ {i}` from those of the regular block `β` (`old`, its
/// `rank` pivots; the new support `ws.support` is exactly `β` and `i`, its
/// block in `ws.block`): `i` bordered on as the last pivot, `L⁻¹ M_βi` its
/// column of `U`, `M_iβ U⁻¹` its row of `L` and `M_ii − M_iβ M_ββ⁻¹ M_βi` its
/// pivot — `O(k²)` where a fresh factorization costs `O(k³)`. `false` (`ws`'s
/// factors unset) when that pivot is below the rank tolerance of
/// [`principal::factor`]: `i` depends on `β`, and the fresh factorization
/// decides which index leaves.
fn border(ws: &mut SupportWorkspace, i: usize, old: &HeldFactors) -> bool {
    let (m, r, k) = (ws.support.len(), old.rank, old.support.len());
    if m != r + 1 {
        return false;
    }
    let at = |j: usize| ws.support.binary_search(&j).ok();
    let Some(pi) = at(i) else { return false };
    // The new support's position of each pivot of β, in pivot order.
    let SupportWorkspace { block, lu, order, .. } = ws;
    order.clear();
    for &p in &old.order[..r] {
        let Some(a) = at(old.support[p]) else { return false };
        order.push(a);
    }
    // (Every entry is written below.)
    lu.resize(m * m, 0.0);
    for t in 0..r {
        lu[t * m..t * m + r].copy_from_slice(&old.lu[t * k..t * k + r]);
    }
    // y = L⁻¹ M_βi (the new column of U), x = M_iβ U⁻¹ (the new row of L).
    for t in 0..r {
        let u = block[order[t] * m + pi] - (0..t).map(|s| lu[t * m + s] * lu[s * m + r]).sum::<f64>();
        lu[t * m + r] = u;
    }
    for t in 0..r {
        let l = block[pi * m + order[t]] - (0..t).map(|s| lu[r * m + s] * lu[s * m + t]).sum::<f64>();
        lu[r * m + t] = l / lu[t * m + t];
    }
    let pivot = block[pi * m + pi] - (0..r).map(|t| lu[r * m + t] * lu[t * m + r]).sum::<f64>();
    let amax = block.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(pivot.abs() > principal::RANK_TOL * amax) {
        return false;
    }
    lu[r * m + r] = pivot;
    order.push(pi);
    ws.rank = m;
    true
}

/// `ws.block` ← `M_SS` for the support `ws.support`. Within a call, the
/// entries of the previous block are copied and only the rows and columns of
/// indices new to the support are formed: an exchange round adds or removes
/// one index, so a round forms `2k` entries instead of `k²` (on a resting
/// 10-box stack forming the block was 11 % of the run, a fresh
/// factorization's share 12 %).
fn form_block(op: &dyn LcpOperator, ws: &mut SupportWorkspace) {
    let m = ws.support.len();
    let SupportWorkspace { support, block, block_support, blocked, block_pos, block_prev, block_fresh, .. } = ws;
    // (Every entry of the block is written below: it is sized, not cleared.)
    if !*blocked {
        block.resize(m * m, 0.0);
        op.block(support, support, block);
        block_support.clone_from(support);
        *blocked = true;
        return;
    }
    std::mem::swap(block, block_prev);
    let (old, k) = (&*block_prev, block_support.len());
    if block_pos.len() != op.n() {
        block_pos.clear();
        block_pos.resize(op.n(), NOT_IN_BLOCK);
    }
    block_support.iter().enumerate().for_each(|(p, &j)| block_pos[j] = p);
    // Positions in the new support of the indices new to it.
    let fresh_at: Vec<usize> = (0..m).filter(|&a| block_pos[support[a]] == NOT_IN_BLOCK).collect();
    block.resize(m * m, 0.0);
    for (a, &i) in support.iter().enumerate() {
        if block_pos[i] != NOT_IN_BLOCK {
            let row = &old[block_pos[i] * k..(block_pos[i] + 1) * k];
            for (b, &j) in support.iter().enumerate() {
                if block_pos[j] != NOT_IN_BLOCK {
                    block[a * m + b] = row[block_pos[j]];
                }
            }
        }
    }
    if !fresh_at.is_empty() {
        // The new indices' columns (every row), then their rows (every column).
        let (f, fresh) = (fresh_at.len(), fresh_at.iter().map(|&a| support[a]).collect::<Vec<_>>());
        block_fresh.resize(m * f, 0.0);
        op.block(support, &fresh, block_fresh);
        for a in 0..m {
            for (t, &b) in fresh_at.iter().enumerate() {
                block[a * m + b] = block_fresh[a * f + t];
            }
        }
        op.block(&fresh, support, block_fresh);
        for (t, &a) in fresh_at.iter().enumerate() {
            block[a * m..(a + 1) * m].copy_from_slice(&block_fresh[t * m..(t + 1) * m]);
        }
    }
    block_support.iter().for_each(|&j| block_pos[j] = NOT_IN_BLOCK);
    block_support.clone_from(support);
}

/// [`form_block`]'s mark of an index outside the previous block.
const NOT_IN_BLOCK: usize = usize::MAX;

/// The natural residual of `(z, w)` is within `accept_tol·(1 + ‖q‖∞)` of `op`.
fn within(op: &dyn LcpOperator, z: &[f64], w: &[f64], accept_tol: f64) -> bool {
    Residuals::of(z, w).residual <= accept_tol * (1.0 + norm_inf(op.q()))
}

/// The natural residual is within `accept_tol·(1 + ‖q‖∞)` on `op` and, with
/// `also`, on `z` mapped into the other units (into `ws.z2`, `ws.w2`).
fn within_both(op: &dyn LcpOperator, also: Option<Also<'_>>, accept_tol: f64, ws: &mut SupportWorkspace) -> bool {
    if !within(op, &ws.z, &ws.w, accept_tol) {
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
fn rule_rejects(
    op: &dyn LcpOperator,
    also: Option<Also<'_>>,
    accept_tol: f64,
    first: bool,
    ws: &mut SupportWorkspace,
) -> Option<usize> {
    let SupportWorkspace { z, w, z2, w2, kept, kept_other, .. } = ws;
    crate::accept::rejected_row_operator(op, z, w, accept_tol, first, kept).or_else(|| {
        let (other, _) = also?;
        crate::accept::rejected_row_operator(other, z2, w2, accept_tol, first, kept_other)
    })
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bordering an index onto the factors of a regular block solves the grown
    /// block as a fresh factorization does (to round-off), and refuses an
    /// index that depends on the block.
    #[test]
    fn a_bordered_index_solves_the_grown_block() {
        for seed in 0..10 {
            let lcp = crate::generate::p_matrix_lcp(24, seed);
            let (mut ws, old) = factored(&lcp, (0..24).filter(|j| j % 4 != 1).collect());
            let m = old.support.len();
            assert_eq!(ws.rank, m, "a P-matrix's principal blocks are regular");
            let i = 5;
            ws.support = (0..24).filter(|&j| j % 4 != 1 || j == i).collect();
            ws.blocked = true;
            form_block(&lcp, &mut ws);
            assert!(border(&mut ws, i, &old), "seed {seed}");
            let b: Vec<f64> = (0..m + 1).map(|t| (t as f64 * 0.37).sin()).collect();
            let (mut x, mut y) = (b.clone(), Vec::new());
            principal::solve(&ws.lu, m + 1, &ws.order, ws.rank, &mut x, &mut y);
            let mut fresh = ws.block.clone();
            let mut order = Vec::new();
            let rank = principal::factor(&mut fresh, m + 1, &mut order, None);
            let mut x0 = b.clone();
            principal::solve(&fresh, m + 1, &order, rank, &mut x0, &mut y);
            for (u, v) in x.iter().zip(&x0) {
                assert!((u - v).abs() <= 1e-10 * (1.0 + v.abs()), "seed {seed}: {u} vs {v}");
            }
        }
        // An index equal to one of the block's columns is refused.
        let m = vec![2.0, 1.0, 2.0, 1.0, 3.0, 1.0, 2.0, 1.0, 2.0];
        let lcp = Lcp::new(m, vec![-1.0; 3]).unwrap();
        let (mut ws, old) = factored(&lcp, vec![0, 1]);
        ws.support = vec![0, 1, 2];
        form_block(&lcp, &mut ws);
        assert!(!border(&mut ws, 2, &old), "column 2 is column 0");
    }

    /// A workspace holding the factors of `lcp`'s block on `support`, and a copy of them.
    fn factored(lcp: &Lcp, support: Vec<usize>) -> (SupportWorkspace, HeldFactors) {
        let mut ws = SupportWorkspace { support: support.clone(), ..Default::default() };
        form_block(lcp, &mut ws);
        ws.lu.clone_from(&ws.block);
        ws.rank = principal::factor(&mut ws.lu, support.len(), &mut ws.order, None);
        let held =
            HeldFactors { lu: ws.lu.clone(), support, order: ws.order.clone(), rank: ws.rank, ..Default::default() };
        (ws, held)
    }

    /// The block grown from the previous one, index by index in and out, is
    /// the block formed afresh, bit for bit.
    #[test]
    fn a_grown_block_is_the_block_formed_afresh() {
        let lcp = crate::generate::p_matrix_lcp(30, 7);
        let mut ws = SupportWorkspace::default();
        let mut mask: Vec<bool> = (0..30).map(|j| j % 3 != 0).collect();
        for (round, toggle) in [None, Some(0), Some(4), Some(29), Some(3), Some(0), Some(12)].into_iter().enumerate() {
            if let Some(j) = toggle {
                mask[j] = !mask[j];
            }
            ws.blocked = round > 0;
            ws.support = (0..30).filter(|&j| mask[j]).collect();
            form_block(&lcp, &mut ws);
            let m = ws.support.len();
            let mut afresh = vec![0.0; m * m];
            lcp.block(&ws.support, &ws.support, &mut afresh);
            assert_eq!(ws.block, afresh, "round {round}");
            assert_eq!(ws.block_support, ws.support);
        }
    }
}
