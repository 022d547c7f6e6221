//! A jointed island's dense LCP solved first with friction unknowns only for
//! the contacts that carry load, the exact reduction of
//! [`super::loaded_friction`] on the dense `M = J P Jᵀ + K` (the body-space
//! stages do not take a jointed island: its `P` couples the bodies through
//! the joints).
//!
//! The sub-LCP (every `fn`; `fd`, `λ` of the active contacts: loaded in the
//! warm basis, or `q_fn < 0`, and a patch's torsion with its points) is solved by the island's solver, grown while
//! inactive contacts take load. Its basis, extended with `λ` and the most
//! opposed `fd` of each inactive contact whose friction rows come out
//! negative, is then the warm start of the same solver on the full LCP: it
//! solves that basis exactly and accepts it by its own rule (0 pivots when
//! the reduction held), or pivots on from it. Measured on the 20-link chain
//! collapsing onto the ground (`benchmarks/joints.py`): see docs/joints.md.

use super::loaded_friction::{kept, lift_and_grow};
use crate::pipeline::island::IslandSolver;
use lcp::contact::ContactLayout;
use lcp::{Lcp, Solution};

/// Rounds of growing the friction set before the full LCP is solved cold.
const ROUNDS: usize = 4;

/// The full LCP's answer from the extended basis of the loaded sub-LCP;
/// `None` when every contact is active (nothing to reduce) or a sub-LCP is
/// not solved (the caller then solves the full LCP as it would have).
pub(super) fn solve(
    lcp: &Lcp,
    lay: ContactLayout,
    solver: &mut IslandSolver<'_>,
    warm: Option<&[bool]>,
) -> Option<Solution> {
    let n = lcp.n();
    let warm = warm.filter(|b| b.len() == n);
    let mut active: Vec<bool> =
        (0..lay.nc).map(|c| lcp.q()[lay.fn_index(c)] < 0.0 || warm.is_some_and(|b| b[lay.fn_index(c)])).collect();
    let mut basis: Option<Vec<bool>> = warm.map(<[bool]>::to_vec);
    let mut pivots = 0;
    let cones = patch_cones(lcp, lay);
    for _ in 0..ROUNDS {
        for &(c, i) in &cones {
            active[c] |= active[i];
        }
        if active.iter().all(|&a| a) {
            return None;
        }
        let keep = kept(lay, &active);
        let sub = lcp.principal(&keep).ok()?;
        let sub_warm: Option<Vec<bool>> = basis.as_ref().map(|b| keep.iter().map(|&i| b[i]).collect());
        let sol = solver(&sub, sub_warm.as_deref());
        pivots += sol.pivots;
        if !sol.ok() {
            return None;
        }
        let (z, mut full, grew) = lift_and_grow(lay, &mut active, &keep, &sol, n);
        if grew {
            basis = Some(full);
            continue;
        }
        // An inactive contact sliding against a direction: its λ and that `fd`.
        for c in (0..lay.nc).filter(|&c| !active[c]) {
            let w_fd = lay.fd_of(c).map(|f| (f, lcp.q()[f] + lcp::problem::dot(lcp.row(f), &z)));
            if let Some((f, _)) = w_fd.filter(|&(_, w)| w < 0.0).min_by(|a, b| a.1.total_cmp(&b.1)) {
                full[f] = true;
                full[lay.lambda_index(c)] = true;
            }
        }
        let mut out = solver(lcp, Some(&full));
        out.pivots += pivots;
        return Some(out);
    }
    None
}

/// `(c, i)`: contact `c`'s cone row reads contact `i`'s normal impulse, `i ≠ c`
/// (a patch's torsional friction, `contact::torsion`): `c` is active with `i`
/// (its normal, pinned at 0, never takes load itself).
fn patch_cones(lcp: &Lcp, lay: ContactLayout) -> Vec<(usize, usize)> {
    (0..lay.nc)
        .flat_map(|c| (0..lay.nc).filter(move |&i| i != c).map(move |i| (c, i)))
        .filter(|&(c, i)| lcp.at(lay.lambda_index(c), lay.fn_index(i)) != 0.0)
        .collect()
}
