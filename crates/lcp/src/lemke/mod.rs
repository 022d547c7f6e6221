//! Lemke's complementary pivoting method.
//!
//! - [`basis`]: the basis in block form, `C⁻¹` kept and updated in O(m²).
//! - [`ratio`]: the lexicographic and the classic (source note's) ratio tests.
//! - [`run`]: the pivoting loop with its cycle guard and pivot limit.
//! - [`refine`]: re-solving the final complementary basis.
//! - [`extended`], [`dd_solve`]: Lemke in double-double arithmetic, the rung
//!   for bases beyond `f64` (a heavy body on a light one); [`precise`]: the
//!   same on demand, for an answer the caller doubts ([`solve_dd`]).
//! - [`exact`]: Lemke in exact integer arithmetic, the ladder's last rung.
//! - [`frame`]: a rung's working (equilibrated) problem and its acceptance test.
//! - [`warm`], [`subbasis`]: the warm start's basis, made regular when the
//!   previous answer's is singular (statically indeterminate contact).
//! - [`workspace`]: the caller-owned buffers of a solve ([`solve_in`]).
//!
//! `Lexicographic` (default) equilibrates `M` (Ruiz, power-of-two factors, so
//! the scaling itself adds no round-off) and normalizes `q`, pivots, re-solves
//! the final basis, maps `z` back and accepts it only if its natural residual
//! in the units given is small. `Classic` pivots on the problem as given with
//! absolute tolerances and trusts its own values, as the source note's did.

mod basis;
mod dd_solve;
mod exact;
mod extended;
mod frame;
mod options;
mod precise;
mod ratio;
mod refine;
mod run;
mod subbasis;
mod warm;
mod workspace;

pub use options::{LemkeOptions, Pivoting};
pub use precise::{solve_dd, DD_MAX_N};
pub use run::PivotRecord;
pub use workspace::Workspace;

/// The basis hash's key of a variable (shared with [`crate::structured`]).
pub(crate) use basis::key as basis_hash_key;

use crate::newton_fb::NewtonFbOptions;
use crate::problem::Lcp;
use crate::solution::{Solution, Status};
use basis::Var;
use ratio::Rule;
use run::RunSettings;
use warm::Start;

/// Solves `lcp` by Lemke's method. Never panics on numerics. Allocates a
/// workspace for the call; a caller that solves often holds one and calls
/// [`solve_in`].
pub fn solve(lcp: &Lcp, o: &LemkeOptions) -> Solution {
    solve_in(lcp, o, None, &mut Workspace::new())
}

/// Solves `lcp` starting from a guessed complementary basis (`basis[j]`: z_j
/// basic), typically the previous time step's `Solution::basis`. A guess
/// whose block `M_αα` is singular (statically indeterminate contact) is first
/// cut down to a regular principal block on the same support (`subbasis`).
/// If that basis solves the problem — its values, round-off negatives
/// clipped, pass the usual residual check — no pivot is needed; else up to
/// `warm::SWAP_ROUNDS` block principal pivots exchange its negative basics
/// for their complements (each exchange counts as a pivot), each result
/// checked the same way; then Lemke runs from the last basis with the
/// covering vector `d = B·1`, and the usual cold start follows if that fails.
/// A basis of the wrong length is ignored. `Classic` pivoting ignores the
/// guess (the source note's Lemke started cold).
pub fn solve_warm(lcp: &Lcp, o: &LemkeOptions, basis: Option<&[bool]>) -> Solution {
    solve_in(lcp, o, basis, &mut Workspace::new())
}

/// As [`solve_warm`], also returning every pivot taken (over all rungs of
/// the repair ladder): the pivot trace of a failure dump.
pub fn solve_traced(lcp: &Lcp, o: &LemkeOptions, basis: Option<&[bool]>) -> (Solution, Vec<PivotRecord>) {
    solve_traced_in(lcp, o, basis, &mut Workspace::new())
}

