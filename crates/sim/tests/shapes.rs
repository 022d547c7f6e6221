//! Every shape pair through the whole pipeline: a body resting on another
//! carries its weight (Σfn = m g h), stays put, and the contact normal points
//! from B to A.

mod common;
use common::*;
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, World, WorldParams};

/// Steps `w` and checks that `top` rests: its contacts carry m g h and it does not move.
fn rests(w: &mut World, top: sim::BodyId, mass: f64) {
    let p0 = w.body(top).unwrap().position();
    for _ in 0..300 {
        let r = step_ok(w);
        // The impulse of the contacts on `top`, whichever side it is on.
        let mut on_top = Vec3::ZERO;
        for (i, c) in r.contacts.iter().enumerate() {
            let imp = c.normal * r.z[i] + r.friction_impulse(i);
            if c.body_a == top.0 {
                on_top += imp;
            } else if c.body_b == top.0 {
                on_top -= imp;
            }
            // The normal separates A from B: A's centre lies on its +normal side.
            let (a, b) = (w.body(sim::BodyId(c.body_a)).unwrap(), w.body(sim::BodyId(c.body_b)).unwrap());
            if !matches!(b.shape(), sim::Shape::Plane(_)) {
                assert!(c.normal.dot(a.position() - b.position()) > 0.0);
            }
        }
        // Degenerate contact sets (8 coplanar points) are solved to Lemke's
        // acceptance, ~1e-9 relative, not to round-off: allow 1e-6.
        assert!(
            (on_top - Vec3::new(0.0, 0.0, mass * G * 1e-3)).norm() < 1e-6 * mass * G * 1e-3,
            "step {}: {:?}",
            r.step,
            on_top
        );
    }
    let b = w.body(top).unwrap();
    assert!((b.position() - p0).norm() < 1e-9 && b.velocity().norm() < 1e-9);
}

#[test]
fn sphere_on_plane_sphere_box_and_sphere() {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let ball = w.add_sphere(0.3, 2.0, Vec3::new(0.0, 0.0, 0.3), 0.5).unwrap();
    rests(&mut w, ball, 2.0);

    // A ball on a static box (sphere A, box B) ...
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_body(BodyDesc::cuboid(Vec3::new(1.0, 1.0, 0.5)).position(Vec3::new(0.0, 0.0, 0.5)).fixed(true)).unwrap();
    let ball = w.add_sphere(0.2, 1.5, Vec3::new(0.3, -0.2, 1.2), 0.5).unwrap();
    rests(&mut w, ball, 1.5);

    // ... on a dynamic box lying on the ground (box listed first: A/B swapped) ...
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let base = w.add_box(Vec3::new(1.0, 1.0, 0.5), 3.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
    let ball = w.add_sphere(0.2, 1.5, Vec3::new(0.0, 0.0, 1.2), 0.5).unwrap();
    rests(&mut w, ball, 1.5);
    let r = w.last_record();
    let ground_total: f64 = r.contacts.iter().enumerate().filter(|(_, c)| c.body_b == 0).map(|(i, _)| r.z[i]).sum();
    assert!(rel(ground_total, 4.5 * G * 1e-3) < 1e-12);
    let _ = base;

    // ... and on top of a static ball.
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_body(BodyDesc::sphere(0.5).fixed(true)).unwrap();
    let ball = w.add_sphere(0.25, 1.0, Vec3::new(0.0, 0.0, 0.75), 0.5).unwrap();
    rests(&mut w, ball, 1.0);
}

#[test]
fn box_on_static_box_and_turned_box_on_box() {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_body(BodyDesc::cuboid(Vec3::new(2.0, 2.0, 0.5)).position(Vec3::new(0.0, 0.0, 0.5)).fixed(true)).unwrap();
    let top = w.add_box(Vec3::new(0.3, 0.2, 0.1), 0.7, Vec3::new(0.5, 0.5, 1.1), 0.5).unwrap();
    rests(&mut w, top, 0.7);

    // A cube turned by 30° about z on another cube on the ground: the flat octagon of clipped
    // points is cut to the 4 that span it.
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    w.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
    let top = w
        .add_body(
            BodyDesc::cuboid(Vec3::splat(0.5))
                .position(Vec3::new(0.0, 0.0, 1.5))
                .orientation(Quat::from_axis_angle(Vec3::Z, 30f64.to_radians())),
        )
        .unwrap();
    let r = step_ok(&mut w);
    assert_eq!(r.contacts.iter().filter(|c| c.body_b == top.0 || c.body_a == top.0).count(), 4);
    rests(&mut w, top, 1.0);
}

#[test]
fn k_friction_directions_are_used_everywhere() {
    let mut w = World::new(WorldParams { friction_dirs: 6, ..Default::default() }).unwrap();
    w.add_ground(0.5).unwrap();
    let ball = w.add_sphere(0.3, 1.0, Vec3::new(0.0, 0.0, 0.3), 0.5).unwrap();
    rests(&mut w, ball, 1.0);
    assert_eq!(w.last_record().lcp_size, 8);
}
