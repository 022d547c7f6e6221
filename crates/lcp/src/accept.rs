//! The acceptance rule: when an answer `z` counts as a solution of the LCP.
//!
//! One rule for every solver, judged row by row on each row's own scale, so
//! that no row is judged against the largest `|q_i|`. For `z ≥ 0` and
//! `w = M z + q` (as computed), row `i` has the *scale* and the *round-off
//! floor*
//!
//! ```text
//! s_i = |q_i| + Σ_j |M_ij| z_j          f_i = ρ·max_j |M_ij|·Σ_j z_j      ρ = 1e-13 (ROUND_OFF)
//! ```
//!
//! and the *violation* `v_i = |w_i|` if `z_i > 0` (complementarity wants
//! `w_i = 0`), else `max(−w_i, 0)` (feasibility wants `w_i ≥ 0`). Its
//! backward error is `η_i = max(v_i − f_i, 0) / s_i` (0 when that is 0,
//! infinite when only the scale is), and
//!
//! ```text
//! η(z) = max_i η_i,   infinite if some z_i < 0 or is not finite.
//! ```
//!
//! `z` is **accepted** iff `η(z) ≤ tol` (default [`DEFAULT_TOL`] = 1e-9),
//! i.e. `v_i ≤ tol·s_i + f_i` for every row: `z` solves exactly an LCP whose
//! rows differ from the ones given by `|ΔM_ij| ≤ tol·|M_ij| + ρ·max_k |M_ik|`,
//! `|Δq_i| ≤ tol·|q_i|` — the Oettli–Prager bound (without `ρ` it is the
//! componentwise measure [`crate::certify::Certificate::backward_error`]
//! evaluates exactly). `ρ` is the round-off of forming and solving a dense
//! LCP (~450 ε): a contact LCP's `J M_b⁻¹ Jᵀ` has entries that are 0 for the
//! exact data and ±1e-16 of their row as computed, and with a heavy body on a
//! light one, or at a stack's sticking contacts, a row is made of nothing
//! else; its `w_i` is then round-off that no relative test can pass. The rule
//! is invariant under positive diagonal row scaling; answers are judged in
//! the units given.
//!
//! `Solution::accepted` records the verdict at the solver's tolerance and
//! `Solution::ok()` needs it: no method (Lemke robust or classic, PGS,
//! Newton–FB) reports `ok` for an answer outside this rule.

use crate::operator::LcpOperator;
use crate::problem::Lcp;

/// Default tolerance of the rule (Lemke's `accept_tol`; PGS and Newton–FB use it too).
pub const DEFAULT_TOL: f64 = 1e-9;

/// `ρ` of the module docs: the round-off floor, relative to a row's largest entry times `Σ z`.
pub const ROUND_OFF: f64 = 1e-13;

/// The violation of row `i`: `|w_i|` where `z_i > 0`, else `max(−w_i, 0)`
/// (0 for a NaN `w_i`: written as a select, which vectorizes).
#[inline(always)]
pub(crate) fn violation(zi: f64, wi: f64) -> f64 {
    if zi > 0.0 {
        wi.abs()
    } else {
        crate::kernels::pick_max(0.0, -wi)
    }
}

/// The scale `s_i = |q_i| + Σ_j |M_ij| z_j` and the floor
/// `f_i = ρ·max_j |M_ij|·Σ_j z_j` of row `i` (`zsum = Σ_j z_j`).
fn row_scale(lcp: &Lcp, i: usize, z: &[f64], zsum: f64) -> (f64, f64) {
    scale_of_row(lcp.row(i), lcp.q()[i], z, zsum)
}

/// [`row_scale`] of a row `m_i` given as a slice, with its `q_i`.
fn scale_of_row(row: &[f64], qi: f64, z: &[f64], zsum: f64) -> (f64, f64) {
    let (mut terms, mut rmax) = (0.0, 0.0f64);
    for (&zj, m) in z.iter().zip(row) {
        rmax = rmax.max(m.abs());
        if zj != 0.0 {
            terms += m.abs() * zj;
        }
    }
    (terms + qi.abs(), ROUND_OFF * rmax * zsum)
}

/// `η_i` of a row with violation `v` (finite), scale and floor.
fn row_eta(v: f64, (scale, floor): (f64, f64)) -> f64 {
    ratio((v - floor).max(0.0), scale)
}

