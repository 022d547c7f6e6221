//! The structured Lemke (`lcp::structured`) on LCPs `M = G H + K` built here
//! from random sparse factors (contact LCPs of the simulator are tested in
//! `sim/tests/structured_lemke.rs`): its answers solve the dense LCP by the
//! dense acceptance rule, agree with enumeration where the solution is
//! unique, and a warm start from its own basis takes no pivot.

use lcp::accept::accepts;
use lcp::enumerate::all_solutions;
use lcp::structured::bpp::{self, BppOptions};
use lcp::structured::{self, Entry, StructuredLcp, StructuredOptions};
use lcp::{lemke, LemkeOptions, Status};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `M = G W Gᵀ + K`: `n` rows over `p` dofs, each row touching `touch`
/// dofs, `W` diagonal positive, `K` = `shift·I` plus a skew-symmetric coupling
/// of `pairs` random pairs (so `M` is positive definite for `shift > 0`:
/// a unique solution) and `q` random.
fn random(n: usize, p: usize, touch: usize, shift: f64, pairs: usize, seed: u64) -> StructuredLcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let w: Vec<f64> = (0..p).map(|_| rng.random_range(0.5..2.0)).collect();
    let (mut g, mut h, mut k): (Vec<Entry>, Vec<Entry>, Vec<Entry>) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        for _ in 0..touch {
            let d = rng.random_range(0..p);
            let v = rng.random_range(-1.0..1.0);
            g.push((i, d, v));
            h.push((d, i, w[d] * v));
        }
        if shift > 0.0 {
            k.push((i, i, shift));
        }
    }
    for _ in 0..pairs {
        let (a, b) = (rng.random_range(0..n), rng.random_range(0..n));
        if a != b {
            let v = rng.random_range(-1.0..1.0);
            k.push((a, b, v));
            k.push((b, a, -v));
        }
    }
    let q = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    StructuredLcp::new(p, &g, &h, &k, q).unwrap()
}

#[test]
fn small_problems_agree_with_enumeration() {
    for seed in 0..40 {
        let op = random(10, 6, 3, 0.1, 4, seed);
        let dense = op.to_dense();
        let sol = structured::solve(&op, &StructuredOptions::default(), None);
        assert!(sol.ok(), "seed {seed}: {:?}", sol.status);
        let all = all_solutions(&dense, 1e-9);
        assert_eq!(all.len(), 1, "seed {seed}: positive definite, one solution");
        let err = sol.z.iter().zip(&all[0]).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(err <= 1e-9 * (1.0 + all[0].iter().fold(0.0f64, |a, v| a.max(v.abs()))), "seed {seed}: {err:e}");
    }
}

#[test]
fn answers_solve_the_dense_lcp_like_dense_lemke() {
    // Positive semidefinite M (rank ≤ p < n, no shift): many solutions, any one will do.
    for seed in 0..20 {
        let op = random(200, 60, 4, 0.0, 0, 100 + seed);
        let dense = op.to_dense();
        let sol = structured::solve(&op, &StructuredOptions::default(), None);
        let reference = lemke::solve(&dense, &LemkeOptions::default());
        assert_eq!(
            sol.status == Status::Solved,
            reference.ok(),
            "seed {seed}: {:?} vs {:?}",
            sol.status,
            reference.status
        );
        if sol.ok() {
            assert!(accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "seed {seed}");
            // The structured rule is the dense rule.
            assert!(structured::accepts(&op, &sol.z, &dense.w_of(&sol.z), 1e-9));
        }
    }
}

#[test]
fn the_structured_rule_rejects_what_the_dense_rule_rejects() {
    let op = random(50, 20, 3, 0.5, 10, 7);
    let dense = op.to_dense();
    let sol = structured::solve(&op, &StructuredOptions::default(), None);
    assert!(sol.ok());
    // Perturb one basic z: complementarity broken in its row.
    let mut z = sol.z.clone();
    let j = (0..z.len()).find(|&j| z[j] > 0.0).expect("a positive z");
    z[j] *= 1.0 + 1e-6;
    let w = dense.w_of(&z);
    assert!(!accepts(&dense, &z, &w, 1e-9));
    assert!(!structured::accepts(&op, &z, &w, 1e-9));
}

