//! `lcp::support::solve_on_basis`: the answer on a guessed basis, checked by
//! residual, with dependent columns dropped and violated indices exchanged.

use lcp::generate::p_matrix_lcp;
use lcp::support::{solve_on_basis, SupportWorkspace};
use lcp::{lemke, LemkeOptions, Lcp};

#[test]
fn lemkes_basis_solves_its_problem_again_without_pivots() {
    let mut ws = SupportWorkspace::default();
    for seed in 0..20 {
        let lcp = p_matrix_lcp(12, seed);
        let sol = lemke::solve(&lcp, &LemkeOptions::default());
        assert!(sol.ok());
        let ans = solve_on_basis(&lcp, sol.basis.as_deref().unwrap(), 1e-9, None, &mut ws).expect("its own basis solves it");
        assert_eq!(ans.solution.pivots, 0);
        assert_eq!(ans.dropped, 0);
        for (a, b) in ans.solution.z.iter().zip(&sol.z) {
            assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }
}

#[test]
fn a_dependent_column_is_dropped_and_the_answer_checked() {
    // Two identical constraints bear one load: M = [[1, 1], [1, 1]], q = [−1, −1].
    // Both basic is singular; one of them carries the load, the other is 0.
    let lcp = Lcp::new(vec![1.0, 1.0, 1.0, 1.0], vec![-1.0, -1.0]).unwrap();
    let ans = solve_on_basis(&lcp, &[true, true], 1e-9, None, &mut SupportWorkspace::default()).unwrap();
    assert_eq!(ans.dropped, 1);
    let z = &ans.solution.z;
    assert!((z[0] + z[1] - 1.0).abs() < 1e-15 && z.iter().all(|&v| v >= 0.0));
    assert!(ans.solution.residuals.residual < 1e-15);
    assert_eq!(ans.solution.basis.as_ref().unwrap().iter().filter(|&&b| b).count(), 1);
}

#[test]
fn a_wrong_basis_is_repaired_or_refused_never_accepted_wrong() {
    let mut ws = SupportWorkspace::default();
    let (mut repaired, mut refused) = (0, 0);
    for seed in 0..40 {
        let lcp = p_matrix_lcp(10, seed);
        let guess: Vec<bool> = (0..10).map(|j| (j + seed as usize) % 3 == 0).collect();
        match solve_on_basis(&lcp, &guess, 1e-9, None, &mut ws) {
            Some(ans) => {
                // Whatever it returns solves the LCP: the unique solution of a P-matrix LCP.
                let exact = lemke::solve(&lcp, &LemkeOptions::default());
                let (w, r) = lcp::Residuals::compute(&lcp, &ans.solution.z);
                assert!(r.residual <= 1e-9 * (1.0 + lcp.q_norm_inf()), "residual {:e}", r.residual);
                assert!(w.iter().zip(&ans.solution.w).all(|(a, b)| (a - b).abs() < 1e-12));
                for (a, b) in ans.solution.z.iter().zip(&exact.z) {
                    assert!((a - b).abs() <= 1e-8 * (1.0 + b.abs()));
                }
                repaired += 1;
            }
            None => refused += 1,
        }
    }
    // The exchanges find the answer from a wrong guess on some problems.
    assert!(repaired > 0, "never repaired ({refused} refused)");
}

#[test]
fn wrong_length_or_non_finite_blocks_are_refused() {
    let lcp = p_matrix_lcp(4, 1);
    let mut ws = SupportWorkspace::default();
    assert!(solve_on_basis(&lcp, &[true; 3], 1e-9, None, &mut ws).is_none());
}

/// `m` with every entry moved by `rel` of its size (a deterministic pattern).
fn perturbed(lcp: &Lcp, rel: f64) -> Lcp {
    let m: Vec<f64> = lcp.m().iter().enumerate().map(|(e, v)| v * (1.0 + rel * ((e % 7) as f64 - 3.0) / 3.0)).collect();
    Lcp::new(m, lcp.q().to_vec()).unwrap()
}

#[test]
fn the_kept_factorization_refines_to_answers_that_solve_the_new_problem() {
    let mut ws = SupportWorkspace::default();
    let (mut reused, mut fresh) = (0, 0);
    for seed in 0..20 {
        let lcp = p_matrix_lcp(12, seed);
        let sol = lemke::solve(&lcp, &LemkeOptions::default());
        let first = solve_on_basis(&lcp, sol.basis.as_deref().unwrap(), 1e-9, None, &mut ws).unwrap();
        assert!(!first.reused);
        // The next problem is a little different (a simulator's next step), or
        // far (the old factors cannot serve): either way the answer meets the
        // bound on the new problem, and agrees with Lemke's (P-matrix: unique).
        for rel in [1e-10, 1e-6, 0.3] {
            let next = perturbed(&lcp, rel);
            solve_on_basis(&lcp, sol.basis.as_deref().unwrap(), 1e-9, None, &mut ws).unwrap();
            let Some(ans) = solve_on_basis(&next, first.solution.basis.as_deref().unwrap(), 1e-9, None, &mut ws) else {
                continue;
            };
            let (z, w) = (&ans.solution.z, &ans.solution.w);
            let (w_exact, r) = lcp::Residuals::compute(&next, z);
            assert!(r.residual <= 1e-9 * (1.0 + next.q_norm_inf()), "seed {seed}, rel {rel}: residual {:e}", r.residual);
            assert!(w.iter().zip(&w_exact).all(|(a, b)| (a - b).abs() < 1e-12));
            let exact = lemke::solve(&next, &LemkeOptions::default());
            for (a, b) in z.iter().zip(&exact.z) {
                assert!((a - b).abs() <= 1e-8 * (1.0 + b.abs()), "seed {seed}, rel {rel}: {a} vs {b}");
            }
            if ans.reused {
                reused += 1;
            } else {
                fresh += 1;
            }
        }
    }
    // Small changes reuse the factors; a 30 % change needs fresh ones.
    assert!(reused >= 40 && fresh > 0, "reused {reused}, fresh {fresh}");
}

/// A deterministic pseudo-random value in [−1, 1) from `(seed, k)`.
fn uniform(seed: u64, k: u64) -> f64 {
    let mut x = (seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ k.wrapping_mul(0xD1B5_4A32_D192_ED03)) | 1;
    for _ in 0..3 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
    }
    2.0 * ((x >> 11) as f64 / (1u64 << 53) as f64) - 1.0
}

