//! Scans the hard corpus with the default Lemke and prints every
//! failure: `hard_scan [count] [scales,..] [families,..]` (corpus seed `CORPUS_SEED`, default
//! 2026 as in the ignored corpus test; `ORDINARY=1` scans `contact_lcp` instead, nc ∈ {1, 2, 4, 8}).
use lcp::{lemke, Lcp, LemkeOptions, Solution, Status};
use sim::generate::{hard_corpus_item, HardScene};

/// The criterion: solved, natural residual ≤ 1e-9·(1 + ‖q‖∞).
fn solved(p: &Lcp, sol: &Solution) -> bool {
    sol.status == Status::Solved && sol.residuals.residual <= 1e-9 * (1.0 + p.q_norm_inf())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let count: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(2000);
    let scales: Vec<f64> = args
        .get(2)
        .map(|s| s.split(',').map(|v| v.parse().unwrap()).collect())
        .unwrap_or(vec![1.0, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8]);
    let fams: Option<Vec<String>> = args.get(3).map(|s| s.split(',').map(String::from).collect());
    let corpus: u64 = std::env::var("CORPUS_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(2026);
    let opts = LemkeOptions::default();
    if std::env::var("ORDINARY").is_ok() {
        // The ordinary generated contact LCPs (one box on a plane).
        for &scale in &scales {
            let mut fails = 0;
            for nc in [1, 2, 4, 8] {
                for seed in 0..count as u64 {
                    let p = sim::generate::contact_lcp(nc, 8, scale, seed);
                    let sol = lemke::solve(&p, &opts);
                    if !solved(&p, &sol) {
                        fails += 1;
                        println!("FAIL ordinary s={scale:e} nc={nc} seed={seed} {:?}", sol.status);
                    }
                }
            }
            println!("ordinary s = {scale:e}: {fails}/{} failures", 4 * count);
        }
        return;
    }
    for &scale in &scales {
        let (mut fails, mut tried) = (0, 0);
        let t = std::time::Instant::now();
        for i in 0..count {
            let (kind, k, seed) = hard_corpus_item(corpus, i);
            if fams.as_ref().is_some_and(|f| !f.iter().any(|x| x == kind.as_str())) {
                continue;
            }
            tried += 1;
            let p = HardScene::random(kind, k, seed).lcp(scale);
            let sol = lemke::solve(&p, &opts);
            if !solved(&p, &sol) {
                fails += 1;
                println!(
                    "FAIL s={scale:e} i={i} {} k={k} seed={seed} n={} {:?} natural {:.2e} pivots {}",
                    kind.as_str(),
                    p.n(),
                    sol.status,
                    sol.residuals.residual,
                    sol.pivots
                );
            }
        }
        println!("s = {scale:e}: {fails}/{tried} failures ({:.1} s)", t.elapsed().as_secs_f64());
    }
}
