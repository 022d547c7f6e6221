//! The structured Lemke's polish (`lcp::structured::solve`): a run that ends
//! on a complementary basis whose vertex is infeasible by a hair — a basic
//! `w_i` a round-off's width below 0 in a row whose scale is that width, so
//! the acceptance rule rejects it — goes on pivoting from that basis with no
//! tolerance, to a vertex that is an answer, instead of starting over.
//!
//! The LCP here is a contact's three rows (normal `f`, friction `b`, cone
//! `g`) beside `m` rows that each need a pivot from the all-slack basis:
//!
//! ```text
//! w_f = f + 0.1          w_b = b + g − δ          w_g = ½ f − b          w_i = z_i − 10⁻³
//! ```
//!
//! The basis `{b} ∪ extras` has `b = δ`, `w_g = −δ`: friction just outside
//! an unloaded contact's cone (what a loose ratio test leaves on a heap's
//! LCP, where a tie within `1e-13` of the largest value was broken the wrong
//! way). Its answer is `g = δ`, `b = f = 0`.

use lcp::accept::accepts;
use lcp::structured::{self, Entry, StructuredLcp, StructuredOptions};
use lcp::Status;

/// The extra rows: a cold run pivots at least once on each.
const EXTRAS: usize = 40;

/// The LCP of the module docs with `δ = delta`.
fn near_cone(delta: f64) -> StructuredLcp {
    let n = 3 + EXTRAS;
    let mut k: Vec<Entry> = vec![(0, 0, 1.0), (1, 1, 1.0), (1, 2, 1.0), (2, 0, 0.5), (2, 1, -1.0)];
    k.extend((3..n).map(|i| (i, i, 1.0)));
    let mut q = vec![0.1, -delta, 0.0];
    q.extend(std::iter::repeat_n(-1e-3, EXTRAS));
    StructuredLcp::new(1, &[], &[], &k, q).unwrap()
}

/// The warm basis `{b} ∪ extras`.
fn hair_off_basis() -> Vec<bool> {
    (0..3 + EXTRAS).map(|j| j == 1 || j >= 3).collect()
}

/// The premise: the vertex of the warm basis is rejected by the rule (its
/// `w_g = −δ` is the whole scale of its row, above the round-off floor).
#[test]
fn the_hair_off_vertex_is_rejected() {
    let delta = 1e-13;
    let op = near_cone(delta);
    let mut z = vec![1e-3; 3 + EXTRAS];
    z[..3].copy_from_slice(&[0.0, delta, 0.0]);
    let mut w = vec![0.0; z.len()];
    op.w_of(&z, &mut w);
    assert!(w[2] < 0.0, "w_g = {:e}", w[2]);
    assert!(!structured::accepts(&op, &z, &w, 1e-9));
}

/// From the hair-off basis the solve ends on the answer, accepted by the
/// dense rule too, in a few pivots (a cold solve would need one per extra row).
#[test]
fn a_hair_off_warm_basis_is_polished_not_restarted() {
    for delta in [1e-13, 3e-13, 1e-12] {
        let op = near_cone(delta);
        let sol = structured::solve(&op, &StructuredOptions::default(), Some(&hair_off_basis()));
        assert_eq!(sol.status, Status::Solved, "δ {delta:e}");
        assert!(sol.ok(), "δ {delta:e}: {:?}", sol.residuals);
        let dense = op.to_dense();
        assert!(accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "δ {delta:e}");
        assert!(
            (sol.z[2] - delta).abs() <= 1e-9 * delta && sol.z[0] == 0.0 && sol.z[1].abs() <= 1e-9 * delta,
            "δ {delta:e}: {:?}",
            &sol.z[..3]
        );
        assert!(sol.pivots < EXTRAS / 4, "δ {delta:e}: {} pivots", sol.pivots);
    }
}
