//! Many bodies: steps per second, islands, LCP sizes, pivots,
//! failures and penetration on piles and heaps, and the broad phase's time
//! per step against the all-pairs loop.
//!
//! `cargo run --release -p lcpsim-sim --example many_bodies -- [SCENE] [STEPS] [THREADS]`
//! with SCENE one of `pile3`, `stack10`, `pile10`, `heap200`, `heap1000`,
//! `heap:N`, `broad` (default: all but `pile10`, `heap1000` and `heap:N`).

use sim::broad_phase::{brute_force_pairs, reach, BroadPhase, PairMargin};
use sim::scenes::{BoxPile, BoxStack, CubeHeap, Scene};
use sim::WorldParams;
use std::time::Instant;

fn run(name: &str, build: impl Fn(WorldParams) -> Scene, steps: usize, threads: usize) {
    let mut s = build(WorldParams { threads, ..Default::default() });
    let bodies = s.bodies.len();
    let (mut failures, mut pivots, mut max_pivots, mut islands, mut max_n, mut pen) = (0, 0, 0, 0, 0, 0.0f64);
    let t0 = Instant::now();
    for _ in 0..steps {
        let ts = Instant::now();
        let r = s.world.step().unwrap();
        if ts.elapsed().as_secs_f64() > 1.0 {
            let n = r.islands.iter().map(|i| i.lcp_size).max().unwrap_or(0);
            eprintln!(
                "  slow step {}: {:.1} s, {} islands, largest LCP {n}, {} pivots",
                r.step,
                ts.elapsed().as_secs_f64(),
                r.islands.len(),
                r.pivots
            );
        }
        for i in r.islands.iter().filter(|i| i.status != lcp::Status::Solved) {
            failures += 1;
            eprintln!(
                "  step {}: island of LCP size {} ended {:?} after {} pivots",
                r.step, i.lcp_size, i.status, i.pivots
            );
        }
        pivots += r.pivots;
        max_pivots = max_pivots.max(r.pivots);
        islands += r.islands.len();
        max_n = max_n.max(r.islands.iter().map(|i| i.lcp_size).max().unwrap_or(0));
        pen = r.contacts.iter().fold(pen, |p, c| p.max(-c.gap));
    }
    let dt = t0.elapsed().as_secs_f64();
    let per = |x: usize| x as f64 / steps as f64;
    println!(
        "{name:<16} {bodies:>5} bodies  {:>9.1} steps/s  islands/step {:>6.1}  largest LCP {max_n:>6}  \
         pivots/step {:>8.1} (max {max_pivots})  failed LCPs {failures}  max penetration {:.2e} m  [{steps} steps, {threads} threads]",
        steps as f64 / dt,
        per(islands),
        per(pivots),
        pen.max(0.0),
    );
}

/// Broad phase time per step on a 1,000-cube heap: sweep and prune vs all pairs.
fn broad() {
    let walls = std::env::var("WALLS").is_ok();
    let mut s = CubeHeap { walls, ..CubeHeap::new(1000, 1) }.build(WorldParams::default()).unwrap();
    s.world.forces_stage().unwrap();
    let (v, w) = s.world.free_velocities();
    let r: Vec<f64> = s.world.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], w[k])).collect();
    let margin = PairMargin { base: 1e-3, h: 1e-3, reach: Some(&r) };
    let (mut bp, mut out) = (BroadPhase::new(), Vec::new());
    let reps = 200;
    let t0 = Instant::now();
    for _ in 0..reps {
        bp.find(s.world.bodies(), &margin);
    }
    let sap = t0.elapsed().as_secs_f64() / reps as f64;
    let t0 = Instant::now();
    for _ in 0..reps / 10 {
        brute_force_pairs(s.world.bodies(), &margin, &mut out);
    }
    let brute = t0.elapsed().as_secs_f64() / (reps / 10) as f64;
    assert_eq!(bp.pairs(), &out[..]);
    println!(
        "broad phase, {} bodies, {} pairs: sweep and prune {:.1} µs, all pairs {:.1} µs per step ({:.0}×)",
        s.world.body_count(),
        out.len(),
        sap * 1e6,
        brute * 1e6,
        brute / sap
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let which = args.get(1).map_or("default", |s| s.as_str());
    let steps = |d: usize| args.get(2).and_then(|s| s.parse().ok()).unwrap_or(d);
    let threads: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let all = which == "default";
    if all || which == "pile3" {
        run("box_pile 3x3x3", |p| BoxPile::default().build(p).unwrap(), steps(300), threads);
    }
    if all || which == "stack10" {
        run("10-box stack", |p| BoxStack::new(10).build(p).unwrap(), steps(100), threads);
    }
    if which == "pile10" {
        run(
            "box_pile 10x10x10",
            |p| BoxPile { nx: 10, ny: 10, nz: 10, ..Default::default() }.build(p).unwrap(),
            steps(5),
            threads,
        );
    }
    if all || which == "heap200" {
        run(
            "cube_heap 200",
            |p| CubeHeap { walls: true, ..CubeHeap::new(200, 0) }.build(p).unwrap(),
            steps(50),
            threads,
        );
    }
    if which == "heap1000" {
        run(
            "cube_heap 1000",
            |p| CubeHeap { walls: true, ..CubeHeap::new(1000, 0) }.build(p).unwrap(),
            steps(3),
            threads,
        );
    }
    if let Some(n) = which.strip_prefix("heap:").and_then(|n| n.parse().ok()) {
        let name = format!("cube_heap {n}");
        run(&name, |p| CubeHeap { walls: true, ..CubeHeap::new(n, 0) }.build(p).unwrap(), steps(300), threads);
    }
    if all || which == "broad" {
        broad();
    }
}
