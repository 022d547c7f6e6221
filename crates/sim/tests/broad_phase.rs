//! Sweep and prune and the BVH find exactly the pairs of the all-pairs
//! loop (bounding spheres and boxes), in the same order, on random scenes (boxes, spheres,
//! static boxes, planes, fast bodies with velocity margins).

use sim::broad_phase::{brute_force_pairs, reach, BroadPhase, PairMargin};
use sim::geometry::Plane;
use sim::math::Vec3;
use sim::scenes::SplitMix64;
use sim::{BodyDesc, World, WorldParams};

/// A random world of `n` bodies in a box of side `extent`: boxes and spheres
/// of random sizes and orientations, some static, random velocities, and two
/// planes.
fn random_world(seed: u64, n: usize, extent: f64, velocity_margin: bool) -> World {
    let mut rng = SplitMix64(seed);
    let params = WorldParams { velocity_margin, margin: rng.uniform(0.0, 0.05), ..Default::default() };
    let mut w = World::new(params).unwrap();
    w.add_ground(0.5).unwrap();
    for _ in 0..n {
        let p = Vec3::new(rng.uniform(0.0, extent), rng.uniform(0.0, 0.3 * extent), rng.uniform(0.0, 0.5 * extent));
        let desc = if rng.next_f64() < 0.5 {
            BodyDesc::cuboid(Vec3::new(rng.uniform(0.05, 0.6), rng.uniform(0.05, 0.6), rng.uniform(0.05, 0.6)))
        } else {
            BodyDesc::sphere(rng.uniform(0.05, 0.6))
        };
        let fixed = rng.next_f64() < 0.15;
        let mut desc = desc.position(p).orientation(rng.rotation()).fixed(fixed);
        if !fixed {
            let v = Vec3::new(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0));
            let o = Vec3::new(rng.uniform(-20.0, 20.0), rng.uniform(-20.0, 20.0), rng.uniform(-20.0, 20.0));
            desc = desc.velocity(v).angular_velocity(o);
        }
        w.add_body(desc).unwrap();
    }
    w.add_plane(Plane::new(Vec3::new(-1.0, 0.0, 0.0), -extent).unwrap(), 0.5).unwrap();
    w
}

/// The reference pairs for the world's current state.
fn reference(w: &World) -> Vec<(usize, usize)> {
    let (v, o) = w.free_velocities();
    let r: Vec<f64> = w.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], o[k])).collect();
    let p = w.params();
    let margin = PairMargin { base: p.margin, h: p.dt, reach: p.velocity_margin.then_some(&r[..]) };
    let mut out = Vec::new();
    brute_force_pairs(w.bodies(), &margin, &mut out);
    out
}

#[test]
fn sweep_and_prune_finds_the_pairs_of_the_all_pairs_loop() {
    let mut total = 0;
    for seed in 0..60u64 {
        let n = [5, 40, 150, 300][seed as usize % 4];
        let extent = [2.0, 6.0, 15.0][seed as usize % 3];
        let mut w = random_world(seed, n, extent, seed % 5 != 0);
        for step in 0..3 {
            w.forces_stage().unwrap();
            w.detect();
            let expect = reference(&w);
            assert_eq!(w.broad_pairs(), &expect[..], "seed {seed}, step {step}");
            total += expect.len();
            nudge(&mut w, step);
        }
    }
    // Not vacuous: plenty of pairs, many between bounded bodies.
    assert!(total > 10_000, "only {total} pairs");
}

/// Moves every dynamic body a little, more each `step` (stepping such a crowd
/// would assemble huge LCPs).
fn nudge(w: &mut World, step: usize) {
    for b in 0..w.body_count() {
        let id = sim::BodyId(b);
        if !w.body(id).unwrap().is_static() {
            let p = w.body(id).unwrap().position() + Vec3::new(0.3, -0.2, 0.1) * (step as f64 + 1.0);
            w.set_position(id, p).unwrap();
        }
    }
}

#[test]
fn a_sweep_and_prune_reused_across_worlds_keeps_no_stale_pairs() {
    let mut bp = BroadPhase::with_method(sim::broad_phase::BroadMethod::Sweep);
    for seed in [3u64, 4, 5] {
        let mut w = random_world(seed, 80, 4.0, true);
        w.forces_stage().unwrap();
        w.detect();
        let (v, o) = w.free_velocities();
        let r: Vec<f64> = w.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], o[k])).collect();
        let margin = PairMargin { base: w.params().margin, h: w.params().dt, reach: Some(&r) };
        assert_eq!(bp.find(w.bodies(), &margin), &reference(&w)[..]);
    }
}

