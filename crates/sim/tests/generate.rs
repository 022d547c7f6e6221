//! `sim::generate::contact_lcp`: the contact LCP of one cube on a slope has
//! exactly the contact-LCP structure (`lcp::contact`) and the physics of its scene, and is a
//! pure function of its seed.

#[path = "../../lcp/tests/common/mod.rs"]
mod lcp_common;
use lcp_common::det;

use lcp::contact::ContactLayout;
use proptest::prelude::*;
use sim::generate::{contact_lcp, BoxOnPlane, CONTACT_H, GRAVITY};
use sim::math::Vec3;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn contact_lcp_has_the_formulation_structure(nc in 1usize..=8, k in 1usize..=10, log_s in -8.0f64..0.5, seed in any::<u64>()) {
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
        let v = Vec3::new(scene.vstar[0], scene.vstar[1], scene.vstar[2]);
        let w = Vec3::new(scene.vstar[3], scene.vstar[4], scene.vstar[5]);
        for (c, &r) in scene.arms.iter().enumerate() {
            let vp = v + w.cross(r);
            prop_assert!((lcp.q()[c] - scene.frame[2].dot(vp)).abs() < 1e-12);
            for j in 0..k {
                prop_assert!((lcp.q()[layout.fd_index(c, j)] - scene.direction(j, k).dot(vp)).abs() < 1e-12);
            }
        }
        // v* = v + h g for a unit mass; ω unchanged.
        for (a, g) in GRAVITY.to_array().iter().enumerate() {
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
            prop_assert!((a.dot(b) - e).abs() < 1e-15);
        }
        prop_assert!(t1.cross(t2).dot(normal) > 0.999);
        prop_assert!(t1.z <= 0.0);
        prop_assert!((normal.z - scene.slope.cos()).abs() < 1e-15);
        prop_assert_eq!(scene.direction(0, 8), t1);
        // Contacts on the bottom face (½ n below the centre), inside the unit square.
        prop_assert_eq!(scene.arms.len(), nc);
        for (c, r) in scene.arms.iter().enumerate() {
            prop_assert!((r.dot(normal) + 0.5).abs() < 1e-15);
            let tangential = (r.dot(*r) - 0.25).sqrt();
            prop_assert!(tangential <= 0.5f64.sqrt() + 1e-12);
            if c < 4 {
                prop_assert!((tangential - 0.5f64.sqrt()).abs() < 1e-12, "corner");
            }
        }
    }

    #[test]
    fn contact_lcp_is_deterministic_per_seed(seed in any::<u64>()) {
        prop_assert_eq!(contact_lcp(4, 8, 1e-3, seed), contact_lcp(4, 8, 1e-3, seed));
        prop_assert_ne!(contact_lcp(4, 8, 1e-3, seed), contact_lcp(4, 8, 1e-3, seed.wrapping_add(1)));
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
fn source_note_sizes() {
    // The source note's sizes: 2 contacts → 20, 4 contacts → 40.
    assert_eq!(contact_lcp(2, 8, 1.0, 0).n(), 20);
    assert_eq!(contact_lcp(4, 8, 1.0, 0).n(), 40);
}
