//! A rank-revealing principal LU: the one factorization that makes a
//! complementary basis regular, for the dense Lemke's warm start
//! (`lemke::subbasis`) and for the body-space check of a guessed basis
//! ([`super::solve_on_basis`]).
//!
//! A complementary basis keeps rows and columns paired (`w_j = 0` exactly
//! where `z_j` is basic), so dependent indices must leave as row *and*
//! column: Gaussian elimination with diagonal pivoting on the Schur
//! complement, choosing at each step its largest diagonal entry, until the
//! remaining diagonal is below [`RANK_TOL`] of the block's largest entry.
//! The pivots taken index a regular principal block `M_ββ`; the others are
//! the dependent indices (statically indeterminate contact: four corners of a
//! box on a box bear a load that three constraints fix).

use crate::kernels::{dot4, LANES};

/// Pivots below this fraction of the block's largest entry count as zero.
pub(crate) const RANK_TOL: f64 = 1e-11;

/// Factors the `k × k` row-major block `a` in place by elimination with
/// diagonal pivoting; `order` gets the pivot order (positions `0..k`), its
/// first `rank` entries (the return value) indexing the regular block. Rows
/// and columns are moved as pivots are taken, so `a` ends as the packed LU
/// of `a[order, order]` (multipliers below the diagonal); read it with
/// [`solve`]. With `first`, that position is the first pivot if it can be
/// (an index entering a basis stays, and a dependent one leaves instead).
pub(crate) fn factor(a: &mut [f64], k: usize, order: &mut Vec<usize>, first: Option<usize>) -> usize {
    let amax = a[..k * k].iter().fold(0.0f64, |x, v| x.max(v.abs()));
    order.clear();
    order.extend(0..k);
    // `[..done]`: pivots taken; the rest is the Schur complement.
    let mut done = 0;
    while done < k {
        let (at, piv) = match first.filter(|&f| done == 0 && f < k && a[f * k + f].abs() > RANK_TOL * amax) {
            Some(f) => (f, a[f * k + f]),
            None => (done..k)
                .map(|t| (t, a[t * k + t]))
                .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
                .expect("a remaining index"),
        };
        if !(piv.abs() > RANK_TOL * amax) {
            break;
        }
        if at != done {
            swap_symmetric(a, k, done, at);
            order.swap(done, at);
        }
        let p = done;
        done += 1;
        // Eliminate pivot p from the remaining rows (the multiplier is kept
        // where the eliminated entry was).
        let (top, below) = a.split_at_mut(done * k);
        let pivot_row = &top[p * k + done..p * k + k];
        for row in below.chunks_exact_mut(k) {
            let f = row[p] / piv;
            row[p] = f;
            if f != 0.0 {
                for (x, &u) in row[done..].iter_mut().zip(pivot_row) {
                    *x -= f * u;
                }
            }
        }
    }
    done
}

/// Swaps rows and columns `i` and `j` of the `k × k` block `a`.
fn swap_symmetric(a: &mut [f64], k: usize, i: usize, j: usize) {
    for c in 0..k {
        a.swap(i * k + c, j * k + c);
    }
    for r in 0..k {
        a.swap(r * k + i, r * k + j);
    }
}

/// Solves `M_ββ x = b` with the factors of [`factor`] (`β = order[..rank]`):
/// `x[p]` for `p ∈ β` from `b[p]` in place (other entries untouched);
/// `y` is scratch.
pub(crate) fn solve(a: &[f64], k: usize, order: &[usize], rank: usize, x: &mut [f64], y: &mut Vec<f64>) {
    y.clear();
    y.extend(order[..rank].iter().map(|&p| x[p]));
    solve_pivoted(a, k, rank, y);
    for (t, &p) in order[..rank].iter().enumerate() {
        x[p] = y[t];
    }
}

/// [`solve`] on `y` in pivot order (`y[t]` the entry of position `order[t]`).
fn solve_pivoted(a: &[f64], k: usize, rank: usize, y: &mut [f64]) {
    // L y = b. (The rows' sums over four lanes: a sequential sum waits on one
    // add after another, and these solves were a fifth of a resting stack's
    // step in wall time — `perf record` on `many_bodies stack10` — though
    // only 8 % of its instructions.)
    for t in 0..rank {
        let s = dot4(&a[t * k..t * k + t], &y[..t]);
        y[t] -= s;
    }
    // U x = y, backwards.
    for t in (0..rank).rev() {
        let s = dot4(&a[t * k + t + 1..t * k + rank], &y[t + 1..rank]);
        y[t] = (y[t] - s) / a[t * k + t];
    }
}

/// The length of a column of [`inverse`]'s `X`: `rank` up to a power of
/// two of at least [`LANES`] (a product over 12 rows compiled to lanes
/// shuffled between registers; 16 do not).
pub(crate) fn inverse_stride(rank: usize) -> usize {
    rank.next_power_of_two().max(LANES)
}

