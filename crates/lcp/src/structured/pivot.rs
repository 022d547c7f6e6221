//! The pivoting loop of the structured Lemke: the lexicographic rule of
//! [`crate::lemke`] (relative pivot and tie tolerances, z0 preferred, ties
//! broken on the rows of `B⁻¹`), with the basis of [`super::factor`].
//! A tie is broken on the columns of `B⁻¹`, one solve per column that is
//! not a basic slack's, computed only when a tie occurs. A leaving row whose
//! pivot would be small is traded, where one is near enough, for the largest
//! pivot of Harris's two-pass test ([`harris`]).
//!
//! With `LCPSIM_LEMKE_TRACE` set, each run prints its counts to standard
//! error ([`super::trace`]).

use super::factor::{Basis, NONBASIC};
use super::operator::StructuredLcp;
use super::trace::{self, Trace};
use crate::lemke::basis_hash_key as key;
use crate::solution::Status;
use std::collections::HashSet;

/// Settings of one run.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Settings {
    /// Smallest pivot, relative to the entering column's largest entry.
    pub piv_tol: f64,
    /// Ratios within this fraction of the largest basic value tie.
    pub tie_tol: f64,
    pub max_pivots: usize,
    /// A warm basis whose least value is `≥ −warm_tol·`(its largest, at least 1) is solved as it stands.
    pub warm_tol: f64,
    /// Refactor after this many column updates.
    pub refactor_every: usize,
}

/// How a run ended: status, pivots, and `z` with its basis mask when the
/// run got as far as a basis.
#[derive(Clone)]
pub(crate) struct Run {
    pub status: Status,
    pub pivots: usize,
    pub z: Vec<f64>,
    pub mask: Vec<bool>,
    /// At a ray: the entering variable (`w_i`: `i`, `z_j`: `n + j`), which
    /// in z0's place completes a complementary basis ([`Run::ray_basis`]).
    pub ray: Option<usize>,
}

impl Run {
    /// At a ray, the complementary basis (`z_j` basic for `j` in it) the
    /// entering variable completes in z0's place: the run's basic `z`, and
    /// the entering one if it is a `z`.
    pub(crate) fn ray_basis(&self) -> Option<Vec<usize>> {
        let n = self.mask.len();
        let e = self.ray?;
        Some((0..n).filter(|&j| self.mask[j] || e == n + j).collect())
    }
}

/// Pivots below this fraction of their column's largest entry trigger a
/// refactorization. (1e-4, the dense path's, refactored after 70 of 1,754
/// pivots on a 100-cube heap LCP, n = 3,030, and the symbolic analysis took
/// 41 % of the solve; 1e-6: 7 refactorizations, answers accepted all the same.)
const SMALL_PIVOT: f64 = 1e-6;

/// Harris's feasibility tolerance, relative to the largest basic value: how
/// far below 0 a value may be pushed so that a small pivot is traded for a
/// larger one ([`harris`]). Measured on the forming 200-cube heap's saved
/// LCPs (`heap_replay solve step`, steps 174–193, n = 9,400–13,520): the runs
/// that failed had taken pivots down to 1e-9 of their column (the pivot
/// tolerance), after which a fresh factorization moved the values by up to
/// 1e45 of the largest — rays, cycles and `Solved` answers far outside the
/// rule followed. With this test: 603,027 pivots in all against 699,759
/// (step 190: 5,165 against 98,150), and step 194, which failed after
/// 246,628, solved (262,379). 1e-11 and 1e-10 on step 176: 13,750 and 36,298
/// pivots against 11,118.
const HARRIS_TOL: f64 = 1e-12;

