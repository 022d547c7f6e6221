//! Lemke's method on a structured LCP `M = G H + K` (see [`StructuredLcp`]):
//! per-pivot work that grows with the nonzeros of `G`, `H`, `K` and of the
//! basis factorization, not with `n²`, and no `n × n` matrix anywhere.
//!
//! - [`operator`]: the problem, its products and rows.
//! - [`factor`]: the basis in the augmented space `[w; z; z0; u = H z]`,
//!   factored by a sparse LU and updated by eta vectors.
//! - [`pivot`]: the lexicographic pivoting loop.
//! - [`guess`]: a basis guessed by projected Gauss–Seidel in body space (contact LCPs).
//! - [`bpp`]: block principal pivoting, which improves a complementary basis
//!   many pairs per factorization (before Lemke's warm start).
//! - [`kept`]: one complementary basis factored once and solved again as the
//!   operator's values change under the same sparsity (a resting island, step after step).
//!
//! Every answer is judged by the acceptance rule of [`crate::accept`] on the
//! operator (each row's scale from its sparse row of `M`); nothing about the
//! problem is changed (no regularization, no equilibration). A failed run is
//! followed by runs on other covering vectors; the caller (a simulator) can
//! fall back to the dense [`crate::lemke`] where `n` allows.

pub mod bpp;
mod factor;
pub mod guess;
pub mod kept;
mod lu;
mod operator;
mod pivot;
mod sparse;
mod trace;

pub use operator::{Entry, StructuredLcp};

use crate::accept::ROUND_OFF;
use crate::solution::{Residuals, Solution, Status};
use bpp::BppOptions;
use pivot::Settings;

/// Options of the structured Lemke, defaults documented on each field.
#[derive(Clone, Debug, PartialEq)]
pub struct StructuredOptions {
    /// Pivot limit over all runs; `None` means `max(1000, 50·n)`.
    pub max_pivots: Option<usize>,
    /// Tolerance of the acceptance rule ([`crate::accept`]). Default 1e-9.
    pub accept_tol: f64,
    /// Column updates (eta vectors) between two sparse refactorizations. Default 100.
    pub refactor_every: usize,
    /// Start from the basis passed to [`solve`] when there is one. Default true.
    pub warm_start: bool,
    /// Improve that basis by block principal pivoting ([`bpp`]) before
    /// Lemke's warm start, when given. Default `None`: it lowered no
    /// infeasible count on a forming heap's contact LCPs (see [`bpp`]).
    pub bpp: Option<BppOptions>,
}

impl Default for StructuredOptions {
    fn default() -> Self {
        StructuredOptions { max_pivots: None, accept_tol: 1e-9, refactor_every: 100, warm_start: true, bpp: None }
    }
}

/// One run's settings beyond the options: covering vector and pivot tolerance.
#[derive(Clone, Copy)]
struct Rung {
    /// 0: `d = 1`; `k ≥ 1`: the `k`-th irregular covering vector of [`crate::lemke`].
    cover: u32,
    piv_tol: f64,
}

/// The cold runs, in order: like the first rungs of the dense ladder.
const RUNGS: [Rung; 3] =
    [Rung { cover: 0, piv_tol: 1e-9 }, Rung { cover: 1, piv_tol: 1e-7 }, Rung { cover: 2, piv_tol: 1e-9 }];

/// Ratios within this fraction of the largest basic value tie (as in [`crate::lemke`]).
const TIE_TOL: f64 = 1e-13;

/// A warm basis this close to feasible (relative to its largest value) is taken as it stands.
const WARM_TOL: f64 = 1e-12;

/// Restarts from failed runs' final bases (see [`solve`]).
const RESTARTS: usize = 4;

/// Polishes at most per solve (see [`solve`]).
const POLISHES: usize = 3;

/// Where a run starts.
enum Start {
    /// From a complementary basis (`z_j` basic for `j` in it).
    Basis(Vec<usize>),
    /// From the complementary basis a run ended on whose answer the rule
    /// rejects: the polish (see [`solve`]).
    Polish(Vec<usize>),
    /// Cold, on rung `RUNGS[k]`.
    Cold(usize),
}

/// The cold runs made on one LCP, for later solves of the same LCP from other
/// starts ([`solve_reusing`]): a cold run depends on nothing but the problem,
/// its rung and its pivot cap, so a run that ended before its cap ends the
/// same under any larger one and need not be made again.
#[derive(Default)]
pub struct ColdRuns {
    runs: [Option<pivot::Run>; RUNGS.len()],
}

impl ColdRuns {
    /// Rung `k`'s run, if it was made and ended below `cap` pivots.
    fn reuse(&self, k: usize, cap: usize) -> Option<pivot::Run> {
        self.runs[k].as_ref().filter(|r| r.status != Status::MaxPivots && r.pivots < cap).cloned()
    }
}

/// The polish's tie tolerance: none, so the least ratio leaves (see [`solve`]).
const POLISH_TIE_TOL: f64 = 0.0;

