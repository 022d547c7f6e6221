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
        }
    }

    /// Factors `a` (`dim × dim`, rows sorted and distinct in each column),
    /// with a fresh COLAMD ordering when `fresh` or when there is none yet,
    /// else in the last one. `false` when it is singular or cannot be built.
    pub(crate) fn factor(&mut self, a: &Csc, fresh: bool) -> bool {
        let n = self.dim;
        self.factored = false;
        self.dependent = None;
        // Panics on unsorted or repeated rows: `a` is built sorted (see `Basis::refactor`).
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &a.ptr, None, &a.idx);
        let a = SparseColMatRef::new(sym, &a.val);
        let req = StackReq::any_of(&[
            colamd::order_scratch::<usize>(n, n, a.compute_nnz()),
            factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
        ]);
        let mut mem = MemBuffer::new(req);
        let stack = MemStack::new(&mut mem);
        if fresh || !self.ordered {
            self.ordered = false;
            let control = colamd::Control::default();
            if colamd::order(&mut self.col_fwd, &mut self.col_inv, a.symbolic(), control, stack).is_err() {
                return false;
            }
            self.ordered = true;
        }
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

    /// Nonzeros of `L` and `U`.
    pub(crate) fn nnz(&self) -> usize {
        self.l.idx.len() + self.u.idx.len() + 2 * self.dim
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
