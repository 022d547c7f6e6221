//! A contact LCP of a 1e6 kg box sliding on a 1 kg box
//! (`crates/sim/tests/mass_ratio.rs`, box–box, 0.5 m/s; step 1876
//! of the run with an LCP sink; n = 80, 8 contacts × (1 + 8 + 1)). Its
//! solution basis has cond ~4e16 (f64 SVD): every `f64` rung of the ladder
//! ended `SingularBasis` or off (1,089 pivots), cold and warm, and exact
//! Lemke is not tried at n = 80. Lemke in double-double arithmetic
//! (`lemke::extended`) solves it in ~100 pivots.

mod common;

use common::sparse::repro_sparse;
use lcp::accept::{backward_error, DEFAULT_TOL};
use lcp::{lemke, LemkeOptions, Status};

#[test]
fn heavy_box_on_light_box_is_solved_within_the_rule() {
    let (p, basis) = repro_sparse("heavy1e6_slide_step1876.lcpsparse");
    assert_eq!(p.n(), 80);
    // The f64 ladder alone (no fallback rungs) fails it.
    let first = lemke::solve(&p, &LemkeOptions { fallback: false, ..Default::default() });
    assert!(!first.ok(), "the first rung solved it: {:?}", first.status);
    for warm in [None, Some(&basis[..])] {
        let sol = lemke::solve_warm(&p, &LemkeOptions::default(), warm);
        assert_eq!(sol.status, Status::Solved, "warm {}", warm.is_some());
        assert!(sol.ok());
        // The rule, recomputed here from z.
        let eta = backward_error(&p, &sol.z, &p.w_of(&sol.z));
        assert!(eta <= DEFAULT_TOL, "warm {}: η = {eta:e}", warm.is_some());
        // The heavy box's weight (1e6 kg · 9.81 m/s² · h, scaled) is carried:
        // the normal impulses (z[0..8]) are not all zero.
        assert!(sol.z[..8].iter().sum::<f64>() > 0.0);
    }
}

/// `lemke::solve_dd` (the double-double rungs on demand, for an answer the
/// caller doubts): it returns only answers that the rule and the caller's
/// check both accept, and it asks the caller about each candidate in turn.
#[test]
fn double_double_on_demand_answers_within_the_rule_and_the_callers_check() {
    let (p, basis) = repro_sparse("heavy1e6_slide_step1876.lcpsparse");
    let o = LemkeOptions::default();
    let sol = lemke::solve_dd(&p, &o, &[&basis[..]], |_| true).expect("the double-double rungs solve it");
    assert!(sol.ok());
    let eta = backward_error(&p, &sol.z, &p.w_of(&sol.z));
    assert!(eta <= DEFAULT_TOL, "η = {eta:e}");
    // A caller that accepts nothing gets nothing, after every candidate was put to it.
    let mut asked = 0;
    assert!(lemke::solve_dd(&p, &o, &[&basis[..]], |_| {
        asked += 1;
        false
    })
    .is_none());
    assert!(asked >= 1, "no candidate was put to the caller");
}
