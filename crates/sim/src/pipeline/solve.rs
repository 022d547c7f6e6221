//! Stage `solve`: every island's LCP goes to the solver (on several threads
//! when it pays, `WorldParams::threads`), is captured, mapped back to
//! physical units and written into the step record in the global contact
//! order. A failed solve never aborts the step: the island's status and
//! answer are recorded, it applies no impulse, and the other islands go on.
//!
//! The step's summary of its islands: `status` is `Solved` iff every island
//! was solved, else the status of the first island (in island order) that
//! was not; `pivots` is the total over the islands; `residuals` are those
//! of the whole physical `z` (so the largest natural residual of any island);
//! `solver_residuals` the worst of each measure over the islands; `zeroed` is
//! set when any island applied no impulse; `basis` is the islands' bases in
//! the global layout when every island reported one.

use super::capture::CapturedLcp;
use super::island::{in_step_order, scatter};
use super::record::IslandRecord;
use crate::error::SimError;
use crate::parallel;
use crate::solve_chain::basis_check_applies;
use crate::world::World;
use lcp::{Lcp, Residuals, Solution, Status};

impl World {
    /// Stage `solve`. `solver = None` uses the world's `method` (warm-started
    /// per island); a caller's solver gets every island's LCP in island order.
    pub fn solve(&mut self, solver: Option<&mut dyn FnMut(&Lcp) -> Solution>) -> Result<(), SimError> {
        if !self.ws.islands.is_ready() {
            self.islands();
        }
        let count = self.ws.islands.len();
        // Each island starts from the previous step's basis of the same island, if any.
        let ws = &mut self.ws;
        for i in 0..count {
            let nc = ws.islands.contacts_of(i).len();
            let isl = &mut ws.pool[i];
            (isl.previous, isl.warm) = ws.warm.take(ws.islands.bodies_of(i), nc);
            isl.previous_stood = isl.previous.is_some_and(|p| !ws.warm.moved(p));
            isl.z_mapped.clear();
        }
        // Coupled islands whose contacts changed (no basis from the same
        // island): the previous basis and impulses mapped by contact (read
        // before the record is reset).
        if count > 0 && basis_check_applies(&self.params.method).is_some() {
            let k = self.params.friction_dirs;
            let pool = &self.ws.pool[..count];
            let wanted = |i: usize| pool[i].warm.is_none();
            let mapped = crate::solve_chain::warm_by_contact::by_contact(
                &self.record,
                &self.ws.contacts,
                &self.ws.islands,
                k,
                wanted,
            );
            for (isl, by_contact) in self.ws.pool.iter_mut().zip(mapped) {
                let Some((basis, z)) = by_contact else { continue };
                if isl.previous.is_none() {
                    isl.z_mapped = z;
                }
                isl.warm = Some(basis);
            }
        }
        self.record_header();
        if count == 0 {
            // Nothing to solve.
            self.ws.warm.clear();
            return Ok(());
        }
        let ws = &mut self.ws;
        let method = self.params.method.clone();
        let name = match solver {
            Some(f) => {
                for isl in &mut ws.pool[..count] {
                    isl.warm = None;
                    isl.solve(&mut |lcp, _warm| f(lcp), None, &[]);
                }
                "custom"
            }
            None => {
                let work = ws.pool[..count].iter().map(|isl| isl.lcp.n().pow(2)).sum();
                let threads = self.threads_for(count, work);
                // One solver workspace per thread, kept from step to step.
                let ws = &mut self.ws;
                if ws.solvers.len() < threads {
                    ws.solvers.resize_with(threads, Default::default);
                }
                // The same stages with or without a sink (`capture` forms M for it).
                let check = basis_check_applies(&method);
                let body = crate::solve_chain::answer_check::body_check_applies(&method);
                let warm = &ws.warm;
                parallel::for_each(&mut ws.pool[..count], &mut ws.solvers[..threads], |solver, isl| {
                    // (The body-space check assumes M_b⁻¹; a jointed island's M is coupled.)
                    isl.body_check = if isl.dense_only() { None } else { body.clone() };
                    let z_mapped = std::mem::take(&mut isl.z_mapped);
                    let z_prev = isl.previous.map_or(&z_mapped[..], |p| warm.impulses(p));
                    isl.solve(&mut |lcp, warm| lcp::solve_in(lcp, &method, warm, solver), check, z_prev)
                });
                method.name()
            }
        };
        if let Some(e) = self.ws.pool[..count].iter_mut().find_map(|isl| isl.error.take()) {
            return Err(SimError::Lcp(e));
        }
        self.capture(name);
        self.record_islands();
        let nb = self.bodies.len();
        self.ws.warm.store(&self.ws.islands, &mut self.ws.pool[..count], nb);
        Ok(())
    }

    /// Threads for `jobs` islands of total work `work` (Σ n²).
    pub(crate) fn threads_for(&self, jobs: usize, work: usize) -> usize {
        if parallel::worth_threads(jobs, work) {
            parallel::resolve_threads(self.params.threads).min(jobs)
        } else {
            1
        }
    }

