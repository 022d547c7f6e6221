//! Solving a complementary basis `M_αα z_α = −q_α` in double-double
//! arithmetic: LU with partial pivoting in [`Dd`], then iterative refinement
//! on residuals that are nearly exact (the data are `f64`, so `M_ij·z_j` in
//! double-double loses nothing but the last of its 106 bits). Refinement
//! converges while `cond(M_αα)·2⁻¹⁰⁶ < 1`, i.e. for bases up to cond ~1e30,
//! where the `f64` re-solve (`refine`) stops at cond ~1e16.

use crate::ddouble::Dd;
use crate::problem::Lcp;

/// Refinement steps after the first solve (each gains ~log10(1/(cond·1e-32)) digits).
const REFINE_STEPS: usize = 3;

/// A pivot below this fraction of the block's largest entry counts as zero.
const SINGULAR: f64 = 1e-30;

/// The LU factors of `M_αα` (row-major, unit lower `L` below the diagonal)
/// and the row permutation.
struct Lu {
    k: usize,
    a: Vec<Dd>,
    perm: Vec<usize>,
}

impl Lu {
    /// Factors `M_αα`; `None` when it is numerically singular (in double-double).
    fn factor(lcp: &Lcp, alpha: &[usize]) -> Option<Lu> {
        let k = alpha.len();
        let mut a: Vec<Dd> = Vec::with_capacity(k * k);
        for &i in alpha {
            let row = lcp.row(i);
            a.extend(alpha.iter().map(|&j| Dd::of(row[j])));
        }
        let amax = a.iter().fold(0.0f64, |m, v| m.max(v.hi.abs()));
        let mut perm: Vec<usize> = (0..k).collect();
        for c in 0..k {
            let p = (c..k).max_by(|&x, &y| a[x * k + c].hi.abs().total_cmp(&a[y * k + c].hi.abs()))?;
            if !(a[p * k + c].hi.abs() > SINGULAR * amax) {
                return None;
            }
            if p != c {
                for j in 0..k {
                    a.swap(p * k + j, c * k + j);
                }
                perm.swap(p, c);
            }
            let piv = a[c * k + c];
            for r in c + 1..k {
                if a[r * k + c].is_zero() {
                    continue;
                }
                let f = a[r * k + c] / piv;
                a[r * k + c] = f;
                for j in c + 1..k {
                    let u = a[c * k + j];
                    if !u.is_zero() {
                        a[r * k + j] = a[r * k + j].sub_mul(f, u);
                    }
                }
            }
        }
        Some(Lu { k, a, perm })
    }

    /// Solves `M_αα x = b` in place.
    fn solve(&self, b: &mut [Dd]) {
        let (k, a) = (self.k, &self.a);
        let mut x: Vec<Dd> = self.perm.iter().map(|&p| b[p]).collect();
        for r in 0..k {
            for c in 0..r {
                x[r] = x[r].sub_mul(a[r * k + c], x[c]);
            }
        }
        for r in (0..k).rev() {
            for c in r + 1..k {
                x[r] = x[r].sub_mul(a[r * k + c], x[c]);
            }
            x[r] = x[r] / a[r * k + r];
        }
        b.copy_from_slice(&x);
    }
}

/// `z_α` in double-double solving `M_αα z_α = −q_α` (in `alpha`'s order),
/// or `None` when `M_αα` is singular in double-double.
pub(crate) fn solve_basis(lcp: &Lcp, alpha: &[usize]) -> Option<Vec<Dd>> {
    let k = alpha.len();
    if k == 0 {
        return Some(Vec::new());
    }
    let lu = Lu::factor(lcp, alpha)?;
    let q = lcp.q();
    let mut x: Vec<Dd> = alpha.iter().map(|&i| Dd::of(-q[i])).collect();
    lu.solve(&mut x);
    let mut res = vec![Dd::ZERO; k];
    for _ in 0..REFINE_STEPS {
        // res = −q_α − M_αα x, nearly exact.
        for (r, &i) in alpha.iter().enumerate() {
            let row = lcp.row(i);
            res[r] = alpha.iter().zip(&x).fold(Dd::of(-q[i]), |acc, (&j, xj)| acc - xj.mul_f64(row[j]));
        }
        lu.solve(&mut res);
        x.iter_mut().zip(&res).for_each(|(x, d)| *x = *x + *d);
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 14 × 14 Hilbert block (cond ~1e19 for its floats), beyond what an
    /// `f64` solve resolves: the double-double residual is at its round-off.
    #[test]
    fn solves_beyond_double_precision() {
        let k = 14;
        let m = |i: usize, j: usize| 1.0 / (i + j + 1) as f64;
        // q = −M·1 in double-double, rounded: the exact answer for these floats is near 1.
        let q: Vec<f64> = (0..k).map(|i| -(0..k).fold(Dd::ZERO, |a, j| a + Dd::of(m(i, j))).to_f64()).collect();
        let lcp = Lcp::from_fn(k, m, q).unwrap();
        let alpha: Vec<usize> = (0..k).collect();
        let z = solve_basis(&lcp, &alpha).unwrap();
        // The residual of the floats given is at double-double round-off.
        for i in 0..k {
            let r = (0..k).fold(Dd::of(lcp.q()[i]), |a, j| a + z[j].mul_f64(lcp.at(i, j)));
            assert!(r.to_f64().abs() < 1e-25, "row {i}: residual {:e}", r.to_f64());
        }
    }
}
