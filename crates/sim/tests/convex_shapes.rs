//! Capsules, cylinders, convex hulls and triangle meshes (parry's contact
//! manifolds) against analytic answers and against the hand-written box and
//! plane routines.

mod common;
use common::*;
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, Downhill, Plane, SimError, World, WorldParams};

/// The rotation taking the body's z onto the unit vector `n`.
fn z_onto(n: Vec3) -> Quat {
    let axis = Vec3::Z.cross(n);
    match axis.try_normalize() {
        Some(a) => Quat::from_axis_angle(a, n.z.clamp(-1.0, 1.0).acos()),
        None => Quat::IDENTITY,
    }
}

/// Downhill speed after `steps` of a body `desc` placed on a slope of `angle`° with μ.
fn downhill_acceleration(desc: BodyDesc, angle: f64, mu: f64, steps: usize) -> f64 {
    let plane = Plane::slope_deg(angle, Downhill::PlusX).unwrap();
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_plane(plane, mu).unwrap();
    let id = w.add_body(desc.mu(mu)).unwrap();
    run_ok(&mut w, steps);
    let v = w.body(id).unwrap().velocity();
    v.dot(plane.downhill().unwrap()) / (steps as f64 * w.params().dt)
}

#[test]
fn sphere_and_cylinder_roll_down_an_incline_without_slipping() {
    let (angle, mu, steps) = (20.0f64, 0.5, 1000);
    let th = angle.to_radians();
    let n = Plane::slope_deg(angle, Downhill::PlusX).unwrap().normal();
    let sphere = BodyDesc::sphere(0.5).position(n * 0.5);
    let a = downhill_acceleration(sphere, angle, mu, steps);
    let expect = 5.0 / 7.0 * G * th.sin();
    eprintln!("sphere: a {a}, expected {expect}, rel {:e}", rel(a, expect));
    assert!(rel(a, expect) < 1e-2, "sphere: a {a} vs 5/7 g sin θ = {expect}");
    // Axis along world y (across the slope): body z onto y.
    let cyl = BodyDesc::cylinder(0.4, 0.5).position(n * 0.4).orientation(z_onto(Vec3::Y));
    let a = downhill_acceleration(cyl, angle, mu, steps);
    let expect = 2.0 / 3.0 * G * th.sin();
    eprintln!("cylinder: a {a}, expected {expect}, rel {:e}", rel(a, expect));
    assert!(rel(a, expect) < 1e-2, "cylinder: a {a} vs 2/3 g sin θ = {expect}");
}

#[test]
fn cylinder_standing_on_its_cap_slides_like_a_box() {
    let (angle, mu, steps) = (30.0f64, 0.3, 1000);
    let th = angle.to_radians();
    let n = Plane::slope_deg(angle, Downhill::PlusX).unwrap().normal();
    let puck = BodyDesc::cylinder(0.3, 0.1).position(n * 0.1).orientation(z_onto(n));
    let a = downhill_acceleration(puck, angle, mu, steps);
    let expect = G * (th.sin() - mu * th.cos());
    eprintln!("puck: a {a}, expected {expect}, rel {:e}", rel(a, expect));
    assert!(rel(a, expect) < 1e-2, "a {a} vs g(sin θ − μ cos θ) = {expect}");
}

#[test]
fn capsule_lying_on_its_side_stays_at_rest() {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let start = Vec3::new(0.0, 0.0, 0.2);
    let id = w.add_body(BodyDesc::capsule(0.2, 0.5).position(start).orientation(z_onto(Vec3::X))).unwrap();
    let r = run_ok(&mut w, 2000);
    let b = w.body(id).unwrap();
    eprintln!("capsule drift {:e}, contacts {}", (b.position() - start).norm(), r.contacts.len());
    assert!((b.position() - start).norm() < 1e-6, "drift {:?}", b.position() - start);
    assert!(b.velocity().norm() < 1e-6 && b.angular_velocity().norm() < 1e-6);
    assert!(r.contacts.len() >= 2, "a capsule on its side touches along a segment");
}