    /// The record's header and contacts, and an empty answer.
    fn record_header(&mut self) {
        let (h, s) = (self.h(), self.scale());
        let rec = &mut self.record;
        let nc = self.ws.contacts.len();
        rec.step = self.steps;
        rec.time = self.time;
        rec.dt = h;
        rec.friction_dirs = self.params.friction_dirs;
        rec.scale = s;
        rec.contacts.clear();
        rec.contacts.extend_from_slice(&self.ws.contacts);
        rec.lcp_size = lcp::contact::ContactLayout::new(nc, self.params.friction_dirs).n();
        rec.zeroed = false;
        rec.status = None;
        rec.pivots = 0;
        rec.residuals = Residuals::default();
        rec.solver_residuals = Residuals::default();
        rec.z.clear();
        rec.w.clear();
        if let Some(b) = rec.basis.take() {
            self.ws.record_basis = b;
        }
        rec.islands.clear();
        rec.island_bodies.clear();
        rec.island_contacts.clear();
    }

    /// Hands every island's LCP, in island order, to the sink, forming the
    /// dense `M` of those a body-space stage answered (after the solve, so
    /// the answer is the one an uncaptured run gets).
    fn capture(&mut self, method: &'static str) {
        let Some(sink) = self.sink.as_mut() else { return };
        for (i, isl) in self.ws.pool[..self.ws.islands.len()].iter_mut().enumerate() {
            if isl.sol.is_none() {
                continue;
            }
            isl.form_matrix();
            let Some(sol) = &isl.sol else { continue };
            sink.capture(&CapturedLcp {
                step: self.steps,
                time: self.time,
                island: i,
                contacts: isl.contacts.len(),
                friction_dirs: self.params.friction_dirs,
                scale: self.record.scale,
                m: isl.lcp.m(),
                q: isl.lcp.q(),
                z: &sol.z,
                w: &sol.w,
                status: sol.status,
                pivots: sol.pivots,
                method,
            });
        }
    }

    /// The islands' answers into the record: per island, and scattered into
    /// the global `z`, `w`, `basis` (summary rules in the module docs).
    fn record_islands(&mut self) {
        let mut basis = std::mem::take(&mut self.ws.record_basis);
        let (ws, rec) = (&self.ws, &mut self.record);
        let (nc, k) = (ws.contacts.len(), self.params.friction_dirs);
        let n = rec.lcp_size;
        let solved = &ws.pool[..ws.islands.len()];
        // The step's only island in the step's layout: its vectors are
        // copied as they are, not scattered into zeroed ones (on a resting
        // 10-box stack the zeroing was 6k instructions of its step's 247k).
        let whole = solved.len() == 1 && solved[0].z.len() == n && in_step_order(ws.islands.contacts_of(0), nc);
        basis.clear();
        if whole {
            rec.z.clear();
            rec.w.clear();
        } else {
            rec.z.resize(n, 0.0);
            rec.w.resize(n, 0.0);
            basis.resize(n, false);
        }
        let mut has_basis = true;
        let mut solver_res: Option<Residuals> = None;
        rec.island_bodies.extend_from_slice(ws.islands.all_bodies());
        rec.island_contacts.extend_from_slice(ws.islands.all_contacts());
        for (i, isl) in solved.iter().enumerate() {
            let sol = isl.sol.as_ref().expect("every island was solved (errors returned above)");
            let ids = ws.islands.contacts_of(i);
            match &sol.basis {
                Some(b) if b.len() == isl.lcp.n() && whole => basis.extend_from_slice(b),
                Some(b) if b.len() == isl.lcp.n() => scatter(ids, nc, k, b, &mut basis),
                _ => has_basis = false,
            }
            if whole {
                rec.z.extend_from_slice(&isl.z);
                rec.w.extend_from_slice(&isl.w);
            } else {
                scatter(ids, nc, k, &isl.z, &mut rec.z);
                scatter(ids, nc, k, &isl.w, &mut rec.w);
            }
            if rec.status.is_none() || (rec.status == Some(Status::Solved) && sol.status != Status::Solved) {
                rec.status = Some(sol.status);
            }
            rec.pivots += sol.pivots;
            rec.zeroed |= isl.zeroed;
            solver_res = Some(solver_res.map_or(sol.residuals, |r| worst(r, sol.residuals)));
            rec.islands.push(IslandRecord {
                bodies: ws.islands.body_range(i),
                contacts: ws.islands.contact_range(i),
                lcp_size: isl.lcp.n(),
                status: sol.status,
                pivots: sol.pivots,
                residual: isl.residuals.residual,
                solver_residual: sol.residuals.residual,
                body_eta: isl.body_eta,
                zeroed: isl.zeroed,
                warm: isl.warmed,
                entered: isl.entered,
                stage: isl.stage,
            });
        }
        // The islands hold every contact once: the step's residuals are the
        // worst of theirs (the same maxima and minima, without a pass over
        // the step's z and w, a tenth of a resting stack's solve).
        let covered = solved.iter().map(|isl| isl.z.len()).sum::<usize>() == n;
        rec.residuals = match solved.iter().map(|isl| isl.residuals).reduce(worst) {
            Some(r) if covered => r,
            _ => Residuals::of(&rec.z, &rec.w),
        };
        rec.solver_residuals = solver_res.unwrap_or_default();
        if has_basis {
            rec.basis = Some(basis);
        } else {
            self.ws.record_basis = basis;
        }
    }
}

/// The worse of two residual reports, measure by measure.
fn worst(a: Residuals, b: Residuals) -> Residuals {
    Residuals {
        residual: a.residual.max(b.residual),
        min_z: a.min_z.min(b.min_z),
        min_w: a.min_w.min(b.min_w),
        max_complementarity: a.max_complementarity.max(b.max_complementarity),
    }
}
