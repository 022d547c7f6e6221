//! Torsional friction of a contact patch: friction about the patch's normal,
//! bounded by `μ_t` times the patch's whole normal load (MuJoCo's condim 4
//! `friction[1]`, PhysX's torsional patch friction).
//!
//! Why: a face pressed on a face is statically indeterminate — any split of
//! its normal load over the manifold's points solves the LCP, and Lemke may
//! put it all on one corner. A point contact has no moment about its normal,
//! so the body then turns about that corner (a gripped cube pivoting between
//! flat pads, docs/joints.md). A bound on the patch's total load holds
//! whichever split the LCP's vertex has.
//!
//! How, in the Stewart–Trinkle structure: each patch — two or more points of
//! one pair with the same normal, `μ_t > 0` (the larger of the two bodies') —
//! gets one more contact after the step's point contacts:
//!
//! ```text
//! friction rows  t1 = μ_t·[0, n] on A, −μ_t·[0, n] on B (the relative spin about n), t2 = 0:
//!                fd_j is a force at radius μ_t, the torque μ_t Σ_j cos(2πj/k) fd_j
//! normal         a virtual unit row pinned at 0 (M_nn = 1, q_n = 0)
//! cone row       w_λ = Σ_{i ∈ patch} fn_i − Σ_j fd_j ≥ 0 ⊥ λ ≥ 0      (M_{λ, fn_i} = s)
//! ```
//!
//! so `|torque| ≤ μ_t Σ fn_i`, reached against a sliding spin (`λ` is the
//! spin's speed times `μ_t`). `M` stays copositive as Stewart–Trinkle's is —
//! `zᵀMz = fᵀAf + s Σ_p λ_p Σ_{i∈p} fn_i ≥ 0`: the cone rows' diagonal `μ`
//! becomes a nonnegative block, and the argument that Lemke processes the LCP
//! does not use its being diagonal. The patch's torsion has its own cone,
//! apart from its points' (a box, where MuJoCo's elliptic cone couples them).
//! An island holding a patch contact is solved on its dense `M` (the
//! body-space stages assume one cone per normal); a single point has none.

use super::assembly::{dot6, row, ContactLcp, Row6};
use crate::dynamics::Body;
use crate::geometry::Contact;
use crate::math::{Mat3, Vec3};
use std::ops::Range;

/// Normals of a patch's points agree to this (`1 − n_a·n_b`).
const SAME_NORMAL: f64 = 1e-9;

/// One patch's torsional friction in this step's LCP.
#[derive(Clone, Debug, PartialEq)]
pub struct TorsionPatch {
    /// The patch's points among the step's contacts (consecutive).
    pub points: Range<usize>,
    /// Dynamic body per side.
    pub body: [Option<usize>; 2],
    /// The friction row per side, `±μ_t·[0, n]`.
    pub jac: [Row6; 2],
}

/// The step's patches; patch `p`'s contact is `first + p`.
#[derive(Clone, Debug, Default)]
pub struct TorsionPatches {
    pub first: usize,
    pub patches: Vec<TorsionPatch>,
}

impl TorsionPatches {
    /// The patch whose contact is the step's contact `g`, if it is one.
    pub fn of_contact(&self, g: usize) -> Option<&TorsionPatch> {
        g.checked_sub(self.first).and_then(|p| self.patches.get(p))
    }

    /// Whether an island (its contacts' indices in the step) holds a patch's contact.
    pub fn in_island(&self, island: &[usize]) -> bool {
        !self.patches.is_empty() && island.iter().any(|&g| self.of_contact(g).is_some())
    }

    /// Appends one contact per patch of `contacts` (the step's point
    /// contacts) whose pair has torsional friction, and records the patches.
    pub fn push_patches(&mut self, contacts: &mut Vec<Contact>, bodies: &[Body]) {
        self.patches.clear();
        self.first = contacts.len();
        let mut start = 0;
        while start < self.first {
            let c = contacts[start];
            let same = |d: &Contact| {
                d.body_a == c.body_a && d.body_b == c.body_b && 1.0 - d.normal.dot(c.normal) <= SAME_NORMAL
            };
            let end = start + 1 + contacts[start + 1..self.first].iter().take_while(|d| same(d)).count();
            let mu_t = bodies[c.body_a].mu_torsion.max(bodies[c.body_b].mu_torsion);
            if end - start >= 2 && mu_t > 0.0 {
                let ang = c.normal * mu_t;
                let side = |b: usize| (!bodies[b].is_static).then_some(b);
                self.patches.push(TorsionPatch {
                    points: start..end,
                    body: [side(c.body_a), side(c.body_b)],
                    jac: [row(Vec3::ZERO, ang), row(Vec3::ZERO, -ang)],
                });
                let centre = contacts[start..end].iter().fold(Vec3::ZERO, |s, d| s + d.point) / (end - start) as f64;
                contacts.push(Contact { point: centre, gap: 0.0, mu: 0.0, ..c });
            }
            start = end;
        }
    }

    /// An island's patch contacts made so in its assembled `lcp` (rows, `q`,
    /// the patch cone): `island` lists its contacts' indices in the step,
    /// ascending. Returns whether it holds one. Call before its dense `M` is formed.
    pub fn set_island_rows(
        &self,
        island: &[usize],
        lcp: &mut ContactLcp,
        inv_inertia: &[Mat3],
        w_free: &[Vec3],
    ) -> bool {
        let mut any = false;
        for (c, &g) in island.iter().enumerate() {
            let Some(p) = self.of_contact(g) else { continue };
            any = true;
            // (Rows with no linear part: only the inverse inertia acts.)
            let minv = [0, 1].map(|s| p.body[s].map_or([0.0; 6], |b| row(Vec3::ZERO, inv_inertia[b] * ang(&p.jac[s]))));
            let jw: f64 = (0..2).filter_map(|s| p.body[s].map(|b| dot6(&p.jac[s], &row(Vec3::ZERO, w_free[b])))).sum();
            let z = [0.0; 6];
            lcp.set_generalized_rows(c, p.body, p.jac.map(|r| [z, r, z]), minv.map(|r| [z, r, z]), [0.0, jw, 0.0]);
            let local = |g: usize| island.partition_point(|&x| x < g);
            lcp.set_patch_cone(c, local(p.points.start)..local(p.points.end));
        }
        any
    }
}

fn ang(r: &Row6) -> Vec3 {
    Vec3::new(r[3], r[4], r[5])
}