#[test]
fn convex_hull_of_a_cube_moves_like_the_box() {
    let corners = sim::geometry::BoxShape::cube(1.0).unwrap().corners();
    let hull = sim::ConvexHull::new(&corners).unwrap();
    assert!(rel(hull.volume(), 1.0) < 1e-12);
    assert!(hull.com_offset().norm() < 1e-14);
    let ib = sim::Shape::cuboid(Vec3::splat(0.5)).unwrap().inertia(2.0).unwrap();
    let ih = hull.inertia(2.0);
    for r in 0..3 {
        for c in 0..3 {
            assert!((ib.m[r][c] - ih.m[r][c]).abs() < 1e-12, "inertia {ih:?} vs {ib:?}");
        }
    }
    // Dropped tilted onto the ground, sliding and spinning.
    let q = Quat::from_axis_angle(Vec3::new(1.0, 0.5, 0.0).try_normalize().unwrap(), 0.3);
    let start =
        |d: BodyDesc| d.mass(2.0).position(Vec3::new(0.0, 0.0, 1.2)).orientation(q).velocity(Vec3::new(1.0, 0.0, 0.0));
    let mut worlds: Vec<(World, sim::BodyId)> =
        [BodyDesc::cuboid(Vec3::splat(0.5)), BodyDesc::convex(&corners).unwrap()]
            .into_iter()
            .map(|d| {
                let mut w = World::new(WorldParams::default()).unwrap();
                w.add_ground(0.5).unwrap();
                let id = w.add_body(start(d)).unwrap();
                (w, id)
            })
            .collect();
    let mut worst = 0.0f64;
    for _ in 0..1500 {
        for (w, _) in worlds.iter_mut() {
            step_ok(w);
        }
        let (pa, pb) = (worlds[0].0.body(worlds[0].1).unwrap(), worlds[1].0.body(worlds[1].1).unwrap());
        worst = worst.max((pa.position() - pb.position()).norm());
        worst = worst.max(pa.orientation().angle_to(pb.orientation()));
    }
    eprintln!("hull vs box: worst {worst:e}");
    assert!(worst < 1e-6, "hull and box part by {worst:e} m");
}

#[test]
fn box_rests_on_a_two_triangle_mesh_as_on_the_plane() {
    let v =
        [Vec3::new(-5.0, -5.0, 0.0), Vec3::new(5.0, -5.0, 0.0), Vec3::new(5.0, 5.0, 0.0), Vec3::new(-5.0, 5.0, 0.0)];
    let f = [[0u32, 1, 2], [0, 2, 3]];
    let start = Vec3::new(0.3, -0.2, 0.5);
    let mut out = Vec::new();
    for mesh in [false, true] {
        let mut w = World::new(WorldParams::default()).unwrap();
        if mesh {
            w.add_body(BodyDesc::mesh(&v, &f).unwrap().mu(0.5)).unwrap();
        } else {
            w.add_ground(0.5).unwrap();
        }
        let id = w.add_body(BodyDesc::cuboid(Vec3::splat(0.5)).position(start)).unwrap();
        run_ok(&mut w, 1000);
        out.push(w.body(id).unwrap().position());
    }
    eprintln!("mesh vs plane: {:e}, drift {:e}", (out[0] - out[1]).norm(), (out[1] - start).norm());
    assert!((out[0] - out[1]).norm() < 1e-9, "plane {:?} vs mesh {:?}", out[0], out[1]);
    assert!((out[1] - start).norm() < 1e-6, "drift {:?}", out[1] - start);
}