/// As [`solve_warm`], in the caller's workspace `ws`: on a workspace that
/// has solved a problem of this size before, nothing is allocated but the
/// answer (see [`Workspace`]). The answer does not depend on what `ws` saw.
pub fn solve_in(lcp: &Lcp, o: &LemkeOptions, basis: Option<&[bool]>, ws: &mut Workspace) -> Solution {
    solve_inner(lcp, o, basis, None, ws)
}

/// As [`solve_traced`], in the caller's workspace `ws`.
pub fn solve_traced_in(
    lcp: &Lcp,
    o: &LemkeOptions,
    basis: Option<&[bool]>,
    ws: &mut Workspace,
) -> (Solution, Vec<PivotRecord>) {
    let mut trace = Vec::new();
    let sol = solve_inner(lcp, o, basis, Some(&mut trace), ws);
    (sol, trace)
}

fn solve_inner(
    lcp: &Lcp,
    o: &LemkeOptions,
    basis: Option<&[bool]>,
    trace: Option<&mut Vec<PivotRecord>>,
    ws: &mut Workspace,
) -> Solution {
    match o.pivoting {
        Pivoting::Classic => solve_classic(lcp, o, trace, ws),
        Pivoting::Lexicographic => solve_lexicographic(lcp, o, basis.filter(|_| o.warm_start), trace, ws),
    }
}

/// Refactor often enough to bound drift, rarely enough to stay O(n²) per pivot.
fn refactor_every(n: usize) -> usize {
    n.max(50)
}

fn solve_classic(lcp: &Lcp, o: &LemkeOptions, trace: Option<&mut Vec<PivotRecord>>, ws: &mut Workspace) -> Solution {
    // z = 0 when no q_i is below −zero_tol.
    if lcp.q().iter().all(|&v| v > -o.zero_tol) {
        return Solution::from_z(lcp, vec![0.0; lcp.n()], Status::Solved, 0);
    }
    // The standard covering vector d = 1. (Moby uses 1 only where q < 0; with
    // d_i = 0 elsewhere Lemke loses its guarantee and this rule ray-terminates
    // on nearly every step of a cube resting on a 30° slope.)
    ws.d.clear();
    ws.d.resize(lcp.n(), 1.0);
    let set = RunSettings {
        rule: Rule::Classic { piv_tol: o.piv_tol, zero_tol: o.zero_tol },
        trace: trace.is_some(),
        max_pivots: o.pivot_limit(lcp.n()),
        refactor_every: refactor_every(lcp.n()),
    };
    let r = run::run(lcp, &ws.d, &set, std::mem::take(&mut ws.basis), &mut ws.pivoting);
    if let Some(t) = trace {
        t.extend_from_slice(&r.trace);
    }
    let mut z = Vec::with_capacity(lcp.n());
    r.basis.z_into(&mut z);
    let mask = basic_mask(&r.basis.s, lcp.n());
    ws.basis = r.basis.into_buffers();
    let mut sol = Solution::from_z(lcp, z, r.status, r.pivots);
    // z0 left, but does z solve the problem? Moby's check, with the user zero
    // on the problem as given: z, w ≥ −zero_tol and |z_i w_i| < zero_tol.
    let res = &sol.residuals;
    if sol.status == Status::Solved
        && !(res.min_z >= -o.zero_tol && res.min_w >= -o.zero_tol && res.max_complementarity < o.zero_tol)
    {
        sol.status = Status::Numerical;
    }
    sol.basis = Some(mask);
    sol
}

/// One rung of the repair ladder.
#[derive(Clone, Copy)]
struct Attempt {
    equilibrate: bool,
    /// Relative pivot tolerance.
    piv_rel: f64,
    /// Covering vector: 0 is `d = 1`; `k ≥ 1` the `k`-th irregular one (see
    /// `covering`), each a different path through the same problem.
    cover: u32,
    /// Relative tolerance under which two ratios tie.
    tie_tol: f64,
}

/// Round-off in a computed column is far above 1e-12 of its largest entry once
/// `C` is ill-conditioned (contact LCPs are rank-deficient): pivots smaller
/// than this are treated as zero.
const MIN_RELATIVE_PIVOT: f64 = 1e-9;