/// `violation / scale` with 0/0 = 0.
#[inline]
fn ratio(violation: f64, scale: f64) -> f64 {
    if violation == 0.0 {
        0.0
    } else if scale > 0.0 {
        violation / scale
    } else {
        f64::INFINITY
    }
}

/// The componentwise backward error `η(z)` of the module docs, for `w = M z + q`.
///
/// # Panics
/// If `z` or `w` do not have `lcp.n()` entries.
pub fn backward_error(lcp: &Lcp, z: &[f64], w: &[f64]) -> f64 {
    check_lengths(lcp, z, w);
    if !z.iter().all(|&v| v >= 0.0 && v.is_finite()) {
        return f64::INFINITY;
    }
    let zsum: f64 = z.iter().sum();
    (0..lcp.n()).fold(0.0f64, |eta, i| {
        let v = violation(z[i], w[i]);
        if v == 0.0 {
            eta
        } else {
            eta.max(if v.is_finite() { row_eta(v, row_scale(lcp, i, z, zsum)) } else { f64::INFINITY })
        }
    })
}

/// Whether `z` is accepted: `η(z) ≤ tol` (see the module docs). Cheaper than
/// [`backward_error`]: a row whose violation is within the lower bound
/// `tol·(|q_i| + |M_ii| z_i) + ρ·|M_ii|·Σ z` of `tol·s_i + f_i` passes without
/// its scale being summed.
///
/// # Panics
/// If `z` or `w` do not have `lcp.n()` entries.
pub fn accepts(lcp: &Lcp, z: &[f64], w: &[f64], tol: f64) -> bool {
    check_lengths(lcp, z, w);
    let (n, m) = (lcp.n(), lcp.m());
    accepts_rows(lcp.q(), z, w, tol, |i| m[i * n + i], |i, zsum| row_scale(lcp, i, z, zsum))
}

/// [`accepts`] for an `M` reached through its diagonal `diag(i) = M_ii` and
/// `scale(i, Σ z) = (s_i, f_i)` of the module docs (a structured `M`, see
/// [`crate::structured`]): the same rule, row by row.
pub(crate) fn accepts_rows(
    q: &[f64],
    z: &[f64],
    w: &[f64],
    tol: f64,
    diag: impl FnMut(usize) -> f64,
    scale: impl FnMut(usize, f64) -> (f64, f64),
) -> bool {
    rejected_rows((q, z, w), tol, None, diag, |_, _| None, scale, true).is_none()
}

