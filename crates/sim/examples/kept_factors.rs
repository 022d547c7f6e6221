//! A pour run until it settles, then stepped on as two copies, one keeping
//! its islands' structured operators and basis factors from step to step
//! (`solve_chain::kept_factors`) and one building them afresh each step,
//! in alternating chunks of steps (so that both see the same load on a
//! shared machine): ms/step and pivots of each, and how far apart the two
//! copies' cubes end (round-off, if the kept factors answer as fresh ones).
//!
//! `cargo run --release -p lcpsim-sim --example kept_factors -- [CUBES] [SETTLE] [STEPS] [CHUNK] [SEED]`
//! (defaults 45, 3000, 1000, 50, 0).

use sim::scenes::CubePour;
use sim::solve_chain::kept_factors;
use sim::WorldParams;
use std::time::{Duration, Instant};

fn main() {
    let arg = |i: usize, default: u64| std::env::args().nth(i).map_or(default, |s| s.parse().expect("a number"));
    let (cubes, settle, steps, chunk, seed) =
        (arg(1, 45) as usize, arg(2, 3000) as usize, arg(3, 1000) as usize, arg(4, 50) as usize, arg(5, 0));
    let mut s = CubePour::new(cubes, seed).build(WorldParams::default()).expect("a valid pour");
    kept_factors::set_enabled(false);
    for _ in 0..settle {
        s.world.step().expect("a finite state");
    }
    let mut worlds = [s.world.clone(), s.world.clone()];
    let (mut time, mut pivots, mut failed) = ([Duration::ZERO; 2], [0usize; 2], [0usize; 2]);
    for first in (0..steps).step_by(chunk) {
        for (k, w) in worlds.iter_mut().enumerate() {
            kept_factors::set_enabled(k == 0);
            let t = Instant::now();
            for _ in first..(first + chunk).min(steps) {
                let r = w.step().expect("a finite state");
                pivots[k] += r.pivots;
                failed[k] += r.islands.iter().filter(|i| i.status != lcp::Status::Solved).count();
            }
            time[k] += t.elapsed();
        }
    }
    let apart = s.bodies.iter().fold(0.0f64, |m, &b| {
        let (p, q) = (worlds[0].body(b).unwrap().position(), worlds[1].body(b).unwrap().position());
        m.max((p - q).norm())
    });
    let ms = |k: usize| time[k].as_secs_f64() * 1e3 / steps as f64;
    println!(
        "{cubes} cubes, seed {seed}, steps {settle}..{}: kept {:.3} ms/step ({} pivots, {} failed), \
         afresh {:.3} ms/step ({} pivots, {} failed), ratio {:.2}; cubes apart at the end {apart:.2e} m",
        settle + steps,
        ms(0),
        pivots[0],
        failed[0],
        ms(1),
        pivots[1],
        failed[1],
        ms(1) / ms(0)
    );
}
