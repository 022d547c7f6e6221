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

/// Pivots below this fraction of the block's largest entry count as zero.
const RANK_TOL: f64 = 1e-11;

/// Keeps in `alpha` a subset `β` whose block `M_ββ` (`m(i, j)` for
/// `i, j ∈ β`) has rank `|β|` = the numerical rank found, choosing at each
/// step the largest diagonal pivot of the remaining Schur complement.
/// `a` is scratch. Returns the number of indices dropped.
pub(crate) fn regular_subset(m: impl Fn(usize, usize) -> f64, alpha: &mut Vec<usize>, a: &mut Vec<f64>) -> usize {
    let k = alpha.len();
    a.clear();
    a.extend((0..k * k).map(|e| m(alpha[e / k], alpha[e % k])));
    let amax = a.iter().fold(0.0f64, |x, v| x.max(v.abs()));
    // `order[..done]`: pivots taken; the rest are still in the Schur complement.
    let mut order: Vec<usize> = (0..k).collect();
    let mut done = 0;
    while done < k {
        let (at, piv) = order[done..]
            .iter()
            .enumerate()
            .map(|(t, &i)| (done + t, a[i * k + i]))
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
            .expect("a remaining index");
        if !(piv.abs() > RANK_TOL * amax) {
            break;
        }
        order.swap(done, at);
        let p = order[done];
        done += 1;
        // Eliminate pivot p from the remaining rows and columns.
        for &r in &order[done..] {
            let f = a[r * k + p] / piv;
            if f != 0.0 {
                for &c in &order[done..] {
                    a[r * k + c] -= f * a[p * k + c];
                }
            }
        }
    }
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
