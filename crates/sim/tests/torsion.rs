//! Torsional friction of a contact patch (`sim::contact::torsion`): a box
//! spun on the ground against the analytic deceleration its bound gives, a
//! torque below the bound held, a single point without any, and a gripper's
//! flat pads holding a cube whichever vertex Lemke reaches — every LCP solved.

mod common;
use common::*;
use sim::math::Vec3;
use sim::{BodyDesc, BodyId, JointDesc, JointId, JointKind, JointParams, World, WorldParams};

const H: f64 = 1e-3;

fn world() -> World {
    World::new(WorldParams::default()).unwrap()
}

/// A frictionless 1 kg cube of half side `a` resting on a frictionless
/// ground, with torsional friction `mu_t`; its `I_zz`.
fn cube_on_ground(a: f64, mu_t: f64) -> (World, BodyId, f64) {
    let mut w = world();
    w.add_ground(0.0).unwrap();
    let b = w.add_box(Vec3::splat(a), 1.0, Vec3::new(0.0, 0.0, a), 0.0).unwrap();
    w.set_torsional_friction(b, mu_t).unwrap();
    (w, b, (2.0 * a) * (2.0 * a) / 6.0)
}

#[test]
fn a_box_spun_on_the_ground_slows_at_the_torsional_bound_and_stops() {
    // Points without friction: only the patch's torsion acts, a torque of
    // μ_t m g while it turns, so ω drops by h μ_t m g / I a step to 0, then stays.
    let (mu_t, w0) = (0.01, 2.0);
    let (mut w, b, inertia) = cube_on_ground(0.1, mu_t);
    w.set_angular_velocity(b, Vec3::new(0.0, 0.0, w0)).unwrap();
    let drop = H * mu_t * G / inertia;
    for k in 1..=200 {
        step_ok(&mut w);
        let omega = w.body(b).unwrap().angular_velocity();
        let expect = (w0 - k as f64 * drop).max(0.0);
        assert!((omega.z - expect).abs() < 1e-9, "step {k}: ω {} vs {expect}", omega.z);
        assert!(omega.x.abs() + omega.y.abs() < 1e-9, "step {k}: tilted ω {omega:?}");
    }
    // (w0 / drop ≈ 136 steps: it has been still for the last 64.)
    assert!(w.body(b).unwrap().position().z - 0.1 > -1e-6);
}

#[test]
fn a_torque_below_the_bound_is_held_and_one_above_it_turns_the_box_at_the_difference() {
    let mu_t = 0.01;
    let bound = mu_t * G;
    for (torque, turns) in [(0.9 * bound, false), (1.5 * bound, true)] {
        let (mut w, b, inertia) = cube_on_ground(0.1, mu_t);
        w.apply_torque(b, Vec3::new(0.0, 0.0, torque)).unwrap();
        run_ok(&mut w, 100);
        let omega = w.body(b).unwrap().angular_velocity().z;
        let expect = if turns { 100.0 * H * (torque - bound) / inertia } else { 0.0 };
        assert!((omega - expect).abs() < 1e-9, "torque {torque}: ω {omega} vs {expect}");
    }
}

#[test]
fn a_single_point_has_no_torsional_friction() {
    // A sphere touches at one point: torsion is a patch's, so it spins on.
    let mut w = world();
    w.add_ground(0.0).unwrap();
    let b = w.add_sphere(0.1, 1.0, Vec3::new(0.0, 0.0, 0.1), 0.0).unwrap();
    w.set_torsional_friction(b, 0.05).unwrap();
    w.set_angular_velocity(b, Vec3::new(0.0, 0.0, 3.0)).unwrap();
    run_ok(&mut w, 100);
    assert_eq!(w.body(b).unwrap().angular_velocity().z, 3.0);
}

#[test]
fn torsional_friction_is_not_negative() {
    let (mut w, b, _) = cube_on_ground(0.1, 0.0);
    assert!(w.set_torsional_friction(b, -0.01).is_err());
    assert!(w.set_torsional_friction(b, f64::NAN).is_err());
}

fn slider(a: Option<usize>, b: usize, anchor: Vec3, axis: Vec3) -> JointDesc {
    JointDesc { kind: JointKind::Slider, body_a: a, body_b: b, anchor, axis, limits: None }
}

