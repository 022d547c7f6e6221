//! A regular complementary basis on the support of a singular one.
//!
//! A resting stack's answer is statically indeterminate: four corner
//! contacts per interface carry a load that three independent normal
//! constraints determine, so the previous step's complementary set `α` may
//! have a singular block `M_αα`, and a warm start from it cannot be factored.
//! Gaussian elimination with diagonal (principal) pivoting finds a largest
//! well-conditioned principal block `M_ββ`, `β ⊆ α`: the `z_j` left out
//! become nonbasic at 0 and their `w_j` basic. As `q_α` lies in the range of
//! `M_αα` for a consistent system, `z_β` solves the rows left out too, and the
//! residual check after the solve has the last word anyway.

use crate::on_basis::principal;

/// Keeps in `alpha` a subset `β` whose block `M_ββ` (`m(i, j)` for
/// `i, j ∈ β`) has rank `|β|` = the numerical rank found by the principal
/// factorization of [`crate::on_basis::principal`] (largest diagonal pivot of
/// the remaining Schur complement first). `a` is scratch. Returns the number
/// of indices dropped.
pub(crate) fn regular_subset(m: impl Fn(usize, usize) -> f64, alpha: &mut Vec<usize>, a: &mut Vec<f64>) -> usize {
    let k = alpha.len();
    a.clear();
    a.extend((0..k * k).map(|e| m(alpha[e / k], alpha[e % k])));
    let mut order = Vec::with_capacity(k);
    let done = principal::factor(a, k, &mut order, None);
    let mut keep = order[..done].to_vec();
    keep.sort_unstable();
    let dropped = k - done;
    let kept: Vec<usize> = keep.iter().map(|&t| alpha[t]).collect();
    *alpha = kept;
    dropped
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_a_dependent_index_and_keeps_a_regular_one() {
        // Rows 0, 1 independent, row 2 = row 0 + row 1 (symmetric PSD, rank 2).
        let g = [[2.0, 1.0, 3.0], [1.0, 2.0, 3.0], [3.0, 3.0, 6.0]];
        let mut alpha = vec![4, 7, 9];
        let mut a = Vec::new();
        let pos = |j: usize| [4, 7, 9].iter().position(|&x| x == j).unwrap();
        let dropped = regular_subset(|i, j| g[pos(i)][pos(j)], &mut alpha, &mut a);
        assert_eq!(dropped, 1);
        assert_eq!(alpha.len(), 2);
        // Any two of the three are independent here; the largest pivot (6) is kept.
        assert!(alpha.contains(&9));
    }

    #[test]
    fn a_zero_diagonal_is_reached_through_the_schur_complement() {
        // [[1, 1], [−1, 0]]: regular, with a zero diagonal entry.
        let g = [[1.0, 1.0], [-1.0, 0.0]];
        let mut alpha = vec![0, 1];
        assert_eq!(regular_subset(|i, j| g[i][j], &mut alpha, &mut Vec::new()), 0);
        assert_eq!(alpha, vec![0, 1]);
    }
}
