//! Issue 15, item 4: one acceptance rule. Every island answer the simulator
//! counts as `ok` passes `lcp::accept::accepts` — also the answers of the
//! previous basis in body space, which never form `M`. Here `M` is formed
//! densely for the check after each step (the island's LCP is kept until the
//! next one), and `w = M z + q` is recomputed from it: on the LCP as solved
//! (cone scale `s`) and on the physical one.

use lcp::accept::accepts;
use lcp::contact::ContactLayout;
use lcp::Lcp;
use sim::contact::ContactLcp;
use sim::scenes::BoxStack;
use sim::{ConeScale, StepRecord, World, WorldParams};

const TOL: f64 = lcp::accept::DEFAULT_TOL;

/// Island `i`'s physical `z` (its own contact order) out of the step's record.
fn island_z(rec: &StepRecord, i: usize) -> Vec<f64> {
    let ids = rec.island_contacts_of(i);
    let (isl, step) = (ContactLayout::new(ids.len(), rec.friction_dirs), rec.layout());
    let mut z = vec![0.0; isl.n()];
    for (c, &g) in ids.iter().enumerate() {
        z[isl.fn_index(c)] = rec.z[step.fn_index(g)];
        z[isl.fd_of(c)].copy_from_slice(&rec.z[step.fd_of(g)]);
        z[isl.lambda_index(c)] = rec.z[step.lambda_index(g)];
    }
    z
}

/// The dense LCP `D M D, D q` as solved and the physical `M, q` (`D = diag(I, I, s·I)`).
fn dense_pair(lcp: &ContactLcp) -> (Lcp, Lcp) {
    let mut lcp = lcp.clone();
    lcp.assemble_matrix();
    let scaled = lcp.to_lcp().expect("finite LCP");
    let (n, s, lay) = (lcp.n(), lcp.scale(), lcp.layout());
    let d: Vec<f64> = (0..n).map(|i| if is_lambda(&lay, i) { s } else { 1.0 }).collect();
    let m: Vec<f64> = (0..n * n).map(|e| scaled.m()[e] / (d[e / n] * d[e % n])).collect();
    let q: Vec<f64> = (0..n).map(|i| scaled.q()[i] / d[i]).collect();
    (scaled, Lcp::new(m, q).expect("finite LCP"))
}

fn is_lambda(lay: &ContactLayout, i: usize) -> bool {
    i == lay.lambda_index(lay.contact_of(i))
}

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
            let (scaled, physical) = dense_pair(contact_lcp);
            let z = island_z(&rec, i);
            let lay = contact_lcp.layout();
            let zs: Vec<f64> = z
                .iter()
                .enumerate()
                .map(|(j, v)| if is_lambda(&lay, j) { v / contact_lcp.scale() } else { *v })
                .collect();
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
