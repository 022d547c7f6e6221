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
//! solve; on the rest, about 1M ([`SparseLu::order_fresh`]). faer, too,
//! factors only the rest ([`SparseLu::factor_peeling`]): on a 45-cube
//! pour's structured LCPs its numeric LU fell from 21 % to 14 % of the
//! samples, the same factors to the bit.

use faer::dyn_stack::{MemBuffer, MemStack};
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
    /// `shift` empty columns, then the off-diagonal entries of `m` with
    /// rows shifted by `shift`, the diagonal being each column's first
    /// (`diag_first`) or last stored entry; `more(k, self)` pushes further
    /// entries of `m`'s column `k`.
    fn copy_of(
        &mut self,
        m: SparseColMatRef<'_, usize, f64>,
        diag_first: bool,
        shift: usize,
        mut more: impl FnMut(usize, &mut Self),
    ) {
        let (ptr, idx, val) = (m.col_ptr(), m.row_idx(), m.val());
        self.ptr.clear();
        self.idx.clear();
        self.val.clear();
        self.ptr.resize(shift + 1, 0);
        for j in 0..m.ncols() {
            let r = if diag_first { ptr[j] + 1..ptr[j + 1] } else { ptr[j]..ptr[j + 1] - 1 };
            self.idx.extend(idx[r.clone()].iter().map(|&i| (i + shift) as u32));
            self.val.extend_from_slice(&val[r]);
            more(j, self);
            self.ptr.push(self.idx.len());
        }
    }
}

