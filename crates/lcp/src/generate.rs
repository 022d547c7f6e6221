//! Seeded generators of test matrices and LCPs. Every random generator takes a
//! `seed` and is deterministic per seed (ChaCha8), across platforms. Contact
//! LCPs come from bodies and contacts, so their generators live next to the
//! simulator (`sim::generate`): this crate never sees a body.
//!
//! - [`p_matrix_lcp`], [`spd_lcp`]: random LCPs with a unique solution.
//! - [`permuted_triangular_lcp`]: ill-conditioned P-matrix LCPs (cond up to 1e20).
//! - [`murty`]: Murty's (1978) example, on which Lemke's method takes 2ⁿ pivots;
//!   [`murty_unit`]: the same matrix with `q = −1`.
//! - [`infeasible_lcp`], [`infeasible_examples`]: LCPs without a solution.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::problem::Lcp;

fn uniform_matrix(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n * n).map(|_| rng.random_range(-1.0..=1.0)).collect()
}

fn uniform_vector(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-1.0..=1.0)).collect()
}

/// `A Aᵀ / n`, exactly symmetric (upper triangle mirrored).
fn gram(a: &[f64], n: usize) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in i..n {
            let v = crate::problem::dot(&a[i * n..(i + 1) * n], &a[j * n..(j + 1) * n]) / n as f64;
            m[i * n + j] = v;
            m[j * n + i] = v;
        }
    }
    m
}

fn build(m: Vec<f64>, q: Vec<f64>, what: &str) -> Lcp {
    match Lcp::new(m, q) {
        Ok(lcp) => lcp,
        Err(e) => panic!("{what}: {e}"),
    }
}

/// A random LCP with a nonsymmetric positive definite — hence P — matrix:
/// `M = A Aᵀ/n + ½ I + (B − Bᵀ)/√n` (`A`, `B` uniform in [−1, 1]), whose
/// symmetric part `A Aᵀ/n + ½ I` is positive definite; `q` uniform in [−1, 1].
/// Unique solution for every `q`.
///
/// # Panics
/// If `n == 0`.
pub fn p_matrix_lcp(n: usize, seed: u64) -> Lcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let a = uniform_matrix(&mut rng, n);
    let b = uniform_matrix(&mut rng, n);
    let q = uniform_vector(&mut rng, n);
    let mut m = gram(&a, n);
    let skew = 1.0 / (n as f64).sqrt();
    for i in 0..n {
        m[i * n + i] += 0.5;
        for j in 0..n {
            m[i * n + j] += skew * (b[i * n + j] - b[j * n + i]);
        }
    }
    build(m, q, "p_matrix_lcp")
}

/// A random ill-conditioned P-matrix LCP: `M = P T Pᵀ` with `T` upper
/// triangular — diagonal uniform in [0.05, 1], each entry above it nonzero
/// with probability ½ and then uniform in [−100, 100] — and `P` a random
/// permutation; `q` uniform in [−1e-3, 1e-3]. Every principal submatrix of
/// `T` is triangular with a positive diagonal, so `M` is a P-matrix (unique
/// solution), while the off-diagonal growth makes cond(M) 1e10–1e20 for
/// n ≈ 12–20 (the family of the acceptance-rule tests, where floating-point Lemke meets false
/// rays). `(M, cond∞(M))` with cond∞ = ‖M‖∞‖M⁻¹‖∞ evaluated in floating point.
///
/// # Panics
/// If `n == 0`.
pub fn permuted_triangular_lcp(n: usize, seed: u64) -> (Lcp, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut t = vec![0.0; n * n];
    for i in 0..n {
        t[i * n + i] = rng.random_range(0.05..=1.0);
        for j in i + 1..n {
            if rng.random_bool(0.5) {
                t[i * n + j] = rng.random_range(-100.0..=100.0);
            }
        }
    }
    let mut perm: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        perm.swap(i, rng.random_range(0..=i));
    }
    let q: Vec<f64> = (0..n).map(|_| rng.random_range(-1e-3..=1e-3)).collect();
    // ‖T⁻¹‖∞ by back substitution, column by column.
    let mut inv_norm = vec![0.0f64; n];
    for c in 0..n {
        let mut x = vec![0.0; n];
        for i in (0..=c).rev() {
            let s: f64 = (i + 1..=c).map(|j| t[i * n + j] * x[j]).sum();
            x[i] = (if i == c { 1.0 } else { 0.0 } - s) / t[i * n + i];
        }
        (0..n).for_each(|i| inv_norm[i] += x[i].abs());
    }
    let norm = (0..n).map(|i| t[i * n..(i + 1) * n].iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let cond = norm * inv_norm.iter().fold(0.0f64, |a, &v| a.max(v));
    let m = (0..n * n).map(|k| t[perm[k / n] * n + perm[k % n]]).collect();
    (build(m, q, "permuted_triangular_lcp"), cond)
}