/// Solves `op` by Lemke's method, first from the complementary basis `warm`
/// (`warm[j]`: `z_j` basic; the previous step's answer; repaired column by
/// column if it is structurally singular) when given, then cold
/// on each rung until an answer passes the acceptance rule at `accept_tol`
/// with a natural residual ≤ `accept_tol·(1 + ‖q‖∞)`. Returns the first such
/// answer, else the first accepted one, else the closest failure.
///
/// A run that ends on a complementary basis whose answer fails the rule is
/// *polished*: Lemke goes on from that basis (covering vector `B·1`, fresh
/// factorization, z0 entering where the least basic value is, however close
/// to 0) with no tie tolerance, so the least ratio leaves at every pivot.
/// Such an end is a vertex that is itself infeasible by a hair, not
/// round-off in its values: the ratio test takes ratios within
/// `1e-13·max|value|` as ties and may let any of them leave, which leaves the
/// least one's variable negative by up to that width at the new vertex.
/// Where such a row's scale is that width (an unloaded contact, `q_i = 0`,
/// friction `β ≈ 5e-14` just outside its cone) the rule rejects it. Measured
/// on a 12-cube heap's sub-LCP (n = 593, `loaded_friction`'s test): every
/// start ended there (min w −1.0e-13; the basis solved in double-double:
/// w = −5.2486e-14, so no more precision helps); the polish from the warm
/// basis took 28 pivots to an accepted answer. Polishes are capped at
/// [`POLISHES`] per solve and one per basis. Past them, and for a run that
/// ends `Numerical` in the loop itself, the end is restarted from its basis
/// with the run's tolerances (as the dense ladder does): on heaps a run can end a hair off after deciding near-ties on
/// values that carry round-off (measured on a 200-cube heap's LCP, n =
/// 3,820, before the polish: three cold runs ended at natural residuals
/// 6e-8, 5e-7 and 1e-10, none accepted). Cold runs that end on a secondary
/// ray or cycle go on to the next cold rung: restarted from the complementary
/// basis of their basic `z` instead, a forming 200-cube heap's steps 175 and
/// 176 (n = 9,900 and 10,550) ended `cycling` and `numerical` after 33,562
/// and 45,110 pivots, where the cold rungs solve them in 25,934 and 3,815.
/// A warm run (from a basis or a polish) that ends on a ray goes on instead
/// from the complementary basis its entering variable completes in z0's
/// place, within [`RESTARTS`] starts: its covering vector `B·1` is not
/// positive, so the ray says nothing about the LCP (Lemke's theorem on rays
/// needs `d > 0`), and the run stopped near the previous answer. On the
/// 200-cube heap test's saved LCPs of steps 138–185 (`heap_replay solve
/// step`): 466,387 → 347,125 pivots; cold runs' rays followed the same way,
/// 392,471.
pub fn solve(op: &StructuredLcp, o: &StructuredOptions, warm: Option<&[bool]>) -> Solution {
    solve_reusing(op, o, warm, &mut ColdRuns::default())
}