/// The inverse `X = M_ββ⁻¹` of the factors of [`factor`], in pivot order
/// (`x_t = Σ_s X_ts b_s` for `b_s`, `x_t` the entries of positions
/// `order[s]`, `order[t]`), column after column into `inv`, each column
/// [`inverse_stride`] entries long (zeros after row `rank`: a product
/// [`inverse_times`] then runs over whole lanes), formed by the same solves
/// as [`solve`]'s (`col` is scratch). Returns `e` such that, in the standard
/// model of rounding (Higham, *Accuracy and Stability of Numerical
/// Algorithms*, ch. 8–9), `|fl(X b)_t − x̂_t| ≤ e·‖b‖∞` for every `b` and
/// `t`, where `x̂` is [`solve`]'s answer: `e = 3 r (r + 2) ε κ ‖X‖∞` with
/// `r` the rank and `κ = ‖L‖∞ ‖U‖∞ ‖X‖∞` (`x̂` and each column of `X` are
/// within `2 (r + 1) ε κ` of their exact values, relative to `‖X‖∞ ‖b‖∞` and
/// `‖X‖∞`; the product's own rounding, in any order of its sums, is
/// `r ε ‖X‖∞ ‖b‖∞`). Infinite when `r ε κ` is not below 1e-6 (a block that
/// ill-conditioned gets no bound) or an entry is not finite.
pub(crate) fn inverse(a: &[f64], k: usize, rank: usize, inv: &mut Vec<f64>, col: &mut Vec<f64>) -> f64 {
    let stride = inverse_stride(rank);
    inv.clear();
    inv.resize(rank * stride, 0.0);
    for (s, x) in inv.chunks_exact_mut(stride).enumerate() {
        col.clear();
        col.resize(rank, 0.0);
        col[s] = 1.0;
        solve_pivoted(a, k, rank, col);
        x[..rank].copy_from_slice(col);
    }
    let max_row_sum = |row: &dyn Fn(usize) -> f64| (0..rank).fold(0.0f64, |m, t| m.max(row(t)));
    let abs_sum = |t: usize, cols: std::ops::Range<usize>| cols.map(|j| a[t * k + j].abs()).sum::<f64>();
    let l = max_row_sum(&|t| 1.0 + abs_sum(t, 0..t));
    let u = max_row_sum(&|t| abs_sum(t, t..rank));
    let x = max_row_sum(&|t| (0..rank).map(|s| inv[s * stride + t].abs()).sum());
    let (r, eps) = (rank as f64, f64::EPSILON);
    let kappa = l * u * x;
    if r * eps * kappa < 1e-6 && inv.iter().all(|v| v.is_finite()) {
        3.0 * r * (r + 2.0) * eps * kappa * x
    } else {
        f64::INFINITY
    }
}

/// The largest rank [`inverse_times`] takes.
pub(crate) const INVERSE_TIMES_MAX: usize = 16;

/// `y = X b` for the `X` of [`inverse`] (rank `r` ≤ [`INVERSE_TIMES_MAX`],
/// `b` and `y` in pivot order, `r` entries each): column by column over
/// whole lanes, even and odd columns summed apart (two chains of adds, not
/// one); returns `‖y‖∞`.
pub(crate) fn inverse_times(inv: &[f64], r: usize, b: &[f64], y: &mut Vec<f64>) -> f64 {
    match inverse_stride(r) {
        4 => times::<4>(inv, r, b, y),
        8 => times::<8>(inv, r, b, y),
        16 => times::<16>(inv, r, b, y),
        _ => panic!("inverse_times: rank {r} above {INVERSE_TIMES_MAX}"),
    }
}

