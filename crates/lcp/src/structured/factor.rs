//! The Lemke basis of a structured LCP, factored in the augmented space.
//!
//! Lemke works on `I w − M z − d z0 = q`. With `M = G H + K` and `u = H z`
//! (`p` unknowns more), the same system reads
//!
//! ```text
//!   [ I_W  −K_S  −d  −G ] [w; z_S; z0; u]   [q]
//!   [  0    H_S   0  −I ]                 = [0]
//! ```
//!
//! whose matrix (`n + p` square: one column per basic variable, the `p`
//! columns of `u` fixed) is as sparse as `G`, `H` and `K`, and regular exactly
//! when the basis is (eliminating `u` leaves `[I_W, −M_S, −d]`). It is factored
//! by a sparse LU ([`super::lu`]: COLAMD ordering, partial pivoting); each pivot then
//! replaces one column, kept as an eta vector (product form of the inverse),
//! until the next refactorization. A solve costs the LU's nonzeros plus the
//! etas' — never `n²`: nothing here is dense but vectors. The etas keep only
//! the `n` basic positions, not the `p` rows of `u`: a pivot reads only
//! those, and `u = H_S x_S − a_u` follows from them where a whole solve is
//! needed. (On the 1,000-cube pour's structured LCPs of steps 1,360–1,363,
//! n up to 9,040 and `p ≈ n/5`, that streamed 24 % fewer eta entries,
//! 6.20G → 4.74G, for the same pivots on each LCP of n ≥ 4,000.)
//!
//! Why the product form and not an LU update (both are in this
//! file's history): `B⁻¹ a` of a heap's basis is dense, and so
//! is the fresh solve `B₀⁻¹ a`, so every update scheme streams a dense
//! vector per update and per solve, and the product form's is the cheapest
//! stream (contiguous, vectorized). Measured solve-only on a 52-cube heap's
//! LCP, n = 1,440 (318.5M instructions with the eta file): a Forrest–Tomlin
//! update of `U` 538.8M (its spikes are short, but they reach all of `U`,
//! whose solves became dense passes at ten instructions an entry, against
//! the eta file's one), and a block-LU (Schur complement, the idea of
//! Siconos' `lcp_pivot_lumod`) 340.7M, worse again as the interval grows
//! (n = 3,030: 1,404M at 100 updates, 2,043M at 200). The interval stays 100:
//! 60 and 150 cost 18 % and 2 % more at n = 1,440 after the cheaper ordering.

use super::lu::{Csc, Order, SparseLu};
use super::operator::StructuredLcp;
use std::cell::RefCell;

/// One column replacement: position `r` took a column whose solve was `y`
/// (`piv = y_r`; `y` over the `n` positions); the other entries of `y` are
/// `Etas::idx`/`Etas::val` in `start..end`, or, when `dense`, all of `y` in
/// `Etas::val[start..end]` with 0 at `r`.
struct Eta {
    r: usize,
    piv: f64,
    start: usize,
    end: usize,
    dense: bool,
    /// Start of its indices in `Etas::idx` (when sparse).
    istart: usize,
}

/// The eta file: the column updates since the last factorization, their
/// entries in two flat buffers kept across refactorizations.
///
/// A basis inverse of a connected heap is dense: on a 52-cube heap
/// (n = 1,440) every `y` had all its entries nonzero. Such an eta is stored
/// dense, which halves its bytes and lets its update vectorize; sparse ones
/// keep their indices.
#[derive(Default)]
struct Etas {
    heads: Vec<Eta>,
    idx: Vec<usize>,
    val: Vec<f64>,
}

impl Etas {
    fn clear(&mut self) {
        self.heads.clear();
        self.idx.clear();
        self.val.clear();
    }

    /// Appends position `r`'s update from `y`.
    fn push(&mut self, r: usize, y: &[f64]) {
        let nnz = y.iter().filter(|&&v| v != 0.0).count();
        let (start, istart) = (self.val.len(), self.idx.len());
        let dense = 2 * nnz >= y.len();
        if dense {
            self.val.extend_from_slice(y);
            self.val[start + r] = 0.0;
        } else {
            for (i, &v) in y.iter().enumerate() {
                if i != r && v != 0.0 {
                    self.idx.push(i);
                    self.val.push(v);
                }
            }
        }
        self.heads.push(Eta { r, piv: y[r], start, end: self.val.len(), dense, istart });
    }