/// Ratios within this fraction of the largest basic value tie. Exact equality
/// (0) lets round-off break the ties that degenerate contact LCPs are full of
/// and ends in false rays on a third of them; 1e-9 merges ratios that differ
/// for real in stacks (loads spread over 10⁻¹⁰ of the largest impulse).
/// Measured: 1e-13 and 1e-14 both solve every generated contact LCP and every
/// stack LCP that 1e-9 and 0 fail on.
const TIE_TOL: f64 = 1e-13;

/// Rungs on other covering vectors after the named ones (see `ladder`).
const EXTRA_COVERS: u32 = 4;

/// Lemke restarts from failed rungs' final bases after the ladder (see `restart_from_ends`).
const RESTARTS: usize = 6;

/// Rungs of the full ladder.
const RUNGS: usize = 5 + EXTRA_COVERS as usize;

/// The repair ladder: each rung runs only if the previous one failed its check
/// (and a restart from its final basis, if complementary, failed too);
/// after the last, restarts from the rungs' final bases and a Newton–FB polish
/// of the closest answer (see `solve_lexicographic`). Returned as an array
/// with the number of rungs in use.
fn ladder(o: &LemkeOptions) -> ([Attempt; RUNGS], usize) {
    let first =
        Attempt { equilibrate: o.equilibrate, piv_rel: o.piv_tol.max(MIN_RELATIVE_PIVOT), cover: 0, tie_tol: TIE_TOL };
    let mut all = [first; RUNGS];
    if !o.fallback {
        return (all, 1);
    }
    let named = [
        first,
        // A coarser pivot tolerance steps around near-singular bases.
        Attempt { piv_rel: 1e-7, ..first },
        // Another covering vector follows another path.
        Attempt { piv_rel: 1e-7, cover: 1, ..first },
        // Coarser ties, for problems whose round-off exceeds TIE_TOL.
        Attempt { tie_tol: 1e-10, ..first },
        // The other scaling.
        Attempt { equilibrate: !o.equilibrate, ..first },
    ];
    // More paths. With twin contacts (normals 1e-6 rad apart) the path crosses
    // bases with pivots ~1e-7 of their column, and ratio tests decided on
    // values that carry cond(C)·ε of round-off end on a basis wrong by ~1e-8;
    // whether a path meets such a basis depends on d. Measured on the hard
    // corpus (seeds 2026, 1, 2, 3; 3000 LCPs each at 6 scales), with restarts:
    // 27 failures without these rungs, 6 (all one LCP) with them.
    let more =
        (2..2 + EXTRA_COVERS).map(|k| Attempt { piv_rel: if k % 2 == 0 { 1e-7 } else { 1e-9 }, cover: k, ..first });
    all.iter_mut().zip(named.into_iter().chain(more)).for_each(|(a, b)| *a = b);
    (all, RUNGS)
}

/// Where a climb down the repair ladder stands: pivots spent, the answers
/// kept and the complementary bases already restarted from.
struct Climb<'t> {
    pivots: usize,
    limit: usize,
    /// `accept_tol·(1 + ‖q‖∞)`: see [`Climb::tight`].
    bound: f64,
    /// The closest failure (by natural residual) of the rungs.
    best: Option<Solution>,
    /// The first answer the acceptance rule accepts.
    within: Option<Solution>,
    /// Final bases of the failed rungs, with their natural residuals.
    ends: Vec<(f64, Vec<bool>)>,
    /// Bases restarted from.
    tried: Vec<Vec<bool>>,
    /// Number of the next rung (for the trace).
    rung: usize,
    trace: Option<&'t mut Vec<PivotRecord>>,
}

