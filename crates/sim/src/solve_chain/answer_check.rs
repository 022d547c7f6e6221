//! An island's answer judged once more in body space
//! ([`crate::contact::body_rule`]: each contact row on the scale of the
//! velocities it relates), and re-solved in double-double when it fails.
//!
//! An `f64` Lemke answer can pass the LCP's acceptance rule yet be wrong in
//! the velocities of a heavy body resting on a light one: at 1e8 kg on 1 kg,
//! `Σ fn` 1.6 % off and the heavy box pushed up at mm/s. Such an
//! answer is not applied as it is: its basis is solved in body space (with
//! exchanges, as the previous step's basis is), then
//! [`lcp::lemke::solve_dd`] re-solves it in double-double and runs Lemke in
//! double-double (on both scalings), and the first answer that passes both
//! rules replaces it. (The body-space rung: a 1e7 kg box sliding on a 1 kg
//! one, 600 steps, largest `η_body` 3.9e-8 → 3.5e-10.) When
//! none does, the answer stays as it was (it passes the LCP's rule, and a
//! failed step would apply less than it) and its error stays in the record
//! ([`crate::pipeline::IslandRecord::body_eta`]). A failed solve of such an island
//! (other than at the pivot limit, the caller's) gets the same rungs: their
//! other scaling can solve what the ladder's double-double rung did not (one
//! step of a 1e7 kg box sliding on a 1 kg one). Only such islands: elsewhere
//! the ladder's own double-double rung has had its try, and the extra runs
//! (up to ~0.1 s each) would only add time to a failed step.
//!
//! The check runs for the robust Lemke with warm starts (the world's
//! default method; not a caller's solver), at its `accept_tol`, on islands
//! where a contact joins bodies of very different mobility
//! ([`crate::contact::BodyCheck::applies`]) and up to [`lcp::lemke::DD_MAX_N`] unknowns.

use super::previous_basis::solve_in_body_space;
use crate::pipeline::island::IslandLcp;
use lcp::{LemkeOptions, Method, Pivoting, Solution, Status};

/// The options the check re-solves with when `method` gets it.
pub fn body_check_applies(method: &Method) -> Option<LemkeOptions> {
    match method {
        Method::Lemke(o @ LemkeOptions { pivoting: Pivoting::Lexicographic, warm_start: true, fallback: true, .. }) => {
            Some(o.clone())
        }
        _ => None,
    }
}

impl IslandLcp {
    /// Judges a solved answer in body space and sets `body_eta` (left at 0
    /// for a failed one); re-solves in double-double an answer that fails, or
    /// a failed solve (from its basis, then from `warm`, the basis the solve
    /// started from), replacing `sol`, `z`, `w` and `residuals` by an answer
    /// that passes. Only where `mixed`: [`crate::contact::BodyCheck::applies`] to the island
    /// (computed once per solve by `IslandLcp::solve`).
    pub(super) fn check_in_body_space(
        &mut self,
        sol: &mut Solution,
        o: &LemkeOptions,
        warm: Option<&[bool]>,
        mixed: bool,
    ) {
        let tol = o.accept_tol;
        match sol.status {
            Status::MaxPivots => return,
            _ if !mixed => return,
            Status::Solved => {
                self.body_eta = self.check.eta(&self.lcp, &self.z, &self.w);
                if self.body_eta <= tol {
                    return;
                }
            }
            _ => {}
        }
        if self.lcp.n() > lcp::lemke::DD_MAX_N {
            return;
        }
        // First the answer's own basis solved in body space, as the previous
        // basis is ([`solve_in_body_space`]): the dense `M` of a heavy body on a
        // light one loses to cancellation digits that the body-space products
        // keep. (With every exchange round: such an answer is rare, and wrong.)
        if let Some(basis) = sol.basis.clone() {
            self.basis_ws.forget_failures();
            if let Some((cand, (z, w))) = solve_in_body_space(&self.lcp, &basis, tol, true, &mut self.basis_ws) {
                let eta = self.check.eta(&self.lcp, &z, &w);
                if eta <= tol {
                    self.adopt(sol, cand, z, w, eta);
                    return;
                }
            }
        }
        if !self.lcp.has_matrix() {
            self.lcp.assemble_matrix();
        }
        let Ok(scaled) = self.lcp.to_lcp() else { return };
        let (mut z, mut w, mut eta) = (Vec::new(), Vec::new(), f64::INFINITY);
        let bases: Vec<&[bool]> = sol.basis.as_deref().into_iter().chain(warm).collect();
        let found = lcp::lemke::solve_dd(&scaled, o, &bases, |cand| {
            self.lcp.unscale_z(&cand.z, &mut z);
            self.lcp.unscaled_w(&z, &mut w);
            eta = self.check.eta(&self.lcp, &z, &w);
            // (A physical z or w that overflows is no answer, as in `IslandLcp::solve`.)
            eta <= tol && lcp::Residuals::of(&z, &w).residual.is_finite()
        });
        if let Some(better) = found {
            self.adopt(sol, better, z, w, eta);
        }
    }

    /// Replaces the answer by `better` (physical `z`, `w`, body-space error
    /// `eta`), its pivots added to those already spent.
    fn adopt(&mut self, sol: &mut Solution, better: Solution, z: Vec<f64>, w: Vec<f64>, eta: f64) {
        self.body_eta = eta;
        self.residuals = lcp::Residuals::of(&z, &w);
        self.zeroed = false;
        self.z = z;
        self.w = w;
        *sol = Solution { pivots: sol.pivots + better.pivots, ..better };
    }
}
