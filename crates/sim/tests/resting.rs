//! A cube resting on flat ground — Σfn = m·g·h every step, no drift.

mod common;
use common::*;
use sim::math::Vec3;
use sim::scenes::CubeOnSlope;
use sim::{ConeScale, WorldParams};

fn resting(params: WorldParams, steps: usize) {
    let h = params.dt;
    let mut s = CubeOnSlope::new(0.0, 0.5).build(params).unwrap();
    let (p0, q0) = pose(&s, s.body);
    let mgh = 1.0 * G * h;
    for _ in 0..steps {
        let r = step_ok(&mut s.world);
        assert_eq!(r.nc(), 4);
        assert_eq!(r.lcp_size, 40);
        let total = r.total_normal_impulse();
        assert!(rel(total, mgh) < 1e-12, "step {}: Σfn = {total:e}, m g h = {mgh:e}", r.step);
        let b = s.world.body(s.body).unwrap();
        assert!(
            b.velocity().norm() < 1e-9 && b.angular_velocity().norm() < 1e-9,
            "step {}: v {:?} ω {:?}",
            r.step,
            b.velocity(),
            b.angular_velocity()
        );
    }
    let (p, q) = pose(&s, s.body);
    assert!((p - p0).norm() < 1e-9, "drift {:?}", p - p0);
    assert!(q.angle_to(q0) < 1e-9);
}

#[test]
fn resting_cube_carries_its_weight_every_step() {
    resting(WorldParams::default(), 2000);
}

#[test]
fn resting_cube_with_scaled_cone_is_unchanged() {
    for scale in [ConeScale::TimeStep, ConeScale::Value(1e-6), ConeScale::Value(10.0)] {
        resting(WorldParams { cone_scale: scale, ..Default::default() }, 300);
    }
}

#[test]
fn resting_cube_with_other_time_steps_and_k() {
    resting(WorldParams { dt: 1e-2, ..Default::default() }, 300);
    let mut s = CubeOnSlope::new(0.0, 0.5).build(WorldParams { friction_dirs: 4, ..Default::default() }).unwrap();
    let r = run_ok(&mut s.world, 100);
    assert_eq!(r.lcp_size, 4 * 6);
    assert!(rel(r.total_normal_impulse(), G * 1e-3) < 1e-12);
}

#[test]
fn energy_of_a_resting_cube_does_not_grow() {
    let mut s = CubeOnSlope::new(0.0, 0.5).build(WorldParams::default()).unwrap();
    let mut e = s.world.energy();
    for _ in 0..1000 {
        step_ok(&mut s.world);
        let e1 = s.world.energy();
        assert!(e1 <= e + 1e-12, "energy grew {e} → {e1}");
        e = e1;
    }
}

#[test]
fn resting_on_a_slope_below_friction_does_not_drift() {
    let mut s = CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap();
    let p0 = s.world.body(s.body).unwrap().position();
    let mgh_cos = G * 1e-3 * 30f64.to_radians().cos();
    let mut e = s.world.energy();
    for _ in 0..2000 {
        let r = step_ok(&mut s.world);
        assert!(rel(r.total_normal_impulse(), mgh_cos) < 1e-9);
        let e1 = s.world.energy();
        assert!(e1 <= e + 1e-12);
        e = e1;
    }
    let b = s.world.body(s.body).unwrap();
    assert!(b.velocity().norm() < 1e-9);
    assert!((b.position() - p0).norm() < 1e-9);
    let _ = Vec3::ZERO;
}
