//! Issue 13: a resting stack costs (close to) no pivots per step. Its LCP is
//! statically indeterminate (four corner contacts per interface, three
//! independent normal constraints), so the previous step's basis can be
//! singular or a hair infeasible at the next step; the warm start must still
//! keep one of the exact solutions instead of pivoting anew every step.

mod common;
use common::*;
use sim::scenes::BoxStack;
use sim::WorldParams;

/// Interface `j` of the stack `s` carries the weight of the `n − j` boxes
/// above it: `(n − j)·m·g·h` (1 kg boxes) within 1e-6 relative.
fn check_interfaces(s: &sim::scenes::Scene, r: &sim::StepRecord, h: f64, step: usize) {
    let n = s.bodies.len();
    for j in 0..n {
        let below = if j == 0 { s.ground.0 } else { s.bodies[j - 1].0 };
        let f = interface_fn(r, below, s.bodies[j].0);
        let expect = (n - j) as f64 * G * h;
        assert!(rel(f, expect) < 1e-6, "step {step}: interface {j} carries {f:e}, expected {expect:e}");
    }
}

#[test]
fn resting_five_box_stack_takes_no_pivots_once_settled() {
    let n = 5;
    let h = 1e-3;
    let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
    let mut pivots = Vec::new();
    for step in 0..300 {
        let r = step_ok(&mut s.world);
        // Each interface carries the weight above it, exactly.
        check_interfaces(&s, &r, h, step);
        if step >= 50 {
            pivots.push(r.pivots);
        }
    }
    pivots.sort_unstable();
    let median = pivots[pivots.len() / 2];
    // Measured: median 0 (cold-start Lemke from the previous basis: 84).
    assert!(median <= 2, "median pivots per settled step {median}, sorted {pivots:?}");
    let top = s.world.body(s.body).unwrap();
    assert!(top.velocity().norm() < 1e-9, "top box moves at {:?}", top.velocity());
}

#[test]
fn resting_ten_box_stack_mostly_keeps_its_basis_and_does_not_drift() {
    let (n, h, steps) = (10, 1e-3, 1000);
    let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
    let top0 = s.world.body(s.body).unwrap().position();
    let mut zero = 0;
    for step in 0..steps {
        let r = step_ok(&mut s.world);
        check_interfaces(&s, &r, h, step);
        zero += usize::from(step >= 50 && r.pivots == 0);
    }
    // Measured (`stack_steps 1000 10`): only the first, cold step pivots; the
    // body-space check of the previous basis, with its kept factorization,
    // serves the others.
    assert!(zero * 100 >= 95 * (steps - 50), "only {zero} of {} settled steps took no pivot", steps - 50);
    let drift = (s.world.body(s.body).unwrap().position() - top0).norm();
    assert!(drift <= 1e-9, "top box drifted {drift:e} m");
}

#[test]
fn resting_ten_box_stack_pivots_on_few_steps_over_two_seconds() {
    // A corner whose nonbasic w_n sits at −5e-12 m/s is within the acceptance
    // bound, but kept step after step it sinks the corner past the gap floor
    // (1e-12 m) and the stabilization term then moves q by 2e-10: hundreds of
    // pivots. The body-space check exchanges such a violation while it is
    // small. Measured (`stack_steps 2000 10`): 7 pivoting steps, 2,663
    // pivots, drift 0 (before: 31 steps, 14,391 pivots, drift 4e-13 m).
    let (n, steps) = (10, 2000);
    let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
    let top0 = s.world.body(s.body).unwrap().position();
    let mut pivoting = 0;
    for _ in 0..steps {
        let r = step_ok(&mut s.world);
        pivoting += usize::from(r.pivots > 0);
    }
    assert!(pivoting <= 12, "{pivoting} of {steps} steps pivoted");
    let drift = (s.world.body(s.body).unwrap().position() - top0).norm();
    assert!(drift <= 1e-9, "top box drifted {drift:e} m");
}
