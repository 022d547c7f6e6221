//! Lemke's method in exact integer arithmetic: the last rung of the ladder.
//!
//! Every finite `f64` is a dyadic rational, so the LCP of the floats given has
//! an exact meaning, and Lemke's method run on it exactly never meets
//! round-off: on a P-matrix it cannot ray-terminate, and the lexicographic
//! ratio test (columns of the basis inverse) cannot cycle. Rows are scaled by
//! powers of two (exact) to integers, the tableau `[I | −M | −d | q]` is kept
//! fraction-free (integer pivoting as in lrs: every entry is a minor, each
//! update divides exactly by the previous pivot), and the answer is rounded
//! to the nearest `f64` once, at the end. Ill-conditioned P-matrices (permuted
//! triangular ones with cond ≥ 1e15) on which floating-point pivoting ends on
//! false rays are solved this way. The cost grows with the bits of the
//! minors (≈ n times an entry's), so the rung runs only up to [`MAX_N`], and
//! gives up (as at the pivot limit) once its arithmetic passes [`WORK_BUDGET`]
//! (about 0.25 s): at n = 48 a pivot is 4,704 big-integer operations, and a
//! fuzzed world whose steps each reached the rung (minors of up to 9,000 bits)
//! took 2 s for one step without it.

use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

use crate::certify::{ratio_to_f64, Dyadic};
use crate::problem::Lcp;

/// Largest problem the exact rung is tried on (a failure path: tens of ms at n = 40).
pub(crate) const MAX_N: usize = 48;

/// What the rung may spend, in limb products: Σ over pivots of
/// `n·(2n + 2)·(OP_COST + limbs²)`, `limbs` the 64-bit words of the current
/// minor. Fitted to release runs here (a big-integer operation costs ~1.4 µs
/// plus ~0.55 ns per limb product), the budget is about 0.25 s; the
/// ill-conditioned P-matrices the rung exists for (n = 20, cond ≥ 1e15,
/// minors of ~1,150 bits, 63 pivots) use a third of it.
const WORK_BUDGET: f64 = 4.5e8;
/// A big-integer operation's fixed cost (allocation, dispatch) in limb products.
const OP_COST: f64 = 2560.0;

/// How an exact run ended.
pub(crate) enum ExactEnd {
    /// `z` (rounded to nearest) and the basic `z_j`.
    Solved(Vec<f64>, Vec<bool>),
    /// A secondary ray, exact (not a round-off artefact).
    Ray,
    /// The pivot limit or the work budget.
    Limit,
}

/// The fraction-free tableau: `rows[i]` holds `2n + 2` integers (columns
/// `w_0..w_{n-1}`, `z_0..z_{n-1}`, `z0`, right side), each the true entry
/// times `det > 0`; `basic[i]` is the variable of row `i`.
struct Tableau {
    n: usize,
    rows: Vec<Vec<BigInt>>,
    det: BigInt,
    basic: Vec<usize>,
}

impl Tableau {
    /// `w − M z − d z0 = q` with each row times a power of two that makes it
    /// integral (`d = 1` before scaling), basis `w`.
    fn new(lcp: &Lcp) -> Tableau {
        let n = lcp.n();
        let rows = (0..n)
            .map(|i| {
                let mut entries: Vec<Dyadic> = vec![Dyadic::of(0.0); 2 * n + 2];
                entries[i] = Dyadic::of(1.0);
                for j in 0..n {
                    entries[n + j] = Dyadic::of(-lcp.at(i, j));
                }
                entries[2 * n] = Dyadic::of(-1.0);
                entries[2 * n + 1] = Dyadic::of(lcp.q()[i]);
                let emin = entries.iter().filter(|d| !d.is_zero()).map(|d| d.e).min().unwrap_or(0);
                entries
                    .iter()
                    .map(|d| if d.is_zero() { BigInt::zero() } else { BigInt::from(d.m) << (d.e - emin) as usize })
                    .collect()
            })
            .collect();
        Tableau { n, rows, det: BigInt::from(1), basic: (0..n).collect() }
    }

    fn rhs(&self, i: usize) -> &BigInt {
        &self.rows[i][2 * self.n + 1]
    }

    /// Integer pivot on row `r`, column `c`; keeps `det > 0` by negating every row.
    fn pivot(&mut self, r: usize, c: usize) {
        let prc = self.rows[r][c].clone();
        let pivot_row = std::mem::take(&mut self.rows[r]);
        for (i, row) in self.rows.iter_mut().enumerate() {
            if i == r {
                continue;
            }
            let aic = row[c].clone();
            for (v, arj) in row.iter_mut().zip(&pivot_row) {
                let mut t = &prc * &*v;
                if !aic.is_zero() && !arj.is_zero() {
                    t -= &aic * arj;
                }
                *v = t / &self.det;
            }
        }
        self.rows[r] = pivot_row;
        self.basic[r] = c;
        if prc.is_negative() {
            self.rows.iter_mut().flatten().for_each(|v| *v = -std::mem::take(v));
            self.det = -prc;
        } else {
            self.det = prc;
        }
    }

