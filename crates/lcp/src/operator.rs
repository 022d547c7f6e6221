//! An LCP whose matrix is reached through products and blocks, not held
//! dense: [`LcpOperator`]. The dense [`Lcp`] is one; the simulator's
//! body-space LCP (`M = J M_b⁻¹ Jᵀ`, never formed) and the structured LCP
//! `M = G H + K` are others. The acceptance rule (`crate::accept`) and the
//! solve on a given basis (`crate::on_basis`) read problems through it.

use crate::problem::Lcp;

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
    /// Row `i` of `M` into `out` (`n` entries), for the acceptance rule's row
    /// scales ([`crate::accept::accepts_operator`]). By default one `1 × n` block.
    fn row(&self, i: usize, out: &mut [f64]) {
        let cols: Vec<usize> = (0..self.n()).collect();
        self.block(&[i], &cols, out);
    }
    /// The diagonal entry `M_ii`, for the acceptance rule's cheap bound of a
    /// row's scale. By default one `1 × 1` block.
    fn diag(&self, i: usize) -> f64 {
        let mut d = [0.0];
        self.block(&[i], &[i], &mut d);
        d[0]
    }
    /// Every diagonal entry `M_ii`, where the operator holds them: the
    /// acceptance rule then reads them without a call per row. By default none.
    fn diagonal(&self) -> Option<&[f64]> {
        None
    }
    /// `w_i = (M z + q)_i` for each `i` of `rows` (other entries untouched):
    /// what a refinement step reads. By default the whole product.
    fn w_rows(&self, z: &[f64], rows: &[usize], w: &mut [f64]) {
        let mut full = vec![0.0; self.n()];
        self.w_of(z, &mut full);
        rows.iter().for_each(|&i| w[i] = full[i]);
    }
    /// `w = M z + q` right after [`LcpOperator::w_rows`] with the same `z` (an
    /// operator may reuse that product's work, e.g. its `M_b⁻¹ Jᵀ z`). By
    /// default [`LcpOperator::w_of`].
    fn w_after_rows(&self, z: &[f64], w: &mut [f64]) {
        self.w_of(z, w);
    }
    /// `w += M_j·d` for each `(j, d)` of `moved` (`w = M z + q` kept for a
    /// `z` whose entries `j` moved by `d`). By default one `n × 1` block each.
    fn add_columns(&self, moved: &[(usize, f64)], w: &mut [f64]) {
        let rows: Vec<usize> = (0..self.n()).collect();
        let mut col = vec![0.0; self.n()];
        for &(j, d) in moved {
            self.block(&rows, &[j], &mut col);
            w.iter_mut().zip(&col).for_each(|(wi, m)| *wi += m * d);
        }
    }
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
            *wi = crate::problem::dot(Lcp::row(self, i), z) + self.q()[i];
        }
    }
    fn row(&self, i: usize, out: &mut [f64]) {
        out.copy_from_slice(Lcp::row(self, i));
    }
    fn diag(&self, i: usize) -> f64 {
        Lcp::row(self, i)[i]
    }
}
