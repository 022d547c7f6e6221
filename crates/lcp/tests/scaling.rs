//! Diagonal scaling: exactness of power-of-two factors, what Ruiz achieves,
//! the friction-cone scaling, and the one fact everything rests on — a
//! positive diagonal scaling maps the solution set onto itself.

use lcp::contact::ContactLayout;
use lcp::enumerate::{all_solutions, is_solution};
use lcp::generate::{p_matrix_lcp, spd_lcp};
use lcp::{newton_fb, Lcp, NewtonFbOptions, Scaling};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::generate::contact_lcp;

fn is_power_of_two(f: f64) -> bool {
    f.is_finite() && f > 0.0 && f.to_bits() & ((1u64 << 52) - 1) == 0
}

/// A dense random LCP whose rows and columns span many orders of magnitude.
fn badly_scaled(n: usize, seed: u64, spread: i32) -> Lcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let r: Vec<f64> = (0..n).map(|_| 2f64.powi(rng.random_range(-spread..=spread))).collect();
    let c: Vec<f64> = (0..n).map(|_| 2f64.powi(rng.random_range(-spread..=spread))).collect();
    let m: Vec<f64> = (0..n * n)
        .map(|e| r[e / n] * c[e % n] * rng.random_range(0.1..1.0) * if rng.random_bool(0.5) { 1.0 } else { -1.0 })
        .collect();
    let q = (0..n).map(|i| r[i] * rng.random_range(-1.0..1.0)).collect();
    Lcp::new(m, q).unwrap()
}

fn row_col_max(lcp: &Lcp) -> (Vec<f64>, Vec<f64>) {
    let n = lcp.n();
    let rows = (0..n).map(|i| lcp.row(i).iter().fold(0.0f64, |m, v| m.max(v.abs()))).collect();
    let cols = (0..n).map(|j| (0..n).fold(0.0f64, |m, i| m.max(lcp.at(i, j).abs()))).collect();
    (rows, cols)
}

/// Same sets of vectors, up to `tol` entrywise (relative to 1 + |entry|).
fn same_sets(a: &[Vec<f64>], b: &[Vec<f64>], tol: f64) -> bool {
    let close = |x: &Vec<f64>, y: &Vec<f64>| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= tol * (1.0 + p.abs()));
    a.len() == b.len() && a.iter().all(|x| b.iter().any(|y| close(x, y)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn ruiz_factors_are_powers_of_two_and_equilibrate(n in 1usize..=12, seed in any::<u64>(), spread in 0i32..=30) {
        let lcp = badly_scaled(n, seed, spread);
        let s = Scaling::ruiz(&lcp, 40);
        prop_assert!(s.row.iter().chain(&s.col).all(|&f| is_power_of_two(f)));
        let scaled = s.apply(&lcp);
        // Exact: every scaled entry is r_i m_ij c_j with no rounding.
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(scaled.at(i, j), s.row[i] * lcp.at(i, j) * s.col[j]);
                prop_assert_eq!(scaled.at(i, j) / s.row[i] / s.col[j], lcp.at(i, j));
            }
        }
        // Equilibrated up to the power-of-two rounding: every row and column max in [1/4, 4].
        let (rows, cols) = row_col_max(&scaled);
        for v in rows.iter().chain(&cols) {
            prop_assert!((0.25..=4.0).contains(v), "row/col max {v} (rows {rows:?}, cols {cols:?})");
        }
    }

    #[test]
    fn ruiz_of_symmetric_matrix_is_symmetric(n in 1usize..=12, seed in any::<u64>()) {
        let lcp = spd_lcp(n, seed);
        let s = Scaling::ruiz(&lcp, 20);
        prop_assert_eq!(&s.row, &s.col);
        let scaled = s.apply(&lcp);
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(scaled.at(i, j), scaled.at(j, i));
            }
        }
    }

    /// z ↦ D_c⁻¹ z and w ↦ D_r w are exact inverses of z_back / w_back for
    /// power-of-two factors, and w' = D_r w holds bit for bit.
    #[test]
    fn power_of_two_round_trip_is_exact(n in 1usize..=10, seed in any::<u64>(), exps in prop::collection::vec(-40i32..=40, 20)) {
        let lcp = p_matrix_lcp(n, seed);
        let s = Scaling { row: exps[..n].iter().map(|&e| 2f64.powi(e)).collect(), col: exps[10..10 + n].iter().map(|&e| 2f64.powi(e)).collect() };
        let scaled = s.apply(&lcp);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let z: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let z_scaled = s.z_forward(&z);
        prop_assert_eq!(s.z_back(&z_scaled), z.clone());
        let w = lcp.w_of(&z);
        let w_scaled = scaled.w_of(&z_scaled);
        prop_assert_eq!(s.w_forward(&w), w_scaled.clone());
        prop_assert_eq!(s.w_back(&w_scaled), w);
    }

    /// The solution set of the scaled problem is exactly D_c⁻¹ (solution set):
    /// enumerate both (random M, so often several or no solutions) and compare.
    #[test]
    fn scaling_maps_solution_sets_onto_each_other(n in 1usize..=6, seed in any::<u64>(), exps in prop::collection::vec(-6i32..=6, 12), s_factor in 0.3f64..3.0) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let m: Vec<f64> = (0..n * n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let q: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let lcp = Lcp::new(m, q).unwrap();
        // Arbitrary positive factors, not only powers of two.
        let s = Scaling {
            row: exps[..n].iter().map(|&e| s_factor * 2f64.powi(e)).collect(),
            col: exps[6..6 + n].iter().map(|&e| 2f64.powi(e) / s_factor).collect(),
        };
        let scaled = s.apply(&lcp);
        let original = all_solutions(&lcp, 1e-9);
        let mapped: Vec<Vec<f64>> = all_solutions(&scaled, 1e-9).iter().map(|z| s.z_back(z)).collect();
        prop_assert!(same_sets(&original, &mapped, 1e-6), "original {original:?} vs mapped {mapped:?}");
        for z in &mapped {
            prop_assert!(is_solution(&lcp, z, 1e-6));
        }
    }
}

