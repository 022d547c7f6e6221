//! Solving an LCP on a guessed complementary basis, without pivoting and
//! without forming `M`.
//!
//! A simulator's LCP changes little from one step to the next, and on most
//! steps the previous step's complementary basis (which `z_j` are basic)
//! solves the new problem as it is: `z_S = −M_SS⁻¹ q_S`, `z = 0` elsewhere,
//! with `z ≥ 0` and `w = M z + q ≥ 0`. Checking that needs only the block
//! `M_SS` and one product `M z`, both of which a caller can compute from a
//! structure far smaller than the dense `n × n` matrix (the simulator keeps
//! `M = J M_b⁻¹ Jᵀ` in body space). [`LcpOperator`] is that access;
//! [`solve_on_basis`] is the check.
//!
//! Statically indeterminate contact (four corners of a box on a box bear a
//! load that three constraints fix) makes a guessed basis rank-deficient. The
//! block is factored by an LU that sets dependent columns aside, so its rank
//! shows; those columns are dropped from the support (`z_j = 0`, `w_j` basic instead),
//! which keeps the previous vertex of the solution set instead of jumping to
//! another — the reason a resting stack needs no pivot.
//!
//! The answer is accepted only by the rule the robust Lemke uses in the units
//! given: natural residual `‖min(z, w)‖∞ ≤ accept_tol·(1 + ‖q‖∞)`, on the
//! problem as given and — when the caller passes one — on a second operator
//! in other units (the simulator's unscaled, physical LCP). Nothing about the
//! problem is changed: no regularization.

use crate::problem::Lcp;
use crate::solution::{Residuals, Solution, Status};

/// An LCP `(M, q)` whose matrix is reached through products and blocks.
pub trait LcpOperator {
    /// Size `n`.
    fn n(&self) -> usize;
    /// The vector `q`.
    fn q(&self) -> &[f64];
    /// `M[rows, cols]` into `out`, row-major (`rows.len() × cols.len()`).
    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]);
    /// `w = M z + q`.
    fn w_of(&self, z: &[f64], w: &mut [f64]);
}

impl LcpOperator for Lcp {
    fn n(&self) -> usize {
        Lcp::n(self)
    }
    fn q(&self) -> &[f64] {
        Lcp::q(self)
    }
    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]) {
        for (r, &i) in rows.iter().enumerate() {
            let row = self.row(i);
            for (c, &j) in cols.iter().enumerate() {
                out[r * cols.len() + c] = row[j];
            }
        }
    }
    fn w_of(&self, z: &[f64], w: &mut [f64]) {
        for (i, wi) in w.iter_mut().enumerate() {
            *wi = crate::problem::dot(self.row(i), z) + self.q()[i];
        }
    }
}

/// A column whose pivot is below this fraction of the block's largest entry
/// counts as dependent on the columns before it.
const RANK_TOL: f64 = 1e-11;

/// Buffers of [`solve_on_basis`], reused across calls by their owner.
#[derive(Clone, Debug, Default)]
pub struct SupportWorkspace {
    /// Which `z_j` are basic in the basis being tried.
    mask: Vec<bool>,
    /// Support `S` (basic `z` indices), then the rank-revealing order of it.
    support: Vec<usize>,
    /// `M_SS`, factored in place (row-major).
    lu: Vec<f64>,
    /// Row and column permutations of the factorization.
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// Right-hand side and solution of the leading block.
    x: Vec<f64>,
    /// `z` and `w` of a candidate in the operator's units.
    z: Vec<f64>,
    w: Vec<f64>,
}

/// The answer of [`solve_on_basis`] when it is accepted.
#[derive(Clone, Debug, PartialEq)]
pub struct BasisAnswer {
    /// `z`, `w = M z + q` and residuals on the operator given.
    pub solution: Solution,
    /// Columns of the guess dropped as linearly dependent.
    pub dropped: usize,
}

