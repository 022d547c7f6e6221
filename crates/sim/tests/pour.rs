//! Pours of cubes (`scenes::CubePour`): contact that changes every step.
//! Each island's answer is taken from a stage of the solve chain, judged by
//! the acceptance rule; a pour must end with every island solved.

use sim::scenes::CubePour;
use sim::WorldParams;

/// Deepest penetration of a step's contacts (m).
fn penetration(r: &sim::StepRecord) -> f64 {
    r.contacts.iter().fold(0.0f64, |p, c| p.max(-c.gap))
}

#[test]
fn a_45_cube_pour_runs_3_s_with_every_island_solved_and_no_cube_sunk() {
    let mut s = CubePour::new(45, 0).build(WorldParams::default()).unwrap();
    let (mut deepest, mut islands) = (0.0f64, 0usize);
    let mut by_stage = [0usize; 4];
    for step in 0..3000 {
        let r = s.world.step().unwrap();
        for (i, isl) in r.islands.iter().enumerate() {
            assert_eq!(isl.status, lcp::Status::Solved, "step {step}, island {i} of LCP size {}", isl.lcp_size);
            let stage = isl.stage.expect("a solved island names the stage that answered");
            by_stage[stage.index()] += 1;
            islands += 1;
        }
        deepest = deepest.max(penetration(r));
    }
    println!("islands {islands}, by stage {by_stage:?}, deepest penetration {deepest:.2e} m");
    // Every cube inside the bin and on or above the floor (a turned cube's
    // centre stands at least half an edge up; the bin's inner half-width is
    // g·spacing/2 = 2.7 m for 45 cubes).
    for &b in &s.bodies {
        let p = s.world.body(b).unwrap().position();
        assert!(p.z > 0.5 - 1e-3 && p.x.abs() < 2.7 && p.y.abs() < 2.7, "cube {b:?} at {p:?}");
    }
    // While the heap forms, tumbling cubes meet at edges and corners (0.19 mm
    // at most on this seed): a box coming down nearly flat across another's
    // edge has contact points at both ends of its edge before it lands.
    assert!(deepest <= 1e-3, "penetration {deepest:.2e} m");
    assert_eq!(by_stage.iter().sum::<usize>(), islands);
}

#[test]
fn a_pour_is_the_same_on_one_thread_and_on_two() {
    let run = |threads: usize| {
        let mut s = CubePour::new(20, 3).build(WorldParams { threads, ..Default::default() }).unwrap();
        for _ in 0..900 {
            s.world.step().unwrap();
        }
        s.bodies.iter().map(|&b| s.world.body(b).unwrap().position().to_array()).collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_pour_starts_with_no_two_cubes_touching() {
    let mut s = CubePour::new(200, 7).build(WorldParams::default()).unwrap();
    let r = s.world.step().unwrap().clone();
    let cube = |b: usize| s.bodies.iter().any(|c| c.0 == b);
    for c in &r.contacts {
        assert!(!(cube(c.body_a) && cube(c.body_b)), "cubes {} and {} touch at the start", c.body_a, c.body_b);
    }
}

#[test]
fn a_pour_rejects_bad_parameters() {
    for bad in [
        CubePour { n: 0, ..CubePour::new(1, 0) },
        CubePour { spacing: 1.0, ..CubePour::new(10, 0) },
        CubePour { jitter: f64::NAN, ..CubePour::new(10, 0) },
        CubePour { mass: -1.0, ..CubePour::new(10, 0) },
        CubePour { mu: -0.5, ..CubePour::new(10, 0) },
    ] {
        assert!(bad.build(WorldParams::default()).is_err(), "{bad:?} was accepted");
    }
}

/// Every island's answer, whichever stage gave it (most of them in body space,
/// without a dense `M`), passes the acceptance rule on the island's dense LCP
/// assembled from the same state.
#[test]
fn every_answer_of_a_small_pour_passes_the_rule_on_its_dense_lcp() {
    let mut s = CubePour::new(10, 4).build(WorldParams::default()).unwrap();
    let (mut checked, mut by_stage) = (0, [0usize; 4]);
    for _ in 0..1500 {
        // The same state stepped stage by stage, up to the dense LCPs.
        let mut probe = s.world.clone();
        probe.forces_stage().unwrap();
        probe.detect();
        probe.islands();
        probe.assemble();
        let r = s.world.step().unwrap();
        assert_eq!(probe.contact_islands().len(), r.islands.len());
        for (i, isl) in r.islands.iter().enumerate() {
            let contact = probe.island_lcp(i).unwrap();
            assert_eq!(contact.scale(), 1.0);
            let lcp = contact.to_lcp().unwrap();
            // The record's physical z, in the island's own layout.
            let (k, ids) = (r.friction_dirs, r.island_contacts_of(i));
            let (lay, whole) = (lcp::ContactLayout::new(ids.len(), k), r.layout());
            let mut z = vec![0.0; lay.n()];
            for (c, &g) in ids.iter().enumerate() {
                z[lay.fn_index(c)] = r.z[whole.fn_index(g)];
                z[lay.fd_of(c)].copy_from_slice(&r.z[whole.fd_of(g)]);
                z[lay.lambda_index(c)] = r.z[whole.lambda_index(g)];
            }
            let mut w = lcp.q().to_vec();
            for (row, wi) in w.iter_mut().enumerate() {
                *wi += lcp.m()[row * lay.n()..(row + 1) * lay.n()].iter().zip(&z).map(|(a, b)| a * b).sum::<f64>();
            }
            assert!(
                lcp::accept::accepts(&lcp, &z, &w, 1e-9),
                "step {}, island {i} ({:?}, n = {}): the rule rejects the answer on the dense LCP",
                r.step,
                isl.stage,
                lay.n()
            );
            by_stage[isl.stage.unwrap().index()] += 1;
            checked += 1;
        }
    }
    println!("{checked} answers checked, by stage {by_stage:?}");
    assert!(by_stage[0] > 0, "no answer came from the previous basis: {by_stage:?}");
}