/// A pair right at the margin: touching spheres are kept, spheres one
/// margin and a bit apart are not, and both answers match the reference.
#[test]
fn pairs_at_the_margin_edge() {
    for gap in [0.0, 0.999e-3, 1.001e-3, 0.5] {
        let mut w = World::new(WorldParams { velocity_margin: false, ..Default::default() }).unwrap();
        w.add_body(BodyDesc::sphere(0.5).position(Vec3::new(0.0, 0.0, 5.0))).unwrap();
        w.add_body(BodyDesc::sphere(0.5).position(Vec3::new(1.0 + gap, 0.0, 5.0))).unwrap();
        w.forces_stage().unwrap();
        w.detect();
        let expect: &[(usize, usize)] = if gap <= 1e-3 { &[(0, 1)] } else { &[] };
        assert_eq!(w.broad_pairs(), expect, "gap {gap}");
        assert_eq!(w.broad_pairs(), &reference(&w)[..]);
    }
}

#[test]
fn the_broad_phase_drops_no_pair_the_narrow_phase_would_touch() {
    // The box test (world-aligned boxes of rotated shapes) only drops pairs
    // farther apart than their margin: every pair of bounded bodies to which
    // the narrow phase itself gives a contact (called on all pairs here) is
    // among the broad phase's pairs; and the box test does drop pairs.
    use sim::geometry::{box_box, sphere_box, sphere_sphere, Placement, Shape};
    let (mut touching, mut dropped) = (0, 0);
    for seed in 0..40u64 {
        let mut w = random_world(1000 + seed, 80, 3.0, seed % 2 == 0);
        w.forces_stage().unwrap();
        w.detect();
        let pairs = reference(&w);
        let (v, o) = w.free_velocities();
        let r: Vec<f64> = w.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], o[k])).collect();
        let p = w.params();
        let margin = PairMargin { base: p.margin, h: p.dt, reach: p.velocity_margin.then_some(&r[..]) };
        let bodies = w.bodies();
        let mut out = Vec::new();
        for i in 0..bodies.len() {
            for j in i + 1..bodies.len() {
                let (a, b) = (&bodies[i], &bodies[j]);
                if a.is_static() && b.is_static() {
                    continue;
                }
                let m = margin.of(i, j);
                out.clear();
                let (pa, pb) = (
                    Placement { center: a.position(), rotation: a.rotation() },
                    Placement { center: b.position(), rotation: b.rotation() },
                );
                match (a.shape(), b.shape()) {
                    (Shape::Box(x), Shape::Box(y)) => box_box(x, &pa, y, &pb, m, &mut out),
                    (Shape::Sphere { radius }, Shape::Box(x)) => sphere_box(a.position(), *radius, x, &pb, m, &mut out),
                    (Shape::Box(x), Shape::Sphere { radius }) => sphere_box(b.position(), *radius, x, &pa, m, &mut out),
                    (Shape::Sphere { radius: ra }, Shape::Sphere { radius: rb }) => {
                        sphere_sphere(a.position(), *ra, b.position(), *rb, m, &mut out)
                    }
                    _ => continue,
                }
                let kept = pairs.binary_search(&(i, j)).is_ok();
                if !out.is_empty() {
                    touching += 1;
                    assert!(kept, "seed {seed}: pair ({i}, {j}) has {} contacts but no broad-phase pair", out.len());
                }
                let sphere_near = (a.position() - b.position()).norm()
                    <= a.shape().bounding_radius() + b.shape().bounding_radius() + m;
                dropped += usize::from(sphere_near && !kept);
            }
        }
    }
    assert!(touching > 500, "only {touching} touching pairs");
    assert!(dropped > 100, "the box test dropped only {dropped} pairs");
}

#[test]
fn the_bvh_and_the_sweep_find_the_pairs_of_the_all_pairs_loop_as_bodies_move() {
    // One BVH kept across steps (built once, then refitted) and across a world
    // with more bodies (rebuilt), one sweep likewise: the reference pairs every time.
    use sim::broad_phase::BroadMethod;
    let mut bvh = BroadPhase::with_method(BroadMethod::Bvh);
    let mut sweep = BroadPhase::with_method(BroadMethod::Sweep);
    let mut total = 0;
    for seed in 0..24u64 {
        let n = [5, 40, 150, 300][seed as usize % 4];
        let extent = [2.0, 6.0, 15.0][seed as usize % 3];
        let mut w = random_world(500 + seed, n, extent, seed % 5 != 0);
        for step in 0..4 {
            w.forces_stage().unwrap();
            let (v, o) = w.free_velocities();
            let r: Vec<f64> = w.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], o[k])).collect();
            let p = w.params();
            let margin = PairMargin { base: p.margin, h: p.dt, reach: p.velocity_margin.then_some(&r[..]) };
            let expect = reference(&w);
            assert_eq!(bvh.find(w.bodies(), &margin), &expect[..], "BVH, seed {seed}, step {step}");
            assert_eq!(sweep.find(w.bodies(), &margin), &expect[..], "sweep, seed {seed}, step {step}");
            total += expect.len();
            nudge(&mut w, step);
        }
    }
    assert!(total > 5_000, "only {total} pairs");
}
