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
