//! PGS and Newton–Fischer–Burmeister against enumeration (the ground truth for
//! n ≤ 8), on degenerate and hopeless problems, and their never-NaN contract.

use lcp::enumerate::{all_solutions, is_solution};
use lcp::generate::{infeasible_examples, murty, murty_unit, p_matrix_lcp, spd_lcp};
use lcp::{newton_fb, pgs, Lcp, NewtonFbOptions, PgsOptions, Solution, Status};
use proptest::prelude::*;
use sim::generate::contact_lcp;

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// The shared contract: sizes right, finite, residuals consistent with z.
fn assert_contract(lcp: &Lcp, s: &Solution) {
    assert_eq!(s.z.len(), lcp.n());
    assert_eq!(s.w.len(), lcp.n());
    assert!(s.z.iter().chain(&s.w).all(|v| v.is_finite()), "non-finite output: {s:?}");
    assert_eq!(s.w, lcp.w_of(&s.z));
    if s.status == Status::Solved {
        assert!(s.residuals.residual.is_finite());
    }
}

/// The unique solution of a P-matrix LCP, by enumeration.
fn unique_solution(lcp: &Lcp) -> Vec<f64> {
    let sols = all_solutions(lcp, 1e-9);
    assert_eq!(sols.len(), 1, "a P-matrix LCP has exactly one solution, got {sols:?}");
    sols.into_iter().next().unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn pgs_solves_spd_and_matches_enumeration(n in 1usize..=8, seed in any::<u64>()) {
        let lcp = spd_lcp(n, seed);
        let s = pgs::solve(&lcp, &PgsOptions::default());
        assert_contract(&lcp, &s);
        prop_assert_eq!(s.status, Status::Solved);
        prop_assert!(s.residuals.residual <= 1e-10);
        // Natural residual 1e-10 and cond(M) ≤ ~40 bound the error by ~1e-8.
        prop_assert!(max_diff(&s.z, &unique_solution(&lcp)) < 1e-7);
    }

    #[test]
    fn sor_converges_for_spd_with_omega_in_0_2(n in 1usize..=8, seed in any::<u64>(), omega in 0.3f64..1.7) {
        let lcp = spd_lcp(n, seed);
        let o = PgsOptions { omega, ..PgsOptions::default() };
        let s = pgs::solve(&lcp, &o);
        prop_assert_eq!(s.status, Status::Solved);
        prop_assert!(max_diff(&s.z, &unique_solution(&lcp)) < 1e-7);
    }

    #[test]
    fn newton_solves_p_matrix_and_matches_enumeration(n in 1usize..=8, seed in any::<u64>()) {
        let lcp = p_matrix_lcp(n, seed);
        let s = newton_fb::solve(&lcp, &NewtonFbOptions::default());
        assert_contract(&lcp, &s);
        prop_assert_eq!(s.status, Status::Solved, "{:?}", s);
        prop_assert!(s.residuals.residual <= 1e-12);
        prop_assert!(max_diff(&s.z, &unique_solution(&lcp)) < 1e-9);
    }

    #[test]
    fn newton_solves_spd_and_matches_enumeration(n in 1usize..=8, seed in any::<u64>()) {
        let lcp = spd_lcp(n, seed);
        let s = newton_fb::solve(&lcp, &NewtonFbOptions::default());
        prop_assert_eq!(s.status, Status::Solved);
        prop_assert!(max_diff(&s.z, &unique_solution(&lcp)) < 1e-9);
    }

    /// Random contact LCPs: zero diagonal, may be unsolvable for PGS; never NaN.
    #[test]
    fn contact_lcps_never_produce_nan(nc in 1usize..=6, seed in any::<u64>(), log_s in -6.0f64..0.0) {
        let lcp = contact_lcp(nc, 8, 10f64.powf(log_s), seed);
        let o = PgsOptions { max_iterations: 200, ..PgsOptions::default() };
        let p = pgs::solve(&lcp, &o);
        assert_contract(&lcp, &p);
        prop_assert!(matches!(p.status, Status::Solved | Status::MaxIterations | Status::Numerical));
        let o = NewtonFbOptions { max_iterations: 50, ..NewtonFbOptions::default() };
        let nfb = newton_fb::solve(&lcp, &o);
        assert_contract(&lcp, &nfb);
        prop_assert!(matches!(nfb.status, Status::Solved | Status::MaxIterations | Status::Numerical));
        for s in [&p, &nfb] {
            if s.ok() {
                prop_assert!(is_solution(&lcp, &s.z, 1e-10));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Every variant of the step (plain Newton or Levenberg–Marquardt, with or
    /// without equilibration) converges on P-matrices.
    #[test]
    fn newton_variants_solve_p_matrix(n in 1usize..=8, seed in any::<u64>(), lm in prop::sample::select(vec![0.0, 0.01, 1.0]), eq in any::<bool>()) {
        let lcp = p_matrix_lcp(n, seed);
        let o = NewtonFbOptions { lm_factor: lm, equilibrate: eq, ..NewtonFbOptions::default() };
        let s = newton_fb::solve(&lcp, &o);
        prop_assert_eq!(s.status, Status::Solved);
        prop_assert!(max_diff(&s.z, &unique_solution(&lcp)) < 1e-9);
    }

    /// Badly scaled rows and columns (factors 2^±10) do not stop the default
    /// (equilibrating) Newton; its answer is judged in the units given, and
    /// mapped back it is the original problem's solution up to the scaling's
    /// amplification of that tolerance.
    #[test]
    fn newton_is_robust_to_diagonal_scaling(n in 2usize..=8, seed in any::<u64>(), exps in prop::collection::vec(-10i32..=10, 16)) {
        let base = spd_lcp(n, seed);
        let sc = lcp::Scaling { row: exps[..n].iter().map(|&e| 2f64.powi(e)).collect(), col: exps[8..8 + n].iter().map(|&e| 2f64.powi(e)).collect() };
        let lcp = sc.apply(&base);
        let s = newton_fb::solve(&lcp, &NewtonFbOptions { tol: 1e-9, ..NewtonFbOptions::default() });
        prop_assert_eq!(s.status, Status::Solved);
        prop_assert!(s.residuals.residual <= 1e-9);
        // z* = D_c z'; a residual of 1e-9 in scaled units is at most 1e-9·2^10 in original ones.
        let z = sc.z_back(&s.z);
        prop_assert!(max_diff(&z, &unique_solution(&base)) < 1e-4);
    }
}

#[test]
fn newton_warm_start() {
    let lcp = p_matrix_lcp(10, 4);
    let o = NewtonFbOptions::default();
    let cold = newton_fb::solve(&lcp, &o);
    assert!(cold.ok() && cold.pivots > 1);
    // From the solution: nothing to do.
    let warm = newton_fb::solve_from(&lcp, &cold.z, &o);
    assert_eq!((warm.status, warm.pivots), (Status::Solved, 0));
    // From a perturbed solution: fewer steps than cold.
    let near: Vec<f64> = cold.z.iter().map(|z| z + 1e-4).collect();
    let warm = newton_fb::solve_from(&lcp, &near, &o);
    assert!(warm.ok() && warm.pivots < cold.pivots, "{} vs {}", warm.pivots, cold.pivots);
    // Unusable starts are ignored.
    assert_eq!(newton_fb::solve_from(&lcp, &[1.0], &o), cold);
    assert_eq!(newton_fb::solve_from(&lcp, &[f64::NAN; 10], &o), cold);
}

#[test]
fn newton_solves_most_contact_lcps() {
    // Measured: 100 % at nc ≤ 4 and s ∈ {1, 1e-3}; the floor here guards regressions.
    for s in [1.0, 1e-3] {
        for nc in [1, 2, 4] {
            let solved = (0..50)
                .filter(|&seed| {
                    let lcp = contact_lcp(nc, 8, s, seed);
                    let r = newton_fb::solve(&lcp, &NewtonFbOptions::default());
                    r.ok() && is_solution(&lcp, &r.z, 1e-12)
                })
                .count();
            assert!(solved >= 47, "s = {s}, nc = {nc}: {solved}/50");
        }
    }
}

#[test]
fn larger_problems_converge() {
    for seed in 0..5 {
        let lcp = spd_lcp(60, seed);
        let n = newton_fb::solve(&lcp, &NewtonFbOptions::default());
        assert_eq!(n.status, Status::Solved, "seed {seed}");
        assert!(n.pivots < 30, "Newton took {} steps", n.pivots);
        let p = pgs::solve(&lcp, &PgsOptions::default());
        assert_eq!(p.status, Status::Solved, "seed {seed}");
        assert!(max_diff(&n.z, &p.z) < 1e-7);

        let lcp = p_matrix_lcp(60, seed);
        let n = newton_fb::solve(&lcp, &NewtonFbOptions::default());
        assert_eq!(n.status, Status::Solved, "seed {seed}");
    }
}

#[test]
fn trivial_q_nonnegative_is_solved_at_zero_without_iterating() {
    let lcp = Lcp::new(vec![2.0, 1.0, 1.0, 2.0], vec![0.5, 0.0]).unwrap();
    for s in [pgs::solve(&lcp, &PgsOptions::default()), newton_fb::solve(&lcp, &NewtonFbOptions::default())] {
        assert_eq!(s.status, Status::Solved);
        assert_eq!(s.pivots, 0);
        assert_eq!(s.z, vec![0.0, 0.0]);
    }
}

#[test]
fn pgs_solves_1x1_in_one_sweep() {
    // z = −q/M exactly.
    let lcp = Lcp::new(vec![4.0], vec![-2.0]).unwrap();
    let s = pgs::solve(&lcp, &PgsOptions::default());
    assert_eq!((s.status, s.pivots), (Status::Solved, 1));
    assert_eq!(s.z, vec![0.5]);
}

#[test]
fn pgs_skips_zero_and_negative_diagonal_rows() {
    // Row 0 has M_00 = 0 and needs z_0 > 0 — PGS cannot provide it.
    let lcp = Lcp::new(vec![0.0, 1.0, -1.0, 1.0], vec![-1.0, 1.0]).unwrap();
    let s = pgs::solve(&lcp, &PgsOptions { max_iterations: 50, ..PgsOptions::default() });
    assert_contract(&lcp, &s);
    assert_eq!(s.status, Status::MaxIterations);
    assert_eq!(s.z[0], 0.0);
    assert_eq!(s.pivots, 50);

    // Negative diagonal: skipped as well; the LCP M=[-1], q=[-1] has no solution anyway.
    let lcp = Lcp::new(vec![-1.0], vec![-1.0]).unwrap();
    let s = pgs::solve(&lcp, &PgsOptions { max_iterations: 10, ..PgsOptions::default() });
    assert_eq!(s.status, Status::MaxIterations);
    assert_eq!(s.z, vec![0.0]);

    // A skipped row whose w is already ≥ 0 at z_i = 0 does not prevent a solution:
    // M = [[0, 0], [0, 2]], q = [1, −1] → z = (0, ½).
    let lcp = Lcp::new(vec![0.0, 0.0, 0.0, 2.0], vec![1.0, -1.0]).unwrap();
    let s = pgs::solve(&lcp, &PgsOptions::default());
    assert_eq!(s.status, Status::Solved);
    assert_eq!(s.z, vec![0.0, 0.5]);
}

#[test]
fn pgs_divergence_is_reported_not_propagated() {
    // ω far outside (0, 2) makes the iteration blow up; the answer must stay finite.
    let lcp = spd_lcp(5, 3);
    let o = PgsOptions { omega: 1e200, max_iterations: 100, ..PgsOptions::default() };
    let s = pgs::solve(&lcp, &o);
    assert_contract(&lcp, &s);
    assert_ne!(s.status, Status::Solved);
    let o = PgsOptions { omega: f64::NAN, ..PgsOptions::default() };
    let s = pgs::solve(&lcp, &o);
    assert_contract(&lcp, &s);
    assert_eq!(s.status, Status::Numerical);
}

#[test]
fn newton_handles_degenerate_problems() {
    let cases: Vec<(Vec<f64>, Vec<f64>)> = vec![
        // z = 0, w = 0: the solution sits on the kink.
        (vec![1.0], vec![0.0]),
        (vec![2.0, 1.0, 1.0, 2.0], vec![0.0, 0.0]),
        // Degenerate pair at the solution z = (½, 0), w = (0, 0).
        (vec![2.0, 1.0, 1.0, 2.0], vec![-1.0, -0.5]),
        // PSD, a segment of solutions z₁ + z₂ = 1.
        (vec![1.0, 1.0, 1.0, 1.0], vec![-1.0, -1.0]),
        // Zero matrix with q ≥ 0: every z ≥ 0 with z ⊥ q solves.
        (vec![0.0, 0.0, 0.0, 0.0], vec![0.0, 1.0]),
        // Singular Jacobian at the start (zero row of M, w₀ = 0 at z = 0).
        (vec![0.0, 0.0, 1.0, 3.0], vec![0.0, -3.0]),
    ];
    for (m, q) in cases {
        let lcp = Lcp::new(m.clone(), q.clone()).unwrap();
        let s = newton_fb::solve(&lcp, &NewtonFbOptions::default());
        assert_contract(&lcp, &s);
        assert_eq!(s.status, Status::Solved, "M = {m:?}, q = {q:?}: {s:?}");
        assert!(is_solution(&lcp, &s.z, 1e-12));
    }
}

#[test]
fn newton_solves_murty_where_lemke_needs_2_to_the_n_pivots() {
    for n in [1, 2, 5, 10, 16, 30] {
        let mut expected = vec![0.0; n];
        expected[0] = 2f64.powi(n as i32);
        // The data are of size 2ⁿ: an absolute tolerance must grow with them.
        let o = NewtonFbOptions { tol: 1e-14 * expected[0], ..NewtonFbOptions::default() };
        let s = newton_fb::solve(&murty(n), &o);
        assert_eq!(s.status, Status::Solved, "n = {n}: {:?}", s.residuals);
        assert!(max_diff(&s.z, &expected) <= 1e-12 * expected[0], "n = {n}: {:?}", s.z);

        expected[0] = 1.0;
        let s = newton_fb::solve(&murty_unit(n), &NewtonFbOptions::default());
        assert_eq!(s.status, Status::Solved, "n = {n}");
        assert!(max_diff(&s.z, &expected) < 1e-12, "n = {n}: {:?}", s.z);
    }
}

#[test]
fn infeasible_problems_are_not_reported_solved() {
    for (name, lcp) in infeasible_examples() {
        let o = NewtonFbOptions { max_iterations: 200, ..NewtonFbOptions::default() };
        let s = newton_fb::solve(&lcp, &o);
        assert_contract(&lcp, &s);
        assert_ne!(s.status, Status::Solved, "{name}");
        let s = pgs::solve(&lcp, &PgsOptions { max_iterations: 200, ..PgsOptions::default() });
        assert_contract(&lcp, &s);
        assert_ne!(s.status, Status::Solved, "{name}");
    }
}

#[test]
fn newton_reports_numerical_on_overflow_instead_of_nan() {
    // Entries near f64::MAX: w overflows as soon as z moves.
    let big = f64::MAX / 2.0;
    let lcp = Lcp::new(vec![big, -big, -big, big], vec![-big, -big]).unwrap();
    let s = newton_fb::solve(&lcp, &NewtonFbOptions::default());
    assert_contract(&lcp, &s);
    assert_ne!(s.status, Status::Solved);
}

#[test]
fn solvers_are_deterministic() {
    let lcp = p_matrix_lcp(12, 99);
    assert_eq!(
        newton_fb::solve(&lcp, &NewtonFbOptions::default()),
        newton_fb::solve(&lcp, &NewtonFbOptions::default())
    );
    let lcp = spd_lcp(12, 99);
    assert_eq!(pgs::solve(&lcp, &PgsOptions::default()), pgs::solve(&lcp, &PgsOptions::default()));
}

#[test]
fn method_dispatch_reaches_these_solvers() {
    let lcp = spd_lcp(6, 1);
    let direct = pgs::solve(&lcp, &PgsOptions::default());
    assert_eq!(lcp::solve(&lcp, &lcp::Method::Pgs(PgsOptions::default())), direct);
    let direct = newton_fb::solve(&lcp, &NewtonFbOptions::default());
    assert_eq!(lcp::solve(&lcp, &lcp::Method::NewtonFb(NewtonFbOptions::default())), direct);
}

/// A case proptest found for `newton_is_robust_to_diagonal_scaling` (n = 5, a
/// 2^8 row factor): the default Levenberg–Marquardt step on the equilibrated
/// problem crawls (100 iterations, natural residual 6e-2; plain Newton, `lm_factor`
/// 0, takes 8). It must say so rather than return a wrong `solved`, and on a
/// positive definite `M` it must still converge (globally, by theory) given
/// enough iterations (measured: 113).
#[test]
fn newton_scaled_slow_case_is_reported_and_converges() {
    let (n, seed) = (5usize, 7615288569255258611u64);
    let exps = [0, 0, 8, 0, 0, 0, 0, 0, -1, 6, -2, 0, 0, 0, 0, 0];
    let base = spd_lcp(n, seed);
    let sc = lcp::Scaling {
        row: exps[..n].iter().map(|&e| 2f64.powi(e)).collect(),
        col: exps[8..8 + n].iter().map(|&e| 2f64.powi(e)).collect(),
    };
    let lcp = sc.apply(&base);
    let exact = unique_solution(&base);
    for it in [100, 1000] {
        let s =
            newton_fb::solve(&lcp, &NewtonFbOptions { tol: 1e-9, max_iterations: it, ..NewtonFbOptions::default() });
        if s.status == Status::Solved {
            assert!(s.residuals.residual <= 1e-9);
            assert!(max_diff(&sc.z_back(&s.z), &exact) < 1e-4);
        } else {
            assert!(s.residuals.residual > 1e-9, "{:?} with residual {:e}", s.status, s.residuals.residual);
            assert!(it < 1000, "not solved in {it} iterations");
        }
    }
}
