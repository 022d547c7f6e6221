//! Generators: the contact LCP has exactly the DESIGN §1 structure and the
//! physics of its scene; the matrix generators have the class they promise;
//! everything is a pure function of its seed.

mod common;
use common::is_positive_definite;

use lcp::contact::ContactLayout;
use lcp::generate::{
    contact_lcp, contact_lcp_from_parts, infeasible_lcp, murty, murty_unit, p_matrix_lcp, spd_lcp, BoxOnPlane,
    ContactParts, MassInverse, PartsError, BOX_MINV_DIAG, CONTACT_H, GRAVITY,
};
use lcp::{lemke, Lcp, LemkeOptions, Pivoting, Status};
use proptest::prelude::*;

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Determinant by Gaussian elimination with partial pivoting.
fn det(mut a: Vec<f64>, n: usize) -> f64 {
    let mut d = 1.0;
    for c in 0..n {
        let p = (c..n).max_by(|&x, &y| a[x * n + c].abs().total_cmp(&a[y * n + c].abs())).unwrap();
        if a[p * n + c] == 0.0 {
            return 0.0;
        }
        if p != c {
            for j in 0..n {
                a.swap(p * n + j, c * n + j);
            }
            d = -d;
        }
        d *= a[c * n + c];
        for r in c + 1..n {
            let f = a[r * n + c] / a[c * n + c];
            for j in c..n {
                a[r * n + j] -= f * a[c * n + j];
            }
        }
    }
    d
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn contact_lcp_has_the_design_structure(nc in 1usize..=8, k in 1usize..=10, log_s in -8.0f64..0.5, seed in any::<u64>()) {
        let s = 10f64.powf(log_s);
        let lcp = contact_lcp(nc, k, s, seed);
        let layout = ContactLayout { nc, k };
        let n = layout.n();
        prop_assert_eq!(lcp.n(), n);
        prop_assert_eq!(n, nc * (k + 2));
        let mu = BoxOnPlane::random(nc, seed).mu;
        prop_assert!((0.1..=1.5).contains(&mu));
        let (f, d, l) = (layout.fn_range(), layout.fd_range(), layout.lambda_range());
        // A-block (fn, fd rows and columns) exactly symmetric.
        for i in f.start..d.end {
            for j in f.start..d.end {
                prop_assert_eq!(lcp.at(i, j), lcp.at(j, i));
            }
        }
        for i in 0..n {
            for j in l.clone() {
                let c = j - l.start;
                // Column λ: 0 in fn rows and λ rows, s·E in fd rows.
                let expected = if d.contains(&i) && (i - d.start) / k == c { s } else { 0.0 };
                prop_assert_eq!(lcp.at(i, j), expected, "M[{}, {}]", i, j);
            }
        }
        for i in l.clone() {
            let c = i - l.start;
            for j in 0..n {
                // Row λ: s·μ on its own fn, −s·Eᵀ on its own fd, 0 elsewhere.
                let expected = if j == c {
                    s * mu
                } else if d.contains(&j) && (j - d.start) / k == c {
                    -s
                } else {
                    0.0
                };
                prop_assert_eq!(lcp.at(i, j), expected, "M[{}, {}]", i, j);
            }
            prop_assert_eq!(lcp.q()[i], 0.0);
        }
    }

    /// A = J M_b⁻¹ Jᵀ is positive semidefinite: xᵀ A x = ‖M_b^{-½} Jᵀ x‖² ≥ 0.
    #[test]
    fn delassus_block_is_psd(nc in 1usize..=6, seed in any::<u64>(), x in prop::collection::vec(-1.0f64..1.0, 54)) {
        let k = 8;
        let lcp = contact_lcp(nc, k, 1.0, seed);
        let m = nc + nc * k;
        let quad: f64 = (0..m).map(|i| (0..m).map(|j| x[i] * lcp.at(i, j) * x[j]).sum::<f64>()).sum();
        prop_assert!(quad >= -1e-12);
        // Rank ≤ 6 (one rigid body): a 7×7 principal minor of A vanishes when m ≥ 7.
        if m >= 7 {
            let idx: Vec<usize> = (0..7).map(|t| t * (m - 1) / 6).collect();
            let sub: Vec<f64> = idx.iter().flat_map(|&i| idx.iter().map(move |&j| (i, j))).map(|(i, j)| lcp.at(i, j)).collect();
            prop_assert!(det(sub, 7).abs() < 1e-9);
        }
    }

    /// q = J v*, checked against the contact-point velocity v* + ω* × r.
    #[test]
    fn q_is_the_free_contact_velocity(nc in 1usize..=8, k in 1usize..=8, seed in any::<u64>()) {
        let scene = BoxOnPlane::random(nc, seed);
        let lcp = contact_lcp(nc, k, 1.0, seed);
        let layout = ContactLayout { nc, k };
        let v = [scene.vstar[0], scene.vstar[1], scene.vstar[2]];
        let w = [scene.vstar[3], scene.vstar[4], scene.vstar[5]];
        for (c, &r) in scene.arms.iter().enumerate() {
            let wxr = cross(w, r);
            let vp = [v[0] + wxr[0], v[1] + wxr[1], v[2] + wxr[2]];
            prop_assert!((lcp.q()[c] - dot3(scene.frame[2], vp)).abs() < 1e-12);
            for j in 0..k {
                prop_assert!((lcp.q()[layout.fd_index(c, j)] - dot3(scene.direction(j, k), vp)).abs() < 1e-12);
            }
        }
        // v* = v + h g for a unit mass; ω unchanged.
        for (a, g) in GRAVITY.iter().enumerate() {
            prop_assert_eq!(scene.vstar[a], scene.velocity[a] + CONTACT_H * g);
            prop_assert_eq!(scene.vstar[a + 3], scene.velocity[a + 3]);
        }
    }

    #[test]
    fn scene_geometry(nc in 1usize..=10, seed in any::<u64>()) {
        let scene = BoxOnPlane::random(nc, seed);
        prop_assert!((0.0..=60f64.to_radians()).contains(&scene.slope));
        let [t1, t2, normal] = scene.frame;
        // Orthonormal, right-handed, t1 downhill, normal tilted by the slope.
        for (a, b, e) in [(t1, t1, 1.0), (t2, t2, 1.0), (normal, normal, 1.0), (t1, t2, 0.0), (t1, normal, 0.0), (t2, normal, 0.0)] {
            prop_assert!((dot3(a, b) - e).abs() < 1e-15);
        }
        prop_assert!(dot3(cross(t1, t2), normal) > 0.999);
        prop_assert!(t1[2] <= 0.0);
        prop_assert!((normal[2] - scene.slope.cos()).abs() < 1e-15);
        prop_assert_eq!(scene.direction(0, 8), t1);
        // Contacts on the plane (the centre sits at ½ n above the origin), inside the unit square.
        prop_assert_eq!(scene.arms.len(), nc);
        for (c, r) in scene.arms.iter().enumerate() {
            prop_assert!((dot3(*r, normal) + 0.5).abs() < 1e-15);
            let tangential = (dot3(*r, *r) - 0.25).sqrt();
            prop_assert!(tangential <= 0.5f64.sqrt() + 1e-12);
            if c < 4 {
                prop_assert!((tangential - 0.5f64.sqrt()).abs() < 1e-12, "corner");
            }
        }
    }

    #[test]
    fn generators_are_deterministic_per_seed(seed in any::<u64>(), n in 1usize..=12) {
        prop_assert_eq!(contact_lcp(4, 8, 1e-3, seed), contact_lcp(4, 8, 1e-3, seed));
        prop_assert_ne!(contact_lcp(4, 8, 1e-3, seed), contact_lcp(4, 8, 1e-3, seed.wrapping_add(1)));
        prop_assert_eq!(p_matrix_lcp(n, seed), p_matrix_lcp(n, seed));
        prop_assert_ne!(p_matrix_lcp(n, seed), p_matrix_lcp(n, seed ^ 1));
        prop_assert_eq!(spd_lcp(n, seed), spd_lcp(n, seed));
        prop_assert_ne!(spd_lcp(n, seed), spd_lcp(n, seed ^ 1));
    }

    #[test]
    fn spd_lcp_is_symmetric_positive_definite(n in 1usize..=30, seed in any::<u64>()) {
        let lcp = spd_lcp(n, seed);
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(lcp.at(i, j), lcp.at(j, i));
            }
        }
        // M = A Aᵀ/n + 0.1 I: even M − 0.099 I is positive definite.
        let shifted: Vec<f64> = (0..n * n).map(|e| lcp.m()[e] - if e / n == e % n { 0.099 } else { 0.0 }).collect();
        prop_assert!(is_positive_definite(&shifted, n));
        prop_assert!(lcp.q().iter().all(|q| (-1.0..=1.0).contains(q)));
    }

    #[test]
    fn p_matrix_lcp_is_a_nonsymmetric_p_matrix(n in 1usize..=7, seed in any::<u64>()) {
        let lcp = p_matrix_lcp(n, seed);
        // Positive definite symmetric part.
        let sym: Vec<f64> = (0..n * n).map(|e| 0.5 * (lcp.m()[e] + lcp.at(e % n, e / n))).collect();
        prop_assert!(is_positive_definite(&sym, n));
        if n > 1 {
            prop_assert!((0..n * n).any(|e| lcp.m()[e] != lcp.at(e % n, e / n)));
        }
        // Every principal minor positive.
        for mask in 1u32..(1 << n) {
            let idx: Vec<usize> = (0..n).filter(|&i| mask & (1 << i) != 0).collect();
            let sub: Vec<f64> = idx.iter().flat_map(|&i| idx.iter().map(move |&j| (i, j))).map(|(i, j)| lcp.at(i, j)).collect();
            prop_assert!(det(sub, idx.len()) > 0.0, "minor {idx:?}");
        }
    }
}

