//! A pour of cubes (`scenes::CubePour`) window by window: wall time per step,
//! pivots, the largest island, how many islands each stage of the solve chain
//! answered, and the deepest penetration — where a forming heap's time goes.
//!
//! `cargo run --release -p lcpsim-sim --example pour -- [CUBES] [STEPS] [WINDOW] [SEED] [DIR FROM TO]`
//! (defaults 45, 3000, 250, 0). With `DIR FROM TO`, the structured LCPs of
//! steps `FROM..TO` are saved to `DIR` (`sim::solve_chain::replay`; solve
//! them again with the `heap_replay` example's `solve`).

use sim::scenes::CubePour;
use sim::solve_chain::replay;
use sim::{SolveStage, WorldParams};
use std::time::Instant;

fn main() {
    let arg = |i: usize, default: u64| std::env::args().nth(i).map_or(default, |s| s.parse().expect("a number"));
    let (cubes, steps, window, seed) = (arg(1, 45) as usize, arg(2, 3000) as usize, arg(3, 250) as usize, arg(4, 0));
    let dump: Option<(String, usize, usize)> = std::env::args().nth(5).map(|dir| {
        std::fs::create_dir_all(&dir).expect("a dump directory");
        (dir, arg(6, 0) as usize, arg(7, u64::MAX) as usize)
    });
    let mut s = CubePour::new(cubes, seed).build(WorldParams::default()).expect("a valid pour");
    let names = SolveStage::ALL.map(SolveStage::as_str);
    println!("{cubes} cubes, seed {seed}: per window of {window} steps; islands per stage {names:?}");
    let (mut failed, mut deepest, mut pivots, mut stages) = (0, 0.0f64, 0, [0usize; 4]);
    let start = Instant::now();
    for first in (0..steps).step_by(window) {
        let t = Instant::now();
        let (mut w_pivots, mut w_max, mut w_n, mut w_pen, mut w_stages) = (0, 0, 0, 0.0f64, [0usize; 4]);
        for step in first..(first + window).min(steps) {
            if let Some((dir, from, to)) = &dump {
                replay::set_dump_dir((from..to).contains(&&step).then(|| dir.into()));
            }
            let r = s.world.step().expect("a finite state");
            (w_pivots, w_max) = (w_pivots + r.pivots, w_max.max(r.pivots));
            for isl in &r.islands {
                w_n = w_n.max(isl.lcp_size);
                failed += usize::from(isl.status != lcp::Status::Solved);
                if let Some(stage) = isl.stage {
                    w_stages[stage.index()] += 1;
                }
            }
            w_pen = r.contacts.iter().fold(w_pen, |p, c| p.max(-c.gap));
        }
        let per = (first + window).min(steps) - first;
        println!(
            "steps {first:>5}+  {:>9.3} ms/step  pivots/step {:>7.1} (max {w_max:>5})  largest n {w_n:>5}  \
             stages {w_stages:?}  penetration {w_pen:.2e} m",
            t.elapsed().as_secs_f64() * 1e3 / per as f64,
            w_pivots as f64 / per as f64,
        );
        pivots += w_pivots;
        deepest = deepest.max(w_pen);
        (0..4).for_each(|i| stages[i] += w_stages[i]);
    }
    let dt = start.elapsed().as_secs_f64();
    println!(
        "total {dt:.2} s, {:.1} steps/s, {pivots} pivots, islands per stage {stages:?} (backstop fraction \
         {:.4}), failed {failed}, deepest penetration {deepest:.2e} m",
        steps as f64 / dt,
        stages[3] as f64 / stages.iter().sum::<usize>().max(1) as f64
    );
}
