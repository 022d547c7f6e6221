//! Minimum-ratio tests: which basic variable leaves.
//!
//! `Lexicographic` detects ties with a tolerance *relative* to the size of the
//! basic values (exact-equality ties break on round-off, which is how
//! Siconos' lexicolemke reports false rays on contact LCPs whose λ rows have
//! q = 0), prefers z0, then breaks ties on the rows of `B⁻¹` divided by the
//! pivot, column by column — the classical rule that makes Lemke finite.
//! `Classic` is the source note's rule, as in Moby's Lemke (Drake's
//! `MobyLCPSolver::SolveLcpLemke`, whose `piv_tol`/`zero_tol` the source note names):
//! absolute tolerances, Harris slack, z0 if it blocks, else the first row.

use super::basis::{Basis, Column, Leaving, Var};
use crate::kernels::{max_abs_finite, min_ratio, ties};

/// A ratio rule with its tolerances.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Rule {
    Lexicographic { piv_tol: f64, tie_tol: f64 },
    Classic { piv_tol: f64, zero_tol: f64 },
}

/// One basic variable seen by the ratio test.
#[derive(Clone, Copy)]
pub(crate) struct Cand {
    at: Leaving,
    value: f64,
    x: f64,
    row: usize,
}

/// Scratch buffers reused across pivots.
#[derive(Default)]
pub(crate) struct Scratch {
    cands: Vec<Cand>,
    tied: Vec<Cand>,
    lex: Vec<f64>,
    hits: Vec<usize>,
}

/// The outcome of a ratio test.
pub(crate) struct Choice {
    pub at: Leaving,
    /// Step length: the entering variable's new value.
    pub theta: f64,
    /// Largest `|x|` over the basics: the scale of this column.
    pub xmax: f64,
}

/// The largest `|x|` over the column, `None` if an entry is not finite.
pub(crate) fn column_max(x: &Column) -> Option<f64> {
    let (s, s_ok) = max_abs_finite(&x.xs, 0.0);
    let (m, w_ok) = max_abs_finite(&x.xw, s);
    (s_ok && w_ok).then_some(m)
}

/// Gathers the basics that can block (`x > 0`), for the classic rule.
fn candidates(basis: &Basis, x: &Column, out: &mut Vec<Cand>) {
    out.clear();
    let mut take = |at, value: f64, x: f64, row| {
        if x > 0.0 {
            out.push(Cand { at, value, x, row });
        }
    };
    for p in 0..basis.m() {
        take(Leaving::S(p), basis.val_s[p], x.xs[p], basis.row_s[p]);
    }
    for i in 0..basis.val_w.len() {
        if basis.w_basic(i) {
            take(Leaving::W(i), basis.val_w[i], x.xw[i], basis.row_w[i]);
        }
    }
}

/// The leaving variable and the step length, or `None` for a ray. `xmax`
/// is [`column_max`] of `x`.
pub(crate) fn leaving(basis: &Basis, x: &Column, xmax: f64, rule: Rule, sc: &mut Scratch) -> Option<Choice> {
    let (at, theta) = match rule {
        Rule::Classic { piv_tol, zero_tol } => {
            candidates(basis, x, &mut sc.cands);
            classic(basis, &sc.cands, piv_tol, zero_tol)?
        }
        Rule::Lexicographic { piv_tol, tie_tol } => lexicographic(basis, x, sc, piv_tol * xmax, tie_tol)?,
    };
    Some(Choice { at, theta, xmax })
}

fn classic(basis: &Basis, c: &[Cand], piv_tol: f64, zero_tol: f64) -> Option<(Leaving, f64)> {
    // Pass 1 (Harris): the largest step that keeps every basic ≥ −zero_tol.
    let theta_max =
        c.iter().filter(|k| k.x > piv_tol).map(|k| (k.value + zero_tol) / k.x).fold(f64::INFINITY, f64::min);
    if !theta_max.is_finite() {
        return None;
    }
    // Pass 2: rows blocking within that step; z0 if it is one, else the first row.
    let blocking = || c.iter().filter(|k| k.x > piv_tol && k.value / k.x <= theta_max);
    let best = blocking()
        .find(|k| matches!(k.at, Leaving::S(p) if basis.s[p] == Var::Z0))
        .or_else(|| blocking().min_by_key(|k| k.row))?;
    Some((best.at, best.value / best.x))
}