    /// `y ← E_k⁻¹ ⋯ E_1⁻¹ y`.
    fn apply(&self, y: &mut [f64]) {
        self.apply_from(0, y);
    }

    /// `y ← E_k⁻¹ ⋯ E_{from+1}⁻¹ y`: the updates after the first `from`,
    /// so that `apply_from(j, ·)` after `apply_from(0, ·)` with `j` updates
    /// is [`Etas::apply`] with all of them, to the bit (the same operations
    /// in the same order).
    #[inline(never)]
    fn apply_from(&self, from: usize, y: &mut [f64]) {
        for e in &self.heads[from.min(self.heads.len())..] {
            let yr = y[e.r] / e.piv;
            let vals = &self.val[e.start..e.end];
            if yr != 0.0 {
                if e.dense {
                    for (yi, &v) in y.iter_mut().zip(vals) {
                        *yi -= v * yr;
                    }
                } else {
                    for (&i, &v) in self.idx[e.istart..e.istart + vals.len()].iter().zip(vals) {
                        y[i] -= v * yr;
                    }
                }
            }
            y[e.r] = yr;
        }
    }
}

/// A kept column order is dropped when its factors' fill (nonzeros of
/// `L + U` over those of the matrix) exceeds this multiple of the fill of
/// the last fresh order. (1.4 cost 8 % more instructions on a 160-cube
/// heap's LCP, n = 5,360; 1.1 cost 17 % more on a 52-cube one.)
pub(super) const FILL_SLACK: f64 = 1.2;

/// A refactorization tries the kept column order only when fewer than this
/// many positions held a basic slack at the last fresh order and hold
/// another variable now (a unit column become a `K`/`H` one); with more,
/// COLAMD orders afresh at once. On a 45-cube pour's structured LCPs (steps
/// 0–2,200) the kept order was tried at all 816 in-run refactorizations and
/// its fill kept at 184; the other 632 factored twice. By this count: under
/// 10, 106 of 107 tries kept (rearranged by `SparseLu::move_last`); 10–40,
/// 155 of 247; 40 and more, 132 of 516.
const KEPT_MAX_GROWN: usize = 10;

/// The solves `B⁻¹ a_v` of columns solved since the last factorization
/// `B_f`, kept for [`Basis::solve_column`] with the number of eta updates
/// they went through: the lexicographic rule solves the same columns of its
/// reference basis at tie after tie (on a 45-cube pour's structured LCPs,
/// 37,022 of its 60,647 solves were of a column already solved on the same
/// factors), and a kept solve needs only the updates made since.
#[derive(Default)]
struct SolvedColumns {
    /// Variable → start of its solve in `val`, and the updates applied to it.
    at: std::collections::HashMap<usize, (usize, usize)>,
    val: Vec<f64>,
}

/// Entries of [`SolvedColumns`] at most (16 MB); columns beyond are solved
/// each time.
const SOLVED_MAX: usize = 1 << 21;

/// Variables are numbered `w_i → i`, `z_j → n + j`, `z0 → 2n`.
pub(crate) const NONBASIC: usize = usize::MAX;

/// A basis: which variable sits at each of the `n` positions, its value, and
/// the factorization of the augmented matrix.
pub(crate) struct Basis<'a> {
    op: &'a StructuredLcp,
    d: &'a [f64],
    n: usize,
    p: usize,
    /// Variable at each position (`n`).
    pub(crate) var: Vec<usize>,
    /// Position of each variable (`2n + 1`), [`NONBASIC`] when nonbasic.
    pub(crate) pos: Vec<usize>,
    /// Value of each position.
    pub(crate) val: Vec<f64>,
    /// Variable at each position when the basis was built: the lexicographic
    /// rule's reference (see `pivot::lex_break`).
    pub(crate) init: Vec<usize>,
    lu: SparseLu,
    etas: Etas,
    /// The augmented matrix of the last factorization (its buffers reused).
    a: Csc,
    /// Fill `nnz(L + U) / nnz(A)` of the last factorization in a fresh order.
    fill_fresh: f64,
    /// Variable at each position at the last factorization in a fresh order.
    fresh_var: Vec<usize>,
    solved: RefCell<SolvedColumns>,
}

