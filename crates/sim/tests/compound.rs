//! Compound bodies (several solid parts in one body frame) against analytic
//! answers: mass properties, a dumbbell resting on its two spheres, a table
//! on four legs, and a compound of one box moving as the box.

mod common;
use common::*;
use sim::geometry::{CompoundPart, Shape};
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, Downhill, Plane, SimError, World, WorldParams};

fn part(shape: Shape, position: Vec3) -> CompoundPart {
    CompoundPart { shape, position, orientation: Quat::IDENTITY }
}

/// Two spheres of radius 0.2 at x = ±0.5 and a bar (capsule, radius 0.05) between them.
fn dumbbell() -> Vec<CompoundPart> {
    let bar = CompoundPart {
        shape: Shape::capsule(0.05, 0.4).unwrap(),
        position: Vec3::ZERO,
        orientation: Quat::from_axis_angle(Vec3::Y, std::f64::consts::FRAC_PI_2),
    };
    vec![
        part(Shape::sphere(0.2).unwrap(), Vec3::new(-0.5, 0.0, 0.0)),
        bar,
        part(Shape::sphere(0.2).unwrap(), Vec3::new(0.5, 0.0, 0.0)),
    ]
}

#[test]
fn compound_mass_properties_are_the_parts_summed_about_their_centre() {
    // Two unit cubes side by side along x, given off the origin: a 2×1×1 box.
    let parts = [
        part(Shape::cuboid(Vec3::splat(0.5)).unwrap(), Vec3::new(3.0, 1.0, 0.0)),
        part(Shape::cuboid(Vec3::splat(0.5)).unwrap(), Vec3::new(4.0, 1.0, 0.0)),
    ];
    let Shape::Compound(c) = Shape::compound(&parts).unwrap() else { unreachable!() };
    assert!((c.com_offset() - Vec3::new(3.5, 1.0, 0.0)).norm() < 1e-14);
    assert!(rel(c.volume(), 2.0) < 1e-14);
    let want = Shape::cuboid(Vec3::new(1.0, 0.5, 0.5)).unwrap().inertia(6.0).unwrap();
    let got = c.inertia(6.0);
    for r in 0..3 {
        for k in 0..3 {
            assert!((got.m[r][k] - want.m[r][k]).abs() < 1e-12, "{got:?} vs {want:?}");
        }
    }
    assert!((c.parts()[0].position - Vec3::new(-0.5, 0.0, 0.0)).norm() < 1e-14);
}

#[test]
fn dumbbell_rests_on_its_two_spheres_at_their_radius() {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let start = Vec3::new(0.0, 0.0, 0.2);
    let id = w.add_body(BodyDesc::new(Shape::compound(&dumbbell()).unwrap()).mass(3.0).position(start)).unwrap();
    let r = run_ok(&mut w, 1000);
    let b = w.body(id).unwrap();
    eprintln!("dumbbell at {:?}, contacts {}", b.position(), r.contacts.len());
    assert!((b.position() - start).norm() < 1e-6, "drift {:?}", b.position() - start);
    assert!(b.velocity().norm() < 1e-6 && b.angular_velocity().norm() < 1e-6);
    // Two contacts (one per sphere, none from the bar), each carrying half the weight.
    assert_eq!(r.contacts.len(), 2);
    let half = 0.5 * 3.0 * G * r.dt;
    for (i, c) in r.contacts.iter().enumerate() {
        assert!((c.point.x.abs() - 0.5).abs() < 1e-9 && c.point.z.abs() < 1e-6, "contact at {:?}", c.point);
        assert!(rel(r.z[i], half) < 1e-6, "fn {} vs m g dt / 2 = {half}", r.z[i]);
    }
}

#[test]
fn dumbbell_dropped_on_a_sphere_pair_settles_at_the_contact_height() {
    // The dumbbell lands across two static spheres of radius 0.3 at x = ±0.5:
    // its spheres' centres rest 0.2 + 0.3 above theirs.
    let mut w = World::new(WorldParams::default()).unwrap();
    for x in [-0.5, 0.5] {
        w.add_body(BodyDesc::sphere(0.3).position(Vec3::new(x, 0.0, 0.0)).fixed(true)).unwrap();
    }
    let id =
        w.add_body(BodyDesc::new(Shape::compound(&dumbbell()).unwrap()).position(Vec3::new(0.0, 0.0, 0.55))).unwrap();
    run_ok(&mut w, 1500);
    let b = w.body(id).unwrap();
    eprintln!("dumbbell at {:?}", b.position());
    assert!((b.position() - Vec3::new(0.0, 0.0, 0.5)).norm() < 1e-4, "at {:?}", b.position());
    assert!(b.velocity().norm() < 1e-6);
}

