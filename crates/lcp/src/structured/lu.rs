//! The sparse LU of a basis: faer's COLAMD column ordering and its
//! simplicial LU with partial pivoting, called directly, and triangular
//! solves of our own on a copy of the factors.
//!
//! faer's `sp_lu` does the same and, before it, an elimination tree and
//! column counts that only choose between its simplicial and supernodal
//! factorizations (a forming 200-cube heap's profile shows only the simplicial one). That choice
//! subtracts 1 from counts that are 0 on a structurally singular matrix: an
//! overflow panic in builds with overflow checks (a box-stack LCP of the hard
//! corpus, `crates/sim/tests/structured_lemke.rs`). Here a singular basis is
//! an error like any other.
//!
//! The solves skip the columns of `L` and `U` whose unknown is 0 (an entering
//! column has a dozen nonzeros: most of `L⁻¹ a` stays 0) and multiply by
//! stored reciprocals of `U`'s diagonal; otherwise they do faer's operations
//! in faer's order, so the answers are the same to the bit. (faer's solves
//! touch every entry of both factors: a quarter of the instructions of a
//! 52-cube heap's solve, n = 1,440.)
//!
//! The caller says whether to order afresh ([`SparseLu::factor`]): COLAMD took
//! 75 % of a refactorization there, and a basis that changed by a few dozen
//! columns factors about as sparsely in its predecessor's order (an order kept
//! without looking at the fill made a forming 200-cube heap's steps 1.5–4×
//! slower: [`super::factor`] watches it).
//!
//! A fresh order puts the matrix's singleton columns first (a basic slack's
//! unit column) and asks COLAMD only about the rest: on the whole augmented
//! matrix COLAMD cost 23M instructions a call at n = 1,440, 15 % of the
//! solve; on the rest, about 1M ([`SparseLu::order_fresh`]).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::colamd;
use faer::sparse::linalg::lu::simplicial::{
    factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch, SimplicialLu,
};
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use std::cell::RefCell;

/// A square sparse matrix by columns, rows sorted within each column.
#[derive(Default)]
pub(crate) struct Csc {
    pub(crate) ptr: Vec<usize>,
    pub(crate) idx: Vec<usize>,
    pub(crate) val: Vec<f64>,
}

impl Csc {
    /// Empties it for a new matrix.
    pub(crate) fn clear(&mut self) {
        self.ptr.clear();
        self.ptr.push(0);
        self.idx.clear();
        self.val.clear();
    }

    /// Closes the current column (its entries pushed since the last call).
    pub(crate) fn end_column(&mut self) {
        self.ptr.push(self.idx.len());
    }
}

/// The column order of a factorization.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Order {
    /// COLAMD's, afresh.
    Fresh,
    /// The last factorization's.
    Kept,
}

/// One triangular factor by columns, its diagonal apart: column `j`'s
/// off-diagonal entries are `idx[ptr[j]..ptr[j + 1]]`, `val` the same range.
/// Rows as `u32`: the solves stream these arrays once per pivot.
#[derive(Default)]
struct Triangle {
    ptr: Vec<usize>,
    idx: Vec<u32>,
    val: Vec<f64>,
}

impl Triangle {
    /// The off-diagonal entries of `m`, the diagonal being each column's
    /// first (`diag_first`) or last stored entry.
    fn copy_of(&mut self, m: SparseColMatRef<'_, usize, f64>, diag_first: bool) {
        let (ptr, idx, val) = (m.col_ptr(), m.row_idx(), m.val());
        self.ptr.clear();
        self.idx.clear();
        self.val.clear();
        self.ptr.push(0);
        for j in 0..m.ncols() {
            let r = if diag_first { ptr[j] + 1..ptr[j + 1] } else { ptr[j]..ptr[j + 1] - 1 };
            self.idx.extend(idx[r.clone()].iter().map(|&i| i as u32));
            self.val.extend_from_slice(&val[r]);
            self.ptr.push(self.idx.len());
        }
    }
}

/// A factored square sparse matrix.
pub(crate) struct SparseLu {
    dim: usize,
    lu: SimplicialLu<usize, f64>,
    /// `L` without its unit diagonal, `U` without its diagonal, and `1 / diag(U)`.
    l: Triangle,
    u: Triangle,
    u_inv_diag: Vec<f64>,
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    col_fwd: Vec<usize>,
    col_inv: Vec<usize>,
    /// Whether `col_fwd` holds an ordering to reuse.
    ordered: bool,
    factored: bool,
    /// After a failed [`SparseLu::factor`]: the column found structurally
    /// dependent on the columns eliminated before it, when that was the failure.
    pub(crate) dependent: Option<usize>,
    /// Workspace of the solves.
    work: RefCell<Vec<f64>>,
    /// Numeric factorizations and fresh column orders made (for the trace and tests).
    pub(crate) counts: (usize, usize),
}