impl Climb<'_> {
    /// The ladder stops at an answer that the acceptance rule accepts *and*
    /// whose natural residual is within `accept_tol·(1 + ‖q‖∞)` (on twin
    /// contacts a basis can pass the rule at η ~ 1e-12 with rows of cancelling
    /// impulses 3e-9 off, which a later rung improves on); the first answer
    /// that passes the rule alone is returned if none does both.
    fn tight(&self, s: &Solution) -> bool {
        s.ok() && s.residuals.residual <= self.bound
    }

    /// Runs one rung (from the complementary basis `start` if given) and
    /// counts its pivots; the answer, and whether it ends the climb.
    fn attempt(
        &mut self,
        lcp: &Lcp,
        o: &LemkeOptions,
        attempt: &Attempt,
        start: Option<&[usize]>,
        ws: &mut Workspace,
    ) -> (Solution, bool) {
        let left = self.limit.saturating_sub(self.pivots);
        let mut sol = solve_attempt(lcp, o, attempt, left, start, self.trace.as_deref_mut(), self.rung, ws);
        self.rung += 1;
        self.pivots += sol.pivots;
        sol.pivots = self.pivots;
        let done = self.tight(&sol);
        if !done && sol.ok() && self.within.is_none() {
            self.within = Some(sol.clone());
        }
        (sol, done)
    }

    /// Restarts Lemke from the complementary basis `start` (on the first
    /// rung's settings) unless it was tried; `Some` answer if that ends the
    /// climb, and the restart's own basis if it ended complementary but off.
    fn restart(
        &mut self,
        lcp: &Lcp,
        o: &LemkeOptions,
        first: &Attempt,
        start: Vec<bool>,
        ws: &mut Workspace,
    ) -> (Option<Solution>, Option<Vec<bool>>) {
        if self.tried.contains(&start) {
            return (None, None);
        }
        let alpha: Vec<usize> = (0..start.len()).filter(|&j| start[j]).collect();
        self.tried.push(start);
        let (sol, done) = self.attempt(lcp, o, first, Some(&alpha), ws);
        if done {
            return (Some(sol), None);
        }
        let next = sol.basis.filter(|b| sol.status == Status::Numerical && !self.tried.contains(b));
        (None, next)
    }
}

fn solve_lexicographic(
    lcp: &Lcp,
    o: &LemkeOptions,
    warm: Option<&[bool]>,
    trace: Option<&mut Vec<PivotRecord>>,
    ws: &mut Workspace,
) -> Solution {
    let mut climb = Climb {
        pivots: 0,
        limit: o.pivot_limit(lcp.n()),
        bound: o.accept_tol * (1.0 + lcp.q_norm_inf()),
        best: None,
        within: None,
        ends: Vec::new(),
        tried: Vec::new(),
        rung: 0,
        trace,
    };
    let (all_rungs, used) = ladder(o);
    let rungs = &all_rungs[..used];
    // A warm start runs first, on the first rung's settings; the cold ladder follows if it fails.
    let mut alpha = std::mem::take(&mut ws.alpha);
    alpha.clear();
    let warm = warm.filter(|b| b.len() == lcp.n());
    if let Some(b) = warm {
        alpha.extend((0..b.len()).filter(|&j| b[j]));
    }
    let warm_rung = warm.map(|_| (rungs[0], Some(alpha.as_slice())));
    for (attempt, start) in warm_rung.into_iter().chain(rungs.iter().map(|&r| (r, None))) {
        // `max_pivots` bounds the whole ladder, not each rung.
        if climb.pivots >= climb.limit && climb.best.is_some() {
            break;
        }
        let (sol, done) = climb.attempt(lcp, o, &attempt, start, ws);
        if done {
            ws.alpha = alpha;
            return sol;
        }
        let end = sol.basis.clone().filter(|b| !climb.ends.iter().any(|(_, e)| e == b));
        // Keep the first failure's status unless a later rung gets closer.
        if climb.best.as_ref().is_none_or(|b| sol.residuals.residual < b.residuals.residual) {
            climb.best = Some(sol.clone());
        }
        let Some(b) = end else { continue };
        climb.ends.push((sol.residuals.residual, b.clone()));
        // A complementary basis off by a hair: restart from it at once (a
        // few pivots) rather than after the other rungs (hundreds each).
        // Measured on the 10-box stack (`stack_steps -- 2000 10`): restarts
        // after the ladder only, 1 failed LCP (cycling) and 21,601 pivots; at
        // once, 0 and 15,000.
        if o.fallback && sol.status == Status::Numerical && climb.pivots < climb.limit {
            match climb.restart(lcp, o, &rungs[0], b, ws) {
                (Some(sol), _) => {
                    ws.alpha = alpha;
                    return sol;
                }
                // Its end is restarted from after the ladder, closest first.
                (None, Some(next)) => climb.ends.push((f64::INFINITY, next)),
                (None, None) => {}
            }
        }
    }
    ws.alpha = alpha;
    if let Some(sol) = restart_from_ends(lcp, o, &rungs[0], &mut climb, ws) {
        return sol;
    }
    finish(lcp, o, rungs[0].equilibrate, climb, ws)
}