    /// Compares rows `a`, `b` lexicographically by `(rhs, w-columns) / entry
    /// in column c`. Both entries have one sign, so their product is positive
    /// and cross-multiplying keeps the order.
    fn lex_cmp(&self, a: usize, b: usize, c: usize) -> Ordering {
        let (ra, rb) = (&self.rows[a], &self.rows[b]);
        let (xa, xb) = (&ra[c], &rb[c]);
        std::iter::once(2 * self.n + 1)
            .chain(0..self.n)
            .map(|k| (&ra[k] * xb).cmp(&(&rb[k] * xa)))
            .find(|o| o.is_ne())
            .unwrap_or(Ordering::Equal)
    }
}

/// Lemke's method on `lcp` in exact arithmetic, at most `max_pivots` pivots;
/// returns how it ended and the pivots taken.
pub(crate) fn solve(lcp: &Lcp, max_pivots: usize) -> (ExactEnd, usize) {
    let n = lcp.n();
    let mut t = Tableau::new(lcp);
    let z0 = 2 * n;
    // z = 0 solves it when q ≥ 0.
    if (0..n).all(|i| !t.rhs(i).is_negative()) {
        return (ExactEnd::Solved(vec![0.0; n], vec![false; n]), 0);
    }
    // z0 enters where q_i/d_i is lexicographically smallest (entries of z0's column are < 0).
    if max_pivots == 0 {
        return (ExactEnd::Limit, 0);
    }
    let r = (1..n).fold(0, |best, i| if t.lex_cmp(i, best, z0) == Ordering::Greater { i } else { best });
    t.pivot(r, z0);
    let mut entering = n + r; // the complement of the w_r that left
    let per_op = (n * (2 * n + 2)) as f64;
    let mut work = 0.0;
    // `pivots` made so far (z0's entry is the first); the loop's pivot is number `pivots + 1`.
    for pivots in 1..max_pivots {
        // Ratio test: rows whose basic variable decreases, lexicographic minimum, z0 first on ties.
        let mut leave: Option<usize> = None;
        for i in (0..n).filter(|&i| t.rows[i][entering].is_positive()) {
            leave = Some(match leave {
                None => i,
                Some(b) => match t.lex_cmp(i, b, entering) {
                    Ordering::Less => i,
                    _ => b,
                },
            });
        }
        let Some(r) = leave else { return (ExactEnd::Ray, pivots) };
        // z0 leaves as soon as its ratio ties the minimum.
        let z0_row = (0..n).find(|&i| t.basic[i] == z0);
        let r = match z0_row {
            Some(k) if t.rows[k][entering].is_positive() && ratio_ties(&t, k, r, entering) => k,
            _ => r,
        };
        let left = t.basic[r];
        let limbs = (t.det.bits() / 64 + 1) as f64;
        work += per_op * (OP_COST + limbs * limbs);
        if work > WORK_BUDGET {
            return (ExactEnd::Limit, pivots);
        }
        t.pivot(r, entering);
        if left == z0 {
            return (answer(&t), pivots + 1);
        }
        entering = if left < n { left + n } else { left - n };
    }
    (ExactEnd::Limit, max_pivots)
}

/// Whether rows `a` and `b` have the same ratio `rhs / entry` in column `c`.
fn ratio_ties(t: &Tableau, a: usize, b: usize, c: usize) -> bool {
    let (ra, rb) = (&t.rows[a], &t.rows[b]);
    let k = 2 * t.n + 1;
    &ra[k] * &rb[c] == &rb[k] * &ra[c]
}

/// The basic `z_j = rhs / det`, rounded to nearest.
fn answer(t: &Tableau) -> ExactEnd {
    let n = t.n;
    let (mut z, mut mask) = (vec![0.0; n], vec![false; n]);
    for (i, &v) in t.basic.iter().enumerate() {
        if (n..2 * n).contains(&v) {
            z[v - n] = ratio_to_f64(t.rhs(i), &t.det, 0).max(0.0);
            mask[v - n] = true;
        }
    }
    ExactEnd::Solved(z, mask)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit lower-triangular P-matrix whose entries span ±2^900: exact
    /// Lemke would solve it, but its minors grow by hundreds of bits a pivot;
    /// the rung stops at its work budget (found by the `world` fuzz target,
    /// where such a step took 1.9 s) instead of stalling the caller.
    #[test]
    fn gives_up_past_its_work_budget() {
        let n = 40;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            m[i * n + i] = 1.0;
            for j in 0..i {
                let r = next();
                let e = (r % 1801) as i32 - 900;
                m[i * n + j] = if r & (1 << 40) == 0 { 1.0 } else { -1.0 } * 2f64.powi(e);
            }
        }
        let lcp = Lcp::new(m, vec![-1.0; n]).unwrap();
        let (end, pivots) = solve(&lcp, 10 * n);
        assert!(matches!(end, ExactEnd::Limit), "expected the work budget to end the rung");
        assert!(pivots < 10 * n, "stopped by the budget, not the pivot limit ({pivots} pivots)");
        // The same structure with entries of a few bits is solved exactly.
        let small = Lcp::from_fn(
            n,
            |i, j| {
                if i == j {
                    1.0
                } else if j < i {
                    0.5
                } else {
                    0.0
                }
            },
            vec![-1.0; n],
        )
        .unwrap();
        assert!(matches!(solve(&small, 10 * n).0, ExactEnd::Solved(..)));
    }
}
