//! Hard contact LCPs: the contact-LCP structure (`lcp::contact`) for every family, the
//! hardness each family promises (duplicates, twins, collinear rows, mass
//! ratios, ill-conditioned inertia, μ = 0), determinism per seed; and, run by
//! hand, how the default Lemke fares on them at every scale.

#[path = "../../lcp/tests/common/mod.rs"]
mod lcp_common;
use lcp_common::is_positive_definite;

use std::collections::BTreeMap;

use lcp::certify::certify_against;
use lcp::contact::ContactLayout;
use lcp::{lemke, LemkeOptions, Status};
use sim::generate::{
    hard_contact_lcp, hard_contact_lcp_k, hard_corpus, hard_corpus_item, HardKind, HardScene, HARD_MAX_CONTACTS,
    TWIN_OFFSET,
};

fn row(a: &[f64], r: usize, cols: usize) -> &[f64] {
    &a[r * cols..(r + 1) * cols]
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// What the checks read of a scene: its dense `J_n`, `J_d` (from the
/// assembly's rows), `M_b⁻¹`, `v*`, stabilization term and μ.
struct Parts {
    jn: Vec<f64>,
    jd: Vec<f64>,
    minv: Vec<f64>,
    vstar: Vec<f64>,
    b0_extra: Vec<f64>,
    mu: Vec<f64>,
}

fn parts(s: &HardScene) -> Parts {
    let (jn, jd) = s.scene.jacobians(s.k);
    Parts { jn, jd, minv: s.scene.minv(), vstar: s.scene.vstar(), b0_extra: s.scene.b0_extra(), mu: s.mu() }
}

/// Row `r` of `J = [J_n; J_d]`.
fn jrow<'a>(s: &HardScene, p: &'a Parts, r: usize) -> &'a [f64] {
    if r < s.nc {
        row(&p.jn, r, s.ndof)
    } else {
        row(&p.jd, r - s.nc, s.ndof)
    }
}

/// Checks the contact-LCP structure of the scene's LCP at scale `sc`.
fn check_structure(s: &HardScene, sc: f64, what: &str) {
    let lcp = s.lcp(sc);
    let p = parts(s);
    let lay = ContactLayout { nc: s.nc, k: s.k };
    let n = lay.n();
    assert_eq!(lcp.n(), n, "{what}");
    assert_eq!(n, s.nc * (s.k + 2), "{what}");
    assert!(s.nc >= 1 && s.nc <= HARD_MAX_CONTACTS, "{what}: nc = {}", s.nc);
    assert_eq!(s.ndof % 6, 0);
    assert!(p.mu.iter().all(|&m| (0.0..=2.0).contains(&m)), "{what}: {:?}", p.mu);
    // q: J v* (+ b0_extra) on fn and fd, exactly 0 on λ.
    for l in lay.lambda_range() {
        assert_eq!(lcp.q()[l], 0.0, "{what}: q[{l}]");
    }
    let nj = s.nc * (s.k + 1);
    for r in 0..nj {
        let extra = if r < s.nc { p.b0_extra[r] } else { 0.0 };
        let want = dot(jrow(s, &p, r), &p.vstar) + extra;
        assert!((lcp.q()[r] - want).abs() <= 1e-12 * (1.0 + want.abs()), "{what}: q[{r}]");
    }
    // Cone blocks: exactly s·μ, s·E, −s·Eᵀ and 0 elsewhere in λ rows/columns.
    for c in 0..s.nc {
        let l = lay.lambda_index(c);
        for j in 0..n {
            let want = if j == c {
                sc * p.mu[c]
            } else if lay.fd_range().contains(&j) && (j - s.nc) / s.k == c {
                -sc
            } else {
                0.0
            };
            assert_eq!(lcp.at(l, j), want, "{what}: M[λ{c}, {j}]");
        }
        for i in 0..n {
            let want = if lay.fd_range().contains(&i) && (i - s.nc) / s.k == c { sc } else { 0.0 };
            assert_eq!(lcp.at(i, l), want, "{what}: M[{i}, λ{c}]");
        }
    }
    // A = J M_b⁻¹ Jᵀ: exactly symmetric, equal to an independent product, PSD up to round-off.
    let mut a = vec![0.0; nj * nj];
    let mut amax = 0.0f64;
    for r in 0..nj {
        for c in 0..nj {
            a[r * nj + c] = lcp.at(r, c);
            amax = amax.max(lcp.at(r, c).abs());
            assert_eq!(lcp.at(r, c), lcp.at(c, r), "{what}: A not symmetric at ({r}, {c})");
        }
    }
    // Round-off bound of the product: a few ulps of |J_r| |M_b⁻¹| |J_c| (cancellation in ill-conditioned M_b).
    let abs = |v: &[f64]| v.iter().map(|x| x.abs()).collect::<Vec<f64>>();
    let minv_abs = abs(&p.minv);
    let minv_j: Vec<Vec<f64>> =
        (0..nj).map(|r| (0..s.ndof).map(|i| dot(row(&p.minv, i, s.ndof), jrow(s, &p, r))).collect()).collect();
    let minv_j_abs: Vec<Vec<f64>> =
        (0..nj).map(|r| (0..s.ndof).map(|i| dot(row(&minv_abs, i, s.ndof), &abs(jrow(s, &p, r)))).collect()).collect();
    for r in 0..nj {
        for c in 0..nj {
            let want = dot(jrow(s, &p, r), &minv_j[c]);
            let bound = 1e-14 * s.ndof as f64 * dot(&abs(jrow(s, &p, r)), &minv_j_abs[c]);
            assert!((a[r * nj + c] - want).abs() <= bound, "{what}: A[{r}, {c}] = {} vs {want}", a[r * nj + c]);
        }
    }
    let shift = 1e-10 * amax * nj as f64;
    let mut shifted = a.clone();
    for i in 0..nj {
        shifted[i * nj + i] += shift;
    }
    assert!(is_positive_definite(&shifted, nj), "{what}: A + {shift:e} I is not positive definite");
    // The scale is the cone scaling of the unscaled problem, entry for entry.
    if sc != 1.0 {
        assert_eq!(ContactLayout::new(s.nc, s.k).cone_scaling(sc).apply(&s.lcp(1.0)), lcp, "{what}: not D M D");
    }
}

