//! The sparse LU of a basis: faer's COLAMD column ordering and its
//! simplicial LU with partial pivoting, called directly.
//!
//! faer's `sp_lu` does the same and, before it, an elimination tree and
//! column counts that only choose between its simplicial and supernodal
//! factorizations (a forming 200-cube heap's profile shows only the simplicial one). That choice
//! subtracts 1 from counts that are 0 on a structurally singular matrix: an
//! overflow panic in builds with overflow checks (a box-stack LCP of the hard
//! corpus, `crates/sim/tests/structured_lemke.rs`). Here a singular basis is
//! an error like any other.
//!
//! The ordering is recomputed at every factorization: kept across
//! refactorizations (up to 100 or 400 replaced columns), it made the factors
//! fill in and a forming 200-cube heap's steps 1.5–4× slower.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::colamd;
use faer::sparse::linalg::lu::simplicial::{
    factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch, SimplicialLu,
};
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par};
use std::cell::RefCell;

/// A factored square sparse matrix.
pub(crate) struct SparseLu {
    dim: usize,
    lu: SimplicialLu<usize, f64>,
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    col_fwd: Vec<usize>,
    col_inv: Vec<usize>,
    factored: bool,
    /// After a failed [`SparseLu::factor`]: the column found structurally
    /// dependent on the columns eliminated before it, when that was the failure.
    pub(crate) dependent: Option<usize>,
    /// Workspace of the solves.
    work: RefCell<Vec<f64>>,
}

impl SparseLu {
    pub(crate) fn new(dim: usize) -> Self {
        SparseLu {
            dim,
            lu: SimplicialLu::new(),
            row_fwd: vec![0; dim],
            row_inv: vec![0; dim],
            col_fwd: vec![0; dim],
            col_inv: vec![0; dim],
            factored: false,
            dependent: None,
            work: RefCell::new(vec![0.0; dim]),
        }
    }

    /// Factors the matrix of `triplets` (repeated entries summed). `false`
    /// when it is singular or cannot be built.
    pub(crate) fn factor(&mut self, triplets: &[Triplet<usize, usize, f64>]) -> bool {
        let n = self.dim;
        self.factored = false;
        self.dependent = None;
        let Ok(a) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, triplets) else { return false };
        let req = StackReq::any_of(&[
            colamd::order_scratch::<usize>(n, n, a.compute_nnz()),
            factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
        ]);
        let mut mem = MemBuffer::new(req);
        let stack = MemStack::new(&mut mem);
        let control = colamd::Control::default();
        if colamd::order(&mut self.col_fwd, &mut self.col_inv, a.symbolic(), control, stack).is_err() {
            return false;
        }
        let col = PermRef::new_checked(&self.col_fwd, &self.col_inv, n);
        let res =
            factorize_simplicial_numeric_lu(&mut self.row_fwd, &mut self.row_inv, &mut self.lu, a.as_ref(), col, stack);
        // Step `index` eliminates column `col_fwd[index]`.
        self.dependent = match res {
            Err(LuError::SymbolicSingular { index }) => self.col_fwd.get(index).copied(),
            _ => None,
        };
        self.factored = res.is_ok();
        self.factored
    }

    /// `x ← A⁻¹ x`.
    pub(crate) fn solve_in_place(&self, x: &mut [f64]) {
        assert!(self.factored, "a factored matrix");
        let n = self.dim;
        let mut work = self.work.borrow_mut();
        let row = PermRef::new_checked(&self.row_fwd, &self.row_inv, n);
        let col = PermRef::new_checked(&self.col_fwd, &self.col_inv, n);
        self.lu.solve_in_place_with_conj(
            row,
            col,
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MatMut::from_column_major_slice_mut(&mut work, n, 1),
        );
    }
}