/// Solves `op` on the complementary basis `basis` (`basis[j]`: `z_j` basic):
/// `M_SS z_S = −q_S` by a rank-revealing LU with one refinement step,
/// dependent columns dropped, `z` clipped at 0. Returns the answer if its
/// natural residual is at most `accept_tol·(1 + ‖q‖∞)` on `op` and, when
/// given, on `also` (the same `z` mapped by `to_also`, e.g. to physical
/// units); `None` otherwise (the caller then pivots). The returned
/// `Solution` has status `Solved`, 0 pivots and the basis actually used.
pub fn solve_on_basis(
    op: &dyn LcpOperator,
    basis: &[bool],
    accept_tol: f64,
    also: Option<(&dyn LcpOperator, &dyn Fn(&[f64], &mut Vec<f64>))>,
    ws: &mut SupportWorkspace,
) -> Option<BasisAnswer> {
    let n = op.n();
    if basis.len() != n {
        return None;
    }
    let tol = accept_tol * (1.0 + norm_inf(op.q()));
    // Violations far below the acceptance bound are already exchanged, so a
    // slowly drifting vertex is left before its values reach the bound.
    let repair = REPAIR_FRACTION * tol;
    ws.mask.clear();
    ws.mask.extend_from_slice(basis);
    let mut best: Option<BasisAnswer> = None;
    for _ in 0..=REPAIR_ROUNDS {
        let Some((rank, m)) = solve_support(op, ws) else { break };
        // Dependent columns carry z = 0: they leave the support.
        for &c in &ws.cols[rank..m] {
            ws.mask[ws.support[c]] = false;
        }
        // Exchange the most violated index (basic z < 0 leaves, nonbasic
        // w < 0 enters): one at a time, as exchanging all of them at once
        // wanders on these degenerate problems.
        let mut worst = (repair, None);
        for i in 0..n {
            let v = if ws.mask[i] { -ws.z[i] } else { -ws.w[i] };
            if v > worst.0 {
                worst = (v, Some(i));
            }
        }
        let changed = worst.1.is_some();
        if let Some(i) = worst.1 {
            ws.mask[i] = !ws.mask[i];
        }
        // Round-off negatives of z are clipped and w recomputed for the check.
        ws.z.iter_mut().for_each(|v| *v = v.max(0.0));
        op.w_of(&ws.z, &mut ws.w);
        let residuals = Residuals::of(&ws.z, &ws.w);
        let closer = best.as_ref().is_none_or(|b| residuals.residual < b.solution.residuals.residual);
        if residuals.residual <= tol && closer && accepted_by(also, &ws.z, accept_tol) {
            let mut used = vec![false; n];
            for &c in &ws.cols[..rank] {
                used[ws.support[c]] = true;
            }
            let solution = Solution {
                z: ws.z.clone(),
                w: ws.w.clone(),
                status: Status::Solved,
                pivots: 0,
                residuals,
                basis: Some(used),
                // By the bound above (normwise: `M` is not formed here, so the
                // componentwise rule of `crate::accept` cannot be evaluated).
                accepted: true,
            };
            best = Some(BasisAnswer { solution, dropped: m - rank });
        }
        if !changed || best.is_some() {
            break;
        }
    }
    best
}

/// Violations above this fraction of the acceptance bound are exchanged.
const REPAIR_FRACTION: f64 = 0.1;

/// Index exchanges tried after the guessed basis itself (block principal
/// pivoting on the violated indices); the caller pivots when they do not do.
const REPAIR_ROUNDS: usize = 8;

/// `z` on the support `ws.mask` (dependent columns dropped, one refinement
/// step) and `w = M z + q`, unclipped; returns `(rank, support size)`.
fn solve_support(op: &dyn LcpOperator, ws: &mut SupportWorkspace) -> Option<(usize, usize)> {
    let n = op.n();
    ws.support.clear();
    ws.support.extend((0..n).filter(|&j| ws.mask[j]));
    let m = ws.support.len();
    let rank = factor(op, ws)?;
    // Solve the leading rank × rank block: L y = −P q_S, U x = y.
    let q = op.q();
    ws.x.clear();
    ws.x.extend(ws.rows[..rank].iter().map(|&r| -q[ws.support[r]]));
    solve_leading(&ws.lu, m, rank, &mut ws.x);
    ws.z.clear();
    ws.z.resize(n, 0.0);
    for (k, &c) in ws.cols[..rank].iter().enumerate() {
        ws.z[ws.support[c]] = ws.x[k];
    }
    // One step of iterative refinement on the leading equations.
    ws.w.clear();
    ws.w.resize(n, 0.0);
    op.w_of(&ws.z, &mut ws.w);
    ws.x.clear();
    ws.x.extend(ws.rows[..rank].iter().map(|&r| -ws.w[ws.support[r]]));
    solve_leading(&ws.lu, m, rank, &mut ws.x);
    for (k, &c) in ws.cols[..rank].iter().enumerate() {
        ws.z[ws.support[c]] += ws.x[k];
    }
    if !ws.z.iter().all(|v| v.is_finite()) {
        return None;
    }
    op.w_of(&ws.z, &mut ws.w);
    Some((rank, m))
}

