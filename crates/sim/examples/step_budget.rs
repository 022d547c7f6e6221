//! One step's budget: the time (and, under callgrind, the instructions) of
//! each stage of a step, on the small scenes where the per-step overhead is
//! what counts: a cube sliding down 30° (μ 0.5), a cube resting on 30°
//! (μ 0.7), a resting 10-box stack.
//!
//! ```text
//! cargo run --release -p lcpsim-sim --example step_budget              # wall time per stage
//! cargo run --release -p lcpsim-sim --example step_budget -- stages SCENE STEPS [FROM]
//!     # only the staged steps (for callgrind), SCENE = slide | rest | stack | stack4
//!     # (stack4: the stack at 4 friction directions, MuJoCo's pyramid as stack10.xml sets it),
//!     # after FROM steps (100 by default; `benchmarks/step_budget.py` times
//!     # the cubes from step ~21,000, where the sliding cube is fast)
//! cargo run --release -p lcpsim-sim --example step_budget -- dump FILE  # trajectories' bits
//! cargo run --release -p lcpsim-sim --example step_budget -- run SCENE STEPS
//!     # `World::run` from the scene's start (for callgrind; what `many_bodies.py` times)
//! cargo run --release -p lcpsim-sim --example step_budget -- profile SCENE STEPS [REPEATS] [WINDOW]
//!     # each step's time from the start (min over REPEATS runs of the same
//!     # trajectory), its pivots, stage and basis, summed over windows of WINDOW steps
//! ```
//!
//! Instructions per stage (inclusive, per step):
//!
//! ```text
//! valgrind --tool=callgrind --callgrind-out-file=cg.out \
//!     target/release/examples/step_budget stages slide 2000
//! callgrind_annotate --inclusive=yes cg.out | grep step_budget::stage_
//! ```
//!
//! The stages are the public stage methods of `World` in the order `step`
//! runs them (`forces_stage`, `detect`, `islands`, `assemble_for_solve`,
//! `solve`, `integrate`) plus `Trajectory::push` (what `World::run` records
//! per step). The broad phase is timed apart (a second `BroadPhase` on the
//! same bodies and margins): narrow = detect − broad. Each stage's time is
//! the minimum over batches of its mean over a batch, so other processes
//! disturb it less; the timer's own cost (one `Instant::now` per stage) is
//! measured and subtracted.

use sim::broad_phase::{reach, BroadPhase, PairMargin};
use sim::scenes::{BoxPile, BoxStack, CubeOnSlope, Scene};
use sim::{Trajectory, World, WorldParams};
use std::hint::black_box;
use std::io::Write;
use std::time::Instant;

const STAGES: [&str; 8] = ["forces", "broad", "narrow", "islands", "assemble", "solve", "integrate", "record"];

fn scene(name: &str) -> Scene {
    let p = WorldParams::default;
    match name {
        "slide" => CubeOnSlope::new(30.0, 0.5).build(p()).unwrap(),
        "rest" => CubeOnSlope::new(30.0, 0.7).build(p()).unwrap(),
        "stack" => BoxStack::new(10).build(p()).unwrap(),
        "stack4" => BoxStack::new(10).build(WorldParams { friction_dirs: 4, ..p() }).unwrap(),
        _ => panic!("scene: slide | rest | stack | stack4"),
    }
}

#[inline(never)]
fn stage_forces(w: &mut World) {
    w.forces_stage().unwrap();
}

#[inline(never)]
fn stage_detect(w: &mut World) {
    w.detect();
}

/// The broad phase alone, as `detect` runs it (not part of the step).
#[inline(never)]
fn stage_broad(w: &World, bp: &mut BroadPhase, r: &mut Vec<f64>) {
    let (v, om) = w.free_velocities();
    r.clear();
    r.extend(w.bodies().iter().enumerate().map(|(k, b)| reach(b, v[k], om[k])));
    let p = w.params();
    let m = PairMargin { base: p.margin, h: p.dt, reach: p.velocity_margin.then_some(&r[..]) };
    black_box(bp.find(w.bodies(), &m));
}

#[inline(never)]
fn stage_islands(w: &mut World) {
    w.islands();
}

#[inline(never)]
fn stage_assemble(w: &mut World) {
    w.assemble_for_solve().unwrap();
}

#[inline(never)]
fn stage_solve(w: &mut World) {
    w.solve(None).unwrap();
}

#[inline(never)]
fn stage_integrate(w: &mut World) {
    w.integrate();
}

#[inline(never)]
fn stage_record(w: &World, t: &mut Trajectory) {
    t.push(w);
}

