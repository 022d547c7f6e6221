//! Brute-force enumeration: problems whose solution sets are known in closed
//! form, P-matrix uniqueness, infeasibility with Farkas certificates.

use lcp::contact::ContactLayout;
use lcp::enumerate::{all_solutions, is_solution, MAX_N};
use lcp::generate::{infeasible_examples, murty, murty_unit, p_matrix_lcp, spd_lcp};
use lcp::Lcp;
use proptest::prelude::*;
use sim::generate::contact_lcp;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// P-matrix ⇔ unique solution for every q: enumeration finds exactly one.
    #[test]
    fn p_matrix_lcps_have_exactly_one_solution(n in 1usize..=8, seed in any::<u64>()) {
        for lcp in [p_matrix_lcp(n, seed), spd_lcp(n, seed)] {
            let sols = all_solutions(&lcp, 1e-9);
            prop_assert_eq!(sols.len(), 1);
            let z = &sols[0];
            prop_assert!(is_solution(&lcp, z, 1e-9));
            // It is the basic solution of its own support: w vanishes there.
            let w = lcp.w_of(z);
            for i in 0..n {
                prop_assert!(z[i] >= -1e-9 && w[i] >= -1e-9 && (z[i].abs() <= 1e-9 || w[i].abs() <= 1e-9));
            }
        }
    }

    /// M = −I, q = 1: z_i ∈ {0, 1} independently — 2ⁿ solutions.
    #[test]
    fn minus_identity_has_two_to_the_n_solutions(n in 1usize..=8) {
        let lcp = Lcp::from_fn(n, |i, j| if i == j { -1.0 } else { 0.0 }, vec![1.0; n]).unwrap();
        let sols = all_solutions(&lcp, 1e-12);
        prop_assert_eq!(sols.len(), 1 << n);
        for z in &sols {
            prop_assert!(z.iter().all(|&v| v == 0.0 || v == 1.0));
        }
        // Distinct.
        for (a, z) in sols.iter().enumerate() {
            prop_assert!(sols[..a].iter().all(|y| y != z));
        }
    }

    /// Every answer is a solution, whatever M is.
    #[test]
    fn every_enumerated_vector_solves(n in 1usize..=6, m in prop::collection::vec(-2.0f64..2.0, 36), q in prop::collection::vec(-2.0f64..2.0, 6)) {
        let lcp = Lcp::new(m[..n * n].to_vec(), q[..n].to_vec()).unwrap();
        for z in all_solutions(&lcp, 1e-9) {
            prop_assert!(is_solution(&lcp, &z, 1e-9));
        }
    }
}

#[test]
fn murty_examples_have_their_documented_solution() {
    for n in 1..=12 {
        let sols = all_solutions(&murty(n), 1e-9);
        let mut expected = vec![0.0; n];
        expected[0] = 2f64.powi(n as i32);
        assert_eq!(sols, vec![expected.clone()], "n = {n}");
        expected[0] = 1.0;
        assert_eq!(all_solutions(&murty_unit(n), 1e-9), vec![expected], "n = {n}");
    }
}