/// The second check of [`solve_on_basis`]: `z` mapped into the other units
/// meets the same bound there.
fn accepted_by(also: Option<(&dyn LcpOperator, &dyn Fn(&[f64], &mut Vec<f64>))>, z: &[f64], accept_tol: f64) -> bool {
    let Some((other, map)) = also else { return true };
    let mut z2 = Vec::with_capacity(z.len());
    map(z, &mut z2);
    let mut w2 = vec![0.0; z.len()];
    other.w_of(&z2, &mut w2);
    Residuals::of(&z2, &w2).residual <= accept_tol * (1.0 + norm_inf(other.q()))
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Loads `M_SS` and factors it in place by LU with partial (row) pivoting
/// that skips dependent columns: a column whose best pivot is below
/// `RANK_TOL` of the largest entry of the block is moved behind the others.
/// Returns the numerical rank `r`; `ws.rows[..r]`, `ws.cols[..r]` index the
/// leading nonsingular block (`None` if the block is not finite).
fn factor(op: &dyn LcpOperator, ws: &mut SupportWorkspace) -> Option<usize> {
    let m = ws.support.len();
    ws.lu.clear();
    ws.lu.resize(m * m, 0.0);
    op.block(&ws.support, &ws.support, &mut ws.lu);
    ws.rows.clear();
    ws.rows.extend(0..m);
    ws.cols.clear();
    ws.cols.extend(0..m);
    let a = &mut ws.lu;
    let scale = a.iter().fold(0.0f64, |x, v| x.max(v.abs()));
    if !scale.is_finite() {
        return None;
    }
    let floor = RANK_TOL * scale;
    let mut k = 0;
    let mut end = m;
    while k < end {
        // The largest entry of column k at or below row k is the pivot.
        let (mut pr, mut best) = (k, 0.0f64);
        for r in k..m {
            let v = a[r * m + k].abs();
            if v > best {
                (pr, best) = (r, v);
            }
        }
        if best <= floor {
            // Dependent on the columns before it: move it behind the others.
            end -= 1;
            for r in 0..m {
                a.swap(r * m + k, r * m + end);
            }
            ws.cols.swap(k, end);
            continue;
        }
        if pr != k {
            for c in 0..m {
                a.swap(k * m + c, pr * m + c);
            }
            ws.rows.swap(k, pr);
        }
        let p = a[k * m + k];
        // Rows below k minus multiples of row k (slices, so the update vectorizes).
        let (top, below) = a.split_at_mut((k + 1) * m);
        let pivot_row = &top[k * m + k + 1..(k + 1) * m];
        for row in below.chunks_exact_mut(m) {
            let l = row[k] / p;
            row[k] = l;
            if l != 0.0 {
                for (x, &u) in row[k + 1..].iter_mut().zip(pivot_row) {
                    *x -= l * u;
                }
            }
        }
        k += 1;
    }
    Some(end)
}

/// Solves `L U x = b` on the leading `r × r` block of a packed LU of order `m`.
fn solve_leading(lu: &[f64], m: usize, r: usize, x: &mut [f64]) {
    for i in 0..r {
        let mut s = x[i];
        for k in 0..i {
            s -= lu[i * m + k] * x[k];
        }
        x[i] = s;
    }
    for i in (0..r).rev() {
        let mut s = x[i];
        for k in i + 1..r {
            s -= lu[i * m + k] * x[k];
        }
        x[i] = s / lu[i * m + i];
    }
}
