//! Stage `solve`: hand the LCP to the solver, capture it, map the answer back
//! to physical units and fill the step record. A failed solve never aborts
//! the step: its status and answer are recorded, and no impulse is applied.

use super::capture::CapturedLcp;
use crate::contact::{BodySpaceLcp, ContactLcp};
use crate::error::SimError;
use crate::world::World;
use lcp::support::{LcpOperator, SupportWorkspace};
use lcp::{LemkeOptions, Lcp, Pivoting, Residuals, Solution};

impl World {
    /// Stage `solve`. `solver = None` uses the world's `method`.
    pub fn solve(&mut self, solver: Option<&mut dyn FnMut(&Lcp) -> Solution>) -> Result<(), SimError> {
        let ws = &mut self.ws;
        let rec = &mut self.record;
        let nc = ws.contacts.len();
        let k = self.params.friction_dirs;
        // The step's header, whatever happens next.
        rec.step = self.steps;
        rec.time = self.time;
        rec.dt = self.params.dt;
        rec.friction_dirs = k;
        rec.scale = self.params.scale();
        rec.contacts.clear();
        rec.contacts.extend_from_slice(&ws.contacts);
        rec.lcp_size = ws.lcp.n();
        rec.zeroed = false;
        if nc == 0 {
            // Nothing to solve.
            rec.status = None;
            rec.iterations = 0;
            rec.residuals = Residuals::default();
            rec.solver_residuals = Residuals::default();
            rec.z.clear();
            rec.w.clear();
            rec.basis = None;
            ws.z_apply.clear();
            return Ok(());
        }
        let n = ws.lcp.n();
        let warm = rec.basis.as_deref().filter(|b| b.len() == n);
        // A coupled LCP (two or more dynamic bodies) first tries the previous
        // basis in body space: no dense M unless that fails (or a sink wants M).
        let fast = match (&solver, &self.params.method, warm) {
            (None, lcp::Method::Lemke(o), Some(basis)) if self.sink.is_none() && body_space_applies(&ws.lcp, o) => {
                try_previous_basis(&ws.lcp, basis, o.accept_tol * BASIS_CHECK_TOL, &mut ws.support)
            }
            _ => None,
        };
        let sol = match fast {
            Some(sol) => sol,
            None => {
                if !ws.lcp.has_matrix() {
                    ws.lcp.assemble_matrix();
                }
                // Lend the buffers to an Lcp, solve, and take them back.
                let lcp = ws.lcp.take_lcp().map_err(SimError::Lcp)?;
                let (sol, method) = match solver {
                    Some(f) => (f(&lcp), "custom"),
                    // Warm start from the previous step's basis when the LCP kept its size.
                    None => (lcp::solve_warm(&lcp, &self.params.method, warm), self.params.method.name()),
                };
                if let Some(sink) = self.sink.as_mut() {
                    sink.capture(&CapturedLcp {
                        step: self.steps,
                        time: self.time,
                        contacts: nc,
                        friction_dirs: k,
                        scale: rec.scale,
                        m: lcp.m(),
                        q: lcp.q(),
                        z: &sol.z,
                        w: &sol.w,
                        status: sol.status,
                        iterations: sol.iterations,
                        method,
                    });
                }
                ws.lcp.restore(lcp);
                sol
            }
        };
        rec.status = Some(sol.status);
        rec.iterations = sol.iterations;
        rec.solver_residuals = sol.residuals;
        rec.basis = sol.basis;
        // Physical z (λ = s·λ_scaled), or zeros if the solver's z is unusable.
        if sol.z.len() == n && sol.z.iter().all(|v| v.is_finite()) {
            ws.lcp.unscale_z(&sol.z, &mut rec.z);
        } else {
            rec.zeroed = true;
            rec.z.clear();
            rec.z.resize(n, 0.0);
        }
        // Residuals on the unscaled LCP, in physical units.
        if ws.lcp.has_matrix() {
            ws.lcp.unscaled_w(&rec.z, &mut rec.w);
        } else {
            rec.w.clear();
            rec.w.resize(n, 0.0);
            BodySpaceLcp::at_scale(&ws.lcp, 1.0).w_of(&rec.z, &mut rec.w);
        }
        rec.residuals = Residuals::of(&rec.z, &rec.w);
        // Impulses to apply: never negative, and none at all from a failed
        // solve (its last iterate can be anything; Moby's Lemke, the seed's,
        // returns z = 0 on failure too). The record keeps the solver's answer.
        ws.z_apply.clear();
        if sol.status == lcp::Status::Solved {
            ws.z_apply.extend(rec.z.iter().map(|v| v.max(0.0)));
        } else {
            rec.zeroed = true;
            ws.z_apply.resize(n, 0.0);
        }
        Ok(())
    }
}

/// The body-space check accepts a previous basis only if its residual is this
/// fraction of Lemke's acceptance bound: pivoting ends on answers refined to
/// round-off, and a resting stack must not creep at the bound's 1e-9 m/s
/// (at 1e-2 a 3-box stack keeps its velocities below 1e-9 m/s over 500 steps).
const BASIS_CHECK_TOL: f64 = 1e-2;

/// The body-space basis check serves LCPs that couple two or more dynamic
/// bodies, solved by the robust Lemke with warm starts. A single body's LCP
/// stays on the dense path, where it is fastest and bit-identical to earlier
/// releases (the seed corpus is made of such LCPs).
fn body_space_applies(lcp: &ContactLcp, o: &LemkeOptions) -> bool {
    o.pivoting == Pivoting::Lexicographic && o.warm_start && lcp.dynamic_body_count() >= 2
}

/// The previous step's basis solved on this step's LCP in body space, accepted
/// by the robust Lemke's rule on the LCP as scaled and in physical units.
fn try_previous_basis(lcp: &ContactLcp, basis: &[bool], accept_tol: f64, ws: &mut SupportWorkspace) -> Option<Solution> {
    let scaled = BodySpaceLcp::new(lcp);
    let physical = BodySpaceLcp::at_scale(lcp, 1.0);
    let to_physical = |z: &[f64], out: &mut Vec<f64>| lcp.unscale_z(z, out);
    lcp::support::solve_on_basis(&scaled, basis, accept_tol, Some((&physical, &to_physical)), ws).map(|a| a.solution)
}