#[test]
fn singular_principal_submatrices_are_skipped() {
    // M = [[1, 1], [1, 1]], q = −1: the solutions are the segment z₁ + z₂ = 1;
    // the full basis is singular, its two vertices are found.
    let lcp = Lcp::new(vec![1.0, 1.0, 1.0, 1.0], vec![-1.0, -1.0]).unwrap();
    assert_eq!(all_solutions(&lcp, 1e-12), vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
    // Interior points of the segment solve too, but are not basic.
    assert!(is_solution(&lcp, &[0.25, 0.75], 1e-12));
    // M = 0, q = 0: every z ≥ 0 solves; only z = 0 is basic.
    let lcp = Lcp::new(vec![0.0; 4], vec![0.0, 0.0]).unwrap();
    assert_eq!(all_solutions(&lcp, 1e-12), vec![vec![0.0, 0.0]]);
}

#[test]
fn degenerate_bases_give_one_solution() {
    // M = I, q = 0: all four bases give z = 0.
    let lcp = Lcp::new(vec![1.0, 0.0, 0.0, 1.0], vec![0.0, 0.0]).unwrap();
    assert_eq!(all_solutions(&lcp, 1e-12), vec![vec![0.0, 0.0]]);
}

#[test]
fn infeasible_examples_have_no_solution_and_a_farkas_certificate() {
    // {z ≥ 0 : M z + q ≥ 0} = ∅ ⇔ ∃ y ≥ 0: Mᵀ y ≤ 0, qᵀ y < 0.
    let certificates: [&[f64]; 3] = [&[1.0], &[1.0, 1.0], &[0.0, 1.0]];
    let examples = infeasible_examples();
    assert_eq!(examples.len(), certificates.len());
    for ((name, lcp), y) in examples.iter().zip(certificates) {
        assert!(all_solutions(lcp, 1e-9).is_empty(), "{name}");
        let n = lcp.n();
        assert!(y.iter().all(|&v| v >= 0.0));
        for j in 0..n {
            let mty: f64 = (0..n).map(|i| lcp.at(i, j) * y[i]).sum();
            assert!(mty <= 0.0, "{name}: (Mᵀy)_{j} = {mty}");
        }
        let qty: f64 = (0..n).map(|i| lcp.q()[i] * y[i]).sum();
        assert!(qty < 0.0, "{name}");
    }
}

#[test]
fn contact_lcps_are_solvable_and_every_solution_respects_the_cone() {
    for seed in 0..40 {
        for (nc, k) in [(1, 8), (1, 4), (2, 4), (3, 2)] {
            let lcp = contact_lcp(nc, k, 1.0, seed);
            let layout = ContactLayout { nc, k };
            let sols = all_solutions(&lcp, 1e-10);
            assert!(!sols.is_empty(), "seed {seed}, nc {nc}, k {k}");
            for z in &sols {
                let w = lcp.w_of(z);
                for c in 0..nc {
                    let fnc = z[c];
                    let fd_sum: f64 = (0..k).map(|j| z[layout.fd_index(c, j)]).sum();
                    let mu = lcp.at(layout.lambda_index(c), c);
                    // Friction inside the cone; no friction without normal force.
                    assert!(fd_sum <= mu * fnc + 1e-9, "seed {seed}: Σfd {fd_sum} > μ fn {}", mu * fnc);
                    // Normal velocity after the step is non-negative.
                    assert!(w[c] >= -1e-10);
                }
            }
        }
    }
}

#[test]
fn is_solution_checks_shape_finiteness_and_tolerance() {
    let lcp = Lcp::new(vec![2.0], vec![-1.0]).unwrap();
    assert!(is_solution(&lcp, &[0.5], 0.0));
    assert!(!is_solution(&lcp, &[0.5, 0.0], 1.0));
    assert!(!is_solution(&lcp, &[f64::NAN], 1.0));
    assert!(!is_solution(&lcp, &[f64::INFINITY], 1.0));
    // z = 0.5 + δ: w = 2δ, min(z, w) = 2δ.
    assert!(is_solution(&lcp, &[0.5 + 1e-7], 2.1e-7));
    assert!(!is_solution(&lcp, &[0.5 + 1e-7], 1.9e-7));
    // Infeasible z: z = −1e-8 < 0.
    let lcp = Lcp::new(vec![1.0], vec![1.0]).unwrap();
    assert!(is_solution(&lcp, &[-1e-8], 1e-8));
    assert!(!is_solution(&lcp, &[-1e-8], 1e-9));
}

#[test]
fn size_limit() {
    assert_eq!(MAX_N, 16);
    // n = 16 still enumerates (65 536 bases) …
    let mut e1 = vec![0.0; 16];
    e1[0] = 1.0;
    assert_eq!(all_solutions(&murty_unit(16), 1e-9), vec![e1]);
    // … n = 17 is refused with an empty list.
    assert!(all_solutions(&murty_unit(17), 1e-9).is_empty());
}
