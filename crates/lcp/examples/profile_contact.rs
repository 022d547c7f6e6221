//! Solves the same 64 contact LCPs (n = 40) many times: a target for
//! `valgrind --tool=callgrind` when tuning Lemke. Arguments: repetitions
//! (default 20) and friction-cone scale (default 1). One workspace serves
//! every solve, as in the simulator and the Python glue.
use lcp::{lemke, LemkeOptions};

fn main() {
    let reps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20);
    let scale: f64 = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let set: Vec<_> = (0..64).map(|seed| sim::generate::contact_lcp(4, 8, scale, seed)).collect();
    let mut pivots = 0;
    let mut ws = lemke::Workspace::new();
    for _ in 0..reps {
        for lcp in &set {
            pivots += lemke::solve_in(lcp, &LemkeOptions::default(), None, &mut ws).pivots;
        }
    }
    println!("{} solves, {} pivots", reps * set.len(), pivots);
}