#[test]
fn resting_corners_have_the_analytic_delassus_diagonal() {
    // Corner arm r: |r × n|² = |r|² − (r·n)² = ¾ − ¼ = ½, so A_nn = 1/m + 6·½ = 4.
    for seed in 0..20 {
        let lcp = contact_lcp(4, 8, 1.0, seed);
        for c in 0..4 {
            assert!((lcp.at(c, c) - 4.0).abs() < 1e-12, "seed {seed}: {}", lcp.at(c, c));
        }
    }
}

#[test]
fn opposite_friction_directions_give_opposite_rows() {
    // d_{j + k/2} = −d_j: rows (and q) of opposite directions are negatives.
    let (nc, k) = (3, 8);
    let lcp = contact_lcp(nc, k, 1.0, 5);
    let layout = ContactLayout { nc, k };
    let a_cols = nc + nc * k;
    for c in 0..nc {
        for j in 0..k / 2 {
            let (p, m) = (layout.fd_index(c, j), layout.fd_index(c, j + k / 2));
            assert!((lcp.q()[p] + lcp.q()[m]).abs() < 1e-12);
            for col in 0..a_cols {
                assert!((lcp.at(p, col) + lcp.at(m, col)).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn layout_ranges_partition_the_unknowns() {
    for (nc, k) in [(1, 8), (2, 8), (4, 8), (3, 1), (5, 6)] {
        let l = ContactLayout { nc, k };
        assert_eq!(l.fn_range().len(), nc);
        assert_eq!(l.fd_range().len(), nc * k);
        assert_eq!(l.lambda_range().len(), nc);
        assert_eq!(
            (l.fn_range().end, l.fd_range().end, l.lambda_range().end),
            (l.fd_range().start, l.lambda_range().start, l.n())
        );
        assert_eq!(l.fd_index(nc - 1, k - 1), l.fd_range().end - 1);
        assert_eq!(l.lambda_index(0), l.lambda_range().start);
    }
    // The seed's sizes: 2 contacts → 20, 4 contacts → 40.
    assert_eq!(contact_lcp(2, 8, 1.0, 0).n(), 20);
    assert_eq!(contact_lcp(4, 8, 1.0, 0).n(), 40);
}

#[test]
fn from_parts_dense_equals_diagonal_and_adds_b0_extra() {
    let scene = BoxOnPlane::random(2, 11);
    let (jn, jd) = scene.jacobians(4);
    let mu = [scene.mu, 0.3];
    let mut dense = vec![0.0; 36];
    for i in 0..6 {
        dense[i * 6 + i] = BOX_MINV_DIAG[i];
    }
    let parts = ContactParts {
        k: 4,
        jn: &jn,
        jd: &jd,
        minv: MassInverse::Diagonal(&BOX_MINV_DIAG),
        vstar: &scene.vstar,
        mu: &mu,
        b0_extra: None,
        scale: 0.5,
    };
    let a = contact_lcp_from_parts(&parts).unwrap();
    let b = contact_lcp_from_parts(&ContactParts { minv: MassInverse::Dense(&dense), ..parts }).unwrap();
    assert_eq!(a, b);
    // Per-contact μ lands on its own λ row.
    let layout = ContactLayout { nc: 2, k: 4 };
    assert_eq!(a.at(layout.lambda_index(1), 1), 0.5 * 0.3);
    // Stabilization term only shifts b0.
    let extra = [0.25, -1.0];
    let c = contact_lcp_from_parts(&ContactParts { b0_extra: Some(&extra), ..parts }).unwrap();
    assert_eq!(a.m(), c.m());
    for (i, (&qc, &qa)) in c.q().iter().zip(a.q()).enumerate() {
        let shift = extra.get(i).copied().unwrap_or(0.0);
        assert_eq!(qc, qa + shift);
    }
}

#[test]
fn from_parts_validates_its_input() {
    let scene = BoxOnPlane::random(1, 0);
    let (jn, jd) = scene.jacobians(8);
    let mu = [0.5];
    let ok = ContactParts {
        k: 8,
        jn: &jn,
        jd: &jd,
        minv: MassInverse::Diagonal(&BOX_MINV_DIAG),
        vstar: &scene.vstar,
        mu: &mu,
        b0_extra: None,
        scale: 1.0,
    };
    assert!(contact_lcp_from_parts(&ok).is_ok());
    assert!(matches!(contact_lcp_from_parts(&ContactParts { k: 4, ..ok }), Err(PartsError::Shape { what: "jd", .. })));
    assert!(matches!(
        contact_lcp_from_parts(&ContactParts { jn: &jn[..5], ..ok }),
        Err(PartsError::Shape { what: "jn", .. })
    ));
    assert!(matches!(
        contact_lcp_from_parts(&ContactParts { minv: MassInverse::Dense(&BOX_MINV_DIAG), ..ok }),
        Err(PartsError::Shape { .. })
    ));
    assert!(matches!(
        contact_lcp_from_parts(&ContactParts { b0_extra: Some(&[1.0, 2.0]), ..ok }),
        Err(PartsError::Shape { .. })
    ));
    assert!(matches!(contact_lcp_from_parts(&ContactParts { mu: &[], ..ok }), Err(PartsError::Empty)));
    assert!(matches!(contact_lcp_from_parts(&ContactParts { k: 0, jd: &[], ..ok }), Err(PartsError::Empty)));
    for s in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(contact_lcp_from_parts(&ContactParts { scale: s, ..ok }), Err(PartsError::Scale(_))));
    }
    assert!(matches!(
        contact_lcp_from_parts(&ContactParts { mu: &[-0.1], ..ok }),
        Err(PartsError::Mu { index: 0, .. })
    ));
    let nan_v = [f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0];
    assert!(matches!(contact_lcp_from_parts(&ContactParts { vstar: &nan_v, ..ok }), Err(PartsError::Lcp(_))));
    // s = 0 is allowed: the degenerate limit with a zero cone row.
    let z = contact_lcp_from_parts(&ContactParts { scale: 0.0, ..ok }).unwrap();
    assert!(z.row(z.n() - 1).iter().all(|&v| v == 0.0));
}

#[test]
fn murty_is_exponential_for_plain_lemke() {
    // Murty (1978): Lemke with covering vector 1 on the problem as given visits 2ⁿ bases.
    for pivoting in [Pivoting::Lexicographic, Pivoting::Classic] {
        for n in 1..=8 {
            let lcp = murty(n);
            let o = LemkeOptions { pivoting, equilibrate: false, max_pivots: Some(10_000), ..LemkeOptions::default() };
            let s = lemke::solve(&lcp, &o);
            assert_eq!(s.status, Status::Solved, "{pivoting:?} n = {n}");
            assert_eq!(s.iterations, 1 << n, "{pivoting:?} n = {n}");
        }
    }
}

#[test]
fn murty_structure() {
    for n in 1..=10 {
        for lcp in [murty(n), murty_unit(n)] {
            for i in 0..n {
                for j in 0..n {
                    let expected = if i == j {
                        1.0
                    } else if i > j {
                        2.0
                    } else {
                        0.0
                    };
                    assert_eq!(lcp.at(i, j), expected);
                }
            }
        }
        // Documented solutions, exactly: z = 2ⁿ e₁, w = (0, 2ⁿ⁻¹, …, 2).
        let mut z = vec![0.0; n];
        z[0] = 2f64.powi(n as i32);
        let w = murty(n).w_of(&z);
        let expected: Vec<f64> = (0..n).map(|i| if i == 0 { 0.0 } else { 2f64.powi((n - i) as i32) }).collect();
        assert_eq!(w, expected);
        z[0] = 1.0;
        let w = murty_unit(n).w_of(&z);
        assert!(w[0] == 0.0 && w[1..].iter().all(|&v| v == 1.0));
    }
}

#[test]
fn infeasible_lcp_is_infeasible() {
    let lcp: Lcp = infeasible_lcp();
    // w = −z − 1 < 0 for every z ≥ 0.
    assert_eq!((lcp.at(0, 0), lcp.q()[0]), (-1.0, -1.0));
}
