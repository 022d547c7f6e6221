//! One complementary basis of a structured LCP, factored once and kept while
//! the operator keeps its sparsity.
//!
//! A simulator's island whose contacts do not change keeps the pattern of
//! `G`, `H` and `K` from step to step (only the values of `J` and `M_b⁻¹`
//! move), and on a resting heap it keeps its basis too. Its augmented basis
//! matrix (the one of [`super::factor`], without `z0`) then has the same
//! pattern each step and values that differ by the bodies' small motion, so
//! the last factorization solves the new matrix by iterative refinement
//! (`x ← x + LU⁻¹ (b − A x)`, `A` the new matrix) in a few sparse solves,
//! with no ordering and no numeric factorization. When refinement does not
//! reach round-off within [`KeptOptions::refine_steps`], the matrix is
//! factored again numerically in the kept column order (fresh if the fill
//! grows), and refined on those factors. The answer is a basis's answer
//! like any other: the caller judges it by the acceptance rule.

use super::factor::FILL_SLACK;
use super::lu::{Csc, Order, SparseLu};
use super::operator::StructuredLcp;

/// Options of [`KeptBasis::solve`], defaults documented on each field.
#[derive(Clone, Debug, PartialEq)]
pub struct KeptOptions {
    /// Refinement steps on the kept factors before the matrix is factored
    /// again, and on the new factors after. Default 4.
    pub refine_steps: usize,
    /// Refinement stops at this backward error `‖b − A x‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)`.
    /// Default 1e-15 (about five units of round-off).
    pub backward_tol: f64,
    /// The kept factors' answer is taken at this backward error when
    /// refinement stalls before [`KeptOptions::backward_tol`]; beyond it the
    /// matrix is factored again. Default 1e-13.
    pub kept_tol: f64,
}

impl Default for KeptOptions {
    fn default() -> Self {
        KeptOptions { refine_steps: 4, backward_tol: 1e-15, kept_tol: 1e-13 }
    }
}

/// The complementary basis `{z_j : j ∈ α} ∪ {w_i : i ∉ α}` of a structured
/// LCP, its augmented matrix and its factorization.
pub struct KeptBasis {
    n: usize,
    p: usize,
    in_alpha: Vec<bool>,
    /// The augmented matrix the values were last built for, and a buffer for the next.
    a: Csc,
    next: Csc,
    lu: SparseLu,
    /// Fill `nnz(L + U) / nnz(A)` of the last fresh order.
    fill_fresh: f64,
}

/// What [`KeptBasis::solve`] found.
#[derive(Clone, Debug)]
pub struct KeptAnswer {
    /// The basic value at each position `i`: `z_i` for `i ∈ α`, else `w_i`.
    pub values: Vec<f64>,
    /// Whether the matrix was factored again (numerically) for it.
    pub refactored: bool,
    /// Backward error of the basis solve.
    pub backward: f64,
}

impl KeptBasis {
    /// The basis `alpha` (`alpha[j]`: `z_j` basic) of `op`, factored in a
    /// fresh order; `None` when it is singular.
    pub fn new(op: &StructuredLcp, alpha: &[bool]) -> Option<Self> {
        let (n, p) = (op.n(), op.p());
        if alpha.len() != n {
            return None;
        }
        let mut b = KeptBasis {
            n,
            p,
            in_alpha: alpha.to_vec(),
            a: Csc::default(),
            next: Csc::default(),
            lu: SparseLu::new(n + p),
            fill_fresh: 0.0,
        };
        build(op, &b.in_alpha, &mut b.a);
        b.factor_fresh().then_some(b)
    }

    /// Whether this is the basis `alpha`.
    pub fn is(&self, alpha: &[bool]) -> bool {
        self.in_alpha == alpha
    }

    /// The basis (`alpha[j]`: `z_j` basic).
    pub fn alpha(&self) -> &[bool] {
        &self.in_alpha
    }

    /// The basis's answer on `op` (same sparsity as the operator it was
    /// factored for): its basic values, from `q`. `None` when `op` has
    /// another pattern, or the basis is singular or its values not finite.
    pub fn solve(&mut self, op: &StructuredLcp, o: &KeptOptions) -> Option<KeptAnswer> {
        if op.n() != self.n || op.p() != self.p {
            return None;
        }
        build(op, &self.in_alpha, &mut self.next);
        if self.next.ptr != self.a.ptr || self.next.idx != self.a.idx {
            return None;
        }
        std::mem::swap(&mut self.a, &mut self.next);
        let mut b = op.q().to_vec();
        b.resize(self.n + self.p, 0.0);
        let (x, eta, stalled) = self.refined(&b, o);
        if eta <= o.backward_tol || (stalled && eta <= o.kept_tol) {
            return Some(self.answer(x, false, eta));
        }
        // The kept order's numeric factors, or a fresh order's.
        let kept = self.lu.factor(&self.a, Order::Kept)
            && (self.lu.nnz() as f64) <= FILL_SLACK * self.fill_fresh * self.a.idx.len().max(1) as f64;
        if !kept && !self.factor_fresh() {
            return None;
        }
        let (x, eta, _) = self.refined(&b, o);
        x.iter().all(|v| v.is_finite()).then(|| self.answer(x, true, eta))
    }

