//! The previous basis of an island solved on its dense `M` (a jointed
//! island's `J P Jᵀ`, or one holding a torsion patch), before
//! `dense_loaded` and the dense Lemke: the body-space stages assume the
//! block-diagonal `M_b⁻¹` and one cone row per normal, so such an island's
//! warm basis is solved here by `lcp::on_basis` on the dense LCP (its kept
//! factorization refined, exchanges of the indices the rule rejects),
//! judged by the same acceptance rule. Reported as the previous-basis stage.
//!
//! The dense `M` is read through [`NonzeroProducts`]: an answer on a basis
//! has few nonzero entries (a held gripper's 130 unknowns, about 30), and
//! its products `M z + q` read only their columns.

use super::stage::Found;
use crate::pipeline::island::IslandLcp;
use lcp::on_basis::{solve_on_basis_ruled, BasisTolerances};
use lcp::operator::LcpOperator;
use lcp::Lcp;
use std::cell::RefCell;

/// The island's `warm` basis solved on its dense LCP at `accept_tol`, or
/// `None` (no basis, a scaled cone, or no accepted answer: the caller pivots).
pub(super) fn attempt(isl: &mut IslandLcp, warm: Option<&[bool]>, accept_tol: f64) -> Option<Found> {
    // (Scaled cones would need the physical LCP's check beside it: left to the Lemke.)
    let warm = warm.filter(|_| isl.lcp.scale() == 1.0)?;
    if !isl.lcp.has_matrix() {
        isl.lcp.assemble_matrix();
    }
    let lcp = isl.lcp.take_lcp().ok()?;
    // At most REPAIR_ROUNDS exchanges: on the chain of `benchmarks/joints.py`
    // the rounds a small block gets beyond them (each a fresh factorization
    // and a dense product) answered fewer steps (2,123 against 2,228 of
    // 3,000) and left more pivots to the Lemke (383,071 against 265,839).
    let tol = BasisTolerances { accept_tol, tight: accept_tol, loose: true, polish: true, more_rounds: false };
    let op = NonzeroProducts { lcp: &lcp, nonzero: RefCell::new(Vec::with_capacity(lcp.n())) };
    let found = solve_on_basis_ruled(&op, warm, tol, None, &mut isl.basis_ws);
    isl.lcp.restore(lcp);
    let sol = found?.solution;
    // At scale 1 the LCP is the physical one: its z and w (M z + q, as
    // checked) are the island's, not formed again by `unscaled_w`.
    let physical = Some((sol.z.clone(), sol.w.clone()));
    Some(Found { sol, physical })
}

/// A dense LCP whose products `M z + q` read only the columns of `z`'s
/// nonzero entries, summed in the same order as the full row's dot product:
/// the same bits (a zero term leaves a sum unchanged), at `n·nnz(z)` instead
/// of `n²` flops.
struct NonzeroProducts<'a> {
    lcp: &'a Lcp,
    /// The nonzero entries' indices of the `z` last multiplied.
    nonzero: RefCell<Vec<usize>>,
}

impl NonzeroProducts<'_> {
    /// `w_i = (M z + q)_i` for each `i` of `rows`.
    fn products(&self, z: &[f64], rows: impl Iterator<Item = usize>, w: &mut [f64]) {
        let mut nz = self.nonzero.borrow_mut();
        nz.clear();
        // (NaN != 0: a NaN in z reaches w as in the full product.)
        nz.extend((0..z.len()).filter(|&j| z[j] != 0.0));
        let q = self.lcp.q();
        for i in rows {
            let row = self.lcp.row(i);
            w[i] = nz.iter().map(|&j| row[j] * z[j]).sum::<f64>() + q[i];
        }
    }
}

impl LcpOperator for NonzeroProducts<'_> {
    fn n(&self) -> usize {
        self.lcp.n()
    }
    fn q(&self) -> &[f64] {
        self.lcp.q()
    }
    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]) {
        self.lcp.block(rows, cols, out);
    }
    fn w_of(&self, z: &[f64], w: &mut [f64]) {
        self.products(z, 0..self.lcp.n(), w);
    }
    fn row(&self, i: usize, out: &mut [f64]) {
        out.copy_from_slice(self.lcp.row(i));
    }
    fn diag(&self, i: usize) -> f64 {
        self.lcp.at(i, i)
    }
    fn w_rows(&self, z: &[f64], rows: &[usize], w: &mut [f64]) {
        self.products(z, rows.iter().copied(), w);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The products skipping `z`'s zeros are the full products' bits.
    #[test]
    fn nonzero_products_are_the_full_products() {
        let n = 7;
        let m: Vec<f64> = (0..n * n).map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0 + 1e-3 * k as f64).collect();
        let lcp = Lcp::new(m, (0..n).map(|i| 0.1 * i as f64 - 0.3).collect()).unwrap();
        let op = NonzeroProducts { lcp: &lcp, nonzero: RefCell::new(Vec::new()) };
        let z = [0.0, 1.5, 0.0, -0.25, 1e-9, 0.0, 3.0];
        let (mut full, mut sparse) = (vec![0.0; n], vec![0.0; n]);
        LcpOperator::w_of(&lcp, &z, &mut full);
        op.w_of(&z, &mut sparse);
        assert_eq!(
            full.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            sparse.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        let mut some = vec![f64::NAN; n];
        op.w_rows(&z, &[1, 4], &mut some);
        assert_eq!((some[1], some[4]), (full[1], full[4]));
        assert!(some[0].is_nan());
    }
}