#[test]
fn every_family_has_the_contact_structure() {
    for kind in HardKind::ALL {
        for seed in 0..12 {
            for k in [4, 8, 16] {
                let s = HardScene::random(kind, k, seed);
                for sc in [1.0, 1e-3, 1e-8] {
                    check_structure(&s, sc, &format!("{} k={k} seed={seed} s={sc:e}", kind.as_str()));
                }
            }
        }
    }
}

#[test]
fn k_8_gives_size_10_nc() {
    for kind in HardKind::ALL {
        for seed in 0..20 {
            let s = HardScene::random(kind, 8, seed);
            let lcp = hard_contact_lcp(kind, 1.0, seed);
            assert_eq!(lcp.n(), 10 * s.nc);
            assert_eq!(lcp, s.lcp(1.0));
            assert_eq!(hard_contact_lcp_k(kind, 8, 0.5, seed), s.lcp(0.5));
        }
    }
}

#[test]
fn families_are_as_promised() {
    let mut max_ratio: f64 = 0.0;
    let mut max_cond: f64 = 0.0;
    let mut zero_mu = 0;
    let mut nc_seen = BTreeMap::new();
    for seed in 0..60 {
        for kind in HardKind::ALL {
            let s = HardScene::random(kind, 8, seed);
            let p = parts(&s);
            let normals = s.normals();
            zero_mu += p.mu.iter().filter(|&&m| m == 0.0).count();
            *nc_seen.entry(kind.as_str()).or_insert(0) = s.nc.max(*nc_seen.get(kind.as_str()).unwrap_or(&0));
            for n in &normals {
                assert!((n.dot(*n) - 1.0).abs() < 1e-15);
            }
            let jn = |c: usize| row(&p.jn, c, s.ndof);
            match kind {
                HardKind::ManyContacts => assert!((5..=16).contains(&s.nc) && s.ndof == 6),
                HardKind::Duplicate => {
                    // Some contact repeats another exactly: identical rows of J_n and of M.
                    let dup = (0..s.nc).any(|c| (0..c).any(|d| jn(c) == jn(d)));
                    assert!(dup, "seed {seed}: no duplicate");
                    let lcp = s.lcp(1.0);
                    let (c, d) =
                        (0..s.nc).flat_map(|c| (0..c).map(move |d| (c, d))).find(|&(c, d)| jn(c) == jn(d)).unwrap();
                    // Equal up to round-off only: A is computed on its upper triangle and mirrored.
                    let big = lcp.row(c).iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    for (x, y) in lcp.row(c).iter().zip(lcp.row(d)) {
                        assert!((x - y).abs() <= 1e-13 * big, "rows {c}, {d}: {x} vs {y}");
                    }
                }
                HardKind::NearlyParallel => {
                    assert_eq!(s.nc % 2, 0);
                    let half = s.nc / 2;
                    for c in 0..half {
                        let (a, b) = (normals[c], normals[c + half]);
                        let sin = a.cross(b).norm();
                        assert!((sin - TWIN_OFFSET).abs() < 1e-9 * TWIN_OFFSET + 1e-15, "tilt {sin:e}");
                        assert_ne!(jn(c), jn(c + half));
                    }
                }
                HardKind::Collinear => {
                    // The first three contacts share a line: their J_n rows are linearly dependent.
                    let g: Vec<f64> =
                        (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).map(|(i, j)| dot(jn(i), jn(j))).collect();
                    let det = g[0] * (g[4] * g[8] - g[5] * g[7]) - g[1] * (g[3] * g[8] - g[5] * g[6])
                        + g[2] * (g[3] * g[7] - g[4] * g[6]);
                    assert!(det.abs() < 1e-12 * g[0] * g[4] * g[8], "Gram determinant {det:e}");
                }
                HardKind::MassRatio | HardKind::Mixed => {
                    assert_eq!(s.ndof, 12);
                    // The first four contacts couple both bodies; ground contacts only the lower one.
                    assert!(jn(0)[..6].iter().any(|&v| v != 0.0) && jn(0)[6..].iter().any(|&v| v != 0.0));
                    assert!(jn(4)[6..].iter().all(|&v| v == 0.0));
                    let m = [p.minv[0], p.minv[6 * 12 + 6]];
                    max_ratio = max_ratio.max(m[0] / m[1]).max(m[1] / m[0]);
                    if kind == HardKind::Mixed {
                        assert!(s.nc <= 16);
                    } else {
                        assert_eq!(s.nc, 8);
                    }
                }
                HardKind::ThinRod => {
                    assert!(s.mass_cond >= 1e2 * 0.999 && s.mass_cond <= 1e8 * 1.001, "{}", s.mass_cond);
                    max_cond = max_cond.max(s.mass_cond);
                    // Dense rotational block (the rod lies at a random yaw).
                    assert!(p.minv[3 * 6 + 4] != 0.0);
                }
            }
            // M_b⁻¹ symmetric positive definite.
            assert!(is_positive_definite(&p.minv, s.ndof));
            for i in 0..s.ndof {
                for j in 0..s.ndof {
                    assert_eq!(p.minv[i * s.ndof + j], p.minv[j * s.ndof + i]);
                }
            }
        }
    }
    assert!(max_ratio > 1e3, "mass ratio reached only {max_ratio:e}");
    assert!(max_cond > 1e7, "cond(M_b) reached only {max_cond:e}");
    assert!(zero_mu > 0, "no μ = 0");
    assert_eq!(nc_seen["many_contacts"], 16);
}

