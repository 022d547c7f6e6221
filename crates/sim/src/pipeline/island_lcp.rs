//! One island's LCP from assembly to the impulses it applies: the unit of
//! work of a solver thread. Its buffers are kept from step to step (one per
//! island slot), so a warm step allocates only what the solver allocates.

use crate::contact::assembly::{AssemblyParams, BodyDynamics};
use crate::contact::ContactLcp;
use crate::geometry::Contact;
use lcp::contact::ContactLayout;
use lcp::{Lcp, LcpError, Residuals, Solution, Status};

/// A solver for one LCP, started from a basis when one is given.
pub type IslandSolver<'a> = dyn FnMut(&Lcp, Option<&[bool]>) -> Solution + 'a;

/// An island's contacts, LCP and answer.
#[derive(Clone, Debug, Default)]
pub struct IslandLcp {
    /// The island's contacts, in global contact order.
    pub contacts: Vec<Contact>,
    pub lcp: ContactLcp,
    /// The basis to start from: the previous step's answer for the same island, if any.
    pub warm: Option<Vec<bool>>,
    /// Whether this step's solve started from such a basis.
    pub warmed: bool,
    /// The solver's answer (scaled LCP), `None` before the solve or when the LCP was invalid.
    pub sol: Option<Solution>,
    /// Set when the LCP could not be handed to the solver (non-finite data).
    pub error: Option<LcpError>,
    /// Physical `z` (λ = s·λ_scaled) and `w` of the unscaled LCP, island order.
    pub z: Vec<f64>,
    pub w: Vec<f64>,
    /// Residuals of that `z` on the unscaled LCP.
    pub residuals: Residuals,
    /// No impulse applied: the solve failed or its `z` was unusable.
    pub zeroed: bool,
    /// Impulses applied (physical `z` clamped at 0; zeros after a failure).
    pub z_apply: Vec<f64>,
}

impl IslandLcp {
    /// Assembles the island's LCP.
    pub fn assemble(&mut self, dynamics: &BodyDynamics<'_>, p: &AssemblyParams) {
        self.lcp.assemble(&self.contacts, dynamics, p);
    }

    /// Solves the assembled LCP, maps the answer to physical units and
    /// decides the impulses. A failed solve applies none (its last iterate
    /// can be anything; Moby's Lemke, the seed's, returns z = 0 on failure
    /// too); the answer is kept for the record.
    pub fn solve(&mut self, solver: &mut IslandSolver<'_>) {
        let n = self.lcp.n();
        self.sol = None;
        self.error = None;
        // Lend the buffers to an Lcp, solve, and take them back.
        let lcp = match self.lcp.take_lcp() {
            Ok(lcp) => lcp,
            Err(e) => {
                self.error = Some(e);
                return;
            }
        };
        let warm = self.warm.take().filter(|b| b.len() == n);
        self.warmed = warm.is_some();
        let sol = solver(&lcp, warm.as_deref());
        self.lcp.restore(lcp);
        // Physical z, or zeros if the solver's z is unusable.
        self.zeroed = false;
        if sol.z.len() == n && sol.z.iter().all(|v| v.is_finite()) {
            self.lcp.unscale_z(&sol.z, &mut self.z);
        } else {
            self.zeroed = true;
            self.z.clear();
            self.z.resize(n, 0.0);
        }
        // Residuals on the unscaled LCP, in physical units.
        self.lcp.unscaled_w(&self.z, &mut self.w);
        self.residuals = Residuals::of(&self.z, &self.w);
        self.z_apply.clear();
        if sol.status == Status::Solved {
            self.z_apply.extend(self.z.iter().map(|v| v.max(0.0)));
        } else {
            self.zeroed = true;
            self.z_apply.resize(n, 0.0);
        }
        self.sol = Some(sol);
    }
}

/// Copies an island's `[fn; fd; λ]` (`m` contacts, layout of its own LCP)
/// into the step's layout (`nc` contacts), contact `c` of the island being
/// the step's contact `ids[c]`.
pub fn scatter<T: Copy>(ids: &[usize], nc: usize, k: usize, src: &[T], dst: &mut [T]) {
    let (island, step) = (ContactLayout::new(ids.len(), k), ContactLayout::new(nc, k));
    for (c, &g) in ids.iter().enumerate() {
        dst[step.fn_index(g)] = src[island.fn_index(c)];
        dst[step.fd_of(g)].copy_from_slice(&src[island.fd_of(c)]);
        dst[step.lambda_index(g)] = src[island.lambda_index(c)];
    }
}