#[test]
fn solving_the_ruiz_scaled_problem_solves_the_original() {
    for seed in 0..20 {
        // A P-matrix stays a P-matrix under positive diagonal scaling: one solution.
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut bad = || (0..8).map(|_| 2f64.powi(rng.random_range(-12..=12))).collect::<Vec<f64>>();
        let lcp = Scaling { row: bad(), col: bad() }.apply(&p_matrix_lcp(8, seed));
        let s = Scaling::ruiz(&lcp, 20);
        let scaled = s.apply(&lcp);
        let o = NewtonFbOptions { equilibrate: false, ..NewtonFbOptions::default() };
        let sol = newton_fb::solve(&scaled, &o);
        assert!(sol.ok(), "seed {seed}");
        // (z, w) of the original are the maps back, consistent with w = M z + q.
        let z = s.z_back(&sol.z);
        let w = s.w_back(&sol.w);
        assert_eq!(w, lcp.w_of(&z), "power-of-two scaling commutes with rounding");
        // A residual of 1e-12 in scaled units is at most 1e-12 · max(1/r, c) in original ones.
        let tol = 1e-12 * s.row.iter().map(|r| 1.0 / r).chain(s.col.iter().copied()).fold(1.0, f64::max);
        assert!(is_solution(&lcp, &z, tol), "seed {seed}");
        let unique = all_solutions(&lcp, tol);
        assert_eq!(unique.len(), 1);
        assert!(same_sets(&unique, &[z], 1e-6));
    }
}

#[test]
fn zero_rows_and_columns_keep_factor_one() {
    // Row 1 and column 1 are zero; the rest is badly scaled.
    let m = vec![1e6, 0.0, 3e3, 0.0, 0.0, 0.0, 2e-4, 0.0, 5e-6];
    let lcp = Lcp::new(m, vec![1.0, -1.0, 1.0]).unwrap();
    let s = Scaling::ruiz(&lcp, 30);
    assert_eq!(s.row[1], 1.0);
    assert_eq!(s.col[1], 1.0);
    assert!(s.row[0] < 1.0 && s.row[2] > 1.0);
    let (rows, cols) = row_col_max(&s.apply(&lcp));
    for i in [0, 2] {
        assert!((0.25..=4.0).contains(&rows[i]) && (0.25..=4.0).contains(&cols[i]), "{rows:?} {cols:?}");
    }
    // The zero matrix: identity.
    let zero = Lcp::new(vec![0.0; 4], vec![1.0, 2.0]).unwrap();
    assert!(Scaling::ruiz(&zero, 10).is_identity());
}