/// Runs Lemke from the all-slack basis with covering vector `d`.
pub(crate) fn run(op: &StructuredLcp, d: &[f64], set: &Settings) -> Run {
    let n = op.n();
    let q = op.q();
    let fail = |status| Run { status, pivots: 0, z: vec![0.0; n], mask: vec![false; n], ray: None };
    if q.iter().all(|&v| v >= 0.0) {
        return Run { status: Status::Solved, ..fail(Status::Solved) };
    }
    let Some(mut basis) = Basis::slack(op, d) else { return fail(Status::SingularBasis) };
    // z0 enters where q_i / d_i is least; on ties the largest index.
    let ratio = |i: usize| q[i] / d[i];
    let min = (0..n).map(ratio).fold(f64::INFINITY, f64::min);
    let scale = op.q_norm_inf();
    let r = (0..n).rev().find(|&i| (ratio(i) - min) * d[i] <= set.tie_tol * scale).unwrap_or(0);
    let mut y = Vec::new();
    basis.column_into(2 * n, &mut y);
    basis.ftran_basic(&mut y);
    if !basis.pivot(2 * n, r, &y, basis.val[r] / y[r]) {
        return fail(Status::SingularBasis);
    }
    pivot_loop(op, basis, n + r, set, "cold")
}

/// Runs Lemke from the complementary basis `alpha` (a warm start) with the
/// covering vector `d = B·1`, which makes z0's entering column `−1`: the most
/// negative basic leaves first. `None` when that basis is singular.
pub(crate) fn run_warm(op: &StructuredLcp, alpha: &[usize], d: &mut Vec<f64>, set: &Settings) -> Option<Run> {
    let n = op.n();
    let mut basis = Basis::complementary(op, alpha, REPAIRS)?;
    cover_into(op, &basis.alpha(), d);
    basis.set_cover(d);
    let (worst, r) =
        basis.val.iter().enumerate().fold((f64::INFINITY, 0), |a, (c, &v)| if v < a.0 { (v, c) } else { a });
    let top = basis.val.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    if worst >= -set.warm_tol * top {
        let mut z = Vec::new();
        basis.z_into(&mut z);
        let mask = (0..n).map(|j| basis.pos[n + j] != NONBASIC).collect();
        return Some(Run { status: Status::Solved, pivots: 0, z, mask, ray: None });
    }
    let mut y = Vec::new();
    basis.column_into(2 * n, &mut y);
    basis.ftran_basic(&mut y);
    if !(y[r] < 0.0) {
        return None;
    }
    let left = basis.var[r];
    if !basis.pivot(2 * n, r, &y, worst / y[r]) {
        return None;
    }
    Some(pivot_loop(op, basis, complement(left, n), set, "warm"))
}

/// Columns swapped at most to make a singular warm basis regular ([`Basis::complementary`]).
const REPAIRS: usize = 64;

/// `d = B·1` for the complementary basis `alpha`: `e_i` for basic `w_i`, `−M_j` for basic `z_j`.
fn cover_into(op: &StructuredLcp, alpha: &[usize], d: &mut Vec<f64>) {
    let n = op.n();
    let mut ones = vec![0.0; n];
    alpha.iter().for_each(|&j| ones[j] = 1.0);
    let mut m1 = vec![0.0; n];
    op.w_of(&ones, &mut m1);
    d.clear();
    d.extend((0..n).map(|i| (ones[i] == 0.0) as u8 as f64 - (m1[i] - op.q()[i])));
}

/// `w_i ↔ z_i`.
fn complement(v: usize, n: usize) -> usize {
    if v < n {
        v + n
    } else {
        v - n
    }
}

