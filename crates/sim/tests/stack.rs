//! In a stack of n boxes the force at interface j is (n − j)·m·g
//! (within 1e-6 relative; the analytic check asks 1e-3) and nothing drifts; the 3×3×3 pile runs without a
//! single LCP failure.

mod common;
use common::*;
use sim::scenes::{BoxPile, BoxStack};
use sim::WorldParams;

fn check_stack(n: usize, steps: usize) {
    let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
    let start: Vec<_> = s.bodies.iter().map(|&b| pose(&s, b)).collect();
    let h = 1e-3;
    for _ in 0..steps {
        let r = step_ok(&mut s.world);
        assert_eq!(r.nc(), 4 * n);
        for j in 0..n {
            // Interface j is under box j: the ground for j = 0, box j − 1 otherwise.
            let below = if j == 0 { s.ground.0 } else { s.bodies[j - 1].0 };
            let f = interface_fn(&r, below, s.bodies[j].0);
            let expect = (n - j) as f64 * G * h;
            assert!(rel(f, expect) < 1e-6, "n {n}, step {}: interface {j} carries {f:e}, expected {expect:e}", r.step);
        }
    }
    for (&b, (p0, q0)) in s.bodies.iter().zip(&start) {
        let body = s.world.body(b).unwrap();
        assert!((body.position() - *p0).norm() < 1e-9, "box {b:?} drifted {:?}", body.position() - *p0);
        assert!(body.orientation().angle_to(*q0) < 1e-9);
        assert!(body.velocity().norm() < 1e-9 && body.angular_velocity().norm() < 1e-9);
    }
}

#[test]
fn stack_of_three_carries_the_weight_above_each_interface() {
    check_stack(3, 500);
}

#[test]
fn stack_of_ten_carries_the_weight_above_each_interface() {
    check_stack(10, 50);
}

#[test]
fn box_pile_runs_without_lcp_failures() {
    let mut s = BoxPile::default().build(WorldParams::default()).unwrap();
    let traj = s.world.run(3).unwrap();
    assert_eq!(traj.failures(), 0, "statuses {:?}", traj.status);
    assert_eq!(traj.contacts[0], 27 * 4);
    assert_eq!(traj.lcp_size[0], 27 * 4 * 10);
}

#[test]
fn turned_pile_rests_on_four_of_each_octagon_without_failures() {
    let pile = BoxPile { nx: 2, ny: 1, nz: 3, yaw: 0.4, seed: 7, spacing: 1.6, ..Default::default() };
    let mut s = pile.build(WorldParams::default()).unwrap();
    let traj = s.world.run(100).unwrap();
    assert_eq!(traj.failures(), 0, "statuses {:?}", traj.status);
    // A turned cube on a cube clips to an octagon, which lies flat: cut to
    // the 4 corners that span it (6 cubes, each on the ground or on a cube).
    assert_eq!(traj.contacts[0], 6 * 4);
    for &b in &s.bodies {
        assert!(s.world.body(b).unwrap().velocity().norm() < 1e-6);
    }
}