impl<'a> Basis<'a> {
    /// The all-slack basis (`w = q`), factored.
    pub(crate) fn slack(op: &'a StructuredLcp, d: &'a [f64]) -> Option<Self> {
        let n = op.n();
        let mut pos = vec![NONBASIC; 2 * n + 1];
        (0..n).for_each(|i| pos[i] = i);
        let mut b = Basis {
            op,
            d,
            n,
            p: op.p(),
            var: (0..n).collect(),
            pos,
            val: vec![0.0; n],
            init: (0..n).collect(),
            lu: SparseLu::new(n + op.p()),
            etas: Etas::default(),
            a: Csc::default(),
            fill_fresh: 0.0,
            fresh_var: Vec::new(),
            solved: RefCell::default(),
        };
        b.refactor().then_some(b)
    }

    /// The complementary basis `{z_j : j ∈ α} ∪ {w_i : i ∉ α}`, factored,
    /// repaired until it factors: a position whose column the sparse LU finds
    /// structurally dependent on the columns eliminated before it takes its
    /// complement's column (`z_j ↔ w_j`), up to `tries` times; `None` if it is
    /// still singular. Its covering vector is empty until
    /// [`Basis::set_cover`] (no column of a complementary basis is `z0`'s),
    /// so that the cover can be that of the repaired basis. (Repairs were
    /// once made on a copy and the repaired basis factored again: two more
    /// factorizations per repair.) A repaired basis is factored in the
    /// column order its singular predecessor was, the flipped column last
    /// ([`Basis::refactor_repaired`]): no COLAMD per repair.
    pub(crate) fn complementary(op: &'a StructuredLcp, alpha: &[usize], tries: usize) -> Option<Self> {
        let n = op.n();
        let mut b = Self::complementary_unfactored(op, alpha);
        let mut ok = b.refactor();
        for _ in 0..tries {
            if ok {
                return Some(b);
            }
            let c = b.lu.dependent.filter(|&c| c < n)?;
            let flipped = if b.var[c] == c { n + c } else { c };
            b.pos[b.var[c]] = NONBASIC;
            (b.var[c], b.init[c], b.pos[flipped]) = (flipped, flipped, c);
            ok = b.refactor_repaired(c);
        }
        ok.then_some(b)
    }

    /// Refactors after the basis was found singular and position `c`
    /// flipped: in the column order of that attempt with `c` last, taken as
    /// the fresh order from then on; [`Basis::refactor`] if its values are
    /// not finite. `false` when it is singular (the next dependent column
    /// found) or its values are not finite.
    fn refactor_repaired(&mut self, c: usize) -> bool {
        self.build_matrix();
        let mut moved = vec![false; self.n + self.p];
        moved[c] = true;
        self.lu.move_last(&self.a, &moved);
        if !self.lu.factor(&self.a, Order::Kept) {
            return false;
        }
        self.fresh_var.clone_from(&self.var);
        self.fill_fresh = self.lu.fill(&self.a);
        self.values() || self.refactor()
    }

    /// [`Basis::complementary`] before its factorization.
    fn complementary_unfactored(op: &'a StructuredLcp, alpha: &[usize]) -> Self {
        let n = op.n();
        let mut pos = vec![NONBASIC; 2 * n + 1];
        let mut var: Vec<usize> = (0..n).collect();
        for &j in alpha {
            var[j] = n + j;
        }
        var.iter().enumerate().for_each(|(c, &v)| pos[v] = c);
        let init = var.clone();
        Basis {
            op,
            d: &[],
            n,
            p: op.p(),
            var,
            pos,
            val: vec![0.0; n],
            init,
            lu: SparseLu::new(n + op.p()),
            etas: Etas::default(),
            a: Csc::default(),
            fill_fresh: 0.0,
            fresh_var: Vec::new(),
            solved: RefCell::default(),
        }
    }

    /// The covering vector, `z0`'s column `−d` (see [`Basis::complementary`]).
    pub(crate) fn set_cover(&mut self, d: &'a [f64]) {
        self.d = d;
    }

