//! Pivots per step of resting box stacks: for each height, the
//! median and largest pivot count per warm-started step, steps per second,
//! failed solves and how far the top box drifted.
//!
//! `cargo run --release -p lcpsim-sim --example stack_pivots [-- STEPS [HEIGHTS,..]]`
//! (default 1000 steps, heights 3,5,10).

use sim::scenes::BoxStack;
use sim::WorldParams;
use std::time::Instant;

fn main() {
    let steps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(1000);
    let heights: Vec<usize> = std::env::args()
        .nth(2)
        .map(|s| s.split(',').map(|v| v.parse().expect("a height")).collect())
        .unwrap_or(vec![3, 5, 10]);
    for n in heights {
        let mut s = BoxStack::new(n).build(WorldParams::default()).unwrap();
        let top = s.world.body(s.body).unwrap().position();
        let mut pivots = Vec::with_capacity(steps);
        let mut failures = 0;
        let t0 = Instant::now();
        for _ in 0..steps {
            let r = s.world.step().unwrap();
            failures += usize::from(!r.ok());
            pivots.push(r.pivots);
        }
        let dt = t0.elapsed().as_secs_f64();
        let drift = (s.world.body(s.body).unwrap().position() - top).norm();
        let zero = pivots.iter().filter(|&&p| p == 0).count();
        let mean = pivots.iter().sum::<usize>() as f64 / steps as f64;
        pivots.sort_unstable();
        println!(
            "{n:>2} boxes, {steps} steps: pivots/step median {:>4} mean {mean:>6.1} max {:>5}, zero-pivot steps {zero:>5}, \
             {:>8.0} steps/s, failures {failures}, top drift {drift:.1e} m",
            pivots[steps / 2],
            pivots[steps - 1],
            steps as f64 / dt,
        );
    }
}