/// The row the rule rejects with the largest `η_i` (`first`: the first row
/// it rejects), `None` when it accepts; a negative or non-finite `z_i` is
/// rejected before any row is read. `diag` and `scale` as in [`accepts_rows`];
/// `entry(i, known)`, when it knows some other entries of the row (e.g. its
/// largest at an earlier read), their `(Σ_j |M_ij| z_j, max_j |M_ij|)`, which
/// sharpen the bound below before the row is read (`s_i ≥ |q_i| + |M_ii|
/// z_i + Σ_j |M_ij| z_j`, `max ≥ max_j |M_ij|`, over those `j ≠ i`): with
/// `known` `None` of one of them, with `Some` (those sums) of all (`None`
/// when that one is all). The bound only grows with entries: one that a
/// part of them clears all of them clear.
/// `M_ii` is read only for a row whose violation is above `tol·|q_i|`, the
/// scale only for a row the lower bound of the module docs' `tol·s_i + f_i`,
/// `tol·(|q_i| + |M_ii| z_i) + ρ·|M_ii|·Σ z`, does not clear (`s_i ≥ |q_i| +
/// |M_ii| z_i` and `max_j |M_ij| ≥ |M_ii|`): reading rows costs where `M` is
/// not stored, and on a resting stack the unloaded friction rows are many,
/// with `q_i = 0` and round-off `w_i < 0` that only their floor admits.
fn rejected_rows(
    (q, z, w): (&[f64], &[f64], &[f64]),
    tol: f64,
    diagonal: Option<&[f64]>,
    mut diag: impl FnMut(usize) -> f64,
    mut entry: impl FnMut(usize, Option<(f64, f64)>) -> Option<(f64, f64)>,
    mut scale: impl FnMut(usize, f64) -> (f64, f64),
    first: bool,
) -> Option<usize> {
    // (One pass without early exits, which vectorizes: the rows are read one
    // by one only when some `z_i` is bad or some row is past the tests on
    // `M_ii` (`diagonal`, when known as a slice; `zsum` summed as below).)
    let sized = z.len() == q.len() && w.len() == q.len();
    let diagonal = diagonal.filter(|d| sized && d.len() == q.len()).map(|d| (d, crate::kernels::sum_in_order(z)));
    // The rows to read one by one: those the pass marks, where it tests the
    // diagonal and there are more rows than a word of marks holds (on a
    // resting stack a few dozen rows of 400 are past the pass's tests, but
    // the first of them comes early) up to `PAST_WORDS` of them, else all
    // from the first row past the tests on (a single body's 40 rows).
    let marked = diagonal.is_some() && (65..=64 * PAST_WORDS).contains(&q.len());
    let mut past = [0u64; PAST_WORDS];
    let marks = marked.then_some(&mut past[..]);
    let (bad_z, from) = crate::kernels::rows_past_cheap_tests((q, z, w), tol, diagonal, marks);
    let from = if sized { from } else { 0 };
    let (mut marks, mut rest) = (crate::kernels::marked_rows(&past, from), from..q.len());
    let mut next = || if marked { marks.next() } else { rest.next() };
    if !bad_z && from == q.len() {
        return None;
    }
    let bad = |v: f64| !(v >= 0.0 && v.is_finite());
    if bad_z || !sized && z.iter().any(|&v| bad(v)) {
        return z.iter().position(|&v| bad(v));
    }
    // (`Σ z` once: a sum in order waits on each add.)
    let mut zsum = diagonal.map(|(_, zs)| zs);
    let mut worst: Option<(usize, f64)> = None;
    // (The rows before `from`, and those not marked, pass the tests on `M_ii` below.)
    while let Some(i) = next() {
        let v = violation(z[i], w[i]);
        // Most rows: no violation, or one within `tol·|q_i|`.
        // (Written `v <= …` so that a NaN falls through to the full check.)
        if v == 0.0 || v <= tol * q[i].abs() {
            continue;
        }
        let zs = *zsum.get_or_insert_with(|| crate::kernels::sum_in_order(z));
        let d = diag(i).abs();
        if v <= tol * (q[i].abs() + d * z[i]) + ROUND_OFF * d * zs {
            continue;
        }
        let clears =
            |(terms, top): (f64, f64)| v <= tol * (q[i].abs() + d * z[i] + terms) + ROUND_OFF * d.max(top) * zs;
        if let Some(first) = entry(i, None) {
            if clears(first) || entry(i, Some(first)).is_some_and(clears) {
                continue;
            }
        }
        let eta = if v.is_finite() { row_eta(v, scale(i, zs)) } else { f64::INFINITY };
        // (A NaN η is rejected.)
        if eta > tol || eta.is_nan() {
            if first {
                return Some(i);
            }
            // (A NaN η counts as the largest.)
            if worst.is_none_or(|(_, e)| eta > e || eta.is_nan()) {
                worst = Some((i, eta));
            }
        }
    }
    worst.map(|(i, _)| i)
}

/// Words of [`crate::kernels::rows_past_cheap_tests`]'s marks [`rejected_rows`]
/// keeps on its stack: rows of LCPs up to `64·PAST_WORDS` are read only where marked.
const PAST_WORDS: usize = 16;

/// [`accepts`] for an `M` reached through an [`LcpOperator`] (blocks and
/// products, e.g. a contact LCP in body space): the same rule, row by row.
/// `M_ii` is read with [`LcpOperator::diag`] and a row's scale with
/// [`LcpOperator::row`], only for the rows the cheap bounds of
/// [`accepts`] do not clear.
///
/// # Panics
/// If `z` or `w` do not have `op.n()` entries.
pub fn accepts_operator(op: &dyn LcpOperator, z: &[f64], w: &[f64], tol: f64) -> bool {
    rejected_row_operator(op, z, w, tol, true, &mut Vec::new(), &mut Vec::new()).is_none()
}

