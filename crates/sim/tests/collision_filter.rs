//! Collision filtering (MuJoCo's contype/conaffinity rule): a filtered pair
//! gets no contact, so a body falls through another as under gravity alone,
//! while the pairs the filter keeps still carry their weight.

mod common;
use common::*;
use sim::math::Vec3;
use sim::{BodyDesc, BodyId, World, WorldParams};

/// A unit cube resting on the ground, a ball dropped on it from 0.5 m above its top face.
fn cube_and_ball(ball: BodyDesc) -> (World, BodyId, BodyId) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let cube = w.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
    let ball = w.add_body(ball.position(Vec3::new(0.0, 0.0, 1.7)).mass(0.5)).unwrap();
    (w, cube, ball)
}

#[test]
fn filtered_ball_falls_through_the_cube_freely_and_the_cube_stays_on_the_ground() {
    // Type 2 / affinity 2 against the cube's default 1 / 1: no bit in common.
    let (mut w, cube, ball) = cube_and_ball(BodyDesc::sphere(0.2).collision_filter(2, 2));
    let steps = 600; // 0.6 s: the ball's centre passes z = 0.5, the cube's centre
    run_ok(&mut w, steps);
    let t = w.time();
    let b = w.body(ball).unwrap();
    // Semi-implicit Euler in free fall: z = z0 − g h² n(n+1)/2, v = −g h n.
    let h = w.params().dt;
    let n = steps as f64;
    let z = 1.7 - G * h * h * n * (n + 1.0) / 2.0;
    assert!(b.position().z < 0.5, "the ball went through the cube: z = {}", b.position().z);
    assert!((b.position().z - z).abs() < 1e-9, "z {} vs free fall {} at t = {t}", b.position().z, z);
    assert!((b.velocity().z + G * h * n).abs() < 1e-9);
    // The ball's filter keeps it off the ground too (ground 1/1 vs ball 2/2) ...
    assert!(w.last_record().contacts.iter().all(|c| c.body_a != ball.0 && c.body_b != ball.0));
    // ... while the cube still rests on the ground.
    let c = w.body(cube).unwrap();
    assert!((c.position() - Vec3::new(0.0, 0.0, 0.5)).norm() < 1e-6, "cube moved to {:?}", c.position());
}

#[test]
fn one_shared_bit_in_either_direction_keeps_the_contact() {
    // Ball type 2, affinity 1: the cube's type 1 meets the ball's affinity 1.
    let (mut w, _cube, ball) = cube_and_ball(BodyDesc::sphere(0.2).collision_filter(2, 1));
    run_ok(&mut w, 1500);
    let b = w.body(ball).unwrap();
    // It landed on the cube and rests there (radius 0.2 above the top face z = 1).
    assert!((b.position().z - 1.2).abs() < 1e-3, "ball at z = {}", b.position().z);
    assert!(b.velocity().norm() < 1e-3);
}

#[test]
fn set_collision_filter_after_adding_lets_a_resting_cube_fall_through_the_ground() {
    let mut w = World::new(WorldParams::default()).unwrap();
    let ground = w.add_ground(0.5).unwrap();
    let cube = w.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
    run_ok(&mut w, 100);
    assert!((w.body(cube).unwrap().position().z - 0.5).abs() < 1e-6);
    w.set_collision_filter(ground, 0, 0).unwrap();
    assert_eq!(w.body(ground).unwrap().collision_filter(), sim::CollisionFilter::new(0, 0));
    run_ok(&mut w, 100);
    assert!(w.body(cube).unwrap().position().z < 0.5 - 0.04, "the cube did not fall");
    assert!(w.set_collision_filter(BodyId(7), 1, 1).is_err());
}

