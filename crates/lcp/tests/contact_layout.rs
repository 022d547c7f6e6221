//! `lcp::contact`: the ranges of `z = [fn; fd; λ]`, the cone scaling against
//! an explicit `D M D`, and the zero rule of the sign patterns on hand-made `z`.

use lcp::contact::{ContactLayout, Pattern, ZeroLevels};
use lcp::generate::spd_lcp;
use lcp::Lcp;

#[test]
fn ranges_tile_z_in_the_layout_order() {
    for (nc, k) in [(1, 1), (1, 8), (2, 4), (3, 8), (5, 16)] {
        let l = ContactLayout::new(nc, k);
        assert_eq!(l.n(), nc * (k + 2));
        assert_eq!(l.impulses(), nc + nc * k);
        assert_eq!(l.fn_range(), 0..nc);
        assert_eq!(l.fd_range(), nc..nc + nc * k);
        assert_eq!(l.lambda_range(), nc + nc * k..nc * (k + 2));
        // Every index belongs to exactly one contact, and the per-contact indices agree.
        let mut seen = vec![0; l.n()];
        for c in 0..nc {
            assert_eq!(l.fn_index(c), c);
            assert_eq!(l.contact_of(l.fn_index(c)), c);
            assert_eq!(l.fd_of(c).len(), k);
            for (j, i) in l.fd_of(c).enumerate() {
                assert_eq!(i, l.fd_index(c, j));
                assert_eq!(l.contact_of(i), c);
                seen[i] += 1;
            }
            assert_eq!(l.contact_of(l.lambda_index(c)), c);
            seen[l.fn_index(c)] += 1;
            seen[l.lambda_index(c)] += 1;
        }
        assert!(seen.iter().all(|&s| s == 1), "nc {nc} k {k}: {seen:?}");
    }
}

#[test]
fn cone_scaling_is_the_explicit_d_m_d_and_unscaling_undoes_it() {
    let (nc, k) = (3, 4);
    let l = ContactLayout::new(nc, k);
    let n = l.n();
    let lcp = spd_lcp(n, 5);
    for s in [1.0, 0.5, 1e-3, 1e-8, 0.0] {
        let d: Vec<f64> = (0..n).map(|i| if i >= nc * (k + 1) { s } else { 1.0 }).collect();
        assert_eq!(l.cone_diagonal(s), d);
        let explicit =
            Lcp::from_fn(n, |i, j| d[i] * lcp.at(i, j) * d[j], (0..n).map(|i| d[i] * lcp.q()[i]).collect()).unwrap();
        assert_eq!(l.scale_lcp(&lcp, s).unwrap(), explicit, "s = {s}");
        // A solution z' of the scaled problem is D⁻¹ z: unscaling multiplies λ by s only.
        let zs: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut z = zs.clone();
        l.unscale_z(&mut z, s);
        for i in 0..n {
            assert_eq!(z[i], d[i] * zs[i], "s = {s}, i = {i}");
        }
    }
    assert!(l.scale_lcp(&spd_lcp(n + 1, 5), 0.5).is_err());
}

/// `z` of one contact for nc = 2, k = 2: `[fn0, fn1, fd00, fd01, fd10, fd11, λ0, λ1]`.
fn z2(fn0: f64, fd0: [f64; 2], l0: f64) -> Vec<f64> {
    vec![fn0, 1.0, fd0[0], fd0[1], 0.0, 0.0, l0, 0.0]
}

#[test]
fn pattern_is_strictly_above_the_threshold_with_the_friction_summed() {
    let l = ContactLayout::new(2, 2);
    let exact = ZeroLevels::absolute(0.0);
    assert_eq!(l.pattern(&z2(0.0, [0.0, 0.0], 0.0), 0, exact).as_str(), "000");
    assert_eq!(l.pattern(&z2(1.0, [0.0, 0.5], 0.0), 0, exact).as_str(), "++0");
    assert_eq!(l.pattern(&z2(1.0, [0.5, 0.5], 2.0), 0, exact).as_str(), "+++");
    assert_eq!(l.pattern(&z2(0.0, [0.0, 0.0], 2.0), 0, exact).as_str(), "00+");
    // The other contact is read from its own slots.
    assert_eq!(l.pattern(&z2(0.0, [0.0, 0.0], 2.0), 1, exact).as_str(), "+00");
    // A value equal to the threshold is zero; a negative round-off sum is zero.
    let zero = ZeroLevels { impulse: 1e-9, velocity: 1e-6 };
    assert_eq!(l.pattern(&z2(1e-9, [2e-9, -3e-9], 1e-6), 0, zero).as_str(), "000");
    assert_eq!(l.pattern(&z2(2e-9, [1e-9, 1e-9], 2e-6), 0, zero).as_str(), "+++");
    // Impulses and λ have their own thresholds.
    assert_eq!(l.pattern(&z2(1e-7, [0.0, 0.0], 1e-7), 0, zero).as_str(), "+00");
    // The impossible ones of the source note's table.
    let impossible: Vec<&str> = (0..8u8)
        .map(|c| Pattern { normal: c & 4 != 0, friction: c & 2 != 0, sliding: c & 1 != 0 })
        .filter(|p| p.impossible())
        .map(|p| p.as_str())
        .collect();
    assert_eq!(impossible, ["0+0", "0++", "+0+"]);
    for (code, name) in Pattern::ALL.iter().enumerate() {
        let p = Pattern { normal: code & 4 != 0, friction: code & 2 != 0, sliding: code & 1 != 0 };
        assert_eq!((p.code() as usize, p.as_str()), (code, *name));
    }
}

#[test]
fn relative_levels_follow_the_lcps_scales() {
    let l = ContactLayout::new(1, 2);
    let n = l.n();
    // A = [[2, 0, 0], [0, 4, 0], [0, 0, 8]] and a cone row; q asks for 3 m/s.
    let mut m = vec![0.0; n * n];
    for (i, a) in [2.0, 4.0, 8.0].into_iter().enumerate() {
        m[i * n + i] = a;
    }
    m[3 * n] = 100.0; // cone block entries are not part of A
    let q = [-3.0, 1.0, 0.5, 0.0];
    // Impulses below ‖q‖/max|A| = 3/8: that one is the impulse scale.
    let z = [0.25, 0.0, 0.125, 7.0];
    let r = ZeroLevels::relative(&l, &m, &q, &z, 1e-9);
    assert_eq!(r, ZeroLevels { impulse: 1e-9 * (3.0 / 8.0), velocity: 1e-9 * 3.0 });
    // A larger impulse in z takes over; λ never counts.
    let z = [5.0, 0.0, 0.125, 70.0];
    assert_eq!(ZeroLevels::relative(&l, &m, &q, &z, 1e-9).impulse, 1e-9 * 5.0);
    // All zero: the floor keeps exact zeros zero and anything positive positive.
    let r = ZeroLevels::relative(&l, &vec![0.0; n * n], &[0.0; 4], &[0.0; 4], 1e-9);
    assert_eq!(r, ZeroLevels { impulse: 1e-9 * 1e-300, velocity: 1e-9 * 1e-300 });
    assert_eq!(l.pattern(&[1e-200, 0.0, 0.0, 0.0], 0, r).as_str(), "+00");
}