/// The row of `(z, w)` the rule rejects on `op`: the one with the largest
/// `η_i`, or with `first` the first one (see [`accepts_operator`]); `None`
/// when `z` is accepted. An index with `z_i < 0` (or not finite) comes first.
/// `kept` (`n` entries, or empty: reset to none known) keeps, from call to
/// call, [`KEPT`] columns of each row found at its last full read: that of
/// its largest entry and those of its largest terms `|M_ij| z_j`. Those
/// entries, read again, often clear the row without the full read (on a
/// resting stack, the unloaded corners' friction rows, whose violation is
/// near their floor and whose scale is a few loaded contacts' terms). Any
/// columns would give valid bounds: the verdict is exact whatever it holds.
///
/// # Panics
/// If `z` or `w` do not have `op.n()` entries.
pub fn rejected_row_operator(
    op: &dyn LcpOperator,
    z: &[f64],
    w: &[f64],
    tol: f64,
    first: bool,
    kept: &mut Vec<KeptColumns>,
    row: &mut Vec<f64>,
) -> Option<usize> {
    let n = op.n();
    check_sizes(n, z, w);
    if kept.len() != n {
        kept.clear();
        kept.resize(n, [NO_COLUMN; KEPT]);
    }
    let kept = std::cell::Cell::from_mut(kept.as_mut_slice()).as_slice_of_cells();
    let entry = |i: usize, first: Option<(f64, f64)>| {
        let cols = kept[i].get();
        let known = cols.iter().take_while(|&&j| j < n).count();
        // (The column of the largest term alone — the one that clears an
        // unloaded friction row on a resting stack — then all of them.)
        let cols = match first {
            None => &cols[known.min(2).saturating_sub(1)..known.min(2)],
            Some(_) if known > 1 => &cols[..known],
            Some(_) => &[],
        };
        (!cols.is_empty()).then(|| {
            let mut x = [0.0; KEPT];
            op.block(&[i], cols, &mut x[..cols.len()]);
            cols.iter()
                .zip(&x)
                .filter(|&(&j, _)| j != i)
                .fold((0.0, 0.0f64), |(terms, top), (&j, m)| (terms + m.abs() * z[j], top.max(m.abs())))
        })
    };
    let scale = |i: usize, zsum: f64| {
        row.resize(n, 0.0);
        op.row(i, row);
        kept[i].set(kept_columns(row, z, i));
        scale_of_row(row, op.q()[i], z, zsum)
    };
    let diagonal = op.diagonal().filter(|d| d.len() == n);
    let diag = |i: usize| diagonal.map_or_else(|| op.diag(i), |d| d[i]);
    rejected_rows((op.q(), z, w), tol, diagonal, diag, entry, scale, first)
}

/// Columns of a row kept by [`rejected_row_operator`] between calls.
pub const KEPT: usize = 4;

/// The columns [`rejected_row_operator`] keeps of a row.
pub type KeptColumns = [usize; KEPT];

/// No column known in a [`KeptColumns`] slot (the known ones come first).
const NO_COLUMN: usize = usize::MAX;

/// Of row `i` (read in full, `row`): the column of its largest entry other
/// than `M_ii`, then those of its `KEPT − 1` largest terms `|M_ij| z_j`
/// (`j ≠ i`, `z_j > 0`), each once.
fn kept_columns(row: &[f64], z: &[f64], i: usize) -> KeptColumns {
    let mut cols = [NO_COLUMN; KEPT];
    if let Some(top) = last_largest_magnitude(row, i) {
        cols[0] = top;
    }
    // Insertion into a short list sorted by term, largest first.
    let mut terms = [(0.0f64, NO_COLUMN); KEPT - 1];
    for j in (0..row.len()).filter(|&j| z[j] > 0.0 && j != i && j != cols[0]) {
        let t = row[j].abs() * z[j];
        if let Some(p) = terms.iter().position(|&(u, c)| c == NO_COLUMN || t > u) {
            terms[p..].rotate_right(1);
            terms[p] = (t, j);
        }
    }
    let after_top = usize::from(cols[0] != NO_COLUMN);
    for (k, &(_, j)) in (after_top..).zip(terms.iter().filter(|&&(_, j)| j != NO_COLUMN)) {
        cols[k] = j;
    }
    cols
}