/// Restarts Lemke from the rungs' final bases, closest first. On twin and
/// duplicate contacts a run crosses bases whose C is ill-conditioned
/// (pivots ~1e-7 of their column), decides near-ties on values carrying that
/// round-off, and ends on a well-conditioned complementary basis that is
/// wrong by a hair: solved exactly (`certify`), a few w_i are −1e-8 where 0
/// was due, so no re-solve helps. Lemke from that basis (covering vector
/// B·1, fresh factorization) takes the few pivots left on accurate values.
/// A restart that ends complementary but off is restarted from in turn.
/// Restarts do not replace `best`: the polish of [`finish`] starts from the
/// ladder's answer (from a restart's end it failed on LCPs it had solved).
fn restart_from_ends(
    lcp: &Lcp,
    o: &LemkeOptions,
    first: &Attempt,
    climb: &mut Climb,
    ws: &mut Workspace,
) -> Option<Solution> {
    if !o.fallback {
        return None;
    }
    climb.ends.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut queue: Vec<Vec<bool>> = climb.ends.iter().rev().map(|(_, b)| b.clone()).collect();
    let mut restarts = 0;
    while let Some(start) = queue.pop() {
        if climb.pivots >= climb.limit || restarts >= RESTARTS {
            break;
        }
        if climb.tried.contains(&start) {
            continue;
        }
        restarts += 1;
        match climb.restart(lcp, o, first, start, ws) {
            (Some(sol), _) => return Some(sol),
            (None, Some(next)) => queue.push(next),
            (None, None) => {}
        }
    }
    None
}

/// The ladder's last rungs on its closest failure: a Newton–FB polish, then
/// Lemke in double-double (when nothing was accepted), then exact Lemke;
/// else the first answer within the rule, else the failure.
fn finish(lcp: &Lcp, o: &LemkeOptions, equilibrate: bool, climb: Climb, ws: &mut Workspace) -> Solution {
    let pivots = climb.pivots;
    let mut sol = climb.best.expect("the ladder has at least one rung");
    sol.pivots = pivots;
    let tight = |s: &Solution| s.ok() && s.residuals.residual <= climb.bound;
    // (Not when the pivot budget ran out: that limit is the caller's to set.)
    if o.fallback && sol.status != Status::MaxPivots && !tight(&sol) {
        // Newton–Fischer–Burmeister polish from the closest answer. Its z is
        // accepted only by the acceptance rule (it solves M, not a
        // regularized M); its basis is the support of z.
        let frame = &mut ws.frame;
        frame.reset(lcp, equilibrate, o.accept_tol);
        let opts = NewtonFbOptions { tol: frame.tol, ..Default::default() };
        let polished = crate::newton_fb::solve_from(lcp, &sol.z, &opts);
        let accepted = crate::accept::accepts(lcp, &polished.z, &polished.w, o.accept_tol);
        if accepted && polished.residuals.residual < sol.residuals.residual {
            let basis = polished.z.iter().zip(&polished.w).map(|(z, w)| z > w).collect();
            sol = Solution { status: Status::Solved, pivots, basis: Some(basis), accepted, ..polished };
        }
    }
    // Nothing accepted so far: the double-double rung (answers the `f64`
    // rungs accepted stay as they were).
    if o.fallback
        && !sol.ok()
        && climb.within.is_none()
        && sol.status != Status::MaxPivots
        && lcp.n() <= extended::MAX_N
    {
        let budget = climb.limit.saturating_sub(sol.pivots);
        sol = solve_extended(lcp, o, equilibrate, sol, budget, ws);
    }
    if o.fallback && !tight(&sol) && sol.status != Status::MaxPivots && lcp.n() <= exact::MAX_N {
        let budget = climb.limit.saturating_sub(sol.pivots);
        sol = solve_exact(lcp, o, sol, budget);
    }
    match climb.within {
        Some(w) if !sol.ok() => Solution { pivots: sol.pivots, ..w },
        _ => sol,
    }
}

