//! The complementary pivoting loop, shared by both pivoting rules.

use super::basis::{key, Basis, BasisBuffers, Column, Leaving, Var};
use super::ratio::{column_max, first_leaving, leaving, Choice, Rule, Scratch};
use crate::problem::Lcp;
use crate::solution::Status;
use std::collections::HashSet;
use std::hash::{BuildHasherDefault, Hasher};

/// The basis hash is already well mixed: hash it as itself.
#[derive(Default)]
pub(crate) struct Identity(u64);

impl Hasher for Identity {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, _: &[u8]) {
        unreachable!("only u64 keys are hashed")
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = v;
    }
}

/// The set of bases seen by a run (see `pivot_loop`).
pub(crate) type Seen = HashSet<u64, BuildHasherDefault<Identity>>;

/// Scratch of the pivoting loop, reused across runs: the entering column,
/// the ratio test's candidate lists and the bases seen.
#[derive(Default)]
pub(crate) struct LoopBuffers {
    pub col: Column,
    pub scratch: Scratch,
    pub seen: Seen,
}

/// Settings of one run of the loop.
pub(crate) struct RunSettings {
    pub rule: Rule,
    /// Record every pivot in `Run::trace`.
    pub trace: bool,
    pub max_pivots: usize,
    /// Refactor `C⁻¹` after this many updates.
    pub refactor_every: usize,
}

/// How the loop ended, with the final basis.
pub(crate) struct Run<'a> {
    pub status: Status,
    pub pivots: usize,
    pub basis: Basis<'a>,
    /// Pivots taken, when `RunSettings::trace` asked for them.
    pub trace: Vec<PivotRecord>,
}

/// One pivot, for failure forensics. Variables are numbered `w_i → i`,
/// `z_j → n + j`, `z0 → 2n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PivotRecord {
    /// Rung of the repair ladder (0 = the first run; a warm start counts as one).
    pub rung: usize,
    pub entering: usize,
    pub leaving: usize,
    /// Step length: the entering variable's new value (working units).
    pub theta: f64,
    /// The pivot element and the largest entry of its column.
    pub pivot: f64,
    pub column_max: f64,
}

/// Pivots below this fraction of their column's largest entry trigger a refactorization.
const SMALL_PIVOT: f64 = 1e-4;

/// A warm basis whose values dip below zero by less than this (relative)
/// is taken as it is; the residual check after the run has the last word.
const WARM_FEASIBLE: f64 = 1e-12;

/// Runs Lemke with covering vector `d` from the all-slack basis, in the
/// basis buffers `bufs` and the loop's scratch `lb`.
pub(crate) fn run<'a>(
    lcp: &'a Lcp,
    d: &'a [f64],
    set: &RunSettings,
    bufs: BasisBuffers,
    lb: &mut LoopBuffers,
) -> Run<'a> {
    let n = lcp.n();
    let mut basis = Basis::slack(lcp, d, bufs);
    // q ≥ 0: z = 0 solves it.
    if lcp.q().iter().all(|&v| v >= 0.0) {
        return Run { status: Status::Solved, pivots: 0, basis, trace: Vec::new() };
    }
    // No budget left: the first pivot would already exceed it.
    if set.max_pivots == 0 {
        return Run { status: Status::MaxPivots, pivots: 0, basis, trace: Vec::new() };
    }
    let col = &mut lb.col;
    // z0 enters at the value that makes every w ≥ 0.
    let r = first_leaving(lcp.q(), d, set.rule);
    basis.column(Var::Z0, col);
    let theta = -lcp.q()[r] / d[r];
    let first = record(n, Var::Z0, Var::W(r), theta, col.xw[r], col);
    basis.pivot(Var::Z0, Leaving::W(r), col, theta);
    let hash = (0..n).fold(0u64, |h, i| h ^ key(i)) ^ key(r) ^ key(Var::Z0.id(n));
    pivot_loop(basis, lb, Var::Z(r), 1, hash, set, first)
}

/// The covering vector that makes a warm start's first pivot uniform:
/// `d = B·1` for the complementary basis `α`, so that `B⁻¹(−d) = −1`;
/// written into `d`, with `in_alpha` as scratch.
pub(crate) fn warm_covering(lcp: &Lcp, alpha: &[usize], d: &mut Vec<f64>, in_alpha: &mut Vec<bool>) {
    in_alpha.clear();
    in_alpha.resize(lcp.n(), false);
    alpha.iter().for_each(|&j| in_alpha[j] = true);
    d.clear();
    d.extend((0..lcp.n()).map(|i| {
        let row = lcp.row(i);
        (!in_alpha[i]) as u8 as f64 - alpha.iter().map(|&j| row[j]).sum::<f64>()
    }));
}

