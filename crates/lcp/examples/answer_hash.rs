//! Prints hashes of Lemke's answers (z, w bits, pivots, status, basis, trace)
//! on ~2600 generated LCPs, cold (robust and classic) and warm-started from
//! the previous problem's basis, apart: run it before and after a change that
//! must keep answers bit-identical and compare the lines.
use lcp::{generate, lemke, Lcp, LemkeOptions, Method, Solution};
use std::hash::{DefaultHasher, Hash, Hasher};

fn feed(h: &mut DefaultHasher, s: &Solution) {
    s.z.iter().chain(&s.w).for_each(|v| v.to_bits().hash(h));
    (s.pivots, s.status, &s.basis).hash(h);
}

fn main() {
    let lex = LemkeOptions::default();
    let classic = LemkeOptions::classic();
    let mut total = DefaultHasher::new();
    let mut group = |name: &str, lcps: Vec<Lcp>| {
        let (mut h, mut hw) = (DefaultHasher::new(), DefaultHasher::new());
        let mut prev: Option<Vec<bool>> = None;
        let mut unsolved = [0usize; 2];
        for lcp in &lcps {
            feed(&mut h, &lemke::solve(lcp, &lex));
            feed(&mut h, &lemke::solve(lcp, &classic));
            // Warm: from the previous problem's basis when sizes match.
            let warm = prev.as_deref().filter(|b| b.len() == lcp.n());
            let (s, trace) = lemke::solve_traced(lcp, &lex, warm);
            feed(&mut hw, &s);
            unsolved[0] += usize::from(!lemke::solve(lcp, &lex).ok());
            unsolved[1] += usize::from(!s.ok());
            for p in &trace {
                (p.rung, p.entering, p.leaving, p.theta.to_bits(), p.pivot.to_bits()).hash(&mut hw);
            }
            prev = s.basis.clone();
        }
        let (v, vw) = (h.finish(), hw.finish());
        let [uc, uw] = unsolved;
        println!("{name:>14} {:5} cold {v:016x} warm {vw:016x} unsolved cold {uc} warm {uw}", lcps.len());
        (v, vw).hash(&mut total);
    };
    for scale in [1.0, 1e-3, 1e-6] {
        for nc in [1, 2, 4, 8] {
            group(
                &format!("contact{nc}@{scale:e}"),
                (0..100).map(|s| sim::generate::contact_lcp(nc, 8, scale, s)).collect(),
            );
        }
    }
    group("spd", (0..200).map(|s| generate::spd_lcp(5 + (s as usize % 60), s)).collect());
    group("pmatrix", (0..200).map(|s| generate::p_matrix_lcp(5 + (s as usize % 30), s)).collect());
    group("spd150", (0..4).map(|s| generate::spd_lcp(150, s)).collect());
    group("murty", (1..9).map(generate::murty).collect());
    for scale in [1.0, 1e-4, 1e-8] {
        group(
            &format!("hard@{scale:e}"),
            sim::generate::hard_corpus(2026, 300, scale).into_iter().map(|(_, l)| l).collect(),
        );
    }
    // Method dispatch, PGS and Newton–FB.
    let mut h = DefaultHasher::new();
    for s in 0..100 {
        let lcp = generate::spd_lcp(20, s);
        for m in [Method::default(), Method::Pgs(Default::default()), Method::NewtonFb(Default::default())] {
            feed(&mut h, &lcp::solve(&lcp, &m));
        }
    }
    println!("{:>12} {:5} {:016x}", "methods", 100, h.finish());
    h.finish().hash(&mut total);
    println!("total {:016x}", total.finish());
}