#[test]
fn a_warm_start_from_the_answer_takes_no_pivot() {
    let op = random(300, 90, 4, 0.05, 20, 3);
    let cold = structured::solve(&op, &StructuredOptions::default(), None);
    assert!(cold.ok() && cold.pivots > 0);
    let warm = structured::solve(&op, &StructuredOptions::default(), cold.basis.as_deref());
    assert!(warm.ok());
    assert_eq!(warm.pivots, 0);
    // A perturbed q: the warm start pivots from the old basis, and solves it.
    let q: Vec<f64> = op.q().iter().enumerate().map(|(i, v)| v + 0.05 * ((i % 7) as f64 - 3.0)).collect();
    let moved = rebuild(&op, q);
    let again = structured::solve(&moved, &StructuredOptions::default(), cold.basis.as_deref());
    assert!(again.ok(), "{:?}", again.status);
    let dense = moved.to_dense();
    assert!(accepts(&dense, &again.z, &dense.w_of(&again.z), 1e-9));
}

/// The same `M` with another `q`.
fn rebuild(op: &StructuredLcp, q: Vec<f64>) -> StructuredLcp {
    op.with_q(q).unwrap()
}

#[test]
fn invalid_input_is_an_error() {
    assert!(StructuredLcp::new(2, &[], &[], &[], vec![]).is_err());
    assert!(StructuredLcp::new(2, &[(0, 5, 1.0)], &[], &[], vec![1.0]).is_err());
    assert!(StructuredLcp::new(2, &[(0, 1, f64::NAN)], &[], &[], vec![1.0]).is_err());
    assert!(StructuredLcp::new(2, &[], &[], &[], vec![f64::INFINITY]).is_err());
}

#[test]
fn a_restriction_is_the_principal_submatrix() {
    let op = random(30, 12, 3, 0.1, 20, 7);
    let (dense, keep) = (op.to_dense(), [0usize, 3, 4, 9, 17, 29]);
    let sub = op.restrict(&keep).unwrap().to_dense();
    for (a, &i) in keep.iter().enumerate() {
        assert_eq!(sub.q()[a], dense.q()[i]);
        for (b, &j) in keep.iter().enumerate() {
            let (x, y) = (sub.m()[a * keep.len() + b], dense.m()[i * 30 + j]);
            assert!((x - y).abs() <= 1e-15 * (1.0 + y.abs()), "({i}, {j}): {x} vs {y}");
        }
    }
}

/// The restriction cut from the compressed factors is the operator built
/// from the kept entries of `G`, `H`, `K`, to the bit; keeps that are not
/// ascending, repeat or leave the range are errors.
#[test]
fn a_restriction_equals_the_operator_of_its_entries() {
    let op = random(40, 15, 3, 0.1, 20, 11);
    let keep = [1usize, 2, 5, 8, 13, 21, 34, 39];
    let mut new_of = vec![usize::MAX; 40];
    keep.iter().enumerate().for_each(|(i, &j)| new_of[j] = i);
    let (p, g, h, k) = structured::parts(&op);
    let g: Vec<_> = g.into_iter().filter(|e| new_of[e.0] != usize::MAX).map(|(r, c, v)| (new_of[r], c, v)).collect();
    let h: Vec<_> = h.into_iter().filter(|e| new_of[e.1] != usize::MAX).map(|(r, c, v)| (r, new_of[c], v)).collect();
    let k: Vec<_> = k
        .into_iter()
        .filter(|e| new_of[e.0] != usize::MAX && new_of[e.1] != usize::MAX)
        .map(|(r, c, v)| (new_of[r], new_of[c], v))
        .collect();
    let q: Vec<f64> = keep.iter().map(|&j| op.q()[j]).collect();
    let built = StructuredLcp::new(p, &g, &h, &k, q).unwrap();
    let cut = op.restrict(&keep).unwrap();
    assert_eq!(structured::parts(&cut), structured::parts(&built));
    assert_eq!(cut.q(), built.q());
    let (mut wc, mut wb) = (vec![0.0; keep.len()], vec![0.0; keep.len()]);
    let z: Vec<f64> = (0..keep.len()).map(|i| (i as f64).cos()).collect();
    cut.w_of(&z, &mut wc);
    built.w_of(&z, &mut wb);
    assert_eq!(wc, wb);
    assert_eq!(cut.to_dense().m(), built.to_dense().m());
    for bad in [&[3usize, 2][..], &[4, 4], &[0, 40], &[]] {
        assert!(op.restrict(bad).is_err(), "{bad:?}");
    }
}

