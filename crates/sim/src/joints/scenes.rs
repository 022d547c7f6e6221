//! The two jointed scenes of `benchmarks/joints.py`, built through the joint
//! API (the same bodies, joints, motors and torsional friction its MJCF
//! gives): `examples/joint_scenes.rs` steps them for profiling, and the
//! tests of the coupled operator and of a held step's allocations use them.

use super::{JointDesc, JointId, JointKind};
use crate::math::{Quat, Vec3};
use crate::{BodyDesc, World, WorldParams};

fn joint(kind: JointKind, a: Option<usize>, b: usize, anchor: Vec3, axis: Vec3) -> JointDesc {
    JointDesc { kind, body_a: a, body_b: b, anchor, axis, limits: None }
}

/// 20 boxes 0.1 × 0.03 × 0.03 m, 0.1 kg, on ball joints end to end, tilted
/// 0.1 rad from upright with the foot 1 cm above the ground (μ = 0.5).
pub fn chain() -> World {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let tilt: f64 = 0.1;
    let a = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let turn = Quat::from_axis_angle(Vec3::Y, -(std::f64::consts::FRAC_PI_2 - tilt));
    let foot = Vec3::new(0.0, 0.0, 0.01);
    for i in 0..20 {
        let c = foot + a * (0.1 * i as f64 + 0.05);
        let link = BodyDesc::cuboid(Vec3::new(0.05, 0.015, 0.015)).mass(0.1).position(c).orientation(turn).mu(0.5);
        let b = w.add_body(link).unwrap().0;
        if i > 0 {
            w.add_joint(joint(JointKind::Ball, Some(b - 1), b, foot + a * (0.1 * i as f64), Vec3::Z)).unwrap();
        }
    }
    w
}

/// The palm on a vertical slider, two fingers on sliders to it with 20 N
/// motors closing at 0.1 m/s, pads with 2 cm of torsional friction, a 1 kg cube
/// (μ = 1) on the ground. Returns the world and the palm's joint.
pub fn gripper() -> (World, JointId) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(1.0).unwrap();
    w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 1.0).unwrap();
    let palm = BodyDesc::cuboid(Vec3::new(0.15, 0.05, 0.02)).mass(1.0).position(Vec3::new(0.0, 0.0, 0.2)).mu(1.0);
    let palm = w.add_body(palm).unwrap().0;
    let lift = w.add_joint(joint(JointKind::Slider, None, palm, Vec3::new(0.0, 0.0, 0.2), Vec3::Z)).unwrap();
    for x in [-0.1, 0.1] {
        let finger = w.add_box(Vec3::new(0.01, 0.04, 0.08), 0.2, Vec3::new(x, 0.0, 0.1), 1.0).unwrap();
        w.set_torsional_friction(finger, 0.02).unwrap();
        let j =
            w.add_joint(joint(JointKind::Slider, Some(palm), finger.0, Vec3::new(x, 0.0, 0.1), -Vec3::X * x.signum()));
        w.set_motor(j.unwrap(), 0.1, 20.0).unwrap();
    }
    (w, lift)
}

/// The palm's motor speed at step `s` of `benchmarks/joints.py`'s phases:
/// closing 1,000 steps, lifting 2,200 (ramped over 200 at each end), holding.
pub fn gripper_lift_speed(s: usize) -> f64 {
    let k = s as f64 - 1000.0;
    if (0.0..2200.0).contains(&k) {
        0.1 * (k / 200.0).min(1.0).min((2200.0 - k) / 200.0)
    } else {
        0.0
    }
}
