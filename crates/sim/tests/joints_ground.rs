//! Jointed bodies resting on the ground, where the joints fix some contacts'
//! normals (`sim::joints::held_contacts`): a bar hinged at one end or at its
//! centre, a box welded to the world, a box on a vertical and on a
//! horizontal slider. Every LCP over 2 s solved, the bodies still, and the
//! loads what statics says where it says anything.

mod common;
use common::*;
use sim::math::Vec3;
use sim::{JointDesc, JointKind, StepRecord, World, WorldParams};

const H: f64 = 1e-3;

/// A 1 m, 1 kg bar (half extents 0.5, 0.05, 0.05) lying on the ground (μ =
/// 0.5) along x, centre at (0, 0, 0.05), held to the world by `kind` at
/// `anchor` along `axis`; the world and the bar.
fn bar_on_ground(kind: JointKind, anchor: Vec3, axis: Vec3) -> (World, usize) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let bar = w.add_box(Vec3::new(0.5, 0.05, 0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 0.5).unwrap().0;
    w.add_joint(JointDesc { kind, body_a: None, body_b: bar, anchor, axis, limits: None }).unwrap();
    (w, bar)
}

/// Runs 2 s, every step solved; the bar's largest displacement and the last record.
fn rest(w: &mut World, bar: usize) -> (f64, StepRecord) {
    let start = w.bodies()[bar].position();
    let (mut moved, mut last) = (0.0f64, StepRecord::default());
    for _ in 0..2000 {
        last = step_ok(w);
        moved = moved.max((w.bodies()[bar].position() - start).norm());
    }
    (moved, last)
}

/// Normal force (N) of the contacts with `x` on the given side of 0.
fn load(r: &StepRecord, right: bool) -> f64 {
    r.contacts.iter().enumerate().filter(|(_, c)| (c.point.x > 0.0) == right).map(|(i, _)| r.z[i] / H).sum()
}

#[test]
fn a_bar_hinged_at_one_end_rests_on_its_far_end_with_half_its_weight() {
    let (mut w, bar) = bar_on_ground(JointKind::Hinge, Vec3::new(-0.5, 0.0, 0.05), Vec3::Y);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the bar moved {moved:e} m");
    // The contacts under the axle are the hinge's: only the far end's are in the LCP.
    assert!(r.contacts.iter().all(|c| c.point.x > 0.0), "{:?}", r.contacts);
    assert!(rel(load(&r, true), G / 2.0) < 1e-9, "far end {} N vs {}", load(&r, true), G / 2.0);
    let hinge = r.joints[0].force;
    assert!(rel(hinge.z, G / 2.0) < 1e-9 && hinge.x.abs() < 1e-9, "hinge {hinge:?}");
}

#[test]
fn a_bar_hinged_at_its_centre_rests_level_on_both_ends() {
    let (mut w, bar) = bar_on_ground(JointKind::Hinge, Vec3::new(0.0, 0.0, 0.05), Vec3::Y);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the bar moved {moved:e} m");
    // How the weight splits between the hinge and the ground is indeterminate;
    // the total and the moment balance about the axle are not.
    let (left, right) = (load(&r, false), load(&r, true));
    assert!(rel(left + right + r.joints[0].force.z, G) < 1e-9, "{left} + {right} + hinge vs {G}");
    assert!((left - right).abs() <= 1e-9 * G, "ends {left} and {right} N");
}

#[test]
fn a_box_welded_to_the_world_on_the_ground_hangs_on_its_weld() {
    // Every contact's normal is the weld's: none is in the LCP.
    let (mut w, bar) = bar_on_ground(JointKind::Fixed, Vec3::new(0.2, 0.0, 0.05), Vec3::Z);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the box moved {moved:e} m");
    assert!(r.contacts.is_empty(), "{} contacts", r.contacts.len());
    assert!((r.joints[0].force - Vec3::new(0.0, 0.0, G)).norm() < 1e-9, "{:?}", r.joints[0].force);
}

#[test]
fn a_box_on_a_vertical_slider_rests_on_the_ground_with_its_weight() {
    // The slider leaves the normal free: the ground carries the weight, the slider nothing.
    let (mut w, bar) = bar_on_ground(JointKind::Slider, Vec3::new(0.0, 0.0, 0.05), Vec3::Z);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the box moved {moved:e} m");
    assert_eq!(r.contacts.len(), 4);
    assert!(rel(load(&r, false) + load(&r, true), G) < 1e-9, "ground {} N", load(&r, false) + load(&r, true));
    assert!(r.joints[0].force.z.abs() < 1e-9, "{:?}", r.joints[0].force);
}

#[test]
fn a_box_on_a_horizontal_slider_at_the_ground_is_carried_by_the_slider() {
    let (mut w, bar) = bar_on_ground(JointKind::Slider, Vec3::new(0.0, 0.0, 0.05), Vec3::X);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the box moved {moved:e} m");
    assert!(r.contacts.is_empty(), "{} contacts", r.contacts.len());
    assert!(rel(r.joints[0].force.z, G) < 1e-9, "{:?}", r.joints[0].force);
}

#[test]
fn a_hinge_just_beside_the_end_keeps_the_contacts_under_it() {
    // 5 cm from the end the contacts there move with the bar: they stay in the LCP.
    let (mut w, bar) = bar_on_ground(JointKind::Hinge, Vec3::new(-0.45, 0.0, 0.05), Vec3::Y);
    let (moved, r) = rest(&mut w, bar);
    assert!(moved <= 1e-9, "the bar moved {moved:e} m");
    assert_eq!(r.contacts.len(), 4);
    assert!(rel(load(&r, false) + load(&r, true) + r.joints[0].force.z, G) < 1e-9);
}