/// The last `j ≠ i` of the largest `|row_j|` in [`f64::total_cmp`]'s order
/// (what `max_by` of that order picks), `None` for a row of `i` alone. An
/// `|x|`'s bits order as that order does: their largest is found over lanes
/// (a full read on a resting stack spans 400 entries), then its last place.
fn last_largest_magnitude(row: &[f64], i: usize) -> Option<usize> {
    let bits = |x: &f64| x.to_bits() & !(1 << 63);
    let lanes = crate::kernels::LANES;
    let largest = |part: &[f64]| {
        let mut acc = [0u64; crate::kernels::LANES];
        let mut chunks = part.chunks_exact(lanes);
        for c in &mut chunks {
            for k in 0..lanes {
                acc[k] = acc[k].max(bits(&c[k]));
            }
        }
        chunks.remainder().iter().fold(acc.into_iter().max().unwrap_or(0), |m, x| m.max(bits(x)))
    };
    let (before, after) = (&row[..i.min(row.len())], row.get(i + 1..).unwrap_or(&[]));
    if before.is_empty() && after.is_empty() {
        return None;
    }
    let top = largest(before).max(largest(after));
    match after.iter().rposition(|x| bits(x) == top) {
        Some(k) => Some(i + 1 + k),
        None => before.iter().rposition(|x| bits(x) == top),
    }
}

fn check_lengths(lcp: &Lcp, z: &[f64], w: &[f64]) {
    check_sizes(lcp.n(), z, w);
}

fn check_sizes(n: usize, z: &[f64], w: &[f64]) {
    assert!(
        z.len() == n && w.len() == n,
        "accept: z and w have {} and {} entries for an LCP of size {}",
        z.len(),
        w.len(),
        n
    );
}

/// Relative thresholds (of the largest weighted entry) below which [`snap`]
/// sets an entry of `z` to 0.
const SNAP_LEVELS: [f64; 3] = [1e-15, 1e-12, 1e-9];

/// A candidate repair of an answer the rule rejects because of entries that
/// are round-off, not values: an iterative method's `z_i ≈ 1e-14` beside
/// `w_i ≈ 1` (a zero it has not reached), or a pivoting method's basic
/// `z_j ≈ 1e-33` at a degenerate contact that leaves a row made of nothing
/// but such noise. The first of `z` (clipped at 0) and its variants with the
/// entries `z_j·c_j ≤ τ·max_k z_k c_k` set to 0 (τ = 1e-15, 1e-12, 1e-9;
/// `c = weights`, all ones by default — a solver passes the column scaling
/// it worked in) that the rule accepts at `tol`, with its `w`; `None` when
/// none is. The rule, not the threshold, decides: a variant that drops a real
/// value fails it.
pub fn snap(lcp: &Lcp, z: &[f64], weights: Option<&[f64]>, tol: f64) -> Option<(Vec<f64>, Vec<f64>)> {
    let clipped: Vec<f64> = z.iter().map(|v| v.max(0.0)).collect();
    let w = lcp.w_of(&clipped);
    if accepts(lcp, &clipped, &w, tol) {
        return Some((clipped, w));
    }
    snap_rejected(lcp, &clipped, weights, tol)
}