/// The main loop from an almost-complementary basis with z0 basic (`kind`
/// names the start in the trace).
fn pivot_loop(op: &StructuredLcp, mut basis: Basis, mut entering: usize, set: &Settings, kind: &str) -> Run {
    let n = basis.val.len();
    let z0 = 2 * n;
    let mut tr = trace::enabled().then(|| Trace::new(n, basis.val[basis.pos[z0]]));
    let mut pivots = 1;
    let (mut y, mut work) = (Vec::new(), Vec::new());
    let mut tied = Vec::new();
    // Basis hash: XOR of the basic variables' keys; a repeat means cycling.
    let mut seen: HashSet<u64> = HashSet::new();
    let mut hash = basis.var.iter().fold(0u64, |h, &v| h ^ key(v));
    seen.insert(hash);
    let status = loop {
        if pivots >= set.max_pivots {
            break Status::MaxPivots;
        }
        basis.solve_column_keeping(entering, &mut y, false);
        let mut ymax = y[..n].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !ymax.is_finite() {
            break Status::Numerical;
        }
        let mut step = leaving(&basis, &y, ymax, set, &mut tied);
        // A ray seen through eta updates may be their round-off: look again
        // at `y` refined once on the same factors, and only if that finds a
        // leaving row, on a fresh factorization. (A refactorization at every
        // such ray confirmed 97 % of them on a 45-cube pour, 1,590 of 1,643
        // in steps 0–2,200, and took a tenth of the run.)
        if step.is_none() && basis.updates() > 0 {
            basis.refine(entering, &mut y, &mut work);
            let top = y[..n].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if top.is_finite() && leaving(&basis, &y, top, set, &mut tied).is_none() {
                if !basis.values() && !basis.refactor() {
                    break Status::SingularBasis;
                }
                break Status::RayTermination;
            }
            if !basis.refactor() {
                break Status::SingularBasis;
            }
            basis.column_into(entering, &mut y);
            basis.ftran_basic(&mut y);
            ymax = y[..n].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            step = leaving(&basis, &y, ymax, set, &mut tied);
        }
        let Some((r, theta)) = step else {
            break Status::RayTermination;
        };
        let small = y[r].abs() < SMALL_PIVOT * ymax;
        let left = basis.var[r];
        if let Some(t) = tr.as_mut() {
            t.before_pivot(&basis.val, &y[..n], theta, set.piv_tol * ymax, tied.len(), y[r].abs() / ymax);
        }
        if !basis.pivot(entering, r, &y, theta) {
            break Status::SingularBasis;
        }
        pivots += 1;
        if let Some(t) = tr.as_mut() {
            t.after_pivot(pivots, entering, left, (left != z0).then(|| basis.val[basis.pos[z0]]), &basis.val);
        }
        if left == z0 {
            break Status::Solved;
        }
        hash ^= key(entering) ^ key(left);
        if !seen.insert(hash) {
            break Status::Cycling;
        }
        if small || basis.updates() >= set.refactor_every {
            if let Some(t) = tr.as_mut() {
                t.before_refactor(&basis.val, small);
            }
            if !basis.refactor() {
                break Status::SingularBasis;
            }
            if let Some(t) = tr.as_mut() {
                t.after_refactor(pivots, &basis.val);
            }
        }
        entering = complement(left, n);
    };
    if status == Status::Solved && basis.updates() > 0 {
        // Shed the updates' round-off: values refined on the factors (a
        // fresh factorization where they are not finite). A refactorization
        // here cost 4 % of the structured solves of a 45-cube pour for the
        // same pivots.
        if !basis.values() {
            basis.refactor();
        }
    }
    if let Some(t) = &tr {
        t.print(kind, pivots, status);
        trace::end(op, &basis, TRACE_TOL);
    }
    let mut z = Vec::new();
    basis.z_into(&mut z);
    let mask = (0..n).map(|j| basis.pos[n + j] != NONBASIC).collect();
    let ray = (status == Status::RayTermination).then_some(entering);
    Run { status, pivots, z, mask, ray }
}

/// The acceptance tolerance the trace measures the final answer against (the solver's default).
const TRACE_TOL: f64 = 1e-9;