#[test]
fn ruiz_with_zero_iterations_or_balanced_input_is_identity() {
    let lcp = badly_scaled(5, 1, 20);
    assert_eq!(Scaling::ruiz(&lcp, 0), Scaling::identity(5));
    let balanced = Lcp::new(vec![1.0, -1.0, 0.5, 1.0], vec![0.0, 0.0]).unwrap();
    assert!(Scaling::ruiz(&balanced, 10).is_identity());
    assert_eq!(Scaling::identity(5).apply(&lcp), lcp);
}

#[test]
fn cone_scaling_is_d_m_d_of_the_unscaled_contact_lcp() {
    for seed in 0..10 {
        for (nc, k) in [(1, 8), (2, 8), (4, 8), (3, 4), (6, 5)] {
            for s in [1.0, 0.5, 1e-3, 1e-6, 0.01] {
                let unscaled = contact_lcp(nc, k, 1.0, seed);
                let d = ContactLayout::new(nc, k).cone_scaling(s);
                let layout = ContactLayout { nc, k };
                assert_eq!(d.n(), layout.n());
                assert_eq!(d.row, d.col);
                assert!(d.row[layout.fn_range()].iter().chain(&d.row[layout.fd_range()]).all(|&f| f == 1.0));
                assert!(d.row[layout.lambda_range()].iter().all(|&f| f == s));
                // Bit-for-bit the generator's scaled problem.
                assert_eq!(d.apply(&unscaled), contact_lcp(nc, k, s, seed), "seed {seed} nc {nc} k {k} s {s}");
            }
        }
    }
}

#[test]
fn cone_scaling_leaves_forces_and_divides_lambda_by_s() {
    // One contact, k = 4 (n = 6): enumerate every basic solution of both problems.
    for seed in 0..30 {
        let (nc, k, s) = (1, 4, 1e-3);
        let unscaled = contact_lcp(nc, k, 1.0, seed);
        let d = ContactLayout::new(nc, k).cone_scaling(s);
        let scaled = d.apply(&unscaled);
        let a = all_solutions(&unscaled, 1e-10);
        let b = all_solutions(&scaled, 1e-10);
        assert!(!a.is_empty(), "the contact LCP has a solution (seed {seed})");
        let mapped: Vec<Vec<f64>> = b.iter().map(|z| d.z_back(z)).collect();
        assert!(same_sets(&a, &mapped, 1e-7), "seed {seed}: {a:?} vs {mapped:?}");
        // λ_scaled = λ / s, fn and fd unchanged.
        for z in &b {
            let back = d.z_back(z);
            assert_eq!(back[..nc + nc * k], z[..nc + nc * k]);
            assert_eq!(back[nc + nc * k], z[nc + nc * k] * s);
        }
    }
}

#[test]
fn try_apply_rejects_wrong_sizes_and_overflow() {
    let lcp = spd_lcp(3, 0);
    assert!(Scaling::identity(2).try_apply(&lcp).is_err());
    let s = Scaling { row: vec![1.0; 3], col: vec![1.0; 4] };
    assert!(s.try_apply(&lcp).is_err());
    let s = Scaling { row: vec![f64::MAX; 3], col: vec![f64::MAX; 3] };
    assert!(s.try_apply(&lcp).is_err());
    let s = Scaling { row: vec![f64::NAN; 3], col: vec![1.0; 3] };
    assert!(s.try_apply(&lcp).is_err());
}

#[test]
#[should_panic(expected = "Scaling::apply")]
fn apply_panics_only_on_misuse() {
    let _ = Scaling::identity(2).apply(&spd_lcp(3, 0));
}