/// [`inverse_times`] with columns `S` entries long.
fn times<const S: usize>(inv: &[f64], r: usize, b: &[f64], y: &mut Vec<f64>) -> f64 {
    let (mut even, mut odd) = ([0.0f64; S], [0.0f64; S]);
    let (cols, b) = (inv[..r * S].as_chunks::<S>().0, &b[..r]);
    for p in 0..r / 2 {
        let (c0, c1, b0, b1) = (&cols[2 * p], &cols[2 * p + 1], b[2 * p], b[2 * p + 1]);
        for t in 0..S {
            even[t] += b0 * c0[t];
            odd[t] += b1 * c1[t];
        }
    }
    if r % 2 == 1 {
        let (c, v) = (&cols[r - 1], b[r - 1]);
        for t in 0..S {
            even[t] += v * c[t];
        }
    }
    // (Rows from `r` on are sums of the columns' zero padding: 0.)
    let sum: [f64; S] = std::array::from_fn(|t| even[t] + odd[t]);
    y.clear();
    y.extend_from_slice(&sum[..r]);
    sum.iter().fold(0.0f64, |m, v| crate::kernels::pick_max(m, v.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonsymmetric_block_with_a_zero_diagonal() {
        // [[2, 1, 1], [1, 3, −1], [−1, 1, 0]]: regular, zero diagonal entry last.
        let m = [2.0, 1.0, 1.0, 1.0, 3.0, -1.0, -1.0, 1.0, 0.0];
        let x_true = [0.5, -2.0, 3.0];
        let b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| m[i * 3 + j] * x_true[j]).sum()).collect();
        let (mut a, mut order) = (m.to_vec(), Vec::new());
        assert_eq!(factor(&mut a, 3, &mut order, None), 3);
        let mut x = b.clone();
        solve(&a, 3, &order, 3, &mut x, &mut Vec::new());
        for (u, v) in x.iter().zip(x_true) {
            assert!((u - v).abs() < 1e-14, "{x:?}");
        }
    }

    #[test]
    fn a_dependent_index_is_left_out_and_the_rest_solved() {
        // Row/column 2 = row/column 0 + row/column 1 (symmetric PSD, rank 2).
        let m = [2.0, 1.0, 3.0, 1.0, 2.0, 3.0, 3.0, 3.0, 6.0];
        let (mut a, mut order) = (m.to_vec(), Vec::new());
        assert_eq!(factor(&mut a, 3, &mut order, None), 2);
        // The largest diagonal (6) is the first pivot.
        assert_eq!(order[0], 2);
        let beta = [order[0], order[1]];
        let x_true = [0.0; 3].map(|_| 0.0);
        let mut x = [0.0; 3];
        // M_ββ x_β = b_β with x_β = (1, −1).
        let mut xb = x_true;
        xb[beta[0]] = 1.0;
        xb[beta[1]] = -1.0;
        for &i in &beta {
            x[i] = beta.iter().map(|&j| m[i * 3 + j] * xb[j]).sum();
        }
        solve(&a, 3, &order, 2, &mut x, &mut Vec::new());
        for &i in &beta {
            assert!((x[i] - xb[i]).abs() < 1e-14, "{x:?}");
        }
    }

    /// The inverse's product is within its returned bound of the solves'
    /// answer, on blocks from well to badly conditioned (the bound is what
    /// lets a refinement step judge a correction by the product alone), and
    /// a block too ill-conditioned for the bound to mean anything gets none.
    #[test]
    fn the_inverse_product_is_within_its_bound_of_the_solves() {
        for (n, seed) in [(3, 1), (5, 6), (7, 2), (11, 3), (16, 4), (30, 5)] {
            let lcp = crate::generate::p_matrix_lcp(n, seed);
            for spread in [0.0, 1.0, 2.0, 4.0] {
                // Rows and columns scaled over `spread` decades: conditioning grows.
                let d: Vec<f64> = (0..n).map(|i| 10f64.powf(spread * i as f64 / n as f64)).collect();
                let m: Vec<f64> = (0..n * n).map(|e| lcp.m()[e] * d[e / n] * d[e % n]).collect();
                let (mut a, mut order) = (m.clone(), Vec::new());
                let rank = factor(&mut a, n, &mut order, None);
                assert_eq!(rank, n);
                let (mut inv, mut col) = (Vec::new(), Vec::new());
                let e = inverse(&a, n, rank, &mut inv, &mut col);
                if spread > 2.0 && e.is_infinite() {
                    continue;
                }
                assert!(e.is_finite(), "n {n} spread {spread}");
                for trial in 0..20 {
                    let b: Vec<f64> = (0..n).map(|i| ((i * 7 + trial * 13) as f64 * 0.61).sin() * 1e-3).collect();
                    let mut x = b.clone();
                    solve(&a, n, &order, rank, &mut x, &mut Vec::new());
                    let bmax = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for t in 0..n {
                        let xb: f64 = (0..n).map(|s| inv[s * inverse_stride(n) + t] * b[order[s]]).sum();
                        let gap = (xb - x[order[t]]).abs();
                        assert!(gap <= e * bmax, "n {n} spread {spread}: {gap:e} > {:e}", e * bmax);
                    }
                    // The product the refinement uses, in pivot order, and its ‖y‖∞.
                    if n <= INVERSE_TIMES_MAX {
                        let bp: Vec<f64> = order.iter().map(|&p| b[p]).collect();
                        let mut y = Vec::new();
                        let ymax = inverse_times(&inv, n, &bp, &mut y);
                        assert_eq!(y.len(), n);
                        for (t, &yt) in y.iter().enumerate() {
                            let gap = (yt - x[order[t]]).abs();
                            assert!(gap <= e * bmax, "n {n} spread {spread}: {gap:e} > {:e}", e * bmax);
                        }
                        assert_eq!(ymax, y.iter().fold(0.0f64, |m, v| m.max(v.abs())));
                    }
                }
            }
        }
        // Nearly singular: [[1, 1], [1, 1 + 1e-10]] has κ ~ 4e10.
        let (mut a, mut order) = (vec![1.0, 1.0, 1.0, 1.0 + 1e-10], Vec::new());
        let rank = factor(&mut a, 2, &mut order, None);
        assert_eq!(rank, 2);
        assert_eq!(inverse(&a, 2, rank, &mut Vec::new(), &mut Vec::new()), f64::INFINITY);
    }
}