#[test]
fn bad_shapes_are_refused_naming_the_field() {
    let err = |e: SimError| e.to_string();
    assert!(err(BodyDesc::convex(&[Vec3::ZERO; 3]).unwrap_err()).contains("at least 4"));
    let flat = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.5, 0.5, 0.0)];
    assert!(err(BodyDesc::convex(&flat).unwrap_err()).contains("not in one plane"));
    let nan = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, f64::NAN)];
    assert!(err(BodyDesc::convex(&nan).unwrap_err()).contains("point 3"));
    let v = [Vec3::ZERO, Vec3::X, Vec3::Y];
    assert!(err(BodyDesc::mesh(&v, &[[0, 1, 3]]).unwrap_err()).contains("out of range"));
    assert!(err(BodyDesc::mesh(&v, &[[0, 1, 1]]).unwrap_err()).contains("degenerate"));
    let mut w = World::new(WorldParams::default()).unwrap();
    let e = w.add_body(BodyDesc::capsule(-1.0, 0.5)).unwrap_err();
    assert_eq!(e, SimError::NotPositive { field: "radius", value: -1.0 });
    let e = w.add_body(BodyDesc::cylinder(1.0, 0.0)).unwrap_err();
    assert_eq!(e, SimError::NotPositive { field: "half_length", value: 0.0 });
    let e = w.add_body(BodyDesc::mesh(&v, &[[0, 1, 2]]).unwrap().fixed(false)).unwrap_err();
    assert_eq!(e, SimError::StaticOnly { kind: "mesh" });
    assert_eq!(w.body_count(), 0);
}

#[test]
fn broad_phase_keeps_every_pair_of_capsules_cylinders_and_hulls_that_touch() {
    use sim::broad_phase::{brute_force_pairs, PairMargin};
    use sim::geometry::{parry_pair, ParryScratch, Placement};
    // A deterministic scatter of turned capsules, cylinders and hulls, closely packed.
    let mut seed = 12345u64;
    let mut rnd = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let tetra = [Vec3::ZERO, Vec3::new(0.4, 0.0, 0.0), Vec3::new(0.0, 0.3, 0.0), Vec3::new(0.0, 0.0, 0.5)];
    let mut w = World::new(WorldParams::default()).unwrap();
    for k in 0..120 {
        let d = match k % 3 {
            0 => BodyDesc::capsule(0.05 + 0.1 * rnd(), 0.1 + 0.4 * rnd()),
            1 => BodyDesc::cylinder(0.05 + 0.2 * rnd(), 0.05 + 0.4 * rnd()),
            _ => BodyDesc::convex(&tetra).unwrap(),
        };
        let axis = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).try_normalize().unwrap_or(Vec3::X);
        let p = Vec3::new(3.0 * rnd(), 3.0 * rnd(), 3.0 * rnd());
        w.add_body(d.position(p).orientation(Quat::from_axis_angle(axis, 6.0 * rnd()))).unwrap();
    }
    let margin = PairMargin { base: 1e-3, h: 1e-3, reach: None };
    let mut pairs = Vec::new();
    brute_force_pairs(w.bodies(), &margin, &mut pairs);
    let (mut touching, mut scratch, mut out) = (0, ParryScratch::default(), Vec::new());
    let bodies = w.bodies();
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            let (a, b) = (&bodies[i], &bodies[j]);
            let pa = Placement { center: a.position(), rotation: a.rotation() };
            let pb = Placement { center: b.position(), rotation: b.rotation() };
            out.clear();
            parry_pair(a.shape(), &pa, b.shape(), &pb, 1e-3, &mut scratch, &mut out);
            if !out.is_empty() {
                touching += 1;
                assert!(pairs.contains(&(i, j)), "pair ({i}, {j}) touches but the broad phase dropped it");
            }
        }
    }
    assert!(touching > 20, "only {touching} touching pairs");
    assert!(pairs.len() < bodies.len() * (bodies.len() - 1) / 2, "the bounds dropped nothing");
}

#[test]
fn a_mesh_holds_from_either_side_whatever_the_winding_of_its_faces() {
    let v =
        [Vec3::new(-5.0, -5.0, 0.0), Vec3::new(5.0, -5.0, 0.0), Vec3::new(5.0, 5.0, 0.0), Vec3::new(-5.0, 5.0, 0.0)];
    for f in [[[0u32, 1, 2], [0, 2, 3]], [[0, 2, 1], [0, 3, 2]]] {
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_body(BodyDesc::mesh(&v, &f).unwrap()).unwrap();
        let id = w.add_body(BodyDesc::cuboid(Vec3::splat(0.5)).position(Vec3::new(0.3, -0.2, 0.6))).unwrap();
        run_ok(&mut w, 500);
        let p = w.body(id).unwrap().position();
        assert!((p - Vec3::new(0.3, -0.2, 0.5)).norm() < 1e-6, "faces {f:?}: box at {p:?}");
    }
}

