//! Issue 5 regressions: every hard-corpus LCP (corpus seed 2026, first 2000
//! items) on which the default Lemke failed before the ladder gained more
//! covering vectors and restarts from its rungs' final bases. Each must be
//! solved, judged here by its own natural residual in the units given.

use lcp::generate::{HardKind, HardScene};
use lcp::{lemke, LemkeOptions, Status};

/// `(family, k, seed, scales)` as `hard_scan` / the ignored corpus test print them.
const CASES: [(HardKind, usize, u64, &[f64]); 8] = [
    (HardKind::Mixed, 8, 4839772600793578341, &[1.0, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8]),
    (HardKind::Mixed, 8, 5702131337896926190, &[1.0, 1e-2, 1e-4, 1e-6, 1e-8]),
    (HardKind::Mixed, 8, 12001955134867197707, &[1e-4, 1e-6]),
    (HardKind::Mixed, 16, 13376074668700641071, &[1.0, 1e-4, 1e-8]),
    (HardKind::Mixed, 16, 2097431372507007774, &[1e-8]),
    (HardKind::NearlyParallel, 8, 8709212949840997477, &[1e-2, 1e-8]),
    (HardKind::NearlyParallel, 8, 11789418395487818503, &[1e-6]),
    (HardKind::NearlyParallel, 8, 17890279517136882127, &[1e-6]),
];

#[test]
fn issue_5_previously_failing_hard_lcps_are_solved() {
    for (kind, k, seed, scales) in CASES {
        for &s in scales {
            let p = HardScene::random(kind, k, seed).lcp(s);
            let sol = lemke::solve(&p, &LemkeOptions::default());
            let what = format!("{} k={k} seed={seed} s={s:e}", kind.as_str());
            assert_eq!(sol.status, Status::Solved, "{what}");
            // The residual recomputed here, not the solver's.
            let n = p.n();
            assert_eq!(sol.z.len(), n, "{what}");
            let natural = (0..n).fold(0.0f64, |a, i| {
                let w = p.q()[i] + (0..n).map(|j| p.at(i, j) * sol.z[j]).sum::<f64>();
                a.max(sol.z[i].min(w).abs())
            });
            let bound = 1e-9 * (1.0 + p.q_norm_inf());
            assert!(natural <= bound, "{what}: natural residual {natural:e} > {bound:e}");
            assert!(sol.z.iter().all(|&v| v >= 0.0), "{what}: negative z");
        }
    }
}
