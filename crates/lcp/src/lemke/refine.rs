//! Re-solving the final complementary basis directly.
//!
//! The pivoting loop carries values updated pivot by pivot; once it has found
//! the complementary set `α`, the answer is defined by `M_αα z_α = −q_α`
//! alone. Solving that system afresh (LU with partial pivoting plus
//! iterative refinement) removes the round-off the updates accumulated.

use crate::problem::Lcp;
use faer::linalg::solvers::Solve;
use faer::Mat;

/// `z` with `z_α` solving `M_αα z_α = −q_α` and zeros elsewhere, or `None`
/// when `M_αα` is numerically singular.
pub(crate) fn resolve_basis(lcp: &Lcp, alpha: &[usize]) -> Option<Vec<f64>> {
    let (n, k) = (lcp.n(), alpha.len());
    let mut z = vec![0.0; n];
    if k == 0 {
        return Some(z);
    }
    let a = Mat::<f64>::from_fn(k, k, |r, c| lcp.at(alpha[r], alpha[c]));
    let lu = a.partial_piv_lu();
    let amax = (0..k).flat_map(|r| (0..k).map(move |c| (r, c))).fold(0.0f64, |m, (r, c)| m.max(a[(r, c)].abs()));
    let u = lu.U();
    if !(0..k).all(|i| u[(i, i)].abs() > 1e-14 * amax) {
        return None;
    }
    let q = lcp.q();
    let mut x = lu.solve(Mat::<f64>::from_fn(k, 1, |r, _| -q[alpha[r]]));
    // Two steps of iterative refinement on the residual −q_α − M_αα x.
    for _ in 0..2 {
        let res = Mat::<f64>::from_fn(k, 1, |r, _| {
            let row = lcp.row(alpha[r]);
            -q[alpha[r]] - (0..k).map(|c| row[alpha[c]] * x[(c, 0)]).sum::<f64>()
        });
        let dx = lu.solve(res);
        for r in 0..k {
            x[(r, 0)] += dx[(r, 0)];
        }
    }
    for (r, &j) in alpha.iter().enumerate() {
        z[j] = x[(r, 0)];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
}
