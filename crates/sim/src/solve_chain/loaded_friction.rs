//! A large island's contact LCP solved with friction unknowns only for the
//! contacts that carry load: an exact reduction, not an approximation.
//!
//! For a contact whose normal impulse is 0, the friction impulses `β = 0`
//! and `γ = max(0, max_j −(M z + q)_{fd_j} / K[fd_j, γ])` (computed with its
//! own `β`, `γ` at 0) satisfy its `k + 1` friction rows and their
//! complementarity exactly: `w_γ = μ·0 − Σβ = 0`, every `w_fd_j ≥ 0` and 0 at
//! the most opposed direction. Its `β`, `γ` enter no other row (`β = 0`;
//! `γ` only its own `fd` rows). So an answer of the principal sub-LCP
//! without those contacts' `fd` and `γ` unknowns extends to an answer of the
//! full LCP whenever their normal impulses come out 0. When some do not,
//! their friction joins and the sub-LCP is solved again from the previous
//! answer's basis. The extended answer is judged by the acceptance rule on
//! the full LCP, like any other; the step record reports the full LCP (its
//! `n`, the extended `z`, `w` and basis, the pivots of every round).
//!
//! A forming heap has many speculative contacts (within the detection margin,
//! not touching): each costs `k + 1` unknowns and, when its tangential
//! velocity opposes a friction direction, Lemke pivots on friction that
//! carries nothing.

use lcp::contact::ContactLayout;
use lcp::structured::{self, StructuredLcp, StructuredOptions};
use lcp::{Residuals, Solution, Status};

/// Rounds of growing the friction set before giving up (the caller then
/// solves the full LCP).
const ROUNDS: usize = 6;

/// Solves the contact LCP `op` (layout `lay`) starting with friction for the
/// contacts flagged in `active`, from the full-layout basis `warm`. Returns
/// the extended answer judged on `op` (pivots summed over the rounds), or
/// `Err(pivots)` when a sub-LCP was not solved.
pub(crate) fn solve(
    op: &StructuredLcp,
    lay: ContactLayout,
    o: &StructuredOptions,
    warm: Option<&[bool]>,
    mut active: Vec<bool>,
) -> Result<Solution, usize> {
    let n = op.n();
    let mut pivots = 0;
    let mut warm: Option<Vec<bool>> = warm.filter(|b| b.len() == n).map(<[bool]>::to_vec);
    for _ in 0..ROUNDS {
        let keep = kept(lay, &active);
        let sub = op.restrict(&keep).map_err(|_| pivots)?;
        let sub_warm: Option<Vec<bool>> = warm.as_ref().map(|b| keep.iter().map(|&i| b[i]).collect());
        // A pivot limit is one for all rounds.
        let left = StructuredOptions { max_pivots: o.max_pivots.map(|m| m.saturating_sub(pivots).max(1)), ..o.clone() };
        let sol = structured::solve(&sub, &left, sub_warm.as_deref());
        pivots += sol.pivots;
        if !sol.ok() {
            return Err(pivots);
        }
        let (z, basis, grew) = lift_and_grow(lay, &mut active, &keep, &sol, n);
        if grew {
            warm = Some(basis);
            continue;
        }
        return Ok(extend(op, lay, &active, z, basis, pivots, o.accept_tol));
    }
    Err(pivots)
}

/// The sub-LCP's unknowns: every `fn`, and `fd`, `λ` of the `active` contacts.
pub(crate) fn kept(lay: ContactLayout, active: &[bool]) -> Vec<usize> {
    lay.fn_range()
        .chain(lay.fd_range().filter(|&i| active[lay.contact_of(i)]))
        .chain(lay.lambda_range().filter(|&i| active[lay.contact_of(i)]))
        .collect()
}