#[test]
fn stacks_of_cylinders_and_of_hulls_rest_without_drift() {
    let prism = [
        Vec3::new(-0.3, -0.2, -0.1),
        Vec3::new(0.3, -0.2, -0.1),
        Vec3::new(0.0, 0.3, -0.1),
        Vec3::new(-0.3, -0.2, 0.1),
        Vec3::new(0.3, -0.2, 0.1),
        Vec3::new(0.0, 0.3, 0.1),
    ];
    for hull in [false, true] {
        let mut w = World::new(WorldParams::default()).unwrap();
        w.add_ground(0.5).unwrap();
        let ids: Vec<_> = (0..3)
            .map(|k| {
                let d = if hull { BodyDesc::convex(&prism).unwrap() } else { BodyDesc::cylinder(0.3, 0.1) };
                // The prism's centre of mass is at half its height (z = 0): stacked face on face.
                w.add_body(d.position(Vec3::new(0.0, 0.0, 0.1 + 0.2 * k as f64))).unwrap()
            })
            .collect();
        let start: Vec<Vec3> = ids.iter().map(|&i| w.body(i).unwrap().position()).collect();
        run_ok(&mut w, 1000);
        for (k, &i) in ids.iter().enumerate() {
            let drift = (w.body(i).unwrap().position() - start[k]).norm();
            // Hull on hull: the top prism slips 5.7e-6 m over the first 90 steps, where parry
            // gives the coincident faces a slanted normal (as much with every point of parry's
            // manifolds kept); still after. Cylinder caps: the same — at step 37 of the settling
            // parry gives the top caps' contact a normal 34° off vertical (penetration 3e-16 m),
            // whose impulse moves the top cylinder 1.2e-6 m sideways in that one step; still
            // before and after (the trajectories before the eager normal rows of
            // `lcp::on_basis` missed that configuration: 2e-12 m).
            let tol = 1e-5;
            assert!(drift < tol, "{} {k}: drift {drift:e} m", if hull { "hull" } else { "cylinder" });
        }
    }
}

#[test]
fn sphere_rolls_down_an_inclined_mesh_as_down_the_slope() {
    let (angle, mu, steps) = (20.0f64, 0.5, 1000);
    let th = angle.to_radians();
    let slope = Plane::slope_deg(angle, Downhill::PlusX).unwrap();
    let (n, down) = (slope.normal(), slope.downhill().unwrap());
    let side = n.cross(down);
    // Two triangles of the slope plane through the origin; the ball crosses their shared
    // edge 1 m down (after 0.9 s), which must not bump it.
    let c = |a: f64, b: f64| down * a + side * b;
    let v = [c(-1.0, -5.0), c(3.0, -5.0), c(3.0, 5.0), c(-1.0, 5.0)];
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_body(BodyDesc::mesh(&v, &[[0, 1, 2], [0, 2, 3]]).unwrap().mu(mu)).unwrap();
    let id = w.add_body(BodyDesc::sphere(0.5).position(n * 0.5).mu(mu)).unwrap();
    run_ok(&mut w, steps);
    let a = w.body(id).unwrap().velocity().dot(down) / (steps as f64 * w.params().dt);
    let expect = 5.0 / 7.0 * G * th.sin();
    assert!(rel(a, expect) < 1e-2, "a {a} vs 5/7 g sin θ = {expect}");
    let p = w.body(id).unwrap().position();
    assert!(p.dot(down) > 1.1 && (p.dot(n) - 0.5).abs() < 1e-6, "the ball left the slope: {p:?}");
}

