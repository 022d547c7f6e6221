//! Steps per second of the simulator on the benchmark scenes (single thread).
//!
//! `cargo run --release -p lcpsim-sim --example steps_per_second [-- STEPS]`

use sim::scenes::{BoxPile, BoxStack, CubeOnSlope};
use sim::WorldParams;
use std::time::Instant;

fn time(name: &str, mut scene: sim::scenes::Scene, steps: usize) {
    // Warm the buffers up first so the timing is of the steady state.
    scene.world.step().unwrap();
    let mut failures = 0;
    let mut pivots = 0usize;
    let mut size = 0;
    let t0 = Instant::now();
    for _ in 0..steps {
        let r = scene.world.step().unwrap();
        failures += usize::from(!r.ok());
        pivots += r.pivots;
        size = size.max(r.lcp_size);
    }
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "{name:<28} {:>10.0} steps/s  {:>8.2} µs/step  LCP size {size:>5}  mean pivots {:>6.1}  failures {failures}",
        steps as f64 / dt,
        dt / steps as f64 * 1e6,
        pivots as f64 / steps as f64
    );
}

fn main() {
    let steps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10_000);
    let p = WorldParams::default;
    time("cube on slope 30°, μ 0.7", CubeOnSlope::new(30.0, 0.7).build(p()).unwrap(), steps);
    time("cube on slope 40°, μ 0.5", CubeOnSlope::new(40.0, 0.5).build(p()).unwrap(), steps);
    time("10-box stack", BoxStack::new(10).build(p()).unwrap(), (steps / 100).max(10));
    time("3x3x3 box pile", BoxPile::default().build(p()).unwrap(), (steps / 1000).max(3));
}