#[test]
fn answers_are_accepted_by_the_componentwise_rule_on_every_row() {
    // Rows of very different scales: the rule judges each on its own scale,
    // not against ‖q‖∞ (a normwise bound would pass a 1e-6 row that is 100 % wrong).
    let mut ws = SupportWorkspace::default();
    let mut answered = 0;
    for seed in 0..40 {
        let base = p_matrix_lcp(10, seed);
        let r: Vec<f64> = (0..10).map(|i| if i % 3 == 0 { 1e-6 } else { 1e3 }).collect();
        let m: Vec<f64> = base.m().iter().enumerate().map(|(e, v)| v * r[e / 10]).collect();
        let q: Vec<f64> = base.q().iter().zip(&r).map(|(v, s)| v * s).collect();
        let lcp = Lcp::new(m, q).unwrap();
        let guess: Vec<bool> = (0..10).map(|j| (j + seed as usize) % 2 == 0).collect();
        if let Some(ans) = solve_on_basis(&lcp, &guess, 1e-9, None, &mut ws) {
            let z = &ans.solution.z;
            assert!(lcp::accept::accepts(&lcp, z, &lcp.w_of(z), 1e-9), "seed {seed}");
            answered += 1;
        }
    }
    assert!(answered > 0);
}

#[test]
fn exchanges_on_rank_deficient_problems_end_on_a_solution_or_refuse() {
    // M = B Bᵀ (positive semidefinite, rank 3 of 6: dependent columns, as
    // statically indeterminate contact makes them), random q; from wrong
    // guesses the exchanges end on one of the solutions the enumeration
    // finds, accepted by the rule, or give up — never on a non-solution.
    let (n, rank) = (6, 3);
    let mut ws = SupportWorkspace::default();
    let (mut solved, mut exchanged) = (0, 0);
    for seed in 0..60u64 {
        let b: Vec<f64> = (0..n * rank).map(|k| uniform(seed, k as u64)).collect();
        let m: Vec<f64> = (0..n * n).map(|e| (0..rank).map(|t| b[(e / n) * rank + t] * b[(e % n) * rank + t]).sum()).collect();
        let q: Vec<f64> = (0..n).map(|i| uniform(seed, 1000 + i as u64)).collect();
        let lcp = Lcp::new(m, q).unwrap();
        let solutions = lcp::enumerate::all_solutions(&lcp, 1e-9);
        let guess: Vec<bool> = (0..n).map(|j| (j as u64 + seed) % 3 == 0).collect();
        let Some(ans) = solve_on_basis(&lcp, &guess, 1e-9, None, &mut ws) else { continue };
        let z = &ans.solution.z;
        assert!(lcp::accept::accepts(&lcp, z, &lcp.w_of(z), 1e-9), "seed {seed}: {z:?}");
        assert!(lcp::enumerate::is_solution(&lcp, z, 1e-9), "seed {seed}");
        assert!(solutions.iter().any(|s| s.iter().zip(z).all(|(a, b)| (a - b).abs() <= 1e-8 * (1.0 + a.abs()))), "seed {seed}: {z:?} not among {solutions:?}");
        solved += 1;
        exchanged += usize::from(ans.solution.basis.as_deref() != Some(&guess[..]));
    }
    assert!(solved >= 20 && exchanged >= 10, "solved {solved}, with exchanges {exchanged}");
}
