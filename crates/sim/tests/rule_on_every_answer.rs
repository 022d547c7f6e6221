//! One acceptance rule. Every island answer the simulator
//! counts as `ok` passes `lcp::accept::accepts` — also the answers of the
//! previous basis in body space, which never form `M`. Here `M` is formed
//! densely for the check after each step (the island's LCP is kept until the
//! next one), and `w = M z + q` is recomputed from it: on the LCP as solved
//! (cone scale `s`) and on the physical one.

use lcp::accept::accepts;
use sim::scenes::BoxStack;
use sim::{ConeScale, World, WorldParams};

#[path = "properties/mod.rs"]
mod properties;
use properties::{as_solved, island_z, physical};

const TOL: f64 = lcp::accept::DEFAULT_TOL;

/// Steps `world` `steps` times; every island counted `ok` must pass the rule on
/// both LCPs. Returns how many of the checked answers took no pivot (the
/// body-space answers of the previous basis, on a resting stack).
fn every_ok_answer_passes_the_rule(world: &mut World, steps: usize) -> (usize, usize) {
    let (mut checked, mut zero_pivot) = (0, 0);
    for _ in 0..steps {
        let rec = world.step().expect("finite state").clone();
        for (i, isl) in rec.islands.iter().enumerate() {
            if isl.status != lcp::Status::Solved {
                continue;
            }
            let contact_lcp = world.island_lcp(i).expect("the island's LCP");
            let z = island_z(&rec, i);
            let (scaled, zs) = as_solved(contact_lcp, &z).expect("a finite island LCP");
            let physical = physical(contact_lcp, &scaled);
            for (lcp, z, which) in [(&physical, &z, "physical LCP"), (&scaled, &zs, "LCP as solved")] {
                let w = lcp.w_of(z);
                assert!(
                    accepts(lcp, z, &w, TOL),
                    "step {}: island {i} counted ok (pivots {}) fails the rule on the {which}, η = {:e}",
                    rec.step,
                    isl.pivots,
                    lcp::accept::backward_error(lcp, z, &w)
                );
            }
            checked += 1;
            zero_pivot += usize::from(isl.pivots == 0 && isl.warm);
        }
    }
    (checked, zero_pivot)
}

#[test]
fn a_resting_ten_box_stack_counts_no_answer_ok_outside_the_rule() {
    // Before: answers of the previous basis accepted by a normwise bound left
    // an unloaded friction row at w ≈ −7e-12, outside the rule.
    let (n, steps) = (10, 2000);
    let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
    let (checked, zero_pivot) = every_ok_answer_passes_the_rule(&mut s.world, steps);
    // The body-space answers are the ones under test: nearly every step is one.
    assert!(checked >= steps - 5, "only {checked} of {steps} answers ok");
    assert!(zero_pivot * 100 >= 95 * steps, "only {zero_pivot} of {checked} answers without pivots");
}

#[test]
fn with_a_cone_scale_too_on_both_the_scaled_and_the_physical_lcp() {
    let (n, steps) = (5, 600);
    let params = WorldParams { cone_scale: ConeScale::TimeStep, ..WorldParams::default() };
    let mut s = BoxStack::new(n).build(params).unwrap();
    let (checked, zero_pivot) = every_ok_answer_passes_the_rule(&mut s.world, steps);
    assert!(checked >= steps - 5, "only {checked} of {steps} answers ok");
    assert!(zero_pivot * 100 >= 90 * steps, "only {zero_pivot} of {checked} answers without pivots");
}
