//! The "cube on slope" scene: rests iff tan θ ≤ min(μ, 1); tips iff tan θ > 1
//! and μ > 1; slides without tipping if μ ≤ 1. The source note's case: the μ = 1 cube on a
//! 45° + ε slope must slide (friction capped at μN puts the normal resultant
//! exactly on the downhill edge), at every friction-cone scale.

mod common;
use common::*;
use sim::scenes::CubeOnSlope;
use sim::{ConeScale, WorldParams};

struct Outcome {
    /// Displacement along the downhill direction (m).
    downhill: f64,
    /// Rotation from the initial orientation (rad).
    tilt: f64,
    failures: usize,
}

fn simulate(angle_deg: f64, mu: f64, seconds: f64, params: WorldParams) -> Outcome {
    let steps = (seconds / params.dt).round() as usize;
    let mut s = CubeOnSlope::new(angle_deg, mu).build(params).unwrap();
    let d = sim::Plane::slope_deg(angle_deg, sim::Downhill::PlusX).unwrap().downhill().unwrap();
    let (p0, q0) = pose(&s, s.body);
    let traj = s.world.run(steps).unwrap();
    let (p, q) = pose(&s, s.body);
    Outcome { downhill: (p - p0).dot(d), tilt: q.angle_to(q0), failures: traj.failures() }
}

#[test]
fn rests_when_tan_theta_below_min_mu_one() {
    for (angle, mu) in [(30.0, 0.7), (40.0, 1.5), (44.0, 1.0), (20.0, 0.5)] {
        let o = simulate(angle, mu, 2.0, WorldParams::default());
        assert_eq!(o.failures, 0);
        assert!(
            o.downhill.abs() < 1e-6 && o.tilt < 1e-6,
            "θ {angle} μ {mu}: moved {} m, tilted {} rad",
            o.downhill,
            o.tilt
        );
    }
}

#[test]
fn tips_when_tan_theta_above_one_and_mu_above_one() {
    for (angle, mu) in [(50.0, 1.5), (47.0, 2.0)] {
        let o = simulate(angle, mu, 2.0, WorldParams::default());
        assert_eq!(o.failures, 0);
        assert!(o.tilt > 0.5, "θ {angle} μ {mu}: tilt only {} rad", o.tilt);
    }
}

#[test]
fn slides_without_tipping_when_mu_at_most_one() {
    for (angle, mu) in [(40.0, 0.5), (50.0, 0.8), (60.0, 1.0)] {
        let o = simulate(angle, mu, 1.0, WorldParams::default());
        let th = f64::to_radians(angle);
        let expect = 0.5 * G * (th.sin() - mu * th.cos());
        assert_eq!(o.failures, 0);
        assert!(rel(o.downhill, expect) < 0.01, "θ {angle} μ {mu}: {} m vs {expect} m", o.downhill);
        assert!(o.tilt < 1e-6, "θ {angle} μ {mu}: tilted {} rad", o.tilt);
    }
}

/// At 45.2° a μ = 1 cube slides 0.097 m in 2 s (½ g (sin θ − cos θ) t²).
#[test]
fn knife_edge_45_2_degrees_slides_at_every_scale() {
    let scales = [ConeScale::Unscaled, ConeScale::Value(0.1), ConeScale::TimeStep, ConeScale::Value(1e-6)];
    slides_at_every_scale(45.2, scales, 0.01, 1e-3);
}

/// The source note's test, 45° + 1e-4°, μ = 1: it must slide (a ≈ 2.4e-5 m/s²), not tip.
#[test]
fn knife_edge_45_plus_1e4_degrees_slides_at_every_scale() {
    let scales = [ConeScale::Unscaled, ConeScale::Value(4e-3), ConeScale::TimeStep, ConeScale::Value(1e-6)];
    slides_at_every_scale(45.0 + 1e-4, scales, 0.05, 1e-6);
}

/// A μ = 1 cube on a slope of `angle` degrees slides for 2 s as a block does,
/// `½ g (sin θ − cos θ) t²` within `rel_tol`, tilting less than `tilt` rad,
/// with no failed LCP, at every cone scale of `scales`.
fn slides_at_every_scale(angle: f64, scales: [ConeScale; 4], rel_tol: f64, tilt: f64) {
    let th = angle.to_radians();
    let expect = 0.5 * G * (th.sin() - th.cos()) * 4.0;
    for scale in scales {
        let o = simulate(angle, 1.0, 2.0, WorldParams { cone_scale: scale, ..Default::default() });
        assert_eq!(o.failures, 0, "{scale:?}");
        assert!(
            rel(o.downhill, expect) < rel_tol && o.tilt < tilt,
            "{scale:?}: slid {:e} m (expected {expect:e}), tilted {:e} rad",
            o.downhill,
            o.tilt
        );
    }
}
