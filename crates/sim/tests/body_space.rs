//! The contact LCP in body space (`sim::contact::BodySpaceLcp`) against the
//! dense assembly, and the zero-pivot step it serves: a coupled LCP whose
//! previous basis still solves it is solved without forming `M`.

mod common;

use common::settled;
use sim::lcp::operator::LcpOperator;
use sim::scenes::{BoxPile, BoxStack};
use sim::{ConeScale, WorldParams};

/// A deterministic pseudo-random vector in [0, 1).
fn noise(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

#[test]
fn body_space_entries_and_products_equal_the_dense_lcp() {
    for scale in [ConeScale::Unscaled, ConeScale::Value(1e-3)] {
        let params = WorldParams { cone_scale: scale, ..Default::default() };
        let worlds =
            [BoxPile::default().build(params.clone()).unwrap().world, BoxStack::new(4).build(params).unwrap().world];
        for w in worlds {
            let w = settled(w, 30);
            let lcp = w.contact_lcp().to_lcp().unwrap();
            let op = sim::contact::BodySpaceLcp::new(w.contact_lcp());
            let n = lcp.n();
            assert_eq!(op.n(), n);
            let all: Vec<usize> = (0..n).collect();
            let mut block = vec![0.0; n * n];
            op.block(&all, &all, &mut block);
            let mmax = lcp.m().iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (i, (a, b)) in block.iter().zip(lcp.m()).enumerate() {
                assert!((a - b).abs() <= 1e-13 * mmax, "M[{}, {}]: body space {a:e}, dense {b:e}", i / n, i % n);
            }
            // A sub-block picks the same entries.
            let rows = [n - 1, 0, n / 2];
            let cols = [3, n - 2];
            let mut sub = [0.0; 6];
            op.block(&rows, &cols, &mut sub);
            for (r, &i) in rows.iter().enumerate() {
                for (c, &j) in cols.iter().enumerate() {
                    assert_eq!(sub[r * 2 + c], block[i * n + j]);
                }
            }
            // Rows (the acceptance rule's row scales) are the same rows.
            let mut row = vec![0.0; n];
            for i in 0..n {
                op.row(i, &mut row);
                for (j, (a, b)) in row.iter().zip(&lcp.m()[i * n..(i + 1) * n]).enumerate() {
                    assert!((a - b).abs() <= 1e-13 * mmax, "row {i}, column {j}: body space {a:e}, dense {b:e}");
                }
            }
            let z = noise(n, n as u64);
            let mut w_op = vec![0.0; n];
            op.w_of(&z, &mut w_op);
            let w_dense = lcp.w_of(&z);
            let wmax = w_dense.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (i, (a, b)) in w_op.iter().zip(&w_dense).enumerate() {
                assert!((a - b).abs() <= 1e-12 * wmax, "w[{i}]: body space {a:e}, dense {b:e}");
            }
            // Some rows of the product are those rows of it, bit for bit; the others are left.
            let picked: Vec<usize> = (0..n).filter(|i| i % 3 != 1).collect();
            let mut w_rows = vec![f64::NAN; n];
            op.w_rows(&z, &picked, &mut w_rows);
            for i in 0..n {
                let (a, b) = (w_rows[i], w_op[i]);
                assert!(
                    if i % 3 != 1 { a.to_bits() == b.to_bits() } else { a.is_nan() },
                    "w_rows[{i}]: {a:e}, w {b:e}"
                );
            }
            // Moving a few entries of z moves w by their columns.
            let moved = [(0, -0.25), (n / 2, 0.5), (n - 1, 2.0), (n / 3, -1.0)];
            let mut z2 = z.clone();
            moved.iter().for_each(|&(j, d)| z2[j] += d);
            let mut w_moved = w_op.clone();
            op.add_columns(&moved, &mut w_moved);
            let w2 = lcp.w_of(&z2);
            for (i, (a, b)) in w_moved.iter().zip(&w2).enumerate() {
                assert!((a - b).abs() <= 1e-12 * wmax, "w[{i}] after the moves: by columns {a:e}, dense {b:e}");
            }
        }
    }
}

#[test]
fn a_resting_stack_mostly_steps_without_pivoting_and_stays_exact() {
    // The stack settles in its first steps; afterwards the previous basis
    // (or a few exchanges on it) solves most steps with no pivot at all.
    let mut s = BoxStack::new(3).build(WorldParams::default()).unwrap();
    let top = *s.bodies.last().unwrap();
    let z0 = s.world.body(top).unwrap().position().z;
    let mut zero = 0;
    let steps = 600;
    for _ in 0..steps {
        let r = s.world.step().unwrap();
        assert!(r.ok(), "step {} not solved: {:?}", r.step, r.status);
        assert!(r.residuals.residual <= 1e-9 * 1.1, "residual {:e}", r.residuals.residual);
        zero += (r.pivots == 0) as usize;
    }
    assert!(zero * 10 >= steps * 8, "only {zero} of {steps} steps without a pivot");
    let drift = (s.world.body(top).unwrap().position().z - z0).abs();
    assert!(drift < 1e-9, "top box drifted {drift:e} m");
}

#[test]
fn the_recorded_physical_w_is_that_of_the_recorded_z_at_any_cone_scale() {
    // A body-space answer hands its checked physical z and w to the record
    // (not formed again): they must be the physical LCP's z and M₁z + q.
    for scale in [ConeScale::Unscaled, ConeScale::Value(1e-3)] {
        let params = WorldParams { cone_scale: scale, ..Default::default() };
        let mut s = BoxStack::new(3).build(params).unwrap();
        for _ in 0..200 {
            let r = s.world.step().unwrap().clone();
            assert!(r.ok(), "step {} not solved", r.step);
            let lcp = s.world.contact_lcp();
            let mut w = vec![0.0; lcp.n()];
            sim::contact::BodySpaceLcp::at_scale(lcp, 1.0).w_of(&r.z, &mut w);
            let wmax = w.iter().fold(1e-300f64, |a, v| a.max(v.abs()));
            for (i, (a, b)) in w.iter().zip(&r.w).enumerate() {
                assert!((a - b).abs() <= 1e-12 * wmax, "step {}, w[{i}]: {a:e} recorded {b:e}", r.step);
            }
        }
    }
}