/// The sub-LCP's answer `sol` on the unknowns `keep` lifted to the full
/// layout of `n` (its `z` and basis, zeros and nonbasic elsewhere), and
/// whether an inactive contact took load (its friction then joins `active`).
pub(crate) fn lift_and_grow(
    lay: ContactLayout,
    active: &mut [bool],
    keep: &[usize],
    sol: &Solution,
    n: usize,
) -> (Vec<f64>, Vec<bool>, bool) {
    let (mut z, mut basis) = (vec![0.0; n], vec![false; n]);
    for (s, &i) in keep.iter().enumerate() {
        z[i] = sol.z[s];
        basis[i] = sol.basis.as_ref().is_some_and(|b| b[s]);
    }
    let mut grew = false;
    for (c, a) in active.iter_mut().enumerate() {
        if !*a && z[lay.fn_index(c)] > 0.0 {
            (*a, grew) = (true, true);
        }
    }
    (z, basis, grew)
}

/// The full answer from the sub-LCP's `z` (zeros at the inactive contacts'
/// friction): each inactive contact's `γ` (see the module docs) and, in the
/// basis, `γ` with the `β` of its most opposed direction when `γ > 0`
/// (the pair that keeps a basis regular: the sliding contacts' friction set by `structured_lemke`).
fn extend(
    op: &StructuredLcp,
    lay: ContactLayout,
    active: &[bool],
    mut z: Vec<f64>,
    mut basis: Vec<bool>,
    pivots: usize,
    tol: f64,
) -> Solution {
    let n = op.n();
    let mut w = vec![0.0; n];
    op.w_of(&z, &mut w);
    for c in (0..lay.nc).filter(|&c| !active[c]) {
        let l = lay.lambda_index(c);
        let opposed = lay.fd_of(c).map(|f| (f, -w[f] / op.at(f, l))).max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((f, g)) = opposed.filter(|&(_, g)| g > 0.0) {
            z[l] = g;
            basis[l] = true;
            basis[f] = true;
        }
    }
    op.w_of(&z, &mut w);
    let accepted = structured::accepts(op, &z, &w, tol);
    let status = if accepted { Status::Solved } else { Status::Numerical };
    let residuals = Residuals::of(&z, &w);
    Solution { z, w, status, pivots, residuals, basis: Some(basis), accepted }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::contact::body_factors::structured_lcp;
    use crate::scenes::{BoxPile, CubeHeap};
    use crate::{World, WorldParams};

    /// `w` stepped `steps` times, with this step's contact LCP assembled.
    fn settled(mut w: World, steps: usize) -> World {
        for _ in 0..steps {
            w.step().unwrap();
        }
        w.forces_stage().unwrap();
        w.detect();
        w.assemble();
        w
    }

    /// A 3×3×2 block of cubes at rest and a 12-cube heap settling, each with its step's contact LCP assembled.
    pub(crate) fn block_and_heap() -> [World; 2] {
        let p = WorldParams::default();
        [
            settled(
                BoxPile { nx: 3, ny: 3, nz: 2, spacing: 1.0, ..Default::default() }.build(p.clone()).unwrap().world,
                20,
            ),
            settled(CubeHeap { walls: true, ..CubeHeap::new(12, 1) }.build(p).unwrap().world, 450),
        ]
    }

    /// Cold, friction first only where `q_fn < 0`: the extended answer solves
    /// the full (dense) LCP by the dense rule, with fewer unknowns pivoted on
    /// (side-by-side cubes and speculative contacts carry no load).
    #[test]
    fn the_extended_answer_solves_the_full_lcp() {
        let worlds = block_and_heap();
        for w in worlds {
            let lcp = w.contact_lcp();
            let lay = lcp.layout();
            let op = structured_lcp(lcp, lcp.scale()).unwrap();
            let active: Vec<bool> = (0..lay.nc).map(|c| lcp.q()[lay.fn_index(c)] < 0.0).collect();
            let unloaded = active.iter().filter(|&&a| !a).count();
            assert!(unloaded > 0 && unloaded < lay.nc, "{unloaded} of {} contacts without friction", lay.nc);
            let sol = solve(&op, lay, &StructuredOptions::default(), None, active).expect("sub-LCPs solved");
            assert!(sol.ok(), "n {}: {:?}", op.n(), sol.residuals);
            let dense = lcp.to_lcp().unwrap();
            assert!(lcp::accept::accepts(&dense, &sol.z, &dense.w_of(&sol.z), 1e-9), "n {}", op.n());
        }
    }
}
