//! Per-stage timing of the cube-on-slope step (minimum over batches, so that
//! other processes on the machine disturb it less).
//!
//! `cargo run --release -p lcpsim-sim --example profile_step`

use sim::lcp::{self, Lcp, Method};
use sim::scenes::CubeOnSlope;
use sim::WorldParams;
use std::time::Instant;

fn min_time(batches: usize, per: usize, mut f: impl FnMut()) -> f64 {
    (0..batches)
        .map(|_| {
            let t0 = Instant::now();
            for _ in 0..per {
                f();
            }
            t0.elapsed().as_secs_f64() / per as f64
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let (batches, per) = (30, 1000);
    let mut s = CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap();
    s.world.step().unwrap();
    let lcp_copy = s.world.contact_lcp().to_lcp().unwrap();
    let cached = lcp::solve(&lcp_copy, &Method::default());
    let mut ws = lcp::Workspace::new();
    let full = min_time(batches, per, || {
        s.world.step().unwrap();
    });
    let rest = min_time(batches, per, || {
        let mut f = |_: &Lcp| cached.clone();
        s.world.step_with(&mut f).unwrap();
    });
    let solve = min_time(batches, per, || {
        std::hint::black_box(lcp::solve_in(&lcp_copy, &Method::default(), None, &mut ws));
    });
    let detect = min_time(batches, per, || {
        s.world.forces_stage().unwrap();
        s.world.detect();
    });
    println!(
        "full step {:.2} µs ({:.0} steps/s) | without solver {:.2} µs | forces+detect {:.2} µs | solver alone {:.2} µs",
        full * 1e6,
        1.0 / full,
        rest * 1e6,
        detect * 1e6,
        solve * 1e6
    );
}