    /// `x = A⁻¹ b` on the current factors, refined on `A` up to
    /// `refine_steps` times; with its backward error and whether refinement
    /// stalled (a step that did not halve it).
    fn refined(&self, b: &[f64], o: &KeptOptions) -> (Vec<f64>, f64, bool) {
        let a = &self.a;
        let dim = b.len();
        // ‖A‖∞ (row sums) and ‖b‖∞.
        let mut rows = vec![0.0f64; dim];
        for j in 0..dim {
            for e in a.ptr[j]..a.ptr[j + 1] {
                rows[a.idx[e]] += a.val[e].abs();
            }
        }
        let a_norm = rows.iter().fold(0.0f64, |m, &v| m.max(v));
        let b_norm = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut x = b.to_vec();
        self.lu.solve_in_place(&mut x);
        let mut r = vec![0.0; dim];
        let mut last = f64::INFINITY;
        for step in 0..=o.refine_steps {
            // r = b − A x
            r.copy_from_slice(b);
            for (j, &xj) in x.iter().enumerate() {
                if xj != 0.0 {
                    for e in a.ptr[j]..a.ptr[j + 1] {
                        r[a.idx[e]] -= a.val[e] * xj;
                    }
                }
            }
            let x_norm = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let eta = r.iter().fold(0.0f64, |m, v| m.max(v.abs())) / (a_norm * x_norm + b_norm).max(f64::MIN_POSITIVE);
            if !eta.is_finite() {
                return (x, f64::INFINITY, true);
            }
            let stalled = eta > 0.5 * last;

            if eta <= o.backward_tol || stalled || step == o.refine_steps {
                return (x, eta, stalled);
            }
            last = eta;
            self.lu.solve_in_place(&mut r);
            x.iter_mut().zip(&r).for_each(|(x, d)| *x += d);
        }
        unreachable!("the loop returns at its last step")
    }

    fn answer(&self, x: Vec<f64>, refactored: bool, backward: f64) -> KeptAnswer {
        let mut values = x;
        values.truncate(self.n);
        KeptAnswer { values, refactored, backward }
    }

    /// Factors `self.a` in a fresh order and records its fill.
    fn factor_fresh(&mut self) -> bool {
        let ok = self.lu.factor(&self.a, Order::Fresh);
        self.fill_fresh = if ok { self.lu.fill(&self.a) } else { 0.0 };
        ok
    }
}

