//! A block on an incline whose downhill direction is a friction
//! direction (`d_0`) sticks iff tan θ ≤ μ and slides with a = g(sin θ − μ cos θ);
//! along a bisector of two friction directions the threshold is μ·cos(π/k).

mod common;
use common::*;
use sim::math::Vec3;
use sim::scenes::CubeOnSlope;
use sim::{Downhill, WorldParams};

/// Runs a cube on a slope for `steps` and returns (downhill speed, speed) at the end.
fn run_block(mut scene: CubeOnSlope, steps: usize) -> (f64, f64, Vec3) {
    scene.size = 0.2; // a flat-ish block: μ < 1 never tips it anyway
    let mut s = scene.build(WorldParams::default()).unwrap();
    let downhill = sim::Plane::slope_deg(scene.angle_deg, scene.downhill).unwrap().downhill().unwrap();
    let r = run_ok(&mut s.world, steps);
    let v = s.world.body(s.body).unwrap().velocity();
    (v.dot(downhill), v.norm(), r.contacts[0].tangent)
}

#[test]
fn downhill_direction_is_the_first_friction_direction() {
    for toward in [Downhill::PlusX, Downhill::MinusX] {
        let mut scene = CubeOnSlope::new(25.0, 0.3);
        scene.downhill = toward;
        let mut s = scene.build(WorldParams::default()).unwrap();
        let r = step_ok(&mut s.world);
        let d = sim::Plane::slope_deg(25.0, toward).unwrap().downhill().unwrap();
        assert_eq!(r.nc(), 4);
        for c in &r.contacts {
            assert!((c.tangent - d).norm() < 1e-15, "{:?} vs {:?}", c.tangent, d);
        }
    }
}

#[test]
fn block_sticks_below_the_friction_angle() {
    for mu in [0.2f64, 0.5, 0.9] {
        let theta = (0.98 * mu).atan().to_degrees();
        let mut sc = CubeOnSlope::new(theta, mu);
        sc.downhill = if mu > 0.4 { Downhill::MinusX } else { Downhill::PlusX };
        let (_, speed, _) = run_block(sc, 1000);
        assert!(speed < 1e-6, "μ {mu}, θ {theta}: drift {speed:e} m/s");
    }
}

#[test]
fn block_slides_above_the_friction_angle_with_the_coulomb_acceleration() {
    for mu in [0.2f64, 0.5, 0.9] {
        let th = (1.02 * mu).atan();
        let steps = 1000;
        let (vd, speed, _) = run_block(CubeOnSlope::new(th.to_degrees(), mu), steps);
        let a = vd / (steps as f64 * 1e-3);
        let expect = G * (th.sin() - mu * th.cos());
        assert!(rel(a, expect) < 0.01, "μ {mu}: a {a} vs {expect}");
        assert!(rel(speed, vd) < 1e-9, "the block must slide straight downhill");
    }
    // Far above the threshold too.
    let th = 40f64.to_radians();
    let (vd, _, _) = run_block(CubeOnSlope::new(40.0, 0.3), 1000);
    assert!(rel(vd, G * (th.sin() - 0.3 * th.cos())) < 1e-6);
}

#[test]
fn along_a_bisector_the_threshold_is_mu_cos_pi_over_k() {
    let k = 8.0f64;
    let mu = 0.6;
    let bisector = |tan_theta: f64| {
        let mut sc = CubeOnSlope::new(tan_theta.atan().to_degrees(), mu);
        sc.tangent_angle = std::f64::consts::PI / k;
        let (vd, speed, t) = run_block(sc, 1000);
        (vd, speed, t)
    };
    let limit = mu * (std::f64::consts::PI / k).cos();
    // Sticks just below μ cos(π/k) ...
    let (_, speed, t) = bisector(0.98 * limit);
    assert!(speed < 1e-6, "drift {speed:e}");
    let d = sim::Plane::slope_deg((0.98 * limit).atan().to_degrees(), Downhill::PlusX).unwrap().downhill().unwrap();
    assert!((t.dot(d) - (std::f64::consts::PI / k).cos()).abs() < 1e-12, "tangent is π/k off downhill");
    // ... slides just above it, and at 0.98 μ where it would stick on a friction direction.
    for tan in [1.02 * limit, 0.98 * mu] {
        let (vd, _, _) = bisector(tan);
        let th = tan.atan();
        let expect = G * (th.sin() - limit * th.cos());
        assert!(vd > 0.5 * expect, "tan θ {tan}: downhill speed {vd} after 1 s, expected ≈ {expect}");
    }
}
