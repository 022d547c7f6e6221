//! Matrix generators: each has the class it promises and is a pure function
//! of its seed (contact LCPs: `crates/sim/tests/generate.rs`).

mod common;
use common::{det, is_positive_definite};

use lcp::contact::ContactLayout;
use lcp::generate::{infeasible_lcp, murty, murty_unit, p_matrix_lcp, spd_lcp};
use lcp::{lemke, Lcp, LemkeOptions, Pivoting, Status};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn generators_are_deterministic_per_seed(seed in any::<u64>(), n in 1usize..=12) {
        prop_assert_eq!(p_matrix_lcp(n, seed), p_matrix_lcp(n, seed));
        prop_assert_ne!(p_matrix_lcp(n, seed), p_matrix_lcp(n, seed ^ 1));
        prop_assert_eq!(spd_lcp(n, seed), spd_lcp(n, seed));
        prop_assert_ne!(spd_lcp(n, seed), spd_lcp(n, seed ^ 1));
    }

    #[test]
    fn spd_lcp_is_symmetric_positive_definite(n in 1usize..=30, seed in any::<u64>()) {
        let lcp = spd_lcp(n, seed);
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(lcp.at(i, j), lcp.at(j, i));
            }
        }
        // M = A Aᵀ/n + 0.1 I: even M − 0.099 I is positive definite.
        let shifted: Vec<f64> = (0..n * n).map(|e| lcp.m()[e] - if e / n == e % n { 0.099 } else { 0.0 }).collect();
        prop_assert!(is_positive_definite(&shifted, n));
        prop_assert!(lcp.q().iter().all(|q| (-1.0..=1.0).contains(q)));
    }

    #[test]
    fn p_matrix_lcp_is_a_nonsymmetric_p_matrix(n in 1usize..=7, seed in any::<u64>()) {
        let lcp = p_matrix_lcp(n, seed);
        // Positive definite symmetric part.
        let sym: Vec<f64> = (0..n * n).map(|e| 0.5 * (lcp.m()[e] + lcp.at(e % n, e / n))).collect();
        prop_assert!(is_positive_definite(&sym, n));
        if n > 1 {
            prop_assert!((0..n * n).any(|e| lcp.m()[e] != lcp.at(e % n, e / n)));
        }
        // Every principal minor positive.
        for mask in 1u32..(1 << n) {
            let idx: Vec<usize> = (0..n).filter(|&i| mask & (1 << i) != 0).collect();
            let sub: Vec<f64> = idx.iter().flat_map(|&i| idx.iter().map(move |&j| (i, j))).map(|(i, j)| lcp.at(i, j)).collect();
            prop_assert!(det(sub, idx.len()) > 0.0, "minor {idx:?}");
        }
    }
}

#[test]
fn layout_ranges_partition_the_unknowns() {
    for (nc, k) in [(1, 8), (2, 8), (4, 8), (3, 1), (5, 6)] {
        let l = ContactLayout { nc, k };
        assert_eq!(l.fn_range().len(), nc);
        assert_eq!(l.fd_range().len(), nc * k);
        assert_eq!(l.lambda_range().len(), nc);
        assert_eq!(
            (l.fn_range().end, l.fd_range().end, l.lambda_range().end),
            (l.fd_range().start, l.lambda_range().start, l.n())
        );
        assert_eq!(l.fd_index(nc - 1, k - 1), l.fd_range().end - 1);
        assert_eq!(l.lambda_index(0), l.lambda_range().start);
    }
}

#[test]
fn murty_is_exponential_for_plain_lemke() {
    // Murty (1978): Lemke with covering vector 1 on the problem as given visits 2ⁿ bases.
    for pivoting in [Pivoting::Lexicographic, Pivoting::Classic] {
        for n in 1..=8 {
            let lcp = murty(n);
            let o = LemkeOptions { pivoting, equilibrate: false, max_pivots: Some(10_000), ..LemkeOptions::default() };
            let s = lemke::solve(&lcp, &o);
            assert_eq!(s.status, Status::Solved, "{pivoting:?} n = {n}");
            assert_eq!(s.pivots, 1 << n, "{pivoting:?} n = {n}");
        }
    }
}

#[test]
fn murty_structure() {
    for n in 1..=10 {
        for lcp in [murty(n), murty_unit(n)] {
            for i in 0..n {
                for j in 0..n {
                    let expected = if i == j {
                        1.0
                    } else if i > j {
                        2.0
                    } else {
                        0.0
                    };
                    assert_eq!(lcp.at(i, j), expected);
                }
            }
        }
        // Documented solutions, exactly: z = 2ⁿ e₁, w = (0, 2ⁿ⁻¹, …, 2).
        let mut z = vec![0.0; n];
        z[0] = 2f64.powi(n as i32);
        let w = murty(n).w_of(&z);
        let expected: Vec<f64> = (0..n).map(|i| if i == 0 { 0.0 } else { 2f64.powi((n - i) as i32) }).collect();
        assert_eq!(w, expected);
        z[0] = 1.0;
        let w = murty_unit(n).w_of(&z);
        assert!(w[0] == 0.0 && w[1..].iter().all(|&v| v == 1.0));
    }
}

#[test]
fn infeasible_lcp_is_infeasible() {
    let lcp: Lcp = infeasible_lcp();
    // w = −z − 1 < 0 for every z ≥ 0.
    assert_eq!((lcp.at(0, 0), lcp.q()[0]), (-1.0, -1.0));
}