/// Double-double operations [`extended::solve`] may spend: ~0.1 s at the
/// ~5 ns an operation that n = 80 takes here (107 pivots, at most 1.4e6
/// operations, 6.7 ms: `extended::tests::timing`).
const EXTENDED_OPS: usize = 20_000_000;

/// The double-double rung (see [`extended`]): Lemke from scratch on the
/// working problem of the first rung. Its answer replaces `best` if the
/// acceptance rule accepts it.
fn solve_extended(
    lcp: &Lcp,
    o: &LemkeOptions,
    equilibrate: bool,
    best: Solution,
    budget: usize,
    ws: &mut Workspace,
) -> Solution {
    let frame = &mut ws.frame;
    frame.reset(lcp, equilibrate, o.accept_tol);
    let pivots = best.pivots;
    let (end, taken) = extended::solve(&frame.work, budget, EXTENDED_OPS);
    if let extended::ExtEnd::Solved(z, mask) = end {
        let sol = frame.solution(lcp, &z, Status::Solved, pivots + taken);
        if sol.accepted {
            return Solution { basis: Some(mask), ..sol };
        }
    }
    Solution { pivots: pivots + taken, ..best }
}

/// The last rung: Lemke in exact arithmetic (see [`exact`]). Its answer,
/// rounded once, replaces `best` if the acceptance rule accepts it and `best`
/// is not accepted or has the larger natural residual; an exact
/// ray replaces a failure's status by `RayTermination` (round-off no longer
/// stands in the way: the ray is the problem's, for the covering vector used).
fn solve_exact(lcp: &Lcp, o: &LemkeOptions, mut best: Solution, budget: usize) -> Solution {
    let (end, taken) = exact::solve(lcp, budget);
    let pivots = best.pivots + taken;
    match end {
        exact::ExactEnd::Solved(z, mask) => {
            let sol = Solution::from_z_tol(lcp, z, Status::Solved, pivots, o.accept_tol);
            if sol.accepted && (!best.ok() || sol.residuals.residual < best.residuals.residual) {
                return Solution { basis: Some(mask), ..sol };
            }
        }
        exact::ExactEnd::Ray if !best.ok() => best.status = Status::RayTermination,
        exact::ExactEnd::Ray => {}
        exact::ExactEnd::Limit => {}
    }
    best.pivots = pivots;
    best
}