/// A warm basis with a structurally dependent column (here `z_1`, whose
/// column of `M` is empty) is repaired (`z_1 → w_1`) rather than dropped for
/// a cold run: the repaired basis is the answer, at no pivot.
#[test]
fn a_singular_warm_basis_is_repaired() {
    let (g, h) = ([(0, 0, 1.0), (2, 0, 1.0)], [(0, 0, 1.0), (0, 2, 1.0)]);
    let op = StructuredLcp::new(1, &g, &h, &[(0, 0, 1.0), (2, 2, 1.0)], vec![-1.0, 1.0, -1.0]).unwrap();
    let sol = structured::solve(&op, &StructuredOptions::default(), Some(&[true, true, true]));
    assert!(sol.ok(), "{:?}", sol.status);
    assert_eq!(sol.pivots, 0);
    assert_eq!(sol.basis.as_deref(), Some(&[true, false, true][..]));
    assert!(accepts(&op.to_dense(), &sol.z, &op.to_dense().w_of(&sol.z), 1e-9));
}

/// Block principal pivoting from the all-`w` basis on positive definite
/// problems (P-matrices: Murty's safeguard makes it finite) ends at the one
/// solution enumeration finds, in a few factorizations.
#[test]
fn block_principal_pivoting_finds_the_unique_solution() {
    for seed in 0..40 {
        let op = random(10, 6, 3, 0.1, 4, seed);
        let dense = op.to_dense();
        let o = BppOptions { max_rounds: 200, ..Default::default() };
        let r = bpp::improve(&op, &[false; 10], &o, None).expect("a regular basis");
        assert_eq!(r.infeasible, 0, "seed {seed}: {r:?}");
        let z: Vec<f64> = r.z.iter().map(|v| v.max(0.0)).collect();
        assert!(accepts(&dense, &z, &dense.w_of(&z), 1e-9), "seed {seed}");
        let all = all_solutions(&dense, 1e-9);
        let err = z.iter().zip(&all[0]).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(err <= 1e-9 * (1.0 + all[0].iter().fold(0.0f64, |a, v| a.max(v.abs()))), "seed {seed}: {err:e}");
    }
}

/// On semidefinite problems (many solutions, singular bases) it never ends
/// worse than it started, and the solver with it on answers what the dense
/// rule accepts, from a basis a perturbed `q` made wrong.
#[test]
fn block_principal_pivoting_improves_a_wrong_basis() {
    for seed in 0..10 {
        let op = random(200, 60, 4, 0.0, 0, 200 + seed);
        let cold = structured::solve(&op, &StructuredOptions::default(), None);
        if !cold.ok() {
            continue;
        }
        let q: Vec<f64> = op.q().iter().enumerate().map(|(i, v)| v + 0.3 * ((i % 5) as f64 - 2.0)).collect();
        let moved = rebuild(&op, q);
        let basis = cold.basis.clone().unwrap();
        let r = bpp::improve(&moved, &basis, &BppOptions::default(), None).expect("a regular basis");
        assert!(r.infeasible <= r.infeasible_start, "seed {seed}: {r:?}");
        let o = StructuredOptions { bpp: Some(BppOptions::default()), ..Default::default() };
        let sol = structured::solve(&moved, &o, Some(&basis));
        let dense = moved.to_dense();
        let reference = lemke::solve(&dense, &LemkeOptions::default());
        assert_eq!(sol.ok(), reference.ok(), "seed {seed}: {:?} vs {:?}", sol.status, reference.status);
        if sol.ok() {
            assert!(accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "seed {seed}");
        }
    }
}

#[test]
fn cold_runs_kept_are_not_made_again() {
    let op = random(60, 30, 3, 0.1, 10, 7);
    let o = StructuredOptions::default();
    let mut cold = structured::ColdRuns::default();
    let first = structured::solve_reusing(&op, &o, None, &mut cold);
    assert!(first.ok() && first.pivots > 0, "{:?}", first.status);
    // The same LCP again: its cold run is taken from `cold`, for no pivots.
    let again = structured::solve_reusing(&op, &o, None, &mut cold);
    assert!(again.ok());
    assert_eq!((&again.z, again.pivots), (&first.z, 0));
    // Under a cap the kept run did not end below, it is made again.
    let capped = StructuredOptions { max_pivots: Some(first.pivots), ..o };
    assert!(structured::solve_reusing(&op, &capped, None, &mut cold).pivots > 0);
}