/// [`solve`], taking the cold runs from `cold` where an earlier solve of the
/// same `op` made them (they cost no pivots then) and keeping those it makes.
/// `cold` must hold runs of this `op` only.
pub fn solve_reusing(
    op: &StructuredLcp,
    o: &StructuredOptions,
    warm: Option<&[bool]>,
    cold: &mut ColdRuns,
) -> Solution {
    let n = op.n();
    let limit = o.max_pivots.unwrap_or_else(|| (50 * n).max(1000));
    let bound = o.accept_tol * (1.0 + op.q_norm_inf());
    let (mut pivots, mut best, mut within): (usize, Option<Solution>, Option<Solution>) = (0, None, None);
    let settings = |piv_tol, pivots: usize| Settings {
        piv_tol,
        tie_tol: TIE_TOL,
        warm_tol: WARM_TOL,
        max_pivots: limit.saturating_sub(pivots),
        refactor_every: o.refactor_every,
    };
    let strict = |pivots| Settings { tie_tol: POLISH_TIE_TOL, warm_tol: 0.0, ..settings(RUNGS[0].piv_tol, pivots) };
    let mask_of = |b: &[bool]| (0..n).filter(|&j| b[j]).collect::<Vec<usize>>();
    // Runs still to do, the next one last.
    let mut todo: Vec<Start> = (0..RUNGS.len()).rev().map(Start::Cold).collect();
    let mut warm = warm.filter(|b| o.warm_start && b.len() == n).map(<[bool]>::to_vec);
    if let (Some(b), Some(bo)) = (&warm, &o.bpp) {
        if let Some(r) = bpp::improve(op, b, bo, None) {
            if r.infeasible == 0 {
                let run =
                    pivot::Run { status: Status::Solved, pivots: 0, z: r.z.clone(), mask: r.basis.clone(), ray: None };
                let sol = judge(op, run, 0, o.accept_tol);
                if sol.ok() && sol.residuals.residual <= bound {
                    return sol;
                }
            }
            if r.infeasible < r.infeasible_start {
                warm = Some(r.basis);
            }
        }
    }
    todo.extend(warm.as_deref().map(mask_of).map(Start::Basis));
    let (mut d, mut tried, mut polished) = (Vec::new(), Vec::new(), Vec::new());
    while let Some(start) = todo.pop() {
        if pivots >= limit && best.is_some() {
            break;
        }
        let warm_run = !matches!(start, Start::Cold(_));
        let run = match start {
            Start::Basis(alpha) => {
                tried.push(alpha.clone());
                match pivot::run_warm(op, &alpha, &mut d, &settings(RUNGS[0].piv_tol, pivots)) {
                    Some(run) => run,
                    None => continue,
                }
            }
            Start::Polish(alpha) => {
                polished.push(alpha.clone());
                match pivot::run_warm(op, &alpha, &mut d, &strict(pivots)) {
                    Some(run) => run,
                    None => continue,
                }
            }
            Start::Cold(k) => match cold.reuse(k, limit.saturating_sub(pivots)) {
                // made before: the same end, judged and followed up as then, for no pivots now
                Some(run) => pivot::Run { pivots: 0, ..run },
                None => {
                    let rung = RUNGS[k];
                    d.clear();
                    d.extend((0..n).map(|i| if rung.cover == 0 { 1.0 } else { crate::lemke::covering(i, rung.cover) }));
                    let run = pivot::run(op, &d, &settings(rung.piv_tol, pivots));
                    cold.runs[k] = Some(run.clone());
                    run
                }
            },
        };
        pivots += run.pivots;
        let ended = run.status;
        // A warm run's ray: on from the complementary basis where it stopped.
        if let Some(alpha) = run.ray_basis().filter(|_| warm_run) {
            if tried.len() < RESTARTS && !tried.contains(&alpha) {
                todo.push(Start::Basis(alpha));
            }
        }
        let sol = judge(op, run, pivots, o.accept_tol);
        if sol.ok() && sol.residuals.residual <= bound {
            return sol;
        }
        if sol.ok() && within.is_none() {
            within = Some(sol.clone());
        }
        if sol.status == Status::Numerical {
            let alpha = mask_of(sol.basis.as_deref().unwrap_or(&[]));
            if ended == Status::Solved && polished.len() < POLISHES && !polished.contains(&alpha) {
                todo.push(Start::Polish(alpha));
            } else if tried.len() < RESTARTS && !tried.contains(&alpha) {
                todo.push(Start::Basis(alpha));
            }
        }
        if best.as_ref().is_none_or(|b| sol.residuals.residual < b.residuals.residual) {
            best = Some(sol);
        }
    }
    let sol = within.or(best).expect("at least one run");
    Solution { pivots, ..sol }
}

/// The factors of `op` as entries: `(p, G, H, K)` (e.g. to save a problem and
/// rebuild it with [`StructuredLcp::new`]).
pub fn parts(op: &StructuredLcp) -> (usize, Vec<Entry>, Vec<Entry>, Vec<Entry>) {
    let n = op.n();
    let (mut g, mut h, mut k) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..n {
        g.extend(op.g_rows.iter(j).map(|(c, v)| (j, c, v)));
        h.extend(op.h_cols.iter(j).map(|(r, v)| (r, j, v)));
        k.extend(op.k_cols.iter(j).map(|(r, v)| (r, j, v)));
    }
    (op.p(), g, h, k)
}

/// A run's answer as a [`Solution`]: `z` clipped at 0, `w` recomputed, judged
/// by the acceptance rule; a run that ended `Solved` but fails it is `Numerical`,
/// one that ended otherwise but stands at an accepted answer is `Solved`.
fn judge(op: &StructuredLcp, run: pivot::Run, pivots: usize, tol: f64) -> Solution {
    let z: Vec<f64> = run.z.iter().map(|v| v.max(0.0)).collect();
    let mut w = vec![0.0; op.n()];
    op.w_of(&z, &mut w);
    let accepted = accepts(op, &z, &w, tol);
    let status = match (run.status, accepted) {
        (Status::Solved, false) => Status::Numerical,
        (Status::RayTermination | Status::SingularBasis | Status::Cycling, true) => Status::Solved,
        (s, _) => s,
    };
    let residuals = Residuals::of(&z, &w);
    Solution { z, w, status, pivots, residuals, basis: Some(run.mask), accepted }
}

/// The acceptance rule of [`crate::accept`] on a structured `M`: each row's
/// scale and round-off floor from its sparse row.
pub fn accepts(op: &StructuredLcp, z: &[f64], w: &[f64], tol: f64) -> bool {
    let mut row = Vec::new();
    crate::accept::accepts_rows(
        op.q(),
        z,
        w,
        tol,
        |i| op.at(i, i),
        |i, zsum| {
            op.row_into(i, &mut row);
            let (terms, rmax) = row.iter().fold((0.0, 0.0f64), |(t, m), &(j, v)| (t + v.abs() * z[j], m.max(v.abs())));
            (terms + op.q()[i].abs(), ROUND_OFF * rmax * zsum)
        },
    )
}