/// One step stage by stage; `mark(i)` after stage `i` of [`STAGES`].
#[inline(always)]
fn staged_step(w: &mut World, bp: &mut BroadPhase, r: &mut Vec<f64>, t: &mut Trajectory, mut mark: impl FnMut(usize)) {
    stage_forces(w);
    mark(0);
    stage_broad(w, bp, r);
    mark(1);
    stage_detect(w);
    mark(2);
    stage_islands(w);
    mark(3);
    stage_assemble(w);
    mark(4);
    stage_solve(w);
    mark(5);
    stage_integrate(w);
    mark(6);
    stage_record(w, t);
    mark(7);
}

#[inline(never)]
fn stages_only(w: &mut World, steps: usize) {
    let (mut bp, mut r) = (BroadPhase::new(), Vec::new());
    let mut t = Trajectory::with_capacity(steps, w.body_count());
    for _ in 0..steps {
        staged_step(w, &mut bp, &mut r, &mut t, |_| {});
    }
    black_box(&t);
}

fn budget(name: &str, label: &str, batches: usize, per: usize) {
    let mut s = scene(name);
    let w = &mut s.world;
    for _ in 0..100 {
        w.step().unwrap();
    }
    // the timer's own cost per mark
    let t0 = Instant::now();
    for _ in 0..100_000 {
        black_box(Instant::now());
    }
    let tick = t0.elapsed().as_secs_f64() / 100_000.0;
    let (mut bp, mut r) = (BroadPhase::new(), Vec::new());
    let mut best = [f64::INFINITY; 8];
    let (mut best_step, mut best_run) = (f64::INFINITY, f64::INFINITY);
    let (mut pivots, mut size, mut failures) = (0usize, 0usize, 0usize);
    for _ in 0..batches {
        let mut t = Trajectory::with_capacity(per, w.body_count());
        let mut sum = [0.0; 8];
        for _ in 0..per {
            let mut last = Instant::now();
            staged_step(w, &mut bp, &mut r, &mut t, |i| {
                let now = Instant::now();
                sum[i] += (now - last).as_secs_f64();
                last = now;
            });
            let rec = w.last_record();
            pivots += rec.pivots;
            size = size.max(rec.lcp_size);
            failures += usize::from(!rec.ok());
        }
        for i in 0..8 {
            best[i] = best[i].min(sum[i] / per as f64 - tick);
        }
        // the whole step, and the step with recording (`World::run`), for comparison
        let t0 = Instant::now();
        for _ in 0..per {
            w.step().unwrap();
        }
        best_step = best_step.min(t0.elapsed().as_secs_f64() / per as f64);
        let t0 = Instant::now();
        black_box(w.run(per).unwrap());
        best_run = best_run.min(t0.elapsed().as_secs_f64() / per as f64);
    }
    // narrow = detect − broad
    let detect = best[2];
    best[2] = (detect - best[1]).max(0.0);
    let total: f64 = best[0] + detect + best[3..].iter().sum::<f64>();
    print!("{label:<34}");
    for (i, b) in best.iter().enumerate() {
        print!(" {:>6.2}", b * 1e6);
        let _ = i;
    }
    println!(
        " | Σ {:>6.2} | step {:>6.2} run {:>6.2} µs | n {size}, {:.2} pivots/step, {failures} failed",
        total * 1e6,
        best_step * 1e6,
        best_run * 1e6,
        pivots as f64 / (batches * per) as f64
    );
}

/// The bits of every position, orientation and velocity of the built-in
/// scenes' runs, one line per step (to compare builds).
fn dump(path: &str) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let p = WorldParams::default;
    let runs: [(&str, Scene, usize); 4] = [
        ("box_stack(10)", BoxStack::new(10).build(p()).unwrap(), 2000),
        ("cube_on_slope(30,0.5)", CubeOnSlope::new(30.0, 0.5).build(p()).unwrap(), 2000),
        ("cube_on_slope(30,0.7)", CubeOnSlope::new(30.0, 0.7).build(p()).unwrap(), 2000),
        ("box_pile()", BoxPile::default().build(p()).unwrap(), 300),
    ];
    for (name, mut s, steps) in runs {
        let t = s.world.run(steps).unwrap();
        let per = t.bodies;
        for k in 0..t.len() {
            write!(out, "{name} {k}").unwrap();
            for a in [&t.position[k * per * 3..][..per * 3], &t.orientation[k * per * 4..][..per * 4]] {
                for v in a {
                    write!(out, " {:016x}", v.to_bits()).unwrap();
                }
            }
            for a in [&t.velocity[k * per * 3..][..per * 3], &t.angular_velocity[k * per * 3..][..per * 3]] {
                for v in a {
                    write!(out, " {:016x}", v.to_bits()).unwrap();
                }
            }
            writeln!(out, " {} {}", t.pivots[k], t.residual[k].to_bits()).unwrap();
        }
    }
}