/// `thresh`: smallest pivot. Two sweeps over the basics (z-type, then `w` by
/// row; the rows of `R` have `x = 0` and never block): the smallest ratio and
/// the largest |value|, then the rows tied with it — those that come within
/// `tie_tol` of that largest value of zero.
fn lexicographic(basis: &Basis, x: &Column, sc: &mut Scratch, thresh: f64, tie_tol: f64) -> Option<(Leaving, f64)> {
    let first = min_ratio(&basis.val_s, &x.xs, thresh, (f64::INFINITY, f64::MIN_POSITIVE));
    let (theta, vmax) = min_ratio(&basis.val_w, &x.xw, thresh, first);
    if !theta.is_finite() {
        return None;
    }
    // Never narrower than the rounding of `v − θ·x` (a few ulps of the
    // largest value): at `zero_tol = 0` the least ratio's row could round
    // to a positive remainder, tie with nothing, and end the run on a false ray.
    let vtol = tie_tol.max(4.0 * f64::EPSILON) * vmax;
    // Rows that reach zero within vtol at this step; z0 among them ends the run.
    sc.tied.clear();
    sc.hits.clear();
    ties(&basis.val_s, &x.xs, thresh, theta, vtol, &mut sc.hits);
    for &p in &sc.hits {
        if basis.s[p] == Var::Z0 {
            return Some((Leaving::S(p), theta));
        }
        sc.tied.push(Cand { at: Leaving::S(p), value: basis.val_s[p], x: x.xs[p], row: basis.row_s[p] });
    }
    sc.hits.clear();
    ties(&basis.val_w, &x.xw, thresh, theta, vtol, &mut sc.hits);
    for &i in &sc.hits {
        sc.tied.push(Cand { at: Leaving::W(i), value: basis.val_w[i], x: x.xw[i], row: basis.row_w[i] });
    }
    if sc.tied.len() > 1 {
        lex_break(basis, &mut sc.tied, &mut sc.lex, tie_tol);
    }
    // Still tied after every column (only under round-off): the largest pivot.
    let best = sc.tied.iter().max_by(|a, b| a.x.total_cmp(&b.x))?;
    Some((best.at, theta))
}

/// Keeps the candidates whose `B⁻¹` row over the pivot is lexicographically
/// smallest. Entries are computed column by column, only while ties remain:
/// most ties are broken within the first columns.
fn lex_break(basis: &Basis, rows: &mut Vec<Cand>, v: &mut Vec<f64>, tie_tol: f64) {
    let n = basis.val_w.len();
    for col in 0..n {
        if rows.len() == 1 {
            break;
        }
        if basis.w_basic(col) {
            // Column `col` of B⁻¹ is the unit vector of basic w_col: every
            // entry is 0 but w_col's 1/x > 0, which is not the minimum.
            rows.retain(|k| k.at != Leaving::W(col));
            continue;
        }
        v.clear();
        v.extend(rows.iter().map(|k| basis.binv_entry(k.at, col) / k.x));
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        let scale = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let mut it = v.iter();
        rows.retain(|_| *it.next().expect("one value per row") <= min + tie_tol * scale);
    }
}

/// The first pivot, where z0 enters at the value that makes every `w ≥ 0`:
/// the row with the most negative `q_i / d_i`.
pub(crate) fn first_leaving(q: &[f64], d: &[f64], rule: Rule) -> usize {
    match rule {
        // The most negative q, first index on ties.
        Rule::Classic { .. } => {
            let qmin = q.iter().copied().fold(f64::INFINITY, f64::min);
            (0..q.len()).find(|&i| q[i] == qmin).unwrap_or(0)
        }
        // Lexicographic: among ties the largest index keeps the other rows lex-positive.
        Rule::Lexicographic { tie_tol, .. } => {
            let ratio = |i: usize| q[i] / d[i];
            let min = (0..q.len()).map(ratio).fold(f64::INFINITY, f64::min);
            let scale = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            (0..q.len()).rev().find(|&i| (ratio(i) - min) * d[i] <= tie_tol * scale).unwrap_or(0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Lcp;

    /// With a zero tie tolerance (`zero_tol = 0`) the least ratio's row
    /// leaves even where `v − (v/x)·x` rounds above 0; no false ray.
    #[test]
    fn a_least_ratio_rounding_above_zero_still_leaves() {
        let (v, x) = (0.30742957079546274, 0.5191046212719266);
        assert!(v - (v / x) * x > 0.0, "the rounding guarded against");
        let lcp = Lcp::from_fn(1, |_, _| 1.0, vec![v]).unwrap();
        let d = [1.0];
        let basis = Basis::slack(&lcp, &d, Default::default());
        let col = Column { xs: Vec::new(), xw: vec![x] };
        let got = lexicographic(&basis, &col, &mut Scratch::default(), 1e-12, 0.0);
        assert!(matches!(got, Some((Leaving::W(0), t)) if t == v / x), "{:?}", got.map(|g| g.1));
    }
}
