//! Steps per second of the 4-contact cube on a slope (LCP size 40).
//! Ignored by default; run it optimized:
//! `cargo test --release -p lcpsim-sim --test perf -- --ignored --nocapture`.
//! The target is ≥ 100,000 steps/s on one core.

use sim::scenes::CubeOnSlope;
use sim::WorldParams;
use std::time::Instant;

#[test]
#[ignore]
fn cube_on_slope_steps_per_second() {
    let mut best = 0.0f64;
    for (angle, mu) in [(30.0, 0.7), (40.0, 0.5)] {
        let mut s = CubeOnSlope::new(angle, mu).build(WorldParams::default()).unwrap();
        s.world.step().unwrap();
        // Best of 5 runs of 10 000 steps: other processes only ever slow a run down.
        let mut rate = 0.0f64;
        for _ in 0..5 {
            let t0 = Instant::now();
            for _ in 0..10_000 {
                let r = s.world.step().unwrap();
                assert!(r.ok() && r.lcp_size == 40);
            }
            rate = rate.max(10_000.0 / t0.elapsed().as_secs_f64());
        }
        println!("cube on slope {angle}°, μ {mu}: {rate:.0} steps/s");
        best = best.max(rate);
    }
    assert!(best >= 100_000.0, "{best:.0} steps/s is below the 100,000 target");
}
