//! Sliding to rest from v0 stops after v0²/(2μg); energy never grows.

mod common;
use common::*;
use sim::scenes::CubeOnSlope;
use sim::WorldParams;

fn slide_distance(v0: f64, mu: f64) -> (f64, usize) {
    let mut sc = CubeOnSlope::new(0.0, mu);
    sc.speed = v0;
    let mut s = sc.build(WorldParams::default()).unwrap();
    let x0 = s.world.body(s.body).unwrap().position().x;
    let mut e = s.world.energy();
    let mut steps = 0;
    loop {
        step_ok(&mut s.world);
        steps += 1;
        let e1 = s.world.energy();
        assert!(e1 <= e + 1e-12, "energy grew while sliding: {e} → {e1}");
        e = e1;
        if s.world.body(s.body).unwrap().velocity().norm() < 1e-12 || steps > 100_000 {
            break;
        }
    }
    // It stays stopped.
    run_ok(&mut s.world, 100);
    let b = s.world.body(s.body).unwrap();
    assert!(b.velocity().norm() < 1e-9);
    (b.position().x - x0, steps)
}

#[test]
fn sliding_cube_stops_after_v0_squared_over_2_mu_g() {
    for (v0, mu) in [(3.0, 0.5), (2.0, 0.3), (4.0, 1.0)] {
        let (d, steps) = slide_distance(v0, mu);
        let expect = v0 * v0 / (2.0 * mu * G);
        assert!(rel(d, expect) < 0.005, "v0 {v0} μ {mu}: {d} m vs {expect} m ({steps} steps)");
    }
}

#[test]
fn energy_of_a_cube_sliding_down_a_slope_does_not_grow() {
    // Friction dissipates exactly μ N·(distance): E(t) = E0 − μ m g cos θ · s(t).
    let (angle, mu) = (35.0f64, 0.4);
    let mut s = CubeOnSlope::new(angle, mu).build(WorldParams::default()).unwrap();
    let p0 = s.world.body(s.body).unwrap().position();
    let e0 = s.world.energy();
    let mut e = e0;
    for _ in 0..1000 {
        step_ok(&mut s.world);
        let e1 = s.world.energy();
        assert!(e1 <= e + 1e-12, "energy grew {e} → {e1}");
        e = e1;
    }
    let dist = (s.world.body(s.body).unwrap().position() - p0).norm();
    let dissipated = mu * G * angle.to_radians().cos() * dist;
    // Semi-implicit Euler loses a little more than friction does (O(h)), never less.
    assert!(e0 - e >= dissipated * (1.0 - 1e-9), "lost {} J, friction alone {} J", e0 - e, dissipated);
    assert!(rel(e0 - e, dissipated) < 2e-3, "lost {} J, friction {} J", e0 - e, dissipated);
}