    /// The `z_j` basic, as indices `j`.
    pub(crate) fn alpha(&self) -> Vec<usize> {
        (0..self.n).filter(|&j| self.pos[self.n + j] != NONBASIC).collect()
    }

    /// Numeric factorizations and fresh column orders (COLAMD) this basis made.
    pub(crate) fn factor_counts(&self) -> (usize, usize) {
        self.lu.counts
    }

    /// Column updates since the last refactorization.
    pub(crate) fn updates(&self) -> usize {
        self.etas.heads.len()
    }

    /// Calls `f(row, value)` for each entry of variable `v`'s augmented column.
    fn column_entries(&self, v: usize, mut f: impl FnMut(usize, f64)) {
        let n = self.n;
        if v < n {
            f(v, 1.0);
        } else if v < 2 * n {
            let j = v - n;
            self.op.k_cols.iter(j).for_each(|(i, k)| f(i, -k));
            self.op.h_cols.iter(j).for_each(|(k, h)| f(n + k, h));
        } else {
            self.d.iter().enumerate().for_each(|(i, &di)| f(i, -di));
        }
    }

    /// Variable `v`'s augmented column, dense (`n + p`), into `out`.
    pub(crate) fn column_into(&self, v: usize, out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.n + self.p, 0.0);
        self.column_entries(v, |i, a| out[i] += a);
    }

    /// `y ← B⁻¹ y` (augmented).
    pub(crate) fn ftran(&self, y: &mut [f64]) {
        if self.etas.heads.is_empty() {
            self.lu.solve_in_place(y);
            return;
        }
        let a_u = y[self.n..].to_vec();
        self.ftran_basic(y);
        self.complete_u(y, &a_u);
    }

    /// `y ← B⁻¹ y` in the `n` basic positions; the `p` rows of `u` are left
    /// as they come (what the pivots read: the ratio test, the eta file, the
    /// lexicographic rule). The eta file holds only those positions: an eta's
    /// pivot row is a position, so `u`'s rows never feed back into them, and
    /// `u = H_S x_S − a_u` follows from them ([`Basis::complete_u`]).
    pub(crate) fn ftran_basic(&self, y: &mut [f64]) {
        self.lu.solve_in_place(y);
        self.etas.apply(&mut y[..self.n]);
    }

    /// The `u` rows of the augmented `x` from its basic positions: the
    /// second block row of `B x = a` reads `H_S x_S − u = a_u`.
    fn complete_u(&self, x: &mut [f64], a_u: &[f64]) {
        let n = self.n;
        let (xs, u) = x.split_at_mut(n);
        u.iter_mut().zip(a_u).for_each(|(u, a)| *u = -a);
        for (c, &v) in self.var.iter().enumerate() {
            if (n..2 * n).contains(&v) && xs[c] != 0.0 {
                self.op.h_cols.iter(v - n).for_each(|(k, h)| u[k] += h * xs[c]);
            }
        }
    }

    /// `out ← B⁻¹ a_v` in the `n` basic positions, the same to the bit as
    /// [`Basis::column_into`] then [`Basis::ftran_basic`]: the solve of `a_v`
    /// is kept until the next factorization, within [`SOLVED_MAX`], and
    /// brought up to date by the eta updates made since it was last asked for.
    pub(crate) fn solve_column(&self, v: usize, out: &mut Vec<f64>) {
        self.solve_column_keeping(v, out, true);
    }

    /// [`Basis::solve_column`], the solve kept only if `keep` (an entering
    /// column: solved once, but read from the kept ones when the
    /// lexicographic rule solved it on the same factors).
    pub(crate) fn solve_column_keeping(&self, v: usize, out: &mut Vec<f64>, keep: bool) {
        let (dim, n, updates) = (self.n + self.p, self.n, self.etas.heads.len());
        let mut solved = self.solved.borrow_mut();
        let solved = &mut *solved;
        if let Some((k, applied)) = solved.at.get_mut(&v) {
            let kept = &mut solved.val[*k..*k + dim];
            self.etas.apply_from(*applied, &mut kept[..n]);
            *applied = updates;
            out.clear();
            out.extend_from_slice(kept);
            return;
        }
        self.column_into(v, out);
        self.ftran_basic(out);
        if keep && solved.val.len() + dim <= SOLVED_MAX {
            solved.at.insert(v, (solved.val.len(), updates));
            solved.val.extend_from_slice(out);
        }
    }

    /// `y ← y + B⁻¹ (a_v − B y)`: `y = B⁻¹ a_v` ([`Basis::ftran_basic`]'s
    /// positions; its `u` rows are completed here) refined once on the
    /// current factors; `work` is scratch.
    pub(crate) fn refine(&self, v: usize, y: &mut [f64], work: &mut Vec<f64>) {
        self.column_into(v, work);
        self.complete_u(y, &work[self.n..]);
        let mut by = vec![0.0; y.len()];
        self.times(y, &mut by);
        work.iter_mut().zip(&by).for_each(|(r, b)| *r -= b);
        self.ftran(work);
        y.iter_mut().zip(work.iter()).for_each(|(y, r)| *y += r);
    }

    /// Variable `e` enters at position `r` with value `theta`, `y = B⁻¹ a_e`.
    /// `false`, and nothing changed, when the pivot `y_r` is 0 or not
    /// finite: the new basis would be singular.
    pub(crate) fn pivot(&mut self, e: usize, r: usize, y: &[f64], theta: f64) -> bool {
        if y[r] == 0.0 || !y[r].is_finite() {
            return false;
        }
        for (v, yi) in self.val.iter_mut().zip(y) {
            *v -= theta * yi;
        }
        self.val[r] = theta;
        self.pos[self.var[r]] = NONBASIC;
        self.var[r] = e;
        self.pos[e] = r;
        self.etas.push(r, &y[..self.n]);
        true
    }

    /// `B x` (augmented) for the augmented vector `x`, into `out`.
    fn times(&self, x: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (c, &v) in self.var.iter().enumerate() {
            if x[c] != 0.0 {
                self.column_entries(v, |i, a| out[i] += a * x[c]);
            }
        }
        for k in 0..self.p {
            let xu = x[self.n + k];
            self.op.g_cols.iter(k).for_each(|(i, g)| out[i] -= g * xu);
            out[self.n + k] -= xu;
        }
    }

    /// Refactors from scratch and recomputes the values from `q` (with one
    /// step of iterative refinement). `false` when the basis is singular or
    /// its values are not finite.
    ///
    /// The column order of the last fresh factorization is kept, its moved
    /// columns last ([`SparseLu::move_last`]), when fewer than
    /// [`KEPT_MAX_GROWN`] slacks left the basis since, and while the fill it
    /// gives stays within [`FILL_SLACK`] of the fill it gave then; otherwise,
    /// or if the basis is singular in it, COLAMD orders afresh.
    pub(crate) fn refactor(&mut self) -> bool {
        self.build_matrix();
        let nnz_a = self.a.idx.len().max(1) as f64;
        let kept = self.fill_fresh > 0.0 && self.grown_since_fresh() < KEPT_MAX_GROWN && {
            let moved: Vec<bool> =
                (0..self.n + self.p).map(|c| c < self.n && self.var[c] != self.fresh_var[c]).collect();
            self.lu.move_last(&self.a, &moved);
            self.lu.factor(&self.a, Order::Kept) && (self.lu.nnz() as f64) <= FILL_SLACK * self.fill_fresh * nnz_a
        };
        if !kept && !self.factor_fresh() {
            return false;
        }
        // Values not finite in a kept order (a pivot that partial pivoting
        // could only take at 0 there): the same from a fresh order.
        self.values() || (kept && self.factor_fresh() && self.values())
    }

    /// The augmented matrix of the basis into `self.a`, and the eta file emptied.
    fn build_matrix(&mut self) {
        let (n, p) = (self.n, self.p);
        // Columns in order, rows ascending: basic variables' (w: a unit; z_j:
        // K's rows < n, then H's at n + k; z0: −d), then u's (G's, −1 at n + k).
        let mut a = std::mem::take(&mut self.a);
        a.clear();
        for &v in &self.var {
            self.column_entries(v, |i, x| {
                a.idx.push(i);
                a.val.push(x);
            });
            a.end_column();
        }
        for k in 0..p {
            for (i, g) in self.op.g_cols.iter(k) {
                a.idx.push(i);
                a.val.push(-g);
            }
            a.idx.push(n + k);
            a.val.push(-1.0);
            a.end_column();
        }
        self.a = a;
        self.etas.clear();
        let solved = self.solved.get_mut();
        solved.at.clear();
        solved.val.clear();
    }

    /// Positions that held a basic slack at the last fresh order and hold
    /// another variable now.
    fn grown_since_fresh(&self) -> usize {
        let n = self.n;
        self.var.iter().zip(&self.fresh_var).filter(|&(&v, &f)| f < n && v >= n).count()
    }

    /// Factors `self.a` in a fresh order and records its fill and basis.
    fn factor_fresh(&mut self) -> bool {
        self.fresh_var.clone_from(&self.var);
        let ok = self.lu.factor(&self.a, Order::Fresh);
        self.fill_fresh = if ok { self.lu.fill(&self.a) } else { 0.0 };
        ok
    }

    /// The basic values from `q` by the current factorization, with one step
    /// of iterative refinement; `false` if they are not finite.
    pub(crate) fn values(&mut self) -> bool {
        let (n, p) = (self.n, self.p);
        let mut rhs = self.op.q().to_vec();
        rhs.resize(n + p, 0.0);
        let mut x = rhs.clone();
        self.ftran(&mut x);
        // One refinement step: x += B⁻¹ (rhs − B x).
        let mut r = vec![0.0; n + p];
        self.times(&x, &mut r);
        r.iter_mut().zip(&rhs).for_each(|(r, b)| *r = b - *r);
        self.ftran(&mut r);
        x.iter_mut().zip(&r).for_each(|(x, r)| *x += r);
        if !x.iter().all(|v| v.is_finite()) {
            return false;
        }
        self.val.copy_from_slice(&x[..n]);
        true
    }

    /// `z` (length n) from the basic values; returns `z0`.
    pub(crate) fn z_into(&self, z: &mut Vec<f64>) -> f64 {
        let n = self.n;
        z.clear();
        z.resize(n, 0.0);
        let mut z0 = 0.0;
        for (c, &v) in self.var.iter().enumerate() {
            if (n..2 * n).contains(&v) {
                z[v - n] = self.val[c];
            } else if v == 2 * n {
                z0 = self.val[c];
            }
        }
        z0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structured::Entry;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random `M = G H + K`: each row touches `touch` of `p` dofs, `K` sparse.
    fn random_op(n: usize, p: usize, touch: usize, seed: u64) -> StructuredLcp {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut g, mut h, mut k): (Vec<Entry>, Vec<Entry>, Vec<Entry>) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            for _ in 0..touch {
                let d = rng.random_range(0..p);
                g.push((i, d, rng.random_range(-1.0..1.0)));
                h.push((d, i, rng.random_range(-1.0..1.0)));
            }
            k.push((i, rng.random_range(0..n), rng.random_range(-1.0..1.0)));
        }
        let q = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        StructuredLcp::new(p, &g, &h, &k, q).unwrap()
    }

    /// `B x − b` in the max norm over `‖b‖∞ + ‖x‖∞`.
    fn residual(b: &Basis, x: &[f64], rhs: &[f64]) -> f64 {
        let mut bx = vec![0.0; x.len()];
        b.times(x, &mut bx);
        let r = bx.iter().zip(rhs).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        r / (rhs.iter().chain(x).fold(0.0f64, |a, v| a.max(v.abs())))
    }

    /// After `k` column updates the solves equal those of a fresh
    /// factorization of the same basis, to round-off, and solve `B x = b`.
    #[test]
    fn solves_after_updates_equal_fresh_solves() {
        for seed in 0..12 {
            let (n, p) = (60, 24);
            let op = random_op(n, p, 3, seed);
            let d = vec![1.0; n];
            let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
            let mut b = Basis::slack(&op, &d).unwrap();
            let mut y = Vec::new();
            let mut done = 0;
            for _ in 0..200 {
                if done == 40 {
                    break;
                }
                // A nonbasic variable enters where its solve is largest.
                let e = rng.random_range(0..2 * n + 1);
                if b.pos[e] != NONBASIC {
                    continue;
                }
                b.column_into(e, &mut y);
                b.ftran(&mut y);
                let r = (0..n).max_by(|&i, &j| y[i].abs().total_cmp(&y[j].abs())).unwrap();
                if y[r].abs() < 1e-3 {
                    continue;
                }
                assert!(b.pivot(e, r, &y, 0.0));
                done += 1;
            }
            assert_eq!(b.updates(), done, "seed {seed}");
            let rhs: Vec<f64> = (0..n + p).map(|_| rng.random_range(-1.0..1.0)).collect();
            let mut updated = rhs.clone();
            b.ftran(&mut updated);
            assert!(residual(&b, &updated, &rhs) < 1e-10, "seed {seed}: {:e}", residual(&b, &updated, &rhs));
            // The positions alone (`u`'s rows completed by `ftran` only) are the same.
            let mut basic = rhs.clone();
            b.ftran_basic(&mut basic);
            assert_eq!(basic[..n], updated[..n], "seed {seed}");
            assert!(b.refactor(), "seed {seed}: regular");
            assert_eq!(b.updates(), 0);
            let mut fresh = rhs.clone();
            b.ftran(&mut fresh);
            let scale = fresh.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            let gap = updated.iter().zip(&fresh).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
            assert!(gap <= 1e-9 * scale, "seed {seed}: {gap:e}");
        }
    }

    /// `B x = rhs` solved on `b`'s factors, then on a fresh order's: the
    /// first's backward error ([`residual`]), the largest gap between the
    /// two, and the largest entry of the second (at least 1).
    fn against_fresh(b: &mut Basis, rhs: &[f64]) -> (f64, f64, f64) {
        let mut x = rhs.to_vec();
        b.ftran(&mut x);
        let backward = residual(b, &x, rhs);
        b.build_matrix();
        assert!(b.factor_fresh());
        let mut x_fresh = rhs.to_vec();
        b.ftran(&mut x_fresh);
        let scale = x_fresh.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        let gap = x.iter().zip(&x_fresh).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        (backward, gap, scale)
    }

    /// `k` pivots of `z` columns into slack positions, each where its solve is largest.
    fn z_pivots(b: &mut Basis, k: usize) {
        let n = b.n;
        let mut y = Vec::new();
        let mut done = 0;
        for j in 0..n {
            if done == k {
                break;
            }
            b.column_into(n + j, &mut y);
            b.ftran(&mut y);
            let r = (0..n).filter(|&i| b.var[i] < n).max_by(|&i, &c| y[i].abs().total_cmp(&y[c].abs())).unwrap();
            if y[r].abs() > 1e-3 && b.pivot(n + j, r, &y, 0.0) {
                done += 1;
            }
        }
        assert_eq!(done, k);
    }

    /// A column's solve kept on the factors is, to the bit, the solve made
    /// afresh (column, LU solve, eta file on the positions), after updates and after a refactorization.
    #[test]
    fn kept_column_solves_equal_fresh_ones_to_the_bit() {
        let op = random_op(60, 24, 3, 7);
        let (n, d) = (op.n(), vec![1.0; 60]);
        let mut b = Basis::slack(&op, &d).unwrap();
        let (mut kept, mut fresh) = (Vec::new(), Vec::new());
        for round in 0..3 {
            for v in (n..2 * n).step_by(7).chain([2 * n, 3, n + 7]) {
                b.solve_column(v, &mut kept);
                b.column_into(v, &mut fresh);
                b.ftran_basic(&mut fresh);
                assert_eq!(kept, fresh, "round {round}, variable {v}");
            }
            z_pivots(&mut b, 4);
            if round == 1 {
                assert!(b.refactor());
            }
        }
    }

    /// A refactorization after a few slacks left the basis keeps the column
    /// order (one numeric factorization, no ordering), and its solves are a
    /// fresh order's to round-off; after many, it orders afresh at once.
    #[test]
    fn few_slacks_left_keep_the_column_order_many_order_afresh() {
        for seed in 0..6 {
            let (n, p) = (80, 30);
            let op = random_op(n, p, 3, 100 + seed);
            let d = vec![1.0; n];
            for grown in [3, KEPT_MAX_GROWN + 5] {
                let mut b = Basis::slack(&op, &d).unwrap();
                z_pivots(&mut b, grown);
                let before = b.factor_counts();
                assert!(b.refactor(), "seed {seed}: regular");
                let (factored, ordered) = (b.factor_counts().0 - before.0, b.factor_counts().1 - before.1);
                if grown < KEPT_MAX_GROWN {
                    assert_eq!((factored, ordered), (1, 0), "seed {seed}: kept order");
                } else {
                    assert_eq!((factored, ordered), (1, 1), "seed {seed}: fresh order, no kept try");
                }
                let rhs: Vec<f64> = (0..n + p).map(|i| (i as f64 * 0.37).cos()).collect();
                let (backward, gap, scale) = against_fresh(&mut b, &rhs);
                assert!(backward < 1e-12, "seed {seed}: {backward:e}");
                assert!(gap <= 1e-10 * scale, "seed {seed}, {grown} grown: {gap:e}");
            }
        }
    }

    /// A structurally singular complementary basis is repaired column by
    /// column, each repair factored in the order of the attempt before it
    /// (one COLAMD in all), and the repaired basis solves `B x = b` to
    /// round-off and as a fresh order's factors do where it is regular.
    #[test]
    fn repairs_keep_the_column_order_and_solve_as_a_fresh_order() {
        let mut compared = 0;
        for seed in 0..6 {
            let (n, p) = (40, 12);
            let mut op = random_op(n, p, 2, 200 + seed);
            // z_0..z_5 have one entry each, all in row 0 (no H, K in row 0 only).
            let (_, g, mut h, mut k) = crate::structured::parts(&op);
            h.retain(|&(_, j, _)| j >= 6);
            k.retain(|&(_, j, _)| j >= 6);
            (0..6).for_each(|j| k.push((0, j, 1.0 + j as f64)));
            op = StructuredLcp::new(p, &g, &h, &k, op.q().to_vec()).unwrap();
            let alpha: Vec<usize> = (0..6).chain((10..n).step_by(3)).collect();
            let mut b = Basis::complementary(&op, &alpha, 16).expect("repaired");
            let repairs = alpha.iter().filter(|&&j| b.pos[n + j] == NONBASIC).count();
            assert!(repairs >= 5, "seed {seed}: five of z_0..z_5 flipped, {repairs} repairs");
            assert_eq!(b.factor_counts(), (repairs + 1, 1), "seed {seed}: one order for all attempts");
            let mut rhs = op.q().to_vec();
            rhs.resize(n + p, 0.0);
            let (backward, gap, scale) = against_fresh(&mut b, &rhs);
            assert!(backward < 1e-12, "seed {seed}: {backward:e}");
            // Values of 1e8 and more: numerically singular (a repair flips
            // structure only), where no two orders' solves need agree.
            if scale < 1e8 {
                assert!(gap <= 1e-10 * scale, "seed {seed}: {gap:e}");
                compared += 1;
            }
        }
        assert!(compared >= 3, "{compared} of 6 regular");
    }

    /// A pivot on a zero entry of the entering column's solve would make the
    /// basis singular: refused, the basis unchanged, and a refactorization
    /// of a singular basis says so.
    #[test]
    fn a_singular_pivot_is_refused() {
        let (n, p) = (30, 12);
        let op = random_op(n, p, 2, 5);
        let d = vec![1.0; n];
        let mut b = Basis::slack(&op, &d).unwrap();
        let mut y = Vec::new();
        // z_j's solve on the slack basis is column j of −M: sparse, zeros to pivot on.
        let (e, r) = (0..n)
            .find_map(|j| {
                b.column_into(n + j, &mut y);
                b.ftran(&mut y);
                (0..n).find(|&i| y[i] == 0.0).map(|i| (n + j, i))
            })
            .expect("a zero in some column");
        let (var, val) = (b.var.clone(), b.val.clone());
        assert!(!b.pivot(e, r, &y, 1.0));
        assert_eq!((b.var.clone(), b.val.clone(), b.updates()), (var, val, 0));
        // Two copies of the same column: singular, refused by the factorization.
        b.var[1] = b.var[0];
        assert!(!b.refactor());
    }
}