/// Does the factored complementary `basis` solve its problem as it stands,
/// up to round-off (the answer is checked by its residual afterwards)?
pub(crate) fn warm_feasible(basis: &Basis) -> bool {
    basis.most_negative().0 >= -warm_tolerance(basis)
}

/// How far below zero a basic value may dip by round-off alone.
pub(crate) fn warm_tolerance(basis: &Basis) -> f64 {
    WARM_FEASIBLE * basis.val_s.iter().chain(&basis.val_w).fold(1.0f64, |a, v| a.max(v.abs()))
}

/// Runs Lemke from a factored complementary basis (a previous answer's,
/// with covering vector `d = warm_covering(lcp, α)`): none at all if it is
/// [`warm_feasible`]. `Err` (with the basis, for its buffers) when z0 cannot enter.
pub(crate) fn run_warm<'a>(
    mut basis: Basis<'a>,
    set: &RunSettings,
    lb: &mut LoopBuffers,
) -> Result<Run<'a>, Basis<'a>> {
    let n = basis.val_w.len();
    if warm_feasible(&basis) {
        return Ok(Run { status: Status::Solved, pivots: 0, basis, trace: Vec::new() });
    }
    if set.max_pivots == 0 {
        return Ok(Run { status: Status::MaxPivots, pivots: 0, basis, trace: Vec::new() });
    }
    let (worst, at) = basis.most_negative();
    // z0 enters; every basic moves by +θ (x = −1), so the most negative leaves.
    let col = &mut lb.col;
    basis.column(Var::Z0, col);
    let x = match at {
        Leaving::S(p) => col.xs[p],
        Leaving::W(i) => col.xw[i],
    };
    if !(x < 0.0) {
        return Err(basis);
    }
    let left = match at {
        Leaving::S(p) => basis.s[p],
        Leaving::W(i) => Var::W(i),
    };
    let first = record(n, Var::Z0, left, worst / x, x, col);
    basis.pivot(Var::Z0, at, col, worst / x);
    let hash = basis.hash(n);
    let Some(entering) = left.complement() else {
        return Err(basis);
    };
    Ok(pivot_loop(basis, lb, entering, 1, hash, set, first))
}

/// The main loop from an almost-complementary basis with z0 basic.
fn pivot_loop<'a>(
    mut basis: Basis<'a>,
    lb: &mut LoopBuffers,
    mut entering: Var,
    mut pivots: usize,
    mut hash: u64,
    set: &RunSettings,
    first: PivotRecord,
) -> Run<'a> {
    let n = basis.val_w.len();
    let mut trace = if set.trace { vec![first] } else { Vec::new() };
    let LoopBuffers { col, scratch, seen } = lb;
    // Basis hash: XOR of the basic variables' keys; a repeat means cycling.
    seen.clear();
    seen.reserve(4 * n);
    seen.insert(hash);
    let status = loop {
        if pivots >= set.max_pivots {
            break Status::MaxPivots;
        }
        basis.column(entering, col);
        let Some(xmax) = column_max(col) else {
            break Status::Numerical;
        };
        let Some(Choice { at: out, theta, xmax }) = leaving(&basis, col, xmax, set.rule, scratch) else {
            break Status::RayTermination;
        };
        let (left, pivot) = match out {
            Leaving::S(p) => (basis.s[p], col.xs[p]),
            Leaving::W(i) => (Var::W(i), col.xw[i]),
        };
        // A pivot small against its column inflates C⁻¹'s round-off: refactor after it.
        let small_pivot = pivot.abs() < SMALL_PIVOT * xmax;
        if set.trace {
            trace.push(PivotRecord { column_max: xmax, ..record(n, entering, left, theta, pivot, col) });
        }
        basis.pivot(entering, out, col, theta);
        pivots += 1;
        if left == Var::Z0 {
            break Status::Solved;
        }
        hash ^= key(entering.id(n)) ^ key(left.id(n));
        if !seen.insert(hash) {
            break Status::Cycling;
        }
        // A singular refactorization ends the robust rule; the classic rule,
        // like the source note's Lemke, has no such check and goes on with its updated
        // inverse (its answer is still checked when z0 leaves).
        let robust = matches!(set.rule, Rule::Lexicographic { .. });
        if (small_pivot || basis.since_refactor >= set.refactor_every) && !basis.refactor() && robust {
            break Status::SingularBasis;
        }
        entering = left.complement().expect("only z0 lacks a complement");
    };
    Run { status, pivots, basis, trace }
}

/// A trace entry (rung 0; the caller renumbers).
fn record(n: usize, entering: Var, leaving: Var, theta: f64, pivot: f64, col: &Column) -> PivotRecord {
    let column_max = col.xs.iter().chain(&col.xw).fold(0.0f64, |a, v| a.max(v.abs()));
    PivotRecord { rung: 0, entering: entering.id(n), leaving: leaving.id(n), theta, pivot, column_max }
}
