//! Criterion bench: median time per solve for contact-structured LCPs
//! (sizes 20 and 40, from `sim::generate`) and random SPD LCPs (40, 200, 1000).
//! Run with `cargo bench -p lcpsim-lcp --bench lemke`. Each solve runs in
//! one reused workspace (`lemke::solve_in`), as the simulator and the Python
//! glue call it.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lcp::{generate, lemke, LemkeOptions};
use std::hint::black_box;

fn contact(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact");
    for (nc, scale) in [(2usize, 1.0), (4, 1.0), (4, 1e-3), (4, 1e-6)] {
        // A fixed set of 64 problems, cycled, so one lucky case cannot dominate.
        let set: Vec<_> = (0..64).map(|seed| sim::generate::contact_lcp(nc, 8, scale, seed)).collect();
        for (name, o) in [("robust", LemkeOptions::default()), ("classic", LemkeOptions::classic())] {
            let id = BenchmarkId::new(name, format!("n{}_s{scale:e}", 10 * nc));
            let mut i = 0;
            let mut ws = lemke::Workspace::new();
            g.bench_function(id, |b| {
                b.iter(|| {
                    i = (i + 1) % set.len();
                    black_box(lemke::solve_in(&set[i], &o, None, &mut ws))
                })
            });
        }
    }
    g.finish();
}

fn spd(c: &mut Criterion) {
    let mut g = c.benchmark_group("spd");
    g.sample_size(10);
    for n in [40usize, 200, 1000] {
        let lcp = generate::spd_lcp(n, 1);
        let mut ws = lemke::Workspace::new();
        g.bench_function(BenchmarkId::new("robust", n), |b| {
            b.iter(|| black_box(lemke::solve_in(&lcp, &LemkeOptions::default(), None, &mut ws)))
        });
    }
    g.finish();
}

criterion_group!(benches, contact, spd);
criterion_main!(benches);
