//! `lcp::on_basis::solve_on_basis`: the answer on a guessed basis, checked by
//! residual, with dependent columns dropped and violated indices exchanged.

use lcp::generate::p_matrix_lcp;
use lcp::on_basis::{solve_on_basis, BasisWorkspace};
use lcp::{lemke, Lcp, LemkeOptions};

#[test]
fn lemkes_basis_solves_its_problem_again_without_pivots() {
    let mut ws = BasisWorkspace::default();
    for seed in 0..20 {
        let lcp = p_matrix_lcp(12, seed);
        let sol = lemke::solve(&lcp, &LemkeOptions::default());
        assert!(sol.ok());
        let ans =
            solve_on_basis(&lcp, sol.basis.as_deref().unwrap(), 1e-9, None, &mut ws).expect("its own basis solves it");
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
    let ans = solve_on_basis(&lcp, &[true, true], 1e-9, None, &mut BasisWorkspace::default()).unwrap();
    assert_eq!(ans.dropped, 1);
    let z = &ans.solution.z;
    assert!((z[0] + z[1] - 1.0).abs() < 1e-15 && z.iter().all(|&v| v >= 0.0));
    assert!(ans.solution.residuals.residual < 1e-15);
    assert_eq!(ans.solution.basis.as_ref().unwrap().iter().filter(|&&b| b).count(), 1);
}

#[test]
fn a_wrong_basis_is_repaired_or_refused_never_accepted_wrong() {
    let mut ws = BasisWorkspace::default();
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
    let mut ws = BasisWorkspace::default();
    assert!(solve_on_basis(&lcp, &[true; 3], 1e-9, None, &mut ws).is_none());
}

/// `m` with every entry moved by `rel` of its size (a deterministic pattern).
fn perturbed(lcp: &Lcp, rel: f64) -> Lcp {
    let m: Vec<f64> = lcp.m().iter().enumerate().map(|(e, v)| v * (1.0 + rel * ((e % 7) as f64 - 3.0) / 3.0)).collect();
    Lcp::new(m, lcp.q().to_vec()).unwrap()
}

#[test]
fn the_kept_factorization_refines_to_answers_that_solve_the_new_problem() {
    refines_on_kept_factors(true);
}

/// Without polish a small kept block (here 12 indices at most) is refined by
/// products with its factors' inverse instead of triangular solves: the
/// same answers, to the same bounds.
#[test]
fn a_small_kept_block_refined_by_its_inverse_solves_the_new_problem() {
    refines_on_kept_factors(false);
}

fn refines_on_kept_factors(polish: bool) {
    use lcp::on_basis::{solve_on_basis_ruled, BasisTolerances};
    let tol = BasisTolerances { accept_tol: 1e-9, tight: 1e-9, loose: false, polish, more_rounds: true, eager_rows: 0 };
    // (With polish this is `solve_on_basis` at 1e-9.)
    let solve = |lcp: &Lcp, basis: &[bool], ws: &mut BasisWorkspace| solve_on_basis_ruled(lcp, basis, tol, None, ws);
    let mut ws = BasisWorkspace::default();
    let (mut reused, mut fresh) = (0, 0);
    for seed in 0..20 {
        let lcp = p_matrix_lcp(12, seed);
        let sol = lemke::solve(&lcp, &LemkeOptions::default());
        let first = solve(&lcp, sol.basis.as_deref().unwrap(), &mut ws).unwrap();
        assert!(!first.reused);
        // The next problem is a little different (a simulator's next step), or
        // far (the old factors cannot serve): either way the answer meets the
        // bound on the new problem, and agrees with Lemke's (P-matrix: unique).
        for rel in [1e-10, 1e-6, 0.3] {
            let next = perturbed(&lcp, rel);
            solve(&lcp, sol.basis.as_deref().unwrap(), &mut ws).unwrap();
            let Some(ans) = solve(&next, first.solution.basis.as_deref().unwrap(), &mut ws) else {
                continue;
            };
            let (z, w) = (&ans.solution.z, &ans.solution.w);
            let (w_exact, r) = lcp::Residuals::compute(&next, z);
            assert!(
                r.residual <= 1e-9 * (1.0 + next.q_norm_inf()),
                "seed {seed}, rel {rel}: residual {:e}",
                r.residual
            );
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

#[test]
fn a_violation_within_the_bound_is_still_exchanged_when_an_exchange_clears_it() {
    // M = I, q = [−1, −ε]: the basis {z₀} leaves w₁ = −ε. With ε = 1e-9 the
    // residual is within 1e-9·(1 + ‖q‖∞), but the violation is above the
    // repair threshold: z₁ enters and the answer is exact.
    let eps = 1e-9;
    let lcp = Lcp::new(vec![1.0, 0.0, 0.0, 1.0], vec![-1.0, -eps]).unwrap();
    let ans = solve_on_basis(&lcp, &[true, false], 1e-9, None, &mut BasisWorkspace::default()).unwrap();
    assert_eq!(ans.solution.basis.as_deref(), Some(&[true, true][..]));
    assert_eq!(ans.solution.z, vec![1.0, eps]);
    assert_eq!(ans.solution.residuals.residual, 0.0);
}

#[test]
fn an_entering_dependent_index_stays_and_its_partner_leaves() {
    // M = [[1, 1], [1, 1]] (singular), q = [−1, −1 − ε]: on {z₀}, w₁ = −ε,
    // within the bound but above the repair threshold. z₁ enters; the block
    // {z₀, z₁} is singular and the entering index is kept, so z₀ leaves:
    // z = (0, 1 + ε), w₀ = ε ≥ 0, exact.
    let eps = 1e-9;
    let lcp = Lcp::new(vec![1.0, 1.0, 1.0, 1.0], vec![-1.0, -1.0 - eps]).unwrap();
    let ans = solve_on_basis(&lcp, &[true, false], 1e-9, None, &mut BasisWorkspace::default()).expect("exact");
    assert_eq!(ans.solution.basis.as_deref(), Some(&[false, true][..]));
    assert_eq!(ans.solution.z, vec![0.0, 1.0 + eps]);
    assert_eq!(ans.solution.residuals.residual, 0.0);
}

#[test]
fn the_rule_through_an_operator_is_the_rule_on_the_dense_matrix() {
    use lcp::accept::{accepts, accepts_operator};
    for seed in 0..30 {
        let lcp = p_matrix_lcp(10, seed);
        let sol = lemke::solve(&lcp, &LemkeOptions::default());
        // The answer, and versions of it perturbed by growing amounts.
        for (k, scale) in [0.0, 1e-14, 1e-11, 1e-9, 1e-6].into_iter().enumerate() {
            let z: Vec<f64> =
                sol.z.iter().enumerate().map(|(j, v)| (v * (1.0 + scale * ((j + k) % 3) as f64)).max(0.0)).collect();
            let w = lcp.w_of(&z);
            for tol in [1e-12, 1e-9, 1e-6] {
                assert_eq!(
                    accepts_operator(&lcp, &z, &w, tol),
                    accepts(&lcp, &z, &w, tol),
                    "seed {seed}, scale {scale:e}, tol {tol:e}"
                );
            }
        }
    }
}

#[test]
fn an_answer_within_the_bound_is_kept_with_its_factors_when_exchanges_do_no_better() {
    // M = [[1, 1], [1, 1e-3]], q = [−1, −1 − ε]: on {z₀}, w₁ = −ε (within the
    // bound, above the repair threshold). Entering z₁ gives z₁ = −ε/0.999 < 0,
    // which leaves again: no exchange does better, the first answer is kept —
    // and its factorization with it, so the next call from its basis reuses it.
    let eps = 1e-9;
    let lcp = Lcp::new(vec![1.0, 1.0, 1.0, 1e-3], vec![-1.0, -1.0 - eps]).unwrap();
    let mut ws = BasisWorkspace::default();
    let first = solve_on_basis(&lcp, &[true, false], 1e-9, None, &mut ws).expect("within the bound");
    assert_eq!(first.solution.basis.as_deref(), Some(&[true, false][..]));
    assert_eq!(first.solution.z, vec![1.0, 0.0]);
    let again = solve_on_basis(&lcp, &[true, false], 1e-9, None, &mut ws).expect("within the bound");
    assert!(again.reused, "the kept answer's factors serve the next call");
    assert_eq!(again.solution.z, first.solution.z);
}

#[test]
fn an_answer_within_only_the_rules_bound_is_kept_with_its_factors_too() {
    use lcp::on_basis::{solve_on_basis_ruled, BasisTolerances};
    // As above with a normwise bound `tight` 100 times below the rule's: w₁ =
    // −6e-10 is within the rule's bound only (the `loose` last resort), and
    // no exchange does better. Its factorization is kept, so the next call
    // from its basis refines on it instead of factoring and exchanging again
    // (a resting stack met this answer on every step for thousands of steps).
    let eps = 6e-10;
    let lcp = Lcp::new(vec![1.0, 1.0, 1.0, 1e-3], vec![-1.0, -1.0 - eps]).unwrap();
    let tol =
        BasisTolerances { accept_tol: 1e-9, tight: 1e-11, loose: true, polish: true, more_rounds: true, eager_rows: 0 };
    let mut ws = BasisWorkspace::default();
    let first = solve_on_basis_ruled(&lcp, &[true, false], tol, None, &mut ws).expect("within the rule's bound");
    assert_eq!(first.solution.basis.as_deref(), Some(&[true, false][..]));
    assert_eq!(first.solution.z, vec![1.0, 0.0]);
    assert!(first.solution.residuals.residual > 1e-11 * 2.0, "not within the tight bound");
    let again = solve_on_basis_ruled(&lcp, &[true, false], tol, None, &mut ws).expect("within the rule's bound");
    assert!(again.reused, "the kept answer's factors serve the next call");
    assert_eq!(again.solution.z, first.solution.z);
    // Without the loose last resort there is no answer.
    let strict = BasisTolerances { loose: false, ..tol };
    assert!(solve_on_basis_ruled(&lcp, &[true, false], strict, None, &mut BasisWorkspace::default()).is_none());
}

#[test]
fn a_row_rejected_after_clipping_a_negative_z_sends_that_z_out_of_the_basis() {
    // An unloaded contact's friction in miniature: `a`, `b` two friction
    // directions, `l` the cone multiplier with the row `w_l = −a − b` (no
    // normal force). On the basis {a, b, l} the block solves to a = 5e-14,
    // b = −5e-14 (|b| far below the exchange threshold); clipping b leaves
    // w_l = −5e-14 on a row whose scale is that small: the rule rejects row l.
    // Exchanging l is undone by the next solve (the old rule ended there,
    // "the same index again"); b leaving gives the answer a = b = 0, l = 1e-13.
    let m = vec![2.0, 0.0, 1.0, 0.0, 2.0, 1.0, -1.0, -1.0, 0.0];
    let lcp = Lcp::new(m, vec![-1e-13, 1e-13, 0.0]).unwrap();
    let ans = solve_on_basis(&lcp, &[true, true, true], 1e-9, None, &mut BasisWorkspace::default())
        .expect("b leaves and the basis {a, l} solves it");
    assert_eq!(ans.solution.basis.as_deref(), Some(&[true, false, true][..]));
    assert_eq!(ans.solution.pivots, 0);
    assert!(ans.solution.accepted && lcp::accept::accepts(&lcp, &ans.solution.z, &lcp.w_of(&ans.solution.z), 1e-9));
    // The solution set is {a = b = 0, l ≥ 1e-13}, a·w_a = 0 fixing l = 1e-13 once a is basic.
    let z = &ans.solution.z;
    assert!(z[0].abs() <= 1e-28 && z[1] == 0.0 && (z[2] - 1e-13).abs() <= 1e-28, "{z:?}");
}
