//! Stage `solve`: hand the LCP to the solver, capture it, map the answer back
//! to physical units and fill the step record. A failed solve never aborts
//! the step: its status and answer are recorded, and no impulse is applied.

use super::capture::CapturedLcp;
use crate::error::SimError;
use crate::world::World;
use lcp::{Lcp, Residuals, Solution};

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
        // Lend the buffers to an Lcp, solve, and take them back.
        let lcp = ws.lcp.take_lcp().map_err(SimError::Lcp)?;
        let (sol, method) = match solver {
            Some(f) => (f(&lcp), "custom"),
            // Warm start from the previous step's basis when the LCP kept its size.
            None => {
                let warm = rec.basis.as_deref().filter(|b| b.len() == n);
                (lcp::solve_in(&lcp, &self.params.method, warm, &mut ws.solver), self.params.method.name())
            }
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
        ws.lcp.unscaled_w(&rec.z, &mut rec.w);
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