/// The augmented matrix of the complementary basis `in_alpha` of `op` into
/// `a`, as [`super::factor`] builds it: position `i` holds `z_i`'s column
/// (`−K`'s rows, then `H`'s at `n + k`) or `w_i`'s unit column, then the `p`
/// columns of `u` (`−G`'s rows, `−1` at `n + k`); rows ascending.
fn build(op: &StructuredLcp, in_alpha: &[bool], a: &mut Csc) {
    let (n, p) = (op.n(), op.p());
    a.clear();
    for (j, &z) in in_alpha.iter().enumerate() {
        if z {
            for (i, k) in op.k_cols.iter(j) {
                a.idx.push(i);
                a.val.push(-k);
            }
            for (k, h) in op.h_cols.iter(j) {
                a.idx.push(n + k);
                a.val.push(h);
            }
        } else {
            a.idx.push(j);
            a.val.push(1.0);
        }
        a.end_column();
    }
    for k in 0..p {
        for (i, g) in op.g_cols.iter(k) {
            a.idx.push(i);
            a.val.push(-g);
        }
        a.idx.push(n + k);
        a.val.push(-1.0);
        a.end_column();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structured::Entry;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Entries of a random `M = G H + K` (`K` with a unit diagonal, so that
    /// every complementary basis is likely regular), their values moved by `eps`.
    fn entries(n: usize, p: usize, seed: u64, eps: f64) -> (Vec<Entry>, Vec<Entry>, Vec<Entry>, Vec<f64>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut wiggle = ChaCha8Rng::seed_from_u64(seed + 7919);
        let mut v = |r: &mut ChaCha8Rng| r.random_range(-1.0..1.0) * (1.0 + eps * wiggle.random_range(-1.0..1.0));
        let (mut g, mut h, mut k) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            for _ in 0..3 {
                let d = rng.random_range(0..p);
                g.push((i, d, v(&mut rng)));
                h.push((d, i, v(&mut rng)));
            }
            k.push((i, i, 2.0 + v(&mut rng)));
        }
        let q = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        (g, h, k, q)
    }

    /// `M_α z_α = −q_α`, `w = M z + q` from the dense `M`: the basis's answer.
    fn dense_answer(op: &StructuredLcp, alpha: &[bool]) -> Vec<f64> {
        let n = op.n();
        let lcp = op.to_dense();
        let idx: Vec<usize> = (0..n).filter(|&j| alpha[j]).collect();
        let m = idx.len();
        // Gaussian elimination with partial pivoting on [M_αα | −q_α].
        let mut a: Vec<Vec<f64>> =
            idx.iter().map(|&i| idx.iter().map(|&j| lcp.m()[i * n + j]).chain([-op.q()[i]]).collect()).collect();
        for c in 0..m {
            let r = (c..m).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs())).unwrap();
            a.swap(c, r);
            for r in c + 1..m {
                let f = a[r][c] / a[c][c];
                for k in c..=m {
                    a[r][k] -= f * a[c][k];
                }
            }
        }
        let mut za = vec![0.0; m];
        for c in (0..m).rev() {
            za[c] = (a[c][m] - (c + 1..m).map(|k| a[c][k] * za[k]).sum::<f64>()) / a[c][c];
        }
        let mut z = vec![0.0; n];
        idx.iter().zip(&za).for_each(|(&j, &v)| z[j] = v);
        let w = lcp.w_of(&z);
        (0..n).map(|i| if alpha[i] { z[i] } else { w[i] }).collect()
    }

    /// Factored on one operator, solved on one whose values moved by 1e-9
    /// (and, beyond what refinement bridges, by 0.3): the basic values are
    /// the dense solve's of the new operator to round-off, from the kept
    /// factors first and from new ones after a large change.
    #[test]
    fn kept_factors_solve_the_new_values() {
        for seed in 0..6 {
            let (n, p) = (60, 24);
            let (g, h, k, q) = entries(n, p, seed, 0.0);
            let mut op = StructuredLcp::refillable(p, &g, &h, &k, q).unwrap();
            let mut rng = ChaCha8Rng::seed_from_u64(100 + seed);
            let alpha: Vec<bool> = (0..n).map(|_| rng.random_bool(0.5)).collect();
            let mut kept = KeptBasis::new(&op, &alpha).expect("regular");
            assert!(kept.is(&alpha));
            for (eps, refactored) in [(1e-9, false), (0.3, true)] {
                let (g, h, k, q) = entries(n, p, seed, eps);
                assert!(op.refill(&g, &h, &k, &q).unwrap());
                let fresh = StructuredLcp::new(p, &g, &h, &k, q.clone()).unwrap();
                for i in 0..n {
                    for j in 0..n {
                        assert_eq!(op.at(i, j).to_bits(), fresh.at(i, j).to_bits(), "seed {seed}: refilled = built");
                    }
                }
                let got = kept.solve(&op, &KeptOptions::default()).expect("solved");
                assert_eq!(got.refactored, refactored, "seed {seed}, eps {eps}: backward {:e}", got.backward);
                let want = dense_answer(&op, &alpha);
                let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let gap = got.values.iter().zip(&want).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(gap <= 1e-10 * scale, "seed {seed}, eps {eps}: {gap:e} of {scale:e}");
            }
        }
    }

    /// Another pattern (an entry moved) is refused by the refill and by the kept basis.
    #[test]
    fn another_pattern_is_refused() {
        let (n, p) = (30, 10);
        let (g, h, k, q) = entries(n, p, 3, 0.0);
        let mut op = StructuredLcp::refillable(p, &g, &h, &k, q.clone()).unwrap();
        let alpha: Vec<bool> = (0..n).map(|j| j % 2 == 0).collect();
        let mut kept = KeptBasis::new(&op, &alpha).expect("regular");
        let mut moved = g.clone();
        moved[0].1 = (moved[0].1 + 1) % p;
        assert!(!op.refill(&moved, &h, &k, &q).unwrap());
        let other = StructuredLcp::refillable(p, &moved, &h, &k, q).unwrap();
        assert!(kept.solve(&other, &KeptOptions::default()).is_none());
    }
}