/// `benchmarks/joints.py`'s gripper (flat pads 2 × 8 × 16 cm on a 10 cm,
/// 1 kg cube, μ = 1, 20 N a finger) with torsional friction `mu_t` on the
/// pads: the cube's lift and its slip against a finger while lifting and
/// holding. `drift` is the joints' `β`; `palm_anchors` puts the fingers'
/// slider anchors at the palm's underside instead of the fingers' centres
/// (the same joints, other last digits of `q`).
fn flat_gripper(mu_t: f64, drift: f64, palm_anchors: bool) -> (f64, f64, f64) {
    let mut w = world();
    w.set_joint_params(JointParams { drift, ..w.joint_params() }).unwrap();
    w.add_ground(1.0).unwrap();
    let cube = w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 1.0).unwrap().0;
    let palm = BodyDesc::cuboid(Vec3::new(0.15, 0.05, 0.02)).mass(1.0).position(Vec3::new(0.0, 0.0, 0.2)).mu(1.0);
    let palm = w.add_body(palm).unwrap().0;
    let pad = Vec3::new(0.01, 0.04, 0.08);
    let left = w.add_box(pad, 0.2, Vec3::new(-0.1, 0.0, 0.1), 1.0).unwrap();
    let right = w.add_box(pad, 0.2, Vec3::new(0.1, 0.0, 0.1), 1.0).unwrap();
    for f in [left, right] {
        w.set_torsional_friction(f, mu_t).unwrap();
    }
    let anchor = |x: f64| if palm_anchors { Vec3::new(x, 0.0, 0.18) } else { Vec3::new(x, 0.0, 0.1) };
    let lift = w.add_joint(slider(None, palm, Vec3::new(0.0, 0.0, 0.2), Vec3::Z)).unwrap();
    let jl = w.add_joint(slider(Some(palm), left.0, anchor(-0.1), Vec3::X)).unwrap();
    let jr = w.add_joint(slider(Some(palm), right.0, anchor(0.1), -Vec3::X)).unwrap();
    w.set_motor(jl, 0.1, 20.0).unwrap();
    w.set_motor(jr, 0.1, 20.0).unwrap();
    let rel_z = |w: &World| w.bodies()[cube].position().z - w.bodies()[left.0].position().z;
    let phase = |w: &mut World, steps: usize, lifting: bool| {
        let start = rel_z(w);
        for s in 0..steps {
            let speed = if lifting { 0.1 * (s as f64 / 200.0).min(1.0).min((steps - s) as f64 / 200.0) } else { 0.0 };
            w.set_motor(lift, speed, 200.0).unwrap();
            step_ok(w);
        }
        (rel_z(w) - start).abs()
    };
    phase(&mut w, 1000, false);
    let slip_lift = phase(&mut w, 2200, true);
    let slip_hold = phase(&mut w, 2000, false);
    for j in 0..3 {
        assert!(w.joint_error(JointId(j)).unwrap().0 <= 1e-6);
    }
    (w.bodies()[cube].position().z - 0.05, slip_lift, slip_hold)
}

#[test]
fn flat_pads_with_torsional_friction_hold_the_cube_whatever_the_last_digits() {
    // 2 cm of torsional friction: μ times about the mean radius of the pads'
    // 8 × 10 cm overlap (2.7 cm). Lemke may load one corner per pad, the two
    // on a line along the grip: gravity's moment about it, m g · 4 cm ≈ 0.39
    // N·m, is then held by torsion alone, up to 2 · 0.02 · 20 = 0.8 N·m.
    for (drift, palm_anchors) in [(1.0, false), (0.0, false), (1.0, true)] {
        let (lift, slip_lift, slip_hold) = flat_gripper(0.02, drift, palm_anchors);
        eprintln!("drift {drift}, palm anchors {palm_anchors}: lift {lift:.6} m, slip {slip_lift:e} / {slip_hold:e} m");
        assert!((lift - 0.2).abs() < 2e-3, "drift {drift}, palm anchors {palm_anchors}: lifted {lift}");
        assert!(
            slip_lift <= 1e-3 && slip_hold <= 1e-3,
            "drift {drift}, palm anchors {palm_anchors}: slip {slip_lift:e}, {slip_hold:e}"
        );
    }
}