/// The lexicographic ratio test: the leaving position and the step, `None` for a ray.
fn leaving(b: &Basis, y: &[f64], ymax: f64, set: &Settings, tied: &mut Vec<usize>) -> Option<(usize, f64)> {
    let n = b.val.len();
    let (val, y) = (&b.val[..], &y[..n]);
    let thresh = set.piv_tol * ymax;
    // Over slices, no index: these passes are O(n) per pivot; the largest
    // value and the least ratio in one.
    let (mut vmax, mut theta, mut least) = (f64::MIN_POSITIVE, f64::INFINITY, 0);
    for (c, (&v, &yc)) in val.iter().zip(y).enumerate() {
        vmax = vmax.max(v.abs());
        if yc > thresh {
            let ratio = v.max(0.0) / yc;
            if ratio < theta {
                (theta, least) = (ratio, c);
            }
        }
    }
    if !theta.is_finite() {
        return None;
    }
    let vtol = set.tie_tol * vmax;
    tied.clear();
    for (c, (&v, &yc)) in val.iter().zip(y).enumerate() {
        if yc > thresh && v.max(0.0) - theta * yc <= vtol {
            tied.push(c);
        }
    }
    // None within a zero tolerance (the polish's) when `v − (v/y)·y` rounds
    // to a positive ulp: the least ratio's row leaves, where the run would
    // otherwise end on a false ray. (Measured on a 200-cube heap's step 175:
    // its polish ended on one after 198 pivots and cold runs took 13,385
    // more; so mended, it passed 17 such pivots to an accepted answer.)
    if tied.is_empty() {
        tied.push(least);
    }
    if let Some(&c) = tied.iter().find(|&&c| b.var[c] == 2 * n) {
        return Some((c, theta));
    }
    if tied.len() > 1 {
        lex_break(b, y, tied, set.tie_tol);
    }
    let best = tied.iter().copied().max_by(|&a, &c| y[a].total_cmp(&y[c]))?;
    if y[best] < SMALL_PIVOT * ymax {
        return Some(harris(val, y, thresh, HARRIS_TOL * vmax, (best, theta)));
    }
    Some((best, theta))
}

/// Harris's two-pass ratio test, for a leaving row `pick` whose pivot is
/// small: the bound `θ_H = min (v⁺ + δ)/y` over the rows above the pivot
/// tolerance, then the row of largest `y` among those with `v⁺/y ≤ θ_H`
/// (`pick` if none is larger) with its own ratio as the step. Values it
/// passes over end at most `δ` below 0 (`v⁺ − θ y ≥ −δ`); the ratio test
/// reads them as 0 from then on, and the acceptance rule judges the end.
fn harris(val: &[f64], y: &[f64], thresh: f64, delta: f64, mut pick: (usize, f64)) -> (usize, f64) {
    let bound = val
        .iter()
        .zip(y)
        .filter(|(_, &yc)| yc > thresh)
        .fold(f64::INFINITY, |a, (&v, &yc)| a.min((v.max(0.0) + delta) / yc));
    for (c, (&v, &yc)) in val.iter().zip(y).enumerate() {
        if yc > y[pick.0] && v.max(0.0) / yc <= bound {
            pick = (c, v.max(0.0) / yc);
        }
    }
    pick
}

