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