#[test]
fn an_excluded_pair_falls_through_while_its_bits_still_let_it_touch_the_rest() {
    // Default bits everywhere; only the ball–cube pair is excluded.
    let (mut w, cube, ball) = cube_and_ball(BodyDesc::sphere(0.2));
    w.exclude_pair(ball, cube).unwrap();
    w.exclude_pair(cube, ball).unwrap(); // either order, kept once
    assert_eq!(w.excluded_pairs(), &[(cube.0, ball.0)]);
    run_ok(&mut w, 1500);
    // The ball passed through the cube and rests on the ground beside the cube's centre.
    let b = w.body(ball).unwrap();
    assert!((b.position().z - 0.2).abs() < 1e-3, "ball at z = {}", b.position().z);
    assert!(w
        .last_record()
        .contacts
        .iter()
        .all(|c| !(c.body_a.min(c.body_b) == cube.0 && c.body_a.max(c.body_b) == ball.0)));
    // The cube still rests on the ground.
    assert!((w.body(cube).unwrap().position().z - 0.5).abs() < 1e-6);
    // A copy keeps the exclusion; bad pairs are refused.
    assert_eq!(w.clone().excluded_pairs(), w.excluded_pairs());
    assert!(w.exclude_pair(ball, ball).is_err());
    assert!(w.exclude_pair(ball, BodyId(9)).is_err());
}

/// A unit cube (μ = `mu`, 1 kg) resting on the ground (μ = `mu`), pushed along x by 2 N.
fn pushed_cube(mu: f64) -> (World, BodyId, BodyId) {
    let mut w = World::new(WorldParams::default()).unwrap();
    let ground = w.add_ground(mu).unwrap();
    let cube = w.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), mu).unwrap();
    w.apply_force(cube, Vec3::new(2.0, 0.0, 0.0), None).unwrap();
    (w, ground, cube)
}

#[test]
fn a_contact_pair_touches_past_the_bits_and_its_own_mu_replaces_the_bodies() {
    // The ground collides with nothing by its bits; the pair makes the cube rest on it,
    // frictionless: 2 N on 1 kg gives 2 m/s² along x, as with no friction at all.
    let (mut w, ground, cube) = pushed_cube(0.9);
    w.set_collision_filter(ground, 0, 0).unwrap();
    w.add_contact_pair(cube, ground, 0.0).unwrap();
    let steps = 1000;
    run_ok(&mut w, steps);
    let (h, n) = (w.params().dt, steps as f64);
    let c = w.body(cube).unwrap();
    assert!((c.position().z - 0.5).abs() < 1e-3, "the cube fell through: z = {}", c.position().z);
    let x = 2.0 * h * h * n * (n + 1.0) / 2.0; // semi-implicit Euler under 2 m/s²
    assert!((c.position().x - x).abs() < 1e-6, "x {} vs frictionless {x}", c.position().x);

    // The pair's μ = 0.5 holds the push (2 N < 0.5 · 9.81 N) where the bodies' μ = 0 would
    // let it slide; given again, the pair takes the new μ.
    let (mut w, ground, cube) = pushed_cube(0.0);
    w.add_contact_pair(ground, cube, 0.2).unwrap();
    w.add_contact_pair(cube, ground, 0.5).unwrap();
    assert_eq!(w.contact_pairs(), (&[(ground.0, cube.0)][..], &[0.5][..]));
    run_ok(&mut w, steps);
    assert!(w.body(cube).unwrap().position().x.abs() < 1e-6, "x = {}", w.body(cube).unwrap().position().x);
    assert!(w.last_record().contacts.iter().all(|c| c.mu == 0.5));
}

#[test]
fn a_contact_pair_touches_past_an_exclusion_and_bad_pairs_are_refused() {
    let (mut w, cube, ball) = cube_and_ball(BodyDesc::sphere(0.2));
    w.exclude_pair(ball, cube).unwrap();
    w.add_contact_pair(ball, cube, 0.5).unwrap();
    run_ok(&mut w, 1500);
    // The ball rests on the cube's top face (z = 1) as if nothing were excluded.
    assert!((w.body(ball).unwrap().position().z - 1.2).abs() < 1e-3);
    assert_eq!(w.clone().contact_pairs(), w.contact_pairs());
    let other_ground = w.add_ground(0.5).unwrap();
    for (a, b, mu) in [(ball, ball, 0.5), (ball, BodyId(9), 0.5), (ball, cube, -1.0), (ball, cube, f64::NAN)] {
        assert!(w.add_contact_pair(a, b, mu).is_err(), "({a:?}, {b:?}, {mu}) accepted");
    }
    let e = w.add_contact_pair(BodyId(0), other_ground, 0.5).unwrap_err().to_string();
    assert!(e.contains("two static bodies"), "{e}");
}