/// Marks a row taken by a leading singleton column in [`SparseLu::factor_peeling`]'s row map.
const TAKEN: usize = 1 << (usize::BITS - 1);

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
    /// faer's row order of the columns after the leading singletons, and
    /// their matrix ([`SparseLu::factor_peeling`]).
    row_rest: Vec<usize>,
    sub: Csc,
    /// Scratch of [`SparseLu::factor_peeling`]: each row's step or number,
    /// the rows not taken, the other columns' entries in taken rows.
    row_map: Vec<usize>,
    rows: Vec<usize>,
    taken: Csc,
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
            row_rest: Vec::new(),
            sub: Csc::default(),
            row_map: Vec::new(),
            rows: Vec::new(),
            taken: Csc::default(),
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
        self.factor_peeling(a, order, usize::MAX)
    }

    /// [`SparseLu::factor`], the order's leading singleton columns (at most
    /// `peel` of them) taken out before faer factors the rest.
    ///
    /// A singleton column eliminated first pivots on its own row with no
    /// arithmetic: its `L` column is empty, and every later column's entry
    /// in its row is that column's `U` entry as it stands (no `L` column
    /// reaches the row). So faer factors only the other columns over the
    /// other rows, and those entries are copied into `U`: the same factors
    /// to the bit (faer's reach visits the taken rows as leaves, which moves
    /// no other row in its order), without faer's depth-first visit of every
    /// entry in a basic slack's row — most of `G`'s entries in a contact
    /// LCP's basis.
    fn factor_peeling(&mut self, a: &Csc, order: Order, peel: usize) -> bool {
        let n = self.dim;
        self.factored = false;
        self.dependent = None;
        if order == Order::Fresh || !self.ordered {
            self.ordered = false;
            self.counts.1 += 1;
            let req = colamd::order_scratch::<usize>(n, n, a.idx.len());
            let mut mem = MemBuffer::new(req);
            if !self.order_fresh(a, MemStack::new(&mut mem)) {
                return false;
            }
            self.ordered = true;
        }
        self.counts.0 += 1;
        let single = singleton_columns(a, n);
        let s = self.col_fwd.iter().take(peel).take_while(|&&j| single[j]).count();
        // Each row: the step that takes it (`TAKEN` set), else its number among the others.
        let mut row_map = std::mem::take(&mut self.row_map);
        row_map.clear();
        row_map.resize(n, 0);
        for (k, &j) in self.col_fwd[..s].iter().enumerate() {
            row_map[a.idx[a.ptr[j]]] = k | TAKEN;
        }
        let mut rows = std::mem::take(&mut self.rows);
        rows.clear();
        for (r, m) in row_map.iter_mut().enumerate() {
            if *m & TAKEN == 0 {
                *m = rows.len();
                rows.push(r);
            }
        }
        // The other columns split in one pass: their rows among the others
        // (faer's to factor) and their entries in taken rows (`U`'s as they stand).
        let (mut sub, mut taken) = (std::mem::take(&mut self.sub), std::mem::take(&mut self.taken));
        sub.clear();
        taken.clear();
        for &j in &self.col_fwd[s..] {
            for e in a.ptr[j]..a.ptr[j + 1] {
                let r = row_map[a.idx[e]];
                if r & TAKEN == 0 {
                    sub.idx.push(r);
                    sub.val.push(a.val[e]);
                } else {
                    taken.idx.push(r & !TAKEN);
                    taken.val.push(a.val[e]);
                }
            }
            sub.end_column();
            taken.end_column();
        }
        let m = n - s;
        let ok = self.factor_rest(&sub, m, s);
        if ok {
            // The full factors: the taken rows' pivots first, then faer's.
            for (k, &j) in self.col_fwd[..s].iter().enumerate() {
                self.row_fwd[k] = a.idx[a.ptr[j]];
                self.u_inv_diag[k] = a.val[a.ptr[j]].recip();
            }
            for k in 0..m {
                self.row_fwd[s + k] = rows[self.row_rest[k]];
            }
            for (k, &r) in self.row_fwd.iter().enumerate() {
                self.row_inv[r] = k;
            }
            // faer's L stores its unit diagonal first in each column, U its diagonal last.
            self.l.copy_of(self.lu.l_factor_unsorted(), true, s, |_, _| {});
            let u = self.lu.u_factor_unsorted();
            self.u.copy_of(u, false, s, |k, t| {
                let r = taken.ptr[k]..taken.ptr[k + 1];
                t.idx.extend(taken.idx[r.clone()].iter().map(|&i| i as u32));
                t.val.extend_from_slice(&taken.val[r]);
            });
        }
        (self.row_map, self.rows, self.sub, self.taken) = (row_map, rows, sub, taken);
        if !ok {
            return false;
        }
        let u = self.lu.u_factor_unsorted();
        let (ptr, val) = (u.col_ptr(), u.val());
        (0..m).for_each(|k| self.u_inv_diag[s + k] = val[ptr[k + 1] - 1].recip());
        self.factored = true;
        true
    }

    /// faer's numeric LU of `sub` (`m` square, columns in elimination
    /// order), the columns after the `s` taken out; on a singular one, the
    /// column found dependent into [`SparseLu::dependent`].
    fn factor_rest(&mut self, sub: &Csc, m: usize, s: usize) -> bool {
        let sym = SymbolicSparseColMatRef::new_checked(m, m, &sub.ptr, None, &sub.idx);
        let mat = SparseColMatRef::new(sym, &sub.val);
        let mut mem = MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(m, m));
        if self.lu.ncols() != m {
            // faer keeps its column pointers at the largest size it saw.
            self.lu = SimplicialLu::new();
        }
        let ident: Vec<usize> = (0..m).collect();
        let col = PermRef::new_checked(&ident, &ident, m);
        self.row_rest.resize(m, 0);
        let mut row_rest_inv = vec![0; m];
        let res = factorize_simplicial_numeric_lu(
            &mut self.row_rest,
            &mut row_rest_inv,
            &mut self.lu,
            mat,
            col,
            MemStack::new(&mut mem),
        );
        // Step `index` of the rest eliminates column `col_fwd[s + index]`.
        self.dependent = match res {
            Err(LuError::SymbolicSingular { index }) => self.col_fwd.get(s + index).copied(),
            _ => None,
        };
        res.is_ok()
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

    /// The leading singleton columns taken out before faer factors the rest
    /// give the factors of the whole matrix in the same order, to the bit:
    /// the same solves, nonzeros, and dependent column of a singular matrix.
    #[test]
    fn singletons_taken_out_give_the_whole_factors_to_the_bit() {
        let mut singular = 0;
        for seed in 0..8 {
            let (dim, units) = (80, 30);
            let mut a = random(dim, units, seed);
            if seed >= 6 {
                // A non-unit column whose rows are all taken by unit columns:
                // structurally singular past the singletons.
                let units_rows: Vec<usize> =
                    (0..dim).filter(|&j| a.ptr[j + 1] - a.ptr[j] == 1).map(|j| a.idx[a.ptr[j]]).take(2).collect();
                let c = (0..dim).find(|&j| a.ptr[j + 1] - a.ptr[j] > 1).unwrap();
                let mut b = Csc::default();
                b.clear();
                for j in 0..dim {
                    if j == c {
                        let mut rows = units_rows.clone();
                        rows.sort();
                        b.idx.extend_from_slice(&rows);
                        b.val.extend_from_slice(&[0.5, -2.0]);
                    } else {
                        b.idx.extend_from_slice(&a.idx[a.ptr[j]..a.ptr[j + 1]]);
                        b.val.extend_from_slice(&a.val[a.ptr[j]..a.ptr[j + 1]]);
                    }
                    b.end_column();
                }
                a = b;
            }
            let (mut whole, mut peeled) = (SparseLu::new(dim), SparseLu::new(dim));
            let ok = whole.factor_peeling(&a, Order::Fresh, 0);
            assert_eq!(peeled.factor(&a, Order::Fresh), ok, "seed {seed}");
            assert_eq!(whole.col_fwd, peeled.col_fwd);
            if !ok {
                assert!(whole.dependent.is_some() && whole.dependent == peeled.dependent, "seed {seed}");
                singular += 1;
                continue;
            }
            assert_eq!(whole.nnz(), peeled.nnz(), "seed {seed}");
            let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.61).sin()).collect();
            let (mut x, mut y) = (b.clone(), b);
            whole.solve_in_place(&mut x);
            peeled.solve_in_place(&mut y);
            assert_eq!(x, y, "seed {seed}");
        }
        assert_eq!(singular, 2, "seeds 6 and 7 singular");
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
