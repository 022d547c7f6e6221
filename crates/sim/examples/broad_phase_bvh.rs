//! The broad phase's two methods on the same moving bodies: the sweep
//! (`BroadMethod::Sweep`, the default) and parry's BVH, refitted each call
//! (`BroadMethod::Bvh`). For each size, bodies (boxes and spheres, 15 %
//! static) spread in a volume of constant density, moved a little and
//! randomly every step; median time per `find` over the steps, and a check
//! that both methods give the same pairs every step. `towers` instead: unit
//! cubes in towers of 10 on a grid 1.5 m apart (as `box_pile`), touching,
//! moved by 1 µm a step (a resting pile: the sweep's best case, its order
//! kept from step to step).
//!
//! `pour N STEPS`: `scenes::cube_pour` of N cubes stepped with each method
//! from the same start; the trajectories must agree bit for bit.
//!
//! ```text
//! cargo run --release -p lcpsim-sim --example broad_phase_bvh -- [towers] [STEPS] [N ...]
//! cargo run --release -p lcpsim-sim --example broad_phase_bvh -- pour 90 500
//! ```

use sim::broad_phase::{BroadMethod, BroadPhase, PairMargin};
use sim::math::Vec3;
use sim::scenes::SplitMix64;
use sim::{BodyDesc, World, WorldParams};
use std::time::Instant;

fn world(n: usize, seed: u64) -> World {
    let mut rng = SplitMix64(seed);
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    // About one body per 1.5 m³, as in a loose heap of unit cubes.
    let side = (1.5 * n as f64).cbrt();
    for _ in 0..n {
        let p = Vec3::new(rng.uniform(0.0, side), rng.uniform(0.0, side), rng.uniform(0.5, side + 0.5));
        let desc = if rng.next_f64() < 0.5 {
            BodyDesc::cuboid(Vec3::splat(rng.uniform(0.2, 0.5)))
        } else {
            BodyDesc::sphere(rng.uniform(0.2, 0.5))
        };
        w.add_body(desc.position(p).orientation(rng.rotation()).fixed(rng.next_f64() < 0.15)).unwrap();
    }
    w
}

/// Towers of 10 unit cubes on a square grid 1.5 m apart, `n` cubes in all (rounded down to towers).
fn towers(n: usize) -> World {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let count = n / 10;
    let side = (count as f64).sqrt().ceil() as usize;
    for t in 0..count {
        for k in 0..10 {
            let p = Vec3::new(1.5 * (t % side) as f64, 1.5 * (t / side) as f64, 0.5 + k as f64);
            w.add_body(BodyDesc::cuboid(Vec3::splat(0.5)).position(p)).unwrap();
        }
    }
    w
}

/// The pour stepped both ways: bitwise the same positions every step, and each way's time.
fn pour(n: usize, steps: usize) {
    let mut worlds: Vec<World> = [BroadMethod::Sweep, BroadMethod::Bvh]
        .into_iter()
        .map(|m| {
            let mut w = sim::scenes::cube_pour(n, 1, true).unwrap().world;
            w.set_broad_method(m);
            w
        })
        .collect();
    let mut secs = [0.0; 2];
    for step in 0..steps {
        for (k, w) in worlds.iter_mut().enumerate() {
            let t = Instant::now();
            w.step().unwrap();
            secs[k] += t.elapsed().as_secs_f64();
        }
        let same = worlds[0].bodies().iter().zip(worlds[1].bodies()).all(|(a, b)| {
            a.position().to_array() == b.position().to_array()
                && a.orientation().to_array() == b.orientation().to_array()
        });
        assert!(same, "step {step}: the trajectories differ");
    }
    println!(
        "pour of {n} cubes, {steps} steps: positions and orientations identical every step; \
         sweep {:.2} s, BVH {:.2} s (whole steps)",
        secs[0], secs[1]
    );
}

fn main() {
    let all: Vec<String> = std::env::args().collect();
    if all.get(1).map(String::as_str) == Some("pour") {
        let num = |i: usize, d: usize| all.get(i).and_then(|a| a.parse().ok()).unwrap_or(d);
        return pour(num(2, 90), num(3, 500));
    }
    let stacked = std::env::args().any(|a| a == "towers");
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let steps = args.first().copied().unwrap_or(30);
    let sizes = if args.len() > 1 { args[1..].to_vec() } else { vec![100, 300, 1000, 2000, 5000, 10000] };
    println!("| bodies | pairs | sweep (ms) | BVH (ms) | sweep ÷ BVH |");
    println!("|---|---|---|---|---|");
    for n in sizes {
        let mut w = if stacked { towers(n) } else { world(n, 7 + n as u64) };
        let amp = if stacked { 1e-6 } else { 0.01 };
        let mut rng = SplitMix64(99);
        let (mut sweep, mut bvh) =
            (BroadPhase::with_method(BroadMethod::Sweep), BroadPhase::with_method(BroadMethod::Bvh));
        let (mut ts, mut tb, mut pairs) = (Vec::new(), Vec::new(), 0);
        let margin = PairMargin { base: w.params().margin, h: w.params().dt, reach: None };
        for step in 0..=steps {
            // Alternate which goes first (caches), time each.
            let t = Instant::now();
            let a = sweep.find(w.bodies(), &margin).to_vec();
            let t_sweep = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let b = bvh.find(w.bodies(), &margin).to_vec();
            let t_bvh = t.elapsed().as_secs_f64();
            assert_eq!(a, b, "n = {n}, step {step}: the methods disagree");
            if step > 0 {
                // Step 0 builds (the sweep's first full sort, the BVH's build): not timed.
                ts.push(t_sweep);
                tb.push(t_bvh);
                pairs = a.len();
            }
            for k in 0..w.body_count() {
                let id = sim::BodyId(k);
                if !w.body(id).unwrap().is_static() {
                    let d = Vec3::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)) * amp;
                    let p = w.body(id).unwrap().position() + d;
                    w.set_position(id, p).unwrap();
                }
            }
        }
        let med = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            1e3 * v[v.len() / 2]
        };
        let (s, b) = (med(&mut ts), med(&mut tb));
        println!("| {n} | {pairs} | {s:.4} | {b:.4} | {:.2} |", s / b);
    }
}
