//! A forming heap's large-island LCPs, recorded and solved again.
//!
//! `cargo run --release -p lcpsim-sim --example heap_replay -- record CUBES STEPS DIR`
//! runs the walled heap of `CUBES` cubes (seed 0, as `tests/heap.rs`) for
//! `STEPS` steps with `LCPSIM_DUMP_DIR=DIR` (`sim::solve_chain::replay`), printing
//! per step the largest LCP, pivots, status, seconds and the files written.
//!
//! `cargo run --release -p lcpsim-sim --example heap_replay -- solve START FILE...`
//! solves each file from `START` (`step`: the step's rule, `previous`, `cold`,
//! `guess:SWEEPS`, `merged:SWEEPS`, `bpp:previous` or `bpp:guess:SWEEPS`: the
//! basis improved by block principal pivoting first) and
//! prints one line per file: n, pivots, status, accepted, natural residual,
//! seconds, and for a guess the seconds of its sweeps and how many basis flags
//! it got wrong against the answer found; for a `bpp:` start, block principal
//! pivoting alone on the full LCP from that basis (infeasible values before
//! and after, factorizations, seconds).
//!
//! `cargo run --release -p lcpsim-sim --example heap_replay -- distance CUBES STEPS HALVINGS [SEED]`
//! runs the walled heap (`max_halvings = HALVINGS`) and prints per step the
//! largest LCP, pivots, the islands' summed `entered` (the fewest pivots
//! that could have reached the answers found from the bases the step started
//! from), seconds, penetration, each failed attempt of a step retaken in
//! parts, and at the end the totals (failed and retaken steps, the deepest
//! penetration) with the seconds the
//! steps would have taken at their own cost per pivot had every island gone
//! straight to its answer: what a shorter path could save at best. A change
//! to the structured Lemke is judged on such whole heaps of several seeds
//! (`distance 200 200 3 SEED`), not on saved LCPs alone: every LCP of a heap
//! has many answers, and the trajectories part.
//!
//! With `LCPSIM_LEMKE_TRACE=1` set, every structured Lemke run prints its
//! counts to standard error (`lemke_trace` and `lemke_end` lines: degenerate
//! pivots, ties, re-entries, z0's course, small pivots and the jumps of the
//! values they cause, how the final answer stands against the acceptance
//! rule; see `lcp::structured`'s pivot loop).

use sim::lcp::structured::bpp::{self, BppOptions};
use sim::lcp::structured::guess::{self, GuessOptions};
use sim::scenes::CubeHeap;
use sim::solve_chain::replay::StructuredProblem;
use sim::solve_chain::structured_lemke::Start;
use sim::WorldParams;
use std::path::Path;
use std::time::Instant;

fn record(cubes: usize, steps: usize, dir: &str) {
    std::fs::create_dir_all(dir).expect("a dump directory");
    std::env::set_var("LCPSIM_DUMP_DIR", dir);
    let mut s = CubeHeap { walls: true, ..CubeHeap::new(cubes, 0) }.build(WorldParams::default()).unwrap();
    let files = || std::fs::read_dir(dir).map(|d| d.count()).unwrap_or(0);
    let t0 = Instant::now();
    for _ in 0..steps {
        let (before, ts) = (files(), Instant::now());
        let r = s.world.step().unwrap();
        let worst = r.islands.iter().max_by_key(|i| i.lcp_size);
        let pen = r.contacts.iter().fold(0.0f64, |p, c| p.max(-c.gap));
        println!(
            "step {} n {} pivots {} status {:?} secs {:.2} dumps {} pen {pen:.2e} total {:.0}",
            r.step,
            worst.map_or(0, |i| i.lcp_size),
            r.pivots,
            worst.map(|i| i.status),
            ts.elapsed().as_secs_f64(),
            files() - before,
            t0.elapsed().as_secs_f64()
        );
    }
}

