//! Regression of the componentwise acceptance rule: the 10-box
//! stack (`sim::scenes::box_stack(10)`, 2000 steps) had one failed LCP, at
//! step 1480: the warm rung and every cold rung ended off by a hair (rows of
//! an unloaded contact's cone made of 1e-13 impulses that the rule rejects),
//! one rung cycled, and the restarts from the rungs' final bases came only
//! after all nine rungs had pivoted (1,232 pivots, `Cycling`). Restarting at
//! once from a rung's complementary final basis solves it.

mod common;

use common::sparse::repro_sparse;
use lcp::accept::{backward_error, DEFAULT_TOL};
use lcp::{lemke, LemkeOptions, Status};

#[test]
fn stack10_step1480_is_solved_within_the_rule() {
    let (p, basis) = repro_sparse("stack10_step1480.lcpsparse");
    assert_eq!(p.n(), 400);
    let sol = lemke::solve_warm(&p, &LemkeOptions::default(), Some(&basis));
    assert_eq!(sol.status, Status::Solved);
    assert!(sol.ok());
    // The rule, recomputed here from z.
    let eta = backward_error(&p, &sol.z, &p.w_of(&sol.z));
    assert!(eta <= DEFAULT_TOL, "η = {eta:e}");
    // Fewer pivots than the failure spent (1,232).
    assert!(sol.pivots < 1232, "{} pivots", sol.pivots);
}