/// Keeps the tied positions whose row of `B⁻¹ B₀` over the pivot is
/// lexicographically smallest, `B₀` the basis the run started from (the
/// identity of a cold run; a warm run's complementary basis, so that its
/// perturbed start `B₀⁻¹(q + B₀ ε)` = values + `ε` is lexicographically
/// positive and the rule keeps it so, which `B⁻¹` alone does not promise;
/// on 9 sub-LCPs of a forming 200-cube heap, n = 4,400–5,800, warm then cold:
/// 23,307 pivots against 23,920). Walks the columns of `B⁻¹ B₀`
/// rather than its rows: column `j` is `e_c` when `B₀`'s variable at `j` is
/// basic at position `c` (no solve: the row at `c` drops out, every other
/// ties at 0), else one solve serves every tied row, its LU part kept for
/// the next ties on the same factors ([`Basis::solve_column`]). (By rows, a tie of
/// 2,000 degenerate rows on a forming heap took 2,000 transposed solves:
/// 11 % of the time.)
fn lex_break(b: &Basis, y: &[f64], tied: &mut Vec<usize>, tie_tol: f64) {
    let n = b.val.len();
    let mut col = Vec::new();
    // Tied positions marked, so that a basic column of `B₀` costs O(1)
    // unless it is one of them (a retain per column made this O(n · ties)).
    let mut is_tied = vec![false; n];
    tied.iter().for_each(|&t| is_tied[t] = true);
    for j in 0..n {
        if tied.len() <= 1 {
            break;
        }
        let c = b.pos[b.init[j]];
        if c != NONBASIC {
            if is_tied[c] {
                is_tied[c] = false;
                tied.retain(|&t| t != c);
            }
            continue;
        }
        b.solve_column(b.init[j], &mut col);
        let min = tied.iter().map(|&t| col[t] / y[t]).fold(f64::INFINITY, f64::min);
        let scale = tied.iter().fold(0.0f64, |a, &t| a.max((col[t] / y[t]).abs()));
        tied.retain(|&t| {
            let keep = col[t] / y[t] <= min + tie_tol * scale;
            is_tied[t] = keep;
            keep
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With a zero tie tolerance (the polish's) the least ratio's row leaves
    /// even where `v − (v/y)·y` rounds above 0; the run does not end on a ray.
    #[test]
    fn a_least_ratio_rounding_above_zero_still_leaves() {
        let (v, y) = (0.30742957079546274, 0.5191046212719266);
        assert!(v - (v / y) * y > 0.0, "the rounding guarded against");
        let op = StructuredLcp::new(1, &[(0, 0, 1.0)], &[(0, 0, 1.0)], &[], vec![v]).unwrap();
        let d = [1.0];
        let b = Basis::slack(&op, &d).unwrap();
        assert_eq!(b.val, [v]);
        let set = Settings { piv_tol: 1e-9, tie_tol: 0.0, max_pivots: 10, warm_tol: 0.0, refactor_every: 100 };
        assert_eq!(leaving(&b, &[y], y, &set, &mut Vec::new()), Some((0, v / y)));
    }

    /// A warm run that ends on a ray goes on from the complementary basis
    /// its entering variable completes in z0's place, not cold. (`M = G Gᵀ`,
    /// positive semidefinite: Lemke's covering `d = B·1` of a warm start is
    /// not positive, so its ray says nothing about the LCP.)
    #[test]
    fn a_warm_ray_goes_on_from_where_it_stopped() {
        let g = [
            (0, 0, -1.0),
            (0, 1, 0.5),
            (0, 2, 0.5),
            (0, 3, 2.0),
            (1, 0, -1.0),
            (1, 1, -1.0),
            (2, 0, -1.5),
            (2, 1, -1.5),
            (3, 0, 2.0),
            (3, 2, 1.0),
            (4, 0, -1.5),
            (4, 1, 2.0),
            (4, 3, 2.0),
            (5, 1, -1.0),
            (5, 2, -1.5),
        ];
        let h: Vec<_> = g.iter().map(|&(i, d, v)| (d, i, v)).collect();
        let op = StructuredLcp::new(4, &g, &h, &[], vec![-1.0, 1.0, -2.0, -1.0, 0.5, -0.5]).unwrap();
        let set = Settings { piv_tol: 1e-9, tie_tol: 1e-13, max_pivots: 100, warm_tol: 1e-12, refactor_every: 100 };
        let mut d = Vec::new();
        let ray = run_warm(&op, &[0, 1, 2, 3], &mut d, &set).unwrap();
        assert_eq!((ray.status, ray.pivots, ray.ray), (Status::RayTermination, 1, Some(2)), "w_2 enters unblocked");
        assert_eq!(ray.ray_basis(), Some(vec![0, 1, 3]));
        let on = run_warm(&op, &[0, 1, 3], &mut d, &set).unwrap();
        assert_eq!(on.status, Status::Solved);
        let o = super::super::StructuredOptions::default();
        let sol = super::super::solve(&op, &o, Some(&[true, true, true, true, false, false]));
        assert!(sol.ok() && sol.accepted);
        assert_eq!(sol.pivots, ray.pivots + on.pivots, "no cold run after the ray");
        assert_eq!(sol.z, on.z);
    }
}