/// A random LCP with an exactly symmetric positive definite matrix:
/// `M = A Aᵀ/n + 0.1 I` (`A` uniform in [−1, 1], so cond(M) ≲ 40); `q` uniform in [−1, 1].
///
/// # Panics
/// If `n == 0`.
pub fn spd_lcp(n: usize, seed: u64) -> Lcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let a = uniform_matrix(&mut rng, n);
    let q = uniform_vector(&mut rng, n);
    let mut m = gram(&a, n);
    for i in 0..n {
        m[i * n + i] += 0.1;
    }
    build(m, q, "spd_lcp")
}

/// Murty's `M̃(n)`: lower triangular, 1 on the diagonal and 2 below it. A
/// P-matrix (every principal submatrix is again of this form, determinant 1).
fn murty_matrix(n: usize) -> Vec<f64> {
    (0..n * n)
        .map(|e| match (e / n).cmp(&(e % n)) {
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Greater => 2.0,
            std::cmp::Ordering::Less => 0.0,
        })
        .collect()
}

/// Murty's example on which Lemke's method takes 2ⁿ pivots (K. G. Murty,
/// "Computational complexity of complementary pivot methods", Math.
/// Programming Study 7, 1978): `M̃(n)` lower triangular with 1 on the diagonal
/// and 2 below it, `q̃_j = −(2ⁿ + 2ⁿ⁻¹ + … + 2ⁿ⁻ʲ⁺¹)` (1-based `j`), i.e.
/// `q̃ = (−2ⁿ, −2ⁿ − 2ⁿ⁻¹, …, −(2ⁿ⁺¹ − 2))`.
///
/// `M̃` is a P-matrix, so the solution is unique: `z = (2ⁿ, 0, …, 0)` with
/// `w = (0, 2ⁿ⁻¹, 2ⁿ⁻², …, 2)`. Lemke's method with covering vector 1 on the
/// problem as given visits 2ⁿ bases (measured with this crate's Lemke without
/// equilibration, both pivoting rules, n ≤ 8); equilibration changes the
/// effective covering vector and the path becomes short. All data are exact
/// for `n ≤ 52`. See [`murty_unit`] for the `q = −1` form.
///
/// # Panics
/// If `n == 0`.
pub fn murty(n: usize) -> Lcp {
    let q = (1..=n).map(|j| -((n + 1 - j)..=n).map(|i| 2f64.powi(i as i32)).sum::<f64>()).collect();
    build(murty_matrix(n), q, "murty")
}

/// Murty's matrix `M̃(n)` (see [`murty`]) with `q = −1`, the form found in
/// LCP test collections: unique solution `z = e₁ = (1, 0, …, 0)`,
/// `w = (0, 1, …, 1)`. Not hard for Lemke (2 pivots, measured). The
/// transposed-order variant (2 above the diagonal) is the same problem with the
/// indices reversed, solution `(0, …, 0, 1)`.
///
/// # Panics
/// If `n == 0`.
pub fn murty_unit(n: usize) -> Lcp {
    build(murty_matrix(n), vec![-1.0; n], "murty_unit")
}

/// The smallest LCP without a solution: `M = [−1]`, `q = [−1]` (`w = −z − 1 < 0`).
pub fn infeasible_lcp() -> Lcp {
    build(vec![-1.0], vec![-1.0], "infeasible_lcp")
}

/// LCPs without a solution, each with a name, all `{z ≥ 0 : M z + q ≥ 0}` empty
/// (a Farkas certificate `y ≥ 0`, `Mᵀ y ≤ 0`, `qᵀ y < 0` is in the name).
/// The last two have copositive-plus `M`, for which Lemke's method must end in
/// ray termination — which then proves infeasibility.
pub fn infeasible_examples() -> Vec<(&'static str, Lcp)> {
    vec![
        ("negative scalar M=[-1] q=[-1]; y=(1)", infeasible_lcp()),
        (
            "PSD M=[[1,-1],[-1,1]] q=[-1,-1]; y=(1,1)",
            build(vec![1.0, -1.0, -1.0, 1.0], vec![-1.0, -1.0], "infeasible_examples"),
        ),
        (
            "skew M=[[0,1],[-1,0]] q=[1,-1]; y=(0,1)",
            build(vec![0.0, 1.0, -1.0, 0.0], vec![1.0, -1.0], "infeasible_examples"),
        ),
    ]
}