#[test]
fn deterministic_per_seed() {
    for kind in HardKind::ALL {
        let a = hard_contact_lcp(kind, 1e-3, 42);
        assert_eq!(a, hard_contact_lcp(kind, 1e-3, 42));
        assert_ne!(a, hard_contact_lcp(kind, 1e-3, 43));
        assert_eq!(HardScene::random(kind, 16, 7), HardScene::random(kind, 16, 7));
    }
    let c1 = hard_corpus(5, 70, 1e-2);
    assert_eq!(c1, hard_corpus(5, 70, 1e-2));
    assert_ne!(c1, hard_corpus(6, 70, 1e-2));
    // Labels are unique and reproduce their LCP; the same seed gives the same scenes at every scale.
    let mut labels: Vec<&String> = c1.iter().map(|(l, _)| l).collect();
    labels.sort();
    labels.dedup();
    assert_eq!(labels.len(), 70);
    let c2 = hard_corpus(5, 70, 1.0);
    let mut kinds = BTreeMap::new();
    let mut ks = BTreeMap::new();
    for (i, ((l1, p1), (l2, p2))) in c1.iter().zip(&c2).enumerate() {
        assert_eq!(l1, l2);
        let (kind, k, seed) = hard_corpus_item(5, i);
        let scene = HardScene::random(kind, k, seed);
        assert_eq!(&scene.label(seed), l1);
        assert_eq!(&scene.lcp(1e-2), p1);
        assert_eq!(&scene.lcp(1.0), p2);
        *kinds.entry(kind.as_str()).or_insert(0) += 1;
        *ks.entry(k).or_insert(0) += 1;
    }
    assert_eq!(kinds.len(), HardKind::ALL.len());
    assert_eq!(ks.keys().copied().collect::<Vec<_>>(), vec![4, 8, 16]);
}

