//! The fuzz target's properties (`tests/properties/mod.rs`)
//! in the normal test suite: on any bytes, `Lcp::new` accepts exactly the
//! well-formed data, every solver returns without panicking, within its
//! budget, and `Solved` only within the documented acceptance rule. Inputs
//! the fuzzer found are kept below as regression cases.

mod properties;

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn any_bytes_keep_the_solver_properties(data in proptest::collection::vec(any::<u8>(), 0..400)) {
        let case = properties::decode(&data);
        if let Err(e) = properties::check(&case) {
            prop_assert!(false, "{}", e);
        }
    }
}

/// Every method on every case of a fixed byte pattern family: the decoder's
/// branches (shapes, methods, warm bases) all reached deterministically.
#[test]
fn every_decoder_branch_keeps_the_properties() {
    for shape in 0..8u8 {
        for method in 0..5u8 {
            for seed in 0..40u8 {
                let mut data = vec![seed % 6, shape];
                data.extend((0..120u32).map(|i| (i as u8).wrapping_mul(seed).wrapping_add(method.wrapping_mul(37))));
                // the method byte sits after n² + n floats of up to 9 bytes; put it everywhere plausible
                data.iter_mut().skip(60).step_by(7).for_each(|b| *b = method);
                properties::check(&properties::decode(&data)).unwrap();
            }
        }
    }
}

/// `max_pivots = 0` used to report 1 pivot (z0 entered before the budget was
/// looked at); the fuzz property "pivots ≤ budget" catches it.
#[test]
fn max_pivots_zero_reports_no_pivot() {
    use lcp::{Lcp, LemkeOptions, Method, Status};
    let lcp = Lcp::new(vec![2.0, 1.0, 1.0, 2.0], vec![-1.0, -1.0]).unwrap();
    for o in [LemkeOptions::default(), LemkeOptions::classic()] {
        let method = Method::Lemke(LemkeOptions { max_pivots: Some(0), ..o });
        let sol = lcp::solve(&lcp, &method);
        assert_eq!((sol.status, sol.pivots), (Status::MaxPivots, 0));
        properties::check_solution(&lcp, &method, &sol).unwrap();
    }
}

/// Found by the property test: the repair ladder's restarts from a failed
/// rung's basis spent the whole remaining budget on Lemke after spending part
/// of it on block principal exchanges, so the total passed `max_pivots`
/// (13 of 10, 40 of 34). The exchanges now count against the budget.
#[test]
fn restarts_keep_the_pivot_budget() {
    use lcp::{Lcp, LemkeOptions, Method};
    let tiny = 1e-300;
    let cases: [(Vec<f64>, Vec<f64>, usize); 2] = [
        (
            vec![
                0.0, 0.0, 0.0, 0.0, 0.0, 1e-20, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1e4, 0.0, 0.0, 0.0, 0.0, tiny, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.25, 0.0, 0.0, tiny, tiny, 0.0, tiny, tiny, 0.0, 0.0, 0.0, 0.0, 0.0,
            ],
            vec![0.0, 0.0, 0.0, 0.0, 0.0, -8.0],
            10,
        ),
        (
            vec![
                1.0,
                1.0,
                -1.0,
                4.25,
                6.375,
                -7.5,
                0.0,
                1.0,
                0.9999999999999998,
                0.0,
                1.0,
                -1.0,
                0.0,
                0.0,
                1.0,
                -7e20,
                2.2250738585072014e-308,
                1.0000000000000033,
                0.0,
                0.0,
                0.0,
                1.0,
                -7.625,
                -5.5,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0,
                -1.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0,
            ],
            vec![0.0, 0.0, -1.0, -7.75, -5.625, 0.0],
            34,
        ),
    ];
    for (m, q, budget) in cases {
        let lcp = Lcp::new(m, q).unwrap();
        for zero_tol in [1e-6, 1e-13] {
            let o = LemkeOptions {
                max_pivots: Some(budget),
                equilibrate: false,
                warm_start: false,
                zero_tol,
                ..Default::default()
            };
            let method = Method::Lemke(o);
            let sol = lcp::solve(&lcp, &method);
            assert!(sol.pivots <= budget, "{} pivots of {budget}", sol.pivots);
            properties::check_solution(&lcp, &method, &sol).unwrap();
        }
    }
}

/// Found by `cargo fuzz` (lcp_solvers): classic Lemke accepted z = [∞, …] as
/// solved — `w = M z + q` held NaN, and the residuals' maxima skipped it.
/// A non-finite z or w now has an infinite residual.
#[test]
fn a_non_finite_answer_is_never_solved() {
    let data = [
        53u8, 34, 254, 254, 13, 13, 0, 0, 0, 0, 0, 2, 69, 0, 0, 102, 0, 0, 0, 0, 43, 43, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0,
    ];
    let mut data = data.to_vec();
    data.extend([186u8; 30]);
    data.extend([147u8; 39]);
    data.extend([186u8; 36]);
    data.extend([13u8, 235, 13, 13, 13]);
    let case = properties::decode(&data);
    properties::check(&case).unwrap();
    let r = lcp::Residuals::of(&[f64::INFINITY, 1.0], &[f64::NAN, 0.0]);
    assert_eq!((r.residual, r.max_complementarity), (f64::INFINITY, f64::INFINITY));
}

/// Found by `cargo fuzz` (lcp_solvers, 10-minute run): Newton–FB converged on
/// the Ruiz-equilibrated problem and reported `solved`, but with `M` holding
/// 1e-300 beside 1e308 the equilibrated products round otherwise and the
/// answer (z₀ = 1e300) leaves w₁ = −1 on the problem as given. Such an answer
/// is now `numerical`.
#[test]
fn newton_solved_on_the_equilibrated_problem_must_hold_as_given() {
    let data = [
        0x0eu8, 0x08, 0x1c, 0x00, 0x00, 0x16, 0x00, 0x72, 0x2d, 0x22, 0x00, 0x7e, 0xe1, 0xcc, 0xf3, 0xb4, 0x2b, 0x00,
        0x22, 0x22, 0x01, 0x00, 0x22, 0x22, 0x22, 0x23, 0x00, 0x72, 0xff, 0xff, 0xff, 0x2d,
    ];
    let case = properties::decode(&data);
    properties::check(&case).unwrap();
}