/// [`snap`] for a `z ≥ 0` that the rule has already rejected at `tol` (its
/// caller formed `w` and judged it, as [`crate::Solution::from_z_tol`] does):
/// only the variants with small entries set to 0, without forming `w` and
/// judging `z` itself once more (a product with the dense `M`, on every
/// rejected round of a Lemke warm start).
pub(crate) fn snap_rejected(
    lcp: &Lcp,
    clipped: &[f64],
    weights: Option<&[f64]>,
    tol: f64,
) -> Option<(Vec<f64>, Vec<f64>)> {
    debug_assert!(clipped.iter().all(|v| *v >= 0.0), "snap_rejected: z must be clipped at 0");
    let weight = |j: usize| weights.map_or(1.0, |c| c[j]);
    let top = (0..clipped.len()).fold(0.0f64, |a, j| a.max(clipped[j] * weight(j)));
    let mut last = clipped.to_vec();
    for tau in SNAP_LEVELS {
        let cand: Vec<f64> =
            (0..clipped.len()).map(|j| if clipped[j] * weight(j) <= tau * top { 0.0 } else { clipped[j] }).collect();
        if cand == last {
            continue;
        }
        let wc = lcp.w_of(&cand);
        if accepts(lcp, &cand, &wc, tol) {
            return Some((cand, wc));
        }
        last = cand;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcp(m: Vec<f64>, q: Vec<f64>) -> Lcp {
        Lcp::new(m, q).unwrap()
    }

    #[test]
    fn each_row_is_judged_on_its_own_scale() {
        // Row 0 is tiny, row 1 large: w_0 = −1e-6 is a 100 % violation of row 0
        // although it is 3e-10 of ‖q‖∞.
        let p = lcp(vec![1.0, 0.0, 0.0, 1.0], vec![1e-6, -3e3]);
        let z = [0.0, 3e3];
        let w = [1e-6 - 2e-6, 0.0];
        assert!(!accepts(&p, &z, &w, 1e-9));
        // (1e-6 − ρ·1·3e3) / 1e-6.
        assert!((backward_error(&p, &z, &w) - (1.0 - 3e-4)).abs() < 1e-12);
        let w = p.w_of(&z);
        assert!(accepts(&p, &z, &w, 1e-9));
        assert_eq!(backward_error(&p, &z, &w), 0.0);
    }

    #[test]
    fn complementarity_and_sign_are_part_of_the_rule() {
        let p = lcp(vec![2.0, 0.0, 0.0, 2.0], vec![-2.0, 1.0]);
        // z_1 > 0 while w_1 = 1 + 2 z_1 > 0: complementarity broken.
        let z = [1.0, 1e-3];
        let w = p.w_of(&z);
        assert!(!accepts(&p, &z, &w, 1e-9));
        assert!(backward_error(&p, &z, &w) > 0.9);
        // A negative z is never accepted.
        let z = [1.0, -1e-300];
        assert!(!accepts(&p, &z, &p.w_of(&z), 1.0));
        // Snapping the unreached zero repairs it.
        let (zs, _) = snap(&p, &[1.0, 1e-16], None, 1e-9).unwrap();
        assert_eq!(zs, vec![1.0, 0.0]);
        // A caller that has judged z already gets the same repair without the repeated check.
        assert_eq!(snap_rejected(&p, &[1.0, 1e-16], None, 1e-9), snap(&p, &[1.0, 1e-16], None, 1e-9));
        assert_eq!(snap_rejected(&p, &[1.0, 1e-3], None, 1e-9), None);
    }

    #[test]
    fn the_rule_ignores_row_scaling() {
        let m = vec![4.0, 1.0, 1.0, 3.0];
        let q = vec![-1.0, -1.0 + 1e-7];
        let z = [2.0 / 11.0, 3.0 / 11.0];
        let p = lcp(m.clone(), q.clone());
        let eta = backward_error(&p, &z, &p.w_of(&z));
        // Rows by 2^10 and 2^-20.
        let r = [1024.0, 2f64.powi(-20)];
        let ps = lcp((0..4).map(|k| r[k / 2] * m[k]).collect(), vec![r[0] * q[0], r[1] * q[1]]);
        assert_eq!(backward_error(&ps, &z, &ps.w_of(&z)), eta);
        assert!(eta > 1e-9 && eta < 1e-6);
    }

    #[test]
    fn the_largest_magnitude_is_the_last_of_max_by() {
        let rows: [&[f64]; 6] = [
            &[1.0, -3.0, 2.0, 3.0, -0.5, 0.0, 1e-300],
            &[-0.0, 0.0, 0.0],
            &[f64::NAN, -5.0, f64::INFINITY, -f64::NAN],
            &[2.0],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 5.0, -5.0, 4.0, 3.0],
            &[],
        ];
        for row in rows {
            for i in 0..row.len() + 1 {
                let plain = (0..row.len()).filter(|&j| j != i).max_by(|&a, &b| row[a].abs().total_cmp(&row[b].abs()));
                assert_eq!(last_largest_magnitude(row, i), plain, "{row:?} without {i}");
            }
        }
    }

    #[test]
    fn round_off_entries_do_not_set_a_row_scale() {
        // Row 0 couples to z_1 only through a 1e-16 entry (0 for the exact
        // data): w_0 = −1e-12 is 100 % of Σ|M_0j| z_j, but 1e-16 of the row's
        // largest entry times Σ z, which the round-off floor admits.
        let p = lcp(vec![1.0, 1e-16, 1e-16, 1.0], vec![-1e-12 - 1e-16 * 1e4, -1e4]);
        let z = [0.0, 1e4];
        let w = p.w_of(&z);
        assert!(w[0] < 0.0 && backward_error(&p, &z, &w) < 1e-9);
    }
}