/// The default Lemke on the hard corpus at the corpus's scales, by family and
/// status, with exact certification of its bases up to n = 40. Information, not
/// a gate: `cargo test --release -p lcpsim-sim --test generate_hard -- --ignored --nocapture`.
#[test]
#[ignore]
fn lemke_on_the_hard_corpus() {
    let count: usize = std::env::var("HARD_COUNT").ok().and_then(|v| v.parse().ok()).unwrap_or(2000);
    let cert_max_n: usize = std::env::var("CERT_MAX_N").ok().and_then(|v| v.parse().ok()).unwrap_or(40);
    let opts = LemkeOptions::default();
    let mut total_failures = 0;
    for scale in [1.0, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8] {
        let corpus = hard_corpus(2026, count, scale);
        let t = std::time::Instant::now();
        let mut by_status: BTreeMap<&str, usize> = BTreeMap::new();
        let mut fails: BTreeMap<String, usize> = BTreeMap::new();
        let (mut cert_tried, mut cert_exact, mut worst_eta) = (0, 0, 0.0f64);
        // Backward error buckets: ≤ 1e-14, ≤ 1e-12, ≤ 1e-9, larger.
        let mut eta_buckets = [0usize; 4];
        let (mut cert_time, mut cert_worst_time, mut cert_singular) = (0.0f64, 0.0f64, 0);
        let mut lemke_time = 0.0f64;
        let mut first_fails = Vec::new();
        for (label, p) in &corpus {
            let t_lemke = std::time::Instant::now();
            let sol = lemke::solve(p, &opts);
            lemke_time += t_lemke.elapsed().as_secs_f64();
            let qn = p.q().iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let ok = sol.status == Status::Solved && sol.residuals.residual <= 1e-9 * (1.0 + qn);
            *by_status.entry(if ok { "solved" } else { sol.status.as_str() }).or_insert(0) += 1;
            if !ok {
                total_failures += 1;
                let kind = label.split('/').next().unwrap().to_string();
                *fails.entry(kind).or_insert(0) += 1;
                if first_fails.len() < 10 {
                    first_fails.push(format!("{label}: {:?} natural {:.2e}", sol.status, sol.residuals.residual));
                }
            }
            if let (true, Some(basis)) = (p.n() <= cert_max_n, sol.basis.as_ref()) {
                let t_cert = std::time::Instant::now();
                let c = certify_against(p, basis, &sol.z);
                let dt = t_cert.elapsed().as_secs_f64();
                cert_time += dt;
                cert_worst_time = cert_worst_time.max(dt);
                cert_singular += (c.status == lcp::certify::CertStatus::Singular) as usize;
                cert_tried += 1;
                cert_exact += c.certified() as usize;
                let bucket = [1e-14, 1e-12, 1e-9].iter().position(|&e| c.backward_error <= e).unwrap_or(3);
                eta_buckets[bucket] += 1;
                worst_eta = worst_eta.max(c.backward_error);
            }
        }
        println!(
            "s = {scale:<6e} {count} LCPs in {:.1} s (Lemke {lemke_time:.2} s): {by_status:?}; failures by family \
             {fails:?}; certified (n ≤ {cert_max_n}) {cert_exact}/{cert_tried} exactly, backward error η \
             ≤1e-14/≤1e-12/≤1e-9/more {eta_buckets:?} (worst {worst_eta:.2e}), {cert_singular} singular; certify {cert_time:.2} s, worst \
             {:.1} ms",
            t.elapsed().as_secs_f64(),
            cert_worst_time * 1e3
        );
        for f in &first_fails {
            println!("    {f}");
        }
    }
    // The target: no failure on the default 2000 per scale. (Item 2505 of
    // this seed, beyond the default count, still fails.)
    assert_eq!(total_failures, 0, "robust Lemke failed on the hard corpus");
}