#[test]
fn table_on_four_legs_carries_equal_shares_on_each_diagonal() {
    // A 1.0 × 0.6 top (0.05 thick) on four capsule legs (radius 0.025): point feet
    // at (±0.45, ±0.25). Rigid contact leaves one share undetermined: every
    // answer is f = W/4 + t(1, −1, 1, −1) over the legs in turn (total W, no
    // moment), so two diagonal legs carry equal shares and two neighbouring
    // ones half the weight; Lemke returns a vertex of that family, not the symmetric quarter.
    let (lx, ly) = (0.45, 0.25);
    let mut parts = vec![part(Shape::cuboid(Vec3::new(0.5, 0.3, 0.025)).unwrap(), Vec3::new(0.0, 0.0, 0.525))];
    let corners = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];
    for (sx, sy) in corners {
        parts.push(part(Shape::capsule(0.025, 0.225).unwrap(), Vec3::new(sx * lx, sy * ly, 0.25)));
    }
    let Shape::Compound(c) = Shape::compound(&parts).unwrap() else { unreachable!() };
    let com = c.com_offset();
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let m = 10.0;
    let id = w.add_body(BodyDesc::new(Shape::Compound(c)).mass(m).position(com)).unwrap();
    let r = run_ok(&mut w, 1000);
    let b = w.body(id).unwrap();
    assert!((b.position() - com).norm() < 1e-6, "drift {:?}", b.position() - com);
    assert_eq!(r.contacts.len(), 4, "one point per foot");
    let mut legs = [0.0f64; 4];
    for (i, c) in r.contacts.iter().enumerate() {
        let k = corners
            .iter()
            .position(|&(sx, sy)| (c.point.x - sx * lx).abs() < 1e-6 && (c.point.y - sy * ly).abs() < 1e-6);
        legs[k.expect("a contact under a foot")] += r.z[i];
    }
    let weight = m * G * r.dt;
    eprintln!("legs {legs:?}, weight {weight}");
    assert!(rel(legs.iter().sum(), weight) < 1e-9);
    assert!(rel(legs[0] + legs[1], 0.5 * weight) < 1e-6, "two neighbouring legs carry half: {legs:?}");
    for (a, b) in [(0, 2), (1, 3)] {
        assert!((legs[a] - legs[b]).abs() < 1e-6 * weight, "diagonal legs {a}, {b} unequal: {legs:?}");
    }
}

#[test]
fn compound_of_one_box_slides_exactly_like_the_box() {
    let (angle, mu) = (30.0f64, 0.3);
    let plane = Plane::slope_deg(angle, Downhill::PlusX).unwrap();
    let n = plane.normal();
    let turn = Quat::from_axis_angle(Vec3::Y, angle.to_radians());
    let run = |shape: Shape| {
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_plane(plane, mu).unwrap();
        let id = w.add_body(BodyDesc::new(shape).mass(2.0).position(n * 0.25).orientation(turn).mu(mu)).unwrap();
        run_ok(&mut w, 800);
        let b = w.body(id).unwrap();
        (b.position(), b.velocity(), b.angular_velocity())
    };
    let half = Vec3::new(0.5, 0.4, 0.25);
    let (pb, vb, wb) = run(Shape::cuboid(half).unwrap());
    let (pc, vc, wc) = run(Shape::compound(&[part(Shape::cuboid(half).unwrap(), Vec3::ZERO)]).unwrap());
    let th = angle.to_radians();
    let a = vb.dot(plane.downhill().unwrap()) / (800.0 * 1e-3);
    eprintln!("box {pb:?} {vb:?}; compound {pc:?} {vc:?}; a {a}");
    assert!(rel(a, G * (th.sin() - mu * th.cos())) < 1e-2, "the box itself slides at g(sin θ − μ cos θ)");
    assert!((pb - pc).norm() < 1e-9 && (vb - vc).norm() < 1e-9 && (wb - wc).norm() < 1e-9);
}

#[test]
fn bad_compounds_are_refused_naming_the_part() {
    let err = |parts: &[CompoundPart]| match Shape::compound(parts) {
        Err(SimError::BadGeometry { field, reason }) => format!("{field} {reason}"),
        other => panic!("expected a refusal, got {other:?}"),
    };
    assert!(err(&[]).contains("at least one part"));
    let bad_radius = err(&[part(Shape::Sphere { radius: -1.0 }, Vec3::ZERO)]);
    assert!(bad_radius.contains("[0]") && bad_radius.contains("radius"), "{bad_radius}");
    let nan = err(&[part(Shape::sphere(1.0).unwrap(), Vec3::new(f64::NAN, 0.0, 0.0))]);
    assert!(nan.contains("position") && nan.contains("NaN"), "{nan}");
    let plane = err(&[part(Shape::Plane(Plane::ground()), Vec3::ZERO)]);
    assert!(plane.contains("is a plane"), "{plane}");
    let zero_q = err(&[CompoundPart {
        shape: Shape::sphere(1.0).unwrap(),
        position: Vec3::ZERO,
        orientation: Quat::from_array([0.0; 4]),
    }]);
    assert!(zero_q.contains("orientation"), "{zero_q}");
}
