//! One componentwise acceptance rule (`lcp::accept`), and
//! ill-conditioned P-matrix LCPs solved rather than reported as `numerical`
//! or a false `ray_termination`. The reproducers are `tests/data/repros/*.npz`.

mod common;

use common::npz::repro;
use lcp::accept::{backward_error, DEFAULT_TOL};
use lcp::certify::certify;
use lcp::generate::permuted_triangular_lcp;
use lcp::{lemke, Lcp, LemkeOptions, Method, NewtonFbOptions, PgsOptions, Solution, Status};

const REPROS: [&str; 4] = ["unit_tri.npz", "repro_tri13.npz", "repro_spd1012.npz", "repro_172.npz"];

/// `ok()` ⇔ solved and inside the rule, recomputed here from `z`.
fn assert_ok_means_the_rule(lcp: &Lcp, sol: &Solution, what: &str) {
    let eta = backward_error(lcp, &sol.z, &lcp.w_of(&sol.z));
    assert_eq!(sol.ok(), sol.status == Status::Solved && eta <= DEFAULT_TOL, "{what}: η = {eta:e}, {:?}", sol.status);
}

fn methods() -> Vec<(&'static str, Method)> {
    vec![
        ("lemke", Method::Lemke(LemkeOptions::default())),
        ("classic", Method::Lemke(LemkeOptions::classic())),
        ("pgs", Method::Pgs(PgsOptions::default())),
        ("newton_fb", Method::NewtonFb(NewtonFbOptions::default())),
    ]
}

#[test]
fn repros_are_solved_within_the_rule() {
    for name in REPROS {
        let p = repro(name);
        let sol = lemke::solve(&p, &LemkeOptions::default());
        assert_eq!(sol.status, Status::Solved, "{name}");
        assert!(sol.ok(), "{name}");
        let eta = backward_error(&p, &sol.z, &p.w_of(&sol.z));
        assert!(eta <= DEFAULT_TOL, "{name}: η = {eta:e}");
        // The basis is the exact solution's (rational arithmetic on the floats given).
        let cert = certify(&p, sol.basis.as_ref().unwrap());
        assert!(cert.certified_within(1e-12), "{name}: exact η = {:e}", cert.backward_error);
    }
}

#[test]
fn ok_is_never_true_outside_the_rule() {
    for name in REPROS {
        let p = repro(name);
        for (m, method) in methods() {
            assert_ok_means_the_rule(&p, &lcp::solve(&p, &method), &format!("{name} {m}"));
        }
    }
    // repro_172: w₀ = −1e-6 is small beside ‖q‖∞ = 3e7 but 100 % of row 0's
    // own scale; the old normwise bound accepted it.
    let p = repro("repro_172.npz");
    let sol = lemke::solve(&p, &LemkeOptions::default());
    assert!(sol.w[0] >= -1e-15, "w₀ = {:e}", sol.w[0]);
}

#[test]
fn classic_keeps_its_word_but_not_ok() {
    // A 1×1 LCP classic calls solved with w = −8.6e-7 (inside its absolute
    // zero_tol 1e-6), far outside the rule: ok must say so.
    let p = Lcp::new(vec![1.0], vec![-8.6e-7]).unwrap();
    let mut sol = lemke::solve(&p, &LemkeOptions::classic());
    assert_eq!(sol.status, Status::Solved);
    assert_eq!(sol.z, vec![0.0]);
    assert!(!sol.ok());
    assert_ok_means_the_rule(&p, &sol, "1×1 classic");
    // The robust Lemke solves it.
    sol = lemke::solve(&p, &LemkeOptions::default());
    assert!(sol.ok() && (sol.z[0] - 8.6e-7).abs() <= 1e-22, "{:?}", sol.z);
}

/// The family of these tests: permuted triangular P-matrices, cond∞ ≥ 1e15.
fn ill_conditioned_family(count: usize) -> Vec<(u64, Lcp, f64)> {
    (0..u64::MAX)
        .map(|seed| {
            let n = 12 + (seed % 9) as usize;
            let (p, cond) = permuted_triangular_lcp(n, seed);
            (seed, p, cond)
        })
        .filter(|(_, _, cond)| *cond >= 1e15)
        .take(count)
        .collect()
}

#[test]
fn ill_conditioned_p_matrices_are_solved() {
    let (mut worst_eta, mut statuses, mut certified) = (0.0f64, std::collections::BTreeMap::new(), 0);
    for (seed, p, cond) in ill_conditioned_family(300) {
        let sol = lemke::solve(&p, &LemkeOptions::default());
        *statuses.entry(sol.status.as_str()).or_insert(0) += 1;
        let what = format!("seed {seed} n {} cond {cond:.1e}", p.n());
        assert_eq!(sol.status, Status::Solved, "{what}");
        assert_ok_means_the_rule(&p, &sol, &what);
        // By the rule, recomputed: every row within 1e-9 of its own scale.
        let eta = backward_error(&p, &sol.z, &p.w_of(&sol.z));
        worst_eta = worst_eta.max(eta);
        // By the residual: z ≥ 0 and w ≥ 0 up to the round-off of forming w.
        let w = p.w_of(&sol.z);
        for i in 0..p.n() {
            let scale: f64 = p.q()[i].abs() + (0..p.n()).map(|j| p.at(i, j).abs() * sol.z[j]).sum::<f64>();
            assert!(sol.z[i] >= 0.0 && w[i] >= -1e-9 * scale, "{what}: w[{i}] = {:e}", w[i]);
            assert!(sol.z[i] == 0.0 || w[i].abs() <= 1e-9 * scale, "{what}: z[{i}] w[{i}] = {:e} {:e}", sol.z[i], w[i]);
        }
        // And its basis, solved exactly, is within the rule too (η evaluated
        // in rational arithmetic; 0 when the basis is the unique solution's).
        let cert = certify(&p, sol.basis.as_ref().unwrap());
        certified += usize::from(cert.certified());
        assert!(cert.certified_within(DEFAULT_TOL), "{what}: exact η = {:e}", cert.backward_error);
    }
    println!("statuses {statuses:?}, worst η {worst_eta:e}, bases certified exactly {certified}/300");
}

#[test]
fn small_ill_conditioned_p_matrices_match_exact_enumeration() {
    // n ≤ 8: every complementary basis checked exactly; a P-matrix has one solution.
    let mut checked = 0;
    for seed in 0..400u64 {
        let n = 4 + (seed % 5) as usize;
        let (p, cond) = permuted_triangular_lcp(n, seed);
        if cond < 1e6 {
            continue;
        }
        let certified: Vec<Vec<bool>> = (0..1u32 << n)
            .map(|bits| (0..n).map(|j| bits >> j & 1 == 1).collect::<Vec<bool>>())
            .filter(|b| certify(&p, b).certified())
            .collect();
        assert_eq!(certified.len(), 1, "seed {seed}: a P-matrix LCP has one solution");
        let sol = lemke::solve(&p, &LemkeOptions::default());
        assert!(sol.ok(), "seed {seed}");
        let exact = certify(&p, &certified[0]);
        for j in 0..n {
            assert!((sol.z[j] - exact.z[j]).abs() <= 1e-6 * exact.z[j].abs(), "seed {seed}: z[{j}]");
        }
        checked += 1;
    }
    assert!(checked >= 50, "only {checked} cases with cond ≥ 1e6");
}