impl SparseLu {
    pub(crate) fn new(dim: usize) -> Self {
        assert!(u32::try_from(dim).is_ok(), "rows fit in u32");
        SparseLu {
            dim,
            lu: SimplicialLu::new(),
            l: Triangle::default(),
            u: Triangle::default(),
            u_inv_diag: vec![0.0; dim],
            row_fwd: vec![0; dim],
            row_inv: vec![0; dim],
            col_fwd: vec![0; dim],
            col_inv: vec![0; dim],
            ordered: false,
            factored: false,
            dependent: None,
            work: RefCell::new(vec![0.0; dim]),
            counts: (0, 0),
        }
    }

    /// Factors `a` (`dim × dim`, rows sorted and distinct in each column)
    /// in the column order `order` (a kept order when there is none yet is a
    /// fresh one). `false` when it is singular or cannot be built.
    pub(crate) fn factor(&mut self, a: &Csc, order: Order) -> bool {
        let n = self.dim;
        self.factored = false;
        self.dependent = None;
        // Panics on unsorted or repeated rows: `a` is built sorted (see `Basis::refactor`).
        let csc = a;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &a.ptr, None, &a.idx);
        let a = SparseColMatRef::new(sym, &a.val);
        let req = StackReq::any_of(&[
            colamd::order_scratch::<usize>(n, n, a.compute_nnz()),
            factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
        ]);
        let mut mem = MemBuffer::new(req);
        let stack = MemStack::new(&mut mem);
        if order == Order::Fresh || !self.ordered {
            self.ordered = false;
            self.counts.1 += 1;
            if !self.order_fresh(csc, stack) {
                return false;
            }
            self.ordered = true;
        }
        self.counts.0 += 1;
        let col = PermRef::new_checked(&self.col_fwd, &self.col_inv, n);
        let res = factorize_simplicial_numeric_lu(&mut self.row_fwd, &mut self.row_inv, &mut self.lu, a, col, stack);
        // Step `index` eliminates column `col_fwd[index]`.
        self.dependent = match res {
            Err(LuError::SymbolicSingular { index }) => self.col_fwd.get(index).copied(),
            _ => None,
        };
        if res.is_err() {
            return false;
        }
        // faer's L stores its unit diagonal first in each column, U its diagonal last.
        self.l.copy_of(self.lu.l_factor_unsorted(), true);
        let u = self.lu.u_factor_unsorted();
        self.u.copy_of(u, false);
        let (ptr, val) = (u.col_ptr(), u.val());
        self.u_inv_diag.iter_mut().enumerate().for_each(|(j, d)| *d = val[ptr[j + 1] - 1].recip());
        self.factored = true;
        true
    }

    /// A fresh column order of `a` into `col_fwd`/`col_inv`: its singleton
    /// columns with distinct rows first (a basic slack's unit column: no
    /// fill, nothing to order), then COLAMD's order of what remains once
    /// they and their rows are taken out. (COLAMD on the whole augmented
    /// matrix took 15 % of a 52-cube heap's solve, n = 1,440.)
    fn order_fresh(&mut self, a: &Csc, stack: &mut MemStack) -> bool {
        let n = self.dim;
        let is_single = singleton_columns(a, n);
        let singles: Vec<usize> = (0..n).filter(|&j| is_single[j]).collect();
        let mut row_new = vec![0usize; n];
        singles.iter().for_each(|&j| row_new[a.idx[a.ptr[j]]] = usize::MAX);
        // The rest: the other columns over the other rows, renumbered.
        let mut next = 0;
        for r in row_new.iter_mut() {
            if *r == 0 {
                *r = next;
                next += 1;
            }
        }
        let mut rest = Vec::with_capacity(n - singles.len());
        let mut sub = Csc::default();
        sub.clear();
        let mut s = singles.iter().peekable();
        for j in 0..n {
            if s.peek() == Some(&&j) {
                s.next();
                continue;
            }
            rest.push(j);
            for &i in &a.idx[a.ptr[j]..a.ptr[j + 1]] {
                if row_new[i] != usize::MAX {
                    sub.idx.push(row_new[i]);
                }
            }
            sub.end_column();
        }
        let m = rest.len();
        let (mut fwd, mut inv) = (vec![0usize; m], vec![0usize; m]);
        if m > 0 {
            let sym = SymbolicSparseColMatRef::new_checked(m, m, &sub.ptr, None, &sub.idx);
            if colamd::order(&mut fwd, &mut inv, sym, colamd::Control::default(), stack).is_err() {
                return false;
            }
        }
        self.col_fwd.clear();
        self.col_fwd.extend_from_slice(&singles);
        self.col_fwd.extend(fwd.iter().map(|&k| rest[k]));
        for (k, &j) in self.col_fwd.iter().enumerate() {
            self.col_inv[j] = k;
        }
        true
    }

    /// The kept column order rearranged for a matrix whose columns `moved`
    /// changed since it was made: the singleton columns of `a` first (as in
    /// a fresh order), then the unmoved columns, then the moved ones, each
    /// group in the kept order. A basic slack's unit column that became a
    /// `z` column would otherwise be eliminated in the slot of a singleton,
    /// before everything COLAMD ordered, and fill in. (On a 45-cube pour's
    /// structured LCPs, a kept order's fill came within 1.2× of a fresh
    /// order's at 220 of 870 in-run refactorizations as it was, 393 so
    /// rearranged; median 1.38× against 1.24×.) No effect without a kept order.
    pub(crate) fn move_last(&mut self, a: &Csc, moved: &[bool]) {
        if !self.ordered {
            return;
        }
        let singles = singleton_columns(a, self.dim);
        let old = std::mem::take(&mut self.col_fwd);
        let group = |j: usize| {
            if singles[j] {
                0
            } else if moved[j] {
                2
            } else {
                1
            }
        };
        for g in 0..3 {
            self.col_fwd.extend(old.iter().copied().filter(|&j| group(j) == g));
        }
        for (k, &j) in self.col_fwd.iter().enumerate() {
            self.col_inv[j] = k;
        }
    }

    /// Nonzeros of `L` and `U`.
    pub(crate) fn nnz(&self) -> usize {
        self.l.idx.len() + self.u.idx.len() + 2 * self.dim
    }

    /// The factors' fill of `a` (the matrix just factored): their nonzeros over its.
    pub(crate) fn fill(&self, a: &Csc) -> f64 {
        self.nnz() as f64 / a.idx.len().max(1) as f64
    }

    /// `x ← A⁻¹ x`.
    #[inline(never)]
    pub(crate) fn solve_in_place(&self, x: &mut [f64]) {
        assert!(self.factored, "a factored matrix");
        let mut work = self.work.borrow_mut();
        let t = &mut work[..];
        for (ti, &r) in t.iter_mut().zip(&self.row_fwd) {
            *ti = x[r];
        }
        let (l, u) = (&self.l, &self.u);
        for j in 0..self.dim {
            let tj = t[j];
            if tj != 0.0 {
                let r = l.ptr[j]..l.ptr[j + 1];
                for (&i, &v) in l.idx[r.clone()].iter().zip(&l.val[r]) {
                    t[i as usize] -= v * tj;
                }
            }
        }
        for j in (0..self.dim).rev() {
            if t[j] != 0.0 {
                let tj = t[j] * self.u_inv_diag[j];
                t[j] = tj;
                let r = u.ptr[j]..u.ptr[j + 1];
                for (&i, &v) in u.idx[r.clone()].iter().zip(&u.val[r]) {
                    t[i as usize] -= v * tj;
                }
            }
        }
        for (xi, &c) in x.iter_mut().zip(&self.col_inv) {
            *xi = t[c];
        }
    }
}