fn solve(start: &str, files: &[String]) {
    let start = match start {
        "previous" => Start::Previous,
        "step" => Start::Step,
        "cold" => Start::Cold,
        "bpp:previous" => Start::PreviousBpp,
        g if g.starts_with("bpp:guess:") => Start::GuessBpp { sweeps: g[10..].parse().expect("bpp:guess:SWEEPS") },
        g if g.starts_with("merged:") => Start::Merged { sweeps: g[7..].parse().expect("merged:SWEEPS") },
        g => Start::Guess { sweeps: g.strip_prefix("guess:").and_then(|s| s.parse().ok()).expect("guess:SWEEPS") },
    };
    for f in files {
        let p = StructuredProblem::read(Path::new(f)).expect("a structured LCP file");
        let t = Instant::now();
        let sol = p.solve(start);
        let secs = t.elapsed().as_secs_f64();
        let mut extra = String::new();
        if let Some(b) = match start {
            Start::PreviousBpp => p.warm.clone(),
            Start::GuessBpp { sweeps } => {
                Some(guess::guess_basis(&p.op, p.layout, &GuessOptions { sweeps, ..Default::default() }, None))
            }
            _ => None,
        } {
            // Block principal pivoting alone on the full LCP, from the same basis.
            let t = Instant::now();
            let r = bpp::improve(&p.op, &b, &BppOptions::default(), Some(p.layout));
            let s = t.elapsed().as_secs_f64();
            extra = r.map_or(" bpp none".into(), |r| {
                format!(" bpp_infeasible {}->{} rounds {} bpp_secs {s:.2}", r.infeasible_start, r.infeasible, r.rounds)
            });
        }
        if let Start::Guess { sweeps } = start {
            let t = Instant::now();
            let g = guess::guess_basis(&p.op, p.layout, &GuessOptions { sweeps, ..Default::default() }, None);
            let gsecs = t.elapsed().as_secs_f64();
            let wrong = sol.basis.as_ref().map_or("-".into(), |b| wrong_by_kind(&p, &g, b));
            extra += &format!(" guess_secs {gsecs:.3} guess_wrong {wrong}");
        }
        let prev_wrong = match (&p.warm, &sol.basis) {
            (Some(w), Some(b)) => wrong_by_kind(&p, w, b),
            _ => "-".into(),
        };
        println!(
            "{} n {} pivots {} status {:?} accepted {} residual {:.1e} secs {secs:.2} warm_wrong {prev_wrong}{extra}",
            Path::new(f).file_name().map_or(f.clone(), |s| s.to_string_lossy().into()),
            p.op.n(),
            sol.pivots,
            sol.status,
            sol.accepted,
            sol.residuals.residual,
        );
    }
}

fn distance(cubes: usize, steps: usize, halvings: u32, seed: u64) {
    let p = WorldParams { max_halvings: halvings, ..WorldParams::default() };
    let mut s = CubeHeap { walls: true, ..CubeHeap::new(cubes, seed) }.build(p).unwrap();
    let (mut pivots, mut entered, mut secs, mut straight) = (0usize, 0usize, 0.0f64, 0.0f64);
    let (mut failed, mut retaken, mut pen) = (0usize, 0usize, 0.0f64);
    for _ in 0..steps {
        let ts = Instant::now();
        let r = s.world.step().unwrap();
        let t = ts.elapsed().as_secs_f64();
        let d: usize = r.islands.iter().filter_map(|i| i.entered).sum();
        let n = r.islands.iter().map(|i| i.lcp_size).max().unwrap_or(0);
        (pivots, entered, secs) = (pivots + r.pivots, entered + d, secs + t);
        // At this step's cost per pivot (a step without pivots costs what it cost).
        straight += if r.pivots > 0 { t * (d.min(r.pivots) as f64 / r.pivots as f64) } else { t };
        failed += usize::from(!r.ok());
        retaken += usize::from(r.parts > 1);
        let step_pen = r.contacts.iter().fold(0.0f64, |p, c| p.max(-c.gap));
        pen = pen.max(step_pen);
        // Each failed attempt before the parts that stood: where it was, and its unsolved islands.
        for a in &r.retakes {
            let unsolved: Vec<_> = a.unsolved().map(|i| (i.lcp_size, i.status, i.pivots)).collect();
            println!("  step {} attempt at t = {:.5}, h = {:.2e}: unsolved {unsolved:?}", r.step, a.time, a.h);
        }
        println!(
            "step {} n {n} islands {} parts {} pivots {} entered {d} secs {t:.3} ok {} pen {step_pen:.2e}",
            r.step,
            r.islands.len(),
            r.parts,
            r.pivots,
            r.ok()
        );
    }
    println!(
        "done: {steps} steps, {secs:.1} s, {pivots} pivots, {entered} entered, {straight:.1} s going straight, \
         {failed} failed, {retaken} retaken, penetration {pen:.2e} m"
    );
}

/// Flags of `guess` that differ from `answer`: all, then those of `fn`, `fd` and `λ`.
fn wrong_by_kind(p: &StructuredProblem, guess: &[bool], answer: &[bool]) -> String {
    let lay = p.layout;
    let count = |r: std::ops::Range<usize>| r.filter(|&i| guess[i] != answer[i]).count();
    let (a, b, c) = (count(lay.fn_range()), count(lay.fd_range()), count(lay.lambda_range()));
    format!("{}={a}+{b}+{c}", a + b + c)
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    match a.first().map(String::as_str) {
        Some("record") if a.len() == 4 => record(a[1].parse().unwrap(), a[2].parse().unwrap(), &a[3]),
        Some("solve") if a.len() >= 3 => solve(&a[1], &a[2..]),
        Some("distance") if a.len() >= 4 => {
            let seed = a.get(4).map_or(0, |x| x.parse().unwrap());
            distance(a[1].parse().unwrap(), a[2].parse().unwrap(), a[3].parse().unwrap(), seed)
        }
        _ => eprintln!(
            "usage: heap_replay record CUBES STEPS DIR | solve START FILE... | distance CUBES STEPS HALVINGS [SEED]"
        ),
    }
}
