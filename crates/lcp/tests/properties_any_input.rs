//! Issue 15, item 6: the fuzz target's properties (`tests/properties/mod.rs`)
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
        assert_eq!((sol.status, sol.iterations), (Status::MaxPivots, 0));
        properties::check_solution(&lcp, &method, &sol).unwrap();
    }
}