/// The singleton columns of `a` (`dim` square) whose row no earlier
/// singleton column took: eliminated first, they cause no fill.
fn singleton_columns(a: &Csc, dim: usize) -> Vec<bool> {
    let mut row_taken = vec![false; dim];
    let mut single = vec![false; dim];
    for j in 0..dim {
        if a.ptr[j + 1] - a.ptr[j] == 1 && !row_taken[a.idx[a.ptr[j]]] {
            row_taken[a.idx[a.ptr[j]]] = true;
            single[j] = true;
        }
    }
    single
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random `dim × dim` matrix: unit columns on the first `units` rows
    /// (in shuffled column places), the others random sparse with a diagonal.
    fn random(dim: usize, units: usize, seed: u64) -> Csc {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut cols: Vec<Vec<(usize, f64)>> = (0..units).map(|i| vec![(i, 1.0)]).collect();
        for j in units..dim {
            let mut c = vec![(j, 2.0 + rng.random_range(0.0..1.0))];
            for _ in 0..4 {
                c.push((rng.random_range(0..dim), rng.random_range(-1.0..1.0)));
            }
            c.sort_by_key(|e| e.0);
            c.dedup_by_key(|e| e.0);
            cols.push(c);
        }
        for j in (1..dim).rev() {
            cols.swap(j, rng.random_range(0..=j));
        }
        let mut a = Csc::default();
        a.clear();
        for c in cols {
            for (i, v) in c {
                a.idx.push(i);
                a.val.push(v);
            }
            a.end_column();
        }
        a
    }

    /// `‖A x − b‖∞` for `x` solved by `lu`, the factors of `a`, and `b_i = sin i`.
    fn solve_error(lu: &SparseLu, a: &Csc) -> f64 {
        let b: Vec<f64> = (0..lu.dim).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        let mut ax = vec![0.0; lu.dim];
        for (j, &xj) in x.iter().enumerate() {
            for e in a.ptr[j]..a.ptr[j + 1] {
                ax[a.idx[e]] += a.val[e] * xj;
            }
        }
        ax.iter().zip(&b).fold(0.0f64, |m, (u, v)| m.max((u - v).abs()))
    }

    /// A kept order rearranged for changed columns (singletons first, the
    /// moved columns last, each group in the kept order) factors the new
    /// matrix so that `A x = b` to round-off.
    #[test]
    fn a_kept_order_with_moved_columns_last_solves() {
        let mut solved = 0;
        for seed in 0..8 {
            let (dim, units) = (80, 30);
            let a = random(dim, units, seed);
            let mut lu = SparseLu::new(dim);
            assert!(lu.factor(&a, Order::Fresh));
            let kept = lu.col_fwd.clone();
            // Every other unit column becomes a random sparse one.
            let mut rng = ChaCha8Rng::seed_from_u64(50 + seed);
            let mut cols: Vec<Vec<(usize, f64)>> =
                (0..dim).map(|j| (a.ptr[j]..a.ptr[j + 1]).map(|e| (a.idx[e], a.val[e])).collect()).collect();
            let units_at: Vec<usize> = (0..dim).filter(|&j| cols[j].len() == 1).collect();
            let mut moved = vec![false; dim];
            for &j in units_at.iter().step_by(2) {
                let mut c = vec![(cols[j][0].0, 3.0)];
                c.extend((0..3).map(|_| (rng.random_range(0..dim), rng.random_range(-1.0..1.0))));
                c.sort_by_key(|e| e.0);
                c.dedup_by_key(|e| e.0);
                (cols[j], moved[j]) = (c, true);
            }
            let mut b = Csc::default();
            b.clear();
            for c in &cols {
                c.iter().for_each(|&(i, v)| {
                    b.idx.push(i);
                    b.val.push(v);
                });
                b.end_column();
            }
            lu.move_last(&b, &moved);
            let singles = singleton_columns(&b, dim);
            let group = |j: usize| {
                if singles[j] {
                    0
                } else if moved[j] {
                    2
                } else {
                    1
                }
            };
            assert!(lu.col_fwd.windows(2).all(|w| group(w[0]) <= group(w[1])), "seed {seed}: groups in order");
            for g in 0..3 {
                let in_kept: Vec<usize> = kept.iter().copied().filter(|&j| group(j) == g).collect();
                let now: Vec<usize> = lu.col_fwd.iter().copied().filter(|&j| group(j) == g).collect();
                assert_eq!(in_kept, now, "seed {seed}: group {g} in the kept order");
            }
            if !lu.factor(&b, Order::Kept) {
                continue; // structurally singular by chance: nothing to solve
            }
            let err = solve_error(&lu, &b);
            assert!(err < 1e-11, "seed {seed}: {err:e}");
            solved += 1;
        }
        assert!(solved >= 6, "{solved} of 8 regular");
    }

    /// Fresh (singletons first, then COLAMD) and kept orders both factor `A` so that `A x = b` to round-off; the fresh order is a
    /// permutation with the unit columns first.
    #[test]
    fn every_order_solves() {
        for seed in 0..8 {
            let (dim, units) = (80, 30);
            let a = random(dim, units, seed);
            let mut lu = SparseLu::new(dim);
            for order in [Order::Fresh, Order::Kept] {
                assert!(lu.factor(&a, order), "seed {seed}, {order:?}");
                if order == Order::Fresh {
                    let mut seen = vec![false; dim];
                    lu.col_fwd.iter().for_each(|&j| seen[j] = true);
                    assert!(seen.iter().all(|&s| s));
                    assert!(lu.col_fwd.iter().enumerate().all(|(k, &j)| lu.col_inv[j] == k));
                    assert!(lu.col_fwd[..units].iter().all(|&j| a.ptr[j + 1] - a.ptr[j] == 1));
                }
                let err = solve_error(&lu, &a);
                assert!(err < 1e-12, "seed {seed}, {order:?}: {err:e}");
            }
        }
    }
}
