//! Helpers shared by the integration tests (each test crate uses some of them).
#![allow(dead_code)]

pub mod npz;
pub mod sparse;

use lcp::Lcp;

/// Checks z ≥ 0, w = Mz + q ≥ 0, zᵀw = 0 to `tol` (relative to the data
/// size), with `w` recomputed here: a solved answer is judged by its
/// residual, never by the solver's word.
pub fn assert_solves(lcp: &Lcp, z: &[f64], tol: f64) {
    assert_solves_case(lcp, z, tol, "");
}

/// [`assert_solves`], naming the case `what` in every failure message.
pub fn assert_solves_case(lcp: &Lcp, z: &[f64], tol: f64, what: &str) {
    assert_eq!(z.len(), lcp.n(), "{what}: z has the wrong length");
    let w = lcp.w_of(z);
    let scale = 1.0 + lcp.q().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for i in 0..lcp.n() {
        assert!(z[i] >= -tol * scale, "{what}: z[{i}] = {} < 0", z[i]);
        assert!(w[i] >= -tol * scale, "{what}: w[{i}] = {} < 0", w[i]);
        assert!(z[i].min(w[i]).abs() <= tol * scale, "{what}: complementarity at {i}: z = {}, w = {}", z[i], w[i]);
    }
}

/// Cholesky succeeds ⇔ symmetric positive definite.
pub fn is_positive_definite(m: &[f64], n: usize) -> bool {
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let d = m[j * n + j] - (0..j).map(|k| l[j * n + k] * l[j * n + k]).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        l[j * n + j] = d.sqrt();
        for i in j + 1..n {
            l[i * n + j] = (m[i * n + j] - (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum::<f64>()) / l[j * n + j];
        }
    }
    true
}

/// Determinant by Gaussian elimination with partial pivoting.
pub fn det(mut a: Vec<f64>, n: usize) -> f64 {
    let mut d = 1.0;
    for c in 0..n {
        let p = (c..n).max_by(|&x, &y| a[x * n + c].abs().total_cmp(&a[y * n + c].abs())).unwrap();
        if a[p * n + c] == 0.0 {
            return 0.0;
        }
        if p != c {
            for j in 0..n {
                a.swap(p * n + j, c * n + j);
            }
            d = -d;
        }
        d *= a[c * n + c];
        for r in c + 1..n {
            let f = a[r * n + c] / a[c * n + c];
            for j in c..n {
                a[r * n + j] -= f * a[c * n + j];
            }
        }
    }
    d
}