/// A capsule or a cylinder (radius 0.1, half length 0.2) touching the top face (z = 0) of a
/// static box: lying on its side, standing on its cap, leaning on its rim (turned 30° about x).
fn on_a_box_top(desc: BodyDesc, tilt: f64, z: f64) -> (World, sim::BodyId) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_body(BodyDesc::cuboid(Vec3::new(2.0, 2.0, 0.5)).position(Vec3::new(0.0, 0.0, -0.5)).fixed(true).mu(0.5))
        .unwrap();
    let q = Quat::from_axis_angle(Vec3::X, tilt);
    let id = w.add_body(desc.position(Vec3::new(0.0, 0.0, z)).orientation(q).mu(0.5)).unwrap();
    (w, id)
}

#[test]
fn round_shapes_on_a_box_face_get_one_contact_per_distinct_point() {
    use sim::geometry::{parry_pair, ParryScratch, Placement};
    use std::f64::consts::FRAC_PI_2;
    let (r, h) = (0.1, 0.2);
    let rim = 0.5236f64; // 30°: the lowest rim point at z = h sin + r cos below the centre
    let cases = [
        ("capsule on its side", BodyDesc::capsule(r, h), FRAC_PI_2, r, 2),
        ("cylinder on its side", BodyDesc::cylinder(r, h), FRAC_PI_2, r, 2),
        ("cylinder on its cap", BodyDesc::cylinder(r, h), 0.0, h, 4),
        ("cylinder on its rim", BodyDesc::cylinder(r, h), rim, h * rim.cos() + r * rim.sin(), 1),
        ("capsule on its end", BodyDesc::capsule(r, h), 0.0, h + r, 1),
    ];
    for (what, desc, tilt, z, points) in cases {
        let (w, id) = on_a_box_top(desc, tilt, z);
        let (a, b) = (w.body(id).unwrap(), &w.bodies()[0]);
        let pa = Placement { center: a.position(), rotation: a.rotation() };
        let pb = Placement { center: b.position(), rotation: b.rotation() };
        let (mut scratch, mut out) = (ParryScratch::default(), Vec::new());
        parry_pair(a.shape(), &pa, b.shape(), &pb, 1e-3, &mut scratch, &mut out);
        assert_eq!(out.len(), points, "{what}: {} contacts", out.len());
        for (k, c) in out.iter().enumerate() {
            assert!(c.gap.abs() < 1e-9, "{what}: gap {}", c.gap);
            for d in &out[..k] {
                assert!((c.point - d.point).norm() > 1e-3, "{what}: two contacts at {:?}", c.point);
            }
        }
    }
}

#[test]
fn round_shapes_rest_on_a_box_face_without_rocking_on_their_kept_points() {
    use std::f64::consts::FRAC_PI_2;
    let (r, h) = (0.1, 0.2);
    for (what, desc, tilt, z) in [
        ("capsule on its side", BodyDesc::capsule(r, h), FRAC_PI_2, r),
        ("cylinder on its side", BodyDesc::cylinder(r, h), FRAC_PI_2, r),
        ("cylinder on its cap", BodyDesc::cylinder(r, h), 0.0, h),
    ] {
        let (mut w, id) = on_a_box_top(desc, tilt, z);
        let (p0, q0) = (w.body(id).unwrap().position(), w.body(id).unwrap().orientation());
        let mut deepest = 0.0f64;
        for _ in 0..2000 {
            run_ok(&mut w, 1);
            deepest = w.last_record().contacts.iter().map(|c| c.gap).fold(deepest, f64::min);
        }
        let b = w.body(id).unwrap();
        let turned =
            (b.orientation().w * q0.w + b.orientation().x * q0.x + b.orientation().y * q0.y + b.orientation().z * q0.z)
                .abs();
        // A cylinder on its side creeps 4.7e-6 m along its axis in 2 s and turns by 7e-5 rad
        // (1 − |q·q₀| = 7e-10; with every point of parry's manifolds kept 1.6e-6 m and
        // 1.6e-5 rad); the others stay put.
        assert!((b.position() - p0).norm() < 1e-5, "{what}: moved {:e} m", (b.position() - p0).norm());
        assert!(1.0 - turned < 1e-8, "{what}: turned by {:e}", 1.0 - turned);
        assert!(deepest > -1e-3, "{what}: penetration {deepest:e} m");
    }
}
