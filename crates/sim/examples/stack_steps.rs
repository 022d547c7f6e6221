//! Steps per second, pivots and drift of resting stacks of n unit cubes
//! (`sim::scenes::box_stack(n)`, dt = 1e-3): the cost of a zero-pivot step
//! and how often a step still pivots.
//!
//! `cargo run --release -p lcpsim-sim --example stack_steps -- [steps] [n ...]`

use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let steps: usize = args.next().map(|s| s.parse().expect("steps")).unwrap_or(2000);
    let sizes: Vec<usize> = args.map(|s| s.parse().expect("n")).collect();
    let sizes = if sizes.is_empty() { vec![1, 2, 3, 5, 10] } else { sizes };
    println!(
        "{:>3} {:>10} {:>8} {:>14} {:>10} {:>9} {:>11}",
        "n", "steps/s", "LCP n", "pivoting steps", "pivots", "failures", "top drift"
    );
    for n in sizes {
        let mut s = sim::scenes::box_stack(n).expect("scene");
        let top = *s.bodies.last().expect("a box");
        let z0 = s.world.body(top).expect("top").position().z;
        let (mut pivoting, mut pivots, mut failures) = (0, 0, 0);
        let t = Instant::now();
        for _ in 0..steps {
            let r = s.world.step().expect("finite state");
            pivoting += (r.pivots > 0) as usize;
            pivots += r.pivots;
            failures += (!r.ok()) as usize;
        }
        let rate = steps as f64 / t.elapsed().as_secs_f64();
        let drift = s.world.body(top).expect("top").position().z - z0;
        let size = s.world.last_record().lcp_size;
        println!("{n:>3} {rate:>10.0} {size:>8} {pivoting:>14} {pivots:>10} {failures:>9} {drift:>11.2e}");
    }
}