/// Per step of a run from the scene's start: the minimum time over
/// `repeats` runs (the trajectory is the same each time), and what the
/// solve did; printed summed over windows of `window` steps.
fn profile(name: &str, steps: usize, repeats: usize, window: usize) {
    let mut best = vec![f64::INFINITY; steps];
    let mut info: Vec<(usize, String, usize, usize, bool)> = Vec::with_capacity(steps);
    for rep in 0..repeats {
        let mut s = scene(name);
        let w = &mut s.world;
        let mut t = Trajectory::with_capacity(steps, w.body_count());
        let mut prev: Option<Vec<bool>> = None;
        for slot in best.iter_mut() {
            let t0 = Instant::now();
            w.step().unwrap();
            t.push(w);
            *slot = slot.min(t0.elapsed().as_secs_f64());
            if rep == 0 {
                let r = w.last_record();
                let stage = r.islands.iter().map(|i| format!("{:?}", i.stage)).collect::<Vec<_>>().join(",");
                let basis = r.basis.as_ref().map_or(0, |b| b.iter().filter(|&&x| x).count());
                let same = r.basis.is_some() && r.basis == prev;
                prev = r.basis.clone();
                info.push((r.pivots, stage, basis, r.lcp_size, same));
            }
        }
    }
    let steady = {
        let mut v = best.clone();
        v.sort_by(f64::total_cmp);
        v[v.len() / 4]
    };
    println!("steady (25th percentile) {:.2} µs; total {:.1} ms", steady * 1e6, best.iter().sum::<f64>() * 1e3);
    println!("window       µs   excess(µs)  >2×steady  pivots  basis-changes  basis(min-max)  stages");
    for w0 in (0..steps).step_by(window) {
        let r = w0..(w0 + window).min(steps);
        let sum: f64 = best[r.clone()].iter().sum();
        let excess: f64 = best[r.clone()].iter().map(|b| (b - steady).max(0.0)).sum();
        let slow = best[r.clone()].iter().filter(|&&b| b > 2.0 * steady).count();
        let piv: usize = info[r.clone()].iter().map(|i| i.0).sum();
        let changes = info[r.clone()].iter().filter(|i| !i.4).count();
        let bmin = info[r.clone()].iter().map(|i| i.2).min().unwrap();
        let bmax = info[r.clone()].iter().map(|i| i.2).max().unwrap();
        let mut stages: Vec<&str> = info[r.clone()].iter().map(|i| i.1.as_str()).collect();
        stages.sort();
        stages.dedup();
        println!(
            "{:>5}-{:<5} {:>8.1} {:>9.1} {:>6} {:>8} {:>8} {:>8}-{:<4} {}",
            r.start,
            r.end,
            sum * 1e6,
            excess * 1e6,
            slow,
            piv,
            changes,
            bmin,
            bmax,
            stages.join(" ")
        );
    }
    if std::env::var_os("PROFILE_STEPS").is_some() {
        for (k, (b, i)) in best.iter().zip(&info).enumerate() {
            println!("step {k} {:.2} µs pivots {} basis {} n {} same {} {}", b * 1e6, i.0, i.2, i.3, i.4, i.1);
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("dump") => dump(&args[1]),
        Some("run") => {
            let mut s = scene(&args[1]);
            let steps: usize = args.get(2).map_or(2000, |a| a.parse().unwrap());
            black_box(s.world.run(steps).unwrap());
        }
        Some("profile") => {
            let steps: usize = args.get(2).map_or(4000, |a| a.parse().unwrap());
            let repeats: usize = args.get(3).map_or(5, |a| a.parse().unwrap());
            let window: usize = args.get(4).map_or(100, |a| a.parse().unwrap());
            profile(&args[1], steps, repeats, window);
        }
        Some("stages") => {
            let mut s = scene(&args[1]);
            let steps: usize = args.get(2).map_or(2000, |a| a.parse().unwrap());
            let from: usize = args.get(3).map_or(100, |a| a.parse().unwrap());
            for _ in 0..from {
                s.world.step().unwrap();
            }
            stages_only(&mut s.world, steps);
        }
        _ => {
            let batches: usize = args.first().map_or(30, |a| a.parse().unwrap());
            print!("µs per step, min over {batches} batches      ");
            for s in STAGES {
                print!(" {s:>6}");
            }
            println!();
            budget("slide", "cube sliding on 30°, μ 0.5", batches, 1000);
            budget("rest", "cube resting on 30°, μ 0.7", batches, 1000);
            budget("stack", "10-box stack, resting", batches.min(10), 200);
        }
    }
}