/// One rung: scale, pivot (from the complementary basis `start` if given),
/// re-solve the final basis, map back and check.
#[allow(clippy::too_many_arguments)]
fn solve_attempt(
    lcp: &Lcp,
    o: &LemkeOptions,
    attempt: &Attempt,
    max_pivots: usize,
    start: Option<&[usize]>,
    trace: Option<&mut Vec<PivotRecord>>,
    rung: usize,
    ws: &mut Workspace,
) -> Solution {
    let n = lcp.n();
    ws.frame.reset(lcp, attempt.equilibrate, o.accept_tol);
    let Workspace { frame, basis: bufs, pivoting, d, z_work, warm: warm_bufs, .. } = ws;
    let work = &frame.work;
    let set = RunSettings {
        rule: Rule::Lexicographic { piv_tol: attempt.piv_rel, tie_tol: o.zero_tol.min(attempt.tie_tol) },
        trace: trace.is_some(),
        max_pivots,
        refactor_every: refactor_every(n),
    };
    let buffers = std::mem::take(bufs);
    let start = match start {
        Some(alpha) => warm::start(lcp, frame, alpha, &set, buffers, pivoting, d, z_work, warm_bufs),
        None => {
            d.clear();
            match attempt.cover {
                0 => d.resize(n, 1.0),
                k => d.extend((0..n).map(|i| covering(i, k))),
            }
            Start::Run(run::run(work, d, &set, buffers, pivoting))
        }
    };
    let mut r = match start {
        Start::Run(r) => r,
        Start::Done(sol, b) => {
            *bufs = b;
            return sol;
        }
        // A singular warm basis: the cold ladder takes over.
        Start::Singular(b, pivots) => {
            *bufs = b;
            return Solution::from_z(lcp, vec![0.0; n], Status::SingularBasis, pivots);
        }
    };
    if let Some(t) = trace {
        t.extend(r.trace.drain(..).map(|p| PivotRecord { rung, ..p }));
    }
    let mask = basic_mask(&r.basis.s, n);
    if r.status == Status::Solved {
        // Shed the round-off of the updates: refine with the kept C⁻¹ first.
        r.basis.polish();
    }
    r.basis.z_into(z_work);
    *bufs = r.basis.into_buffers();
    let mut sol = frame.solution(lcp, z_work, r.status, r.pivots);
    if sol.status == Status::Solved && !sol.accepted {
        // C⁻¹ drifted: re-solve the final basis from scratch by LU.
        let alpha: Vec<usize> = (0..n).filter(|&j| mask[j]).collect();
        if let Some(z_work) = refine::resolve_basis(work, &alpha) {
            let fresh = frame.solution(lcp, &z_work, Status::Solved, r.pivots);
            if fresh.accepted || fresh.residuals.residual < sol.residuals.residual {
                sol = fresh;
            }
        }
        if !sol.accepted {
            snap_in_working_units(lcp, frame, &mut sol);
        }
        if !sol.accepted {
            sol.status = Status::Numerical;
        }
    }
    sol.basis = Some(mask);
    // A run that ended on a (false) ray or a singular basis may still stand at
    // an answer: the residual check, not the pivoting, decides. Its basis is
    // then the support of z, as the pivoting's basis is not complementary.
    if matches!(sol.status, Status::RayTermination | Status::SingularBasis | Status::Cycling) && sol.accepted {
        sol.status = Status::Solved;
        sol.basis = Some(sol.z.iter().zip(&sol.w).map(|(z, w)| z > w).collect());
    }
    sol
}

/// Degenerate bases leave round-off (~1e-17 of the largest value, in
/// working units) in basic `z_j` that are 0 for the exact data; a row made
/// only of such terms fails the rule. Those entries are zeroed, judged in the
/// working units (equilibrated, so a cone-scaled λ does not set the scale),
/// and the result kept if the rule accepts it (see [`crate::accept::snap`]).
/// `sol` is a rejected answer of [`frame::Frame::solution`] (clipped, its `w`
/// formed and judged at `frame.accept_tol`), so only the variants are tried.
fn snap_in_working_units(lcp: &Lcp, frame: &frame::Frame, sol: &mut Solution) {
    debug_assert!(!sol.accepted);
    let weights: Vec<f64> = frame.scaling.col.iter().map(|c| frame.qscale / c).collect();
    if let Some((z, w)) = crate::accept::snap_rejected(lcp, &sol.z, Some(&weights), frame.accept_tol) {
        sol.residuals = crate::Residuals::of(&z, &w);
        (sol.z, sol.w, sol.accepted) = (z, w, true);
    }
}

/// Which `z_j` are basic.
fn basic_mask(s: &[Var], n: usize) -> Vec<bool> {
    let mut mask = vec![false; n];
    for v in s {
        if let Var::Z(j) = *v {
            mask[j] = true;
        }
    }
    mask
}

/// Entry `i` of the `k`-th (`k ≥ 1`) fixed, irregular covering vector, in
/// [1, 2): a golden-ratio sequence, shifted by `(k − 1)(√2 − 1)` per vector.
pub(crate) fn covering(i: usize, k: u32) -> f64 {
    1.0 + ((i as f64 + 1.0) * 0.618_033_988_749_895 + (k - 1) as f64 * 0.414_213_562_373_095).fract()
}
