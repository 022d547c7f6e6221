//! The time step as a flat list of named stages (MuJoCo's `mj_step` style):
//!
//! ```text
//! forces     v* = v + h M⁻¹ f_ext                      (gravity, applied forces, torques)
//! detect     contacts with gap φ ≤ margin              (sweep and prune, then one narrow-phase file per shape pair)
//! islands    dynamic bodies linked by contacts          (union-find; static bodies link nothing)
//! assemble   one Stewart–Trinkle LCP (M, q) per island, z = [fn; fd; λ]
//! solve      each island with any lcp::Method (or a caller's solver), map z back, record
//! integrate  v⁺ = v* + M⁻¹(J_nᵀ fn + J_dᵀ fd), then positions from v⁺, energy audit
//!            (a failed island applies its answer made admissible, scaled not to add energy: `energy`)
//! ```
//!
//! Every stage is a public method of [`World`] so a caller can run them one by
//! one (and look at the contacts or the LCP in between); `step` runs them all,
//! and takes a step whose LCP failed again in halves where
//! `WorldParams::max_halvings` allows (`retake`).

pub(crate) mod capture;
mod detect;
pub mod energy;
pub(crate) mod island;
pub(crate) mod record;
pub(crate) mod retake;
mod solve;
mod trajectory;

pub use capture::{Captured, CapturedLcp, LcpBuffer, LcpSink, OwnedLcp};
pub use energy::EnergyAudit;
pub use record::{IslandRecord, Retake, StepRecord};
pub use trajectory::Trajectory;

use crate::contact::assembly::{AssemblyParams, BodyDynamics};
use crate::dynamics::{free_velocity, integrate_positions};
use crate::error::SimError;
use crate::limits;
use crate::math::{Mat3, Vec3};
use crate::parallel;
use crate::solve_chain::{basis_check_applies, STRUCTURED_MIN_N};
use crate::world::World;
use lcp::{Lcp, Solution};

impl World {
    /// One time step with the world's `method`. Solver trouble is never an
    /// error (see [`StepRecord::status`]); only a non-finite state is.
    pub fn step(&mut self) -> Result<&StepRecord, SimError> {
        self.step_inner(None)
    }

    /// One time step with a caller-supplied LCP solver instead of `method`
    /// (e.g. an external solver to compare against). It receives the scaled
    /// LCP exactly as `method` would.
    pub fn step_with(&mut self, solver: &mut dyn FnMut(&Lcp) -> Solution) -> Result<&StepRecord, SimError> {
        self.step_inner(Some(solver))
    }

    fn step_inner(&mut self, solver: Option<&mut dyn FnMut(&Lcp) -> Solution>) -> Result<&StepRecord, SimError> {
        let (step, time) = (self.steps, self.time);
        self.ws.parts.begin();
        let taken = self.take_part(solver, self.params.dt, self.params.max_halvings);
        self.ws.part_h = None;
        taken?;
        // However many parts it took, it is one step of `dt`.
        (self.steps, self.time) = (step + 1, time + self.params.dt);
        self.ws.parts.finish(&mut self.record, step);
        Ok(&self.record)
    }

    /// The stages over a part of length `h` of the step (the whole step at
    /// first); a part whose LCP fails is taken again as two halves while
    /// `halvings` allow (`retake`).
    fn take_part(
        &mut self,
        mut solver: Option<&mut dyn FnMut(&Lcp) -> Solution>,
        h: f64,
        halvings: u32,
    ) -> Result<(), SimError> {
        self.ws.part_h = (h != self.params.dt).then_some(h);
        // external forces → free velocities v*
        self.forces_stage()?;
        // contacts with φ ≤ margin
        self.detect();
        // bodies linked through contacts, one LCP each (each checked to fit in memory)
        self.islands();
        self.reserve_islands()?;
        // the Stewart–Trinkle LCP (`contact::assembly`), per island
        self.assemble_islands(false);
        if halvings > 0 {
            self.ws.parts.keep_start(&self.ws.warm, &self.record);
        }
        // solve the islands, map to physical units, fill the step record, capture
        self.solve(reborrow(&mut solver))?;
        if halvings > 0 && !self.record.ok() {
            // undone (nothing has moved yet) and taken again in halves
            self.ws.parts.undo_failed(&mut self.ws.warm, &mut self.record, h);
            // An error in a later part (a body's state no longer finite, an
            // island too large) leaves the bodies where the step began, as an
            // error in a step taken whole does: the outermost retake keeps them.
            let start = (h == self.params.dt).then(|| (self.bodies.clone(), self.time));
            let taken = self
                .take_part(reborrow(&mut solver), h / 2.0, halvings - 1)
                .and_then(|()| self.take_part(solver, h / 2.0, halvings - 1));
            if let (Err(_), Some((bodies, time))) = (&taken, start) {
                (self.bodies, self.time) = (bodies, time);
            }
            return taken;
        }
        // contact impulses → v⁺, then positions
        self.integrate();
        self.ws.parts.add(&self.record);
        Ok(())
    }

    /// The `h` of the step being taken: `params.dt`, or a part of it while a
    /// failed step is retaken (`retake`).
    pub(crate) fn h(&self) -> f64 {
        self.ws.part_h.unwrap_or(self.params.dt)
    }

    /// The friction-cone scale `s` of the step being taken (it may follow `h`).
    pub(crate) fn scale(&self) -> f64 {
        self.params.cone_scale.value(self.h())
    }

    /// Runs `steps` steps and returns the trajectory (state after each step
    /// plus per-step contact physics and LCP statistics).
    pub fn run(&mut self, steps: usize) -> Result<Trajectory, SimError> {
        self.run_until(steps, |_| false)
    }

    /// Like [`World::run`], calling `observe(world, record)` after every step.
    pub fn run_with(
        &mut self,
        steps: usize,
        mut observe: impl FnMut(&World, &StepRecord),
    ) -> Result<Trajectory, SimError> {
        self.run_until(steps, |w| {
            observe(w, &w.record);
            false
        })
    }

    /// Like [`World::run`], but stops early, after a step, once `stop(world)`
    /// says so (e.g. when an LCP sink holds enough to be drained).
    pub fn run_until(&mut self, steps: usize, mut stop: impl FnMut(&World) -> bool) -> Result<Trajectory, SimError> {
        limits::check_trajectory(steps, self.bodies.len(), self.joints.len())?;
        let mut traj = Trajectory::for_world(steps, self);
        for _ in 0..steps {
            self.step()?;
            traj.push(self);
            if stop(self) {
                break;
            }
        }
        Ok(traj)
    }

    /// Stage `forces`: sums gravity, applied forces and torques per body and
    /// forms the free velocities `v* = v + h f/m`, `ω* = ω + h I⁻¹ τ`.
    pub fn forces_stage(&mut self) -> Result<(), SimError> {
        let h = self.h();
        let nb = self.bodies.len();
        let ws = &mut self.ws;
        // gravity on every dynamic body
        ws.force.clear();
        ws.force
            .extend(self.bodies.iter().map(|b| if b.is_static { Vec3::ZERO } else { self.params.gravity * b.mass }));
        ws.torque.clear();
        ws.torque.resize(nb, Vec3::ZERO);
        // constant forces, with the torque of those applied off the centre of mass
        for f in &self.forces {
            let b = &self.bodies[f.body];
            ws.force[f.body] += f.force;
            if let Some(p) = f.point {
                ws.torque[f.body] += b.orientation.rotate(p).cross(f.force);
            }
        }
        for t in &self.torques {
            ws.torque[t.body] += t.torque;
        }
        // inverse inertia in the world frame, then v* and ω*
        ws.inv_inertia.clear();
        ws.inv_inertia.extend(self.bodies.iter().map(|b| b.inv_inertia_world()));
        ws.v_free.clear();
        ws.w_free.clear();
        for (i, b) in self.bodies.iter().enumerate() {
            if b.is_static {
                ws.v_free.push(Vec3::ZERO);
                ws.w_free.push(Vec3::ZERO);
                continue;
            }
            let (v, w) = free_velocity(b, ws.force[i], ws.torque[i], h);
            if !(v.is_finite() && w.is_finite() && b.position.is_finite() && b.orientation.is_finite()) {
                return Err(SimError::NonFiniteState { body: i });
            }
            ws.v_free.push(v);
            ws.w_free.push(w);
        }
        // v* projected onto the joints (nothing without joints)
        self.joints_project();
        Ok(())
    }

    /// Free velocities for every body, computing them (stage `forces_stage`)
    /// if a stage is called out of order; `false` if that fails.
    pub(crate) fn free_velocities_ready(&mut self) -> bool {
        self.ws.v_free.len() == self.bodies.len() || self.forces_stage().is_ok()
    }

    /// Stage `islands`: groups this step's contacts by island (see `islands`)
    /// and hands each island its contacts.
    pub fn islands(&mut self) {
        let ws = &mut self.ws;
        ws.islands.build_linked(&ws.contacts, &self.bodies, &ws.joints.links);
        let count = ws.islands.len();
        if ws.pool.len() < count {
            ws.pool.resize_with(count, Default::default);
        }
        for (i, isl) in ws.pool[..count].iter_mut().enumerate() {
            isl.contacts.clear();
            isl.contacts.extend(ws.islands.contacts_of(i).iter().map(|&c| ws.contacts[c]));
        }
    }

    /// Stage `islands` → `assemble`: each island's dense LCP checked against
    /// memory and its matrix reserved, so an island too large fails the step
    /// with [`SimError::TooLarge`] before anything is assembled — but for the
    /// large islands the structured Lemke takes, whose `M` is reserved only if
    /// they fall back to the dense Lemke (a failed reservation keeps the
    /// structured answer, reported as not solved). Each slot's matrix is
    /// trimmed to its island, so the pool does not keep every size it saw.
    pub(crate) fn reserve_islands(&mut self) -> Result<(), SimError> {
        let k = self.params.friction_dirs;
        // Islands the structured Lemke takes need no dense M (unless a sink captures it).
        let structured = self.sink.is_none() && basis_check_applies(&self.params.method).is_some();
        let ws = &mut self.ws;
        for (i, isl) in ws.pool[..ws.islands.len()].iter_mut().enumerate() {
            let what = || format!("step {}, contact island {i}", self.steps);
            limits::check_contact_lcp(what, isl.contacts.len(), k)?;
            let n = limits::lcp_size(isl.contacts.len(), k).unwrap_or(usize::MAX);
            // A large island of two or more dynamic bodies and no joint goes to the
            // structured Lemke, which reserves the dense M only if the island falls back
            // to the dense Lemke (`solve_chain::structured_lemke`).
            let bodies = ws.islands.bodies_of(i);
            if structured
                && n >= STRUCTURED_MIN_N
                && bodies.len() >= 2
                && !ws.joints.holds_jointed(bodies)
                && !ws.torsion.in_island(ws.islands.contacts_of(i))
            {
                isl.lcp.trim_matrix(0);
                continue;
            }
            isl.lcp.trim_matrix(n);
            isl.lcp.reserve_matrix(n).map_err(|mut e| {
                e.what = format!("{}: the dense matrix of a contact LCP of {n} unknowns", what());
                SimError::TooLarge(e)
            })?;
        }
        Ok(())
    }

    /// Stage `assemble` as `step` runs it: each island checked against memory
    /// (`SimError::TooLarge`), then its rows and `q`, the dense `M` left to
    /// `solve` (which forms it only where the body-space stages do not
    /// answer). With `forces_stage`, `detect`, `islands`, `solve` and
    /// `integrate` it is the step, stage by stage (`examples/step_budget.rs`
    /// times them).
    pub fn assemble_for_solve(&mut self) -> Result<(), SimError> {
        if !self.ws.islands.is_ready() {
            self.islands();
        }
        self.reserve_islands()?;
        self.assemble_islands(false);
        Ok(())
    }

    /// Stage `assemble`: each island's LCP from its contacts and the free velocities.
    pub fn assemble(&mut self) {
        self.assemble_islands(true);
    }

    /// Stage `assemble`, forming each island's dense `M` only if `matrix`
    /// (the step leaves that to `solve`, which needs it only when the
    /// previous basis does not solve the island in body space).
    fn assemble_islands(&mut self, matrix: bool) {
        if !self.free_velocities_ready() {
            self.ws.contacts.clear();
            self.ws.islands.invalidate();
        }
        if !self.ws.islands.is_ready() {
            self.islands();
        }
        let p = AssemblyParams {
            h: self.h(),
            k: self.params.friction_dirs,
            s: self.scale(),
            stabilization: self.params.stabilization,
            restitution: self.params.restitution,
        };
        let count = self.ws.islands.len();
        let k2 = self.params.friction_dirs + 2;
        let work = self.ws.pool[..count].iter().map(|isl| (isl.contacts.len() * k2).pow(2)).sum();
        let threads = self.threads_for(count, work);
        let ws = &mut self.ws;
        let dynamics = BodyDynamics {
            bodies: &self.bodies,
            inv_inertia_world: &ws.inv_inertia,
            v_free: &ws.v_free,
            w_free: &ws.w_free,
        };
        let mut states = vec![(); threads];
        parallel::for_each(&mut ws.pool[..count], &mut states, |_, isl| isl.assemble(&dynamics, &p, matrix));
        // islands with a torsion patch: its rows and cone (the dense M formed again if it was)
        for (i, isl) in ws.pool[..count].iter_mut().enumerate() {
            let (island, torsion) = (ws.islands.contacts_of(i), &ws.torsion);
            isl.torsion = !torsion.patches.is_empty()
                && torsion.set_island_rows(island, &mut isl.lcp, &ws.inv_inertia, &ws.w_free);
            if isl.torsion && matrix {
                isl.lcp.assemble_matrix();
            }
        }
        // islands with a joint: their coupling through the joints (and M coupled, if formed)
        self.joints_couple(matrix);
    }

    /// Stage `integrate`: `v⁺ = v* + M⁻¹ Jᵀ z` with the impulses chosen by
    /// `solve`, then `x += h v⁺` and the quaternion update (renormalized).
    pub fn integrate(&mut self) {
        let h = self.h();
        let nb = self.bodies.len();
        let before = self.energy();
        let ws = &mut self.ws;
        ws.dv.clear();
        ws.dv.resize(nb, Vec3::ZERO);
        ws.dw.clear();
        ws.dw.resize(nb, Vec3::ZERO);
        for isl in &ws.pool[..ws.islands.len()] {
            if isl.z_apply.len() == isl.lcp.n() {
                isl.lcp.apply_impulses(&isl.z_apply, &mut ws.dv, &mut ws.dw);
            }
        }
        // failed islands: their answer made admissible, scaled not to add energy
        self.fallback_impulses();
        // the joint impulses of the contact impulses; the joints' reactions
        self.joints_apply();
        let (ws, g) = (&mut self.ws, self.params.gravity);
        let mut work = 0.0;
        for (i, b) in self.bodies.iter_mut().enumerate() {
            if b.is_static {
                continue;
            }
            b.velocity = ws.v_free[i] + ws.dv[i];
            b.angular_velocity = ws.w_free[i] + ws.dw[i];
            work += h * ((ws.force[i] - g * b.mass).dot(b.velocity) + ws.torque[i].dot(b.angular_velocity));
            integrate_positions(b, h);
        }
        // the joints' position error projected away (nothing without joints), the energy it changed
        let unsettled = (!self.joints.is_empty()).then(|| self.energy());
        self.joints_settle();
        let after = self.energy();
        let (motor_work, joint_drift) = self.joint_work(h);
        let ws = &mut self.ws;
        self.time += h;
        // the parts of a retaken step count as one (`step_inner` counts it)
        self.steps += u64::from(ws.part_h.is_none());
        let stab = &self.params.stabilization;
        // the geometric contacts of each island (its joint limits and motors, last, are the joints')
        let first_limit = ws.joints.first_limit;
        let stabilization = (0..ws.islands.len())
            .map(|i| {
                let (isl, geometric) = (&ws.pool[i], ws.islands.contacts_of(i).partition_point(|&g| g < first_limit));
                energy::stabilization_work(&isl.contacts[..geometric], &isl.z_apply, isl.lcp.layout(), stab, h)
            })
            .sum();
        self.record.energy = energy::EnergyAudit {
            before,
            after,
            external_work: work,
            stabilization,
            motor_work,
            joint_drift,
            joint_projection: unsettled.map_or(0.0, |e| after - e),
        };
    }

    /// The failed-solve policy of [`energy`]: each failed island applies its
    /// answer's admissible part times the energy-minimizing `α ∈ [0, 1]`
    /// (recorded as its `z_apply`).
    fn fallback_impulses(&mut self) {
        let (h, g, nb) = (self.h(), self.params.gravity, self.bodies.len());
        let ws = &mut self.ws;
        for i in 0..ws.islands.len() {
            let isl = &mut ws.pool[i];
            if !isl.zeroed {
                continue;
            }
            let mut cand = Vec::new();
            energy::admissible(&isl.z, isl.lcp.layout(), isl.lcp.mu(), &mut cand);
            let (mut dv, mut dw) = (vec![Vec3::ZERO; nb], vec![Vec3::ZERO; nb]);
            isl.lcp.apply_impulses(&cand, &mut dv, &mut dw);
            // With joints, the motion is that of the joint impulses it causes too
            // (which `joints_apply` adds to what is applied here).
            let (mut jv, mut jw) = (dv.clone(), dw.clone());
            if let Some(rows) = ws.joints.contact_row_impulses(&isl.coupling, &isl.lcp, &cand) {
                ws.joints.add_velocity(&rows, &mut jv, &mut jw);
            }
            let bodies = ws.islands.bodies_of(i);
            let shares = bodies.iter().map(|&b| energy::Share {
                v: ws.v_free[b],
                w: ws.w_free[b],
                dv: jv[b],
                dw: jw[b],
                mass: self.bodies[b].mass,
                inertia: self.bodies[b].inertia_world(),
            });
            let alpha = energy::fallback_scale(shares, g, h);
            for &b in bodies {
                ws.dv[b] += dv[b] * alpha;
                ws.dw[b] += dw[b] * alpha;
            }
            isl.z_apply.clear();
            isl.z_apply.extend(cand.iter().map(|v| v * alpha));
        }
    }

    /// The contacts found by the last `detect` stage.
    pub fn contacts(&self) -> &[crate::geometry::Contact] {
        &self.ws.contacts
    }

    /// The LCP of the first island built by the last `assemble` stage (with
    /// its Jacobian rows): the whole step's LCP when the contacts form one
    /// island; an empty one without contacts.
    pub fn contact_lcp(&self) -> &crate::contact::ContactLcp {
        self.island_lcp(0).unwrap_or(&self.ws.no_lcp)
    }

    /// The LCP of island `i` built by the last `assemble` stage.
    pub fn island_lcp(&self, i: usize) -> Option<&crate::contact::ContactLcp> {
        (i < self.ws.islands.len()).then(|| &self.ws.pool[i].lcp)
    }

    /// The islands of the last `islands` stage.
    pub fn contact_islands(&self) -> &crate::islands::Islands {
        &self.ws.islands
    }

    /// Free velocities `(v*, ω*)` of the last `forces` stage.
    pub fn free_velocities(&self) -> (&[Vec3], &[Vec3]) {
        (&self.ws.v_free, &self.ws.w_free)
    }

    /// World-frame inverse inertias of the last `forces` stage.
    pub fn inv_inertias(&self) -> &[Mat3] {
        &self.ws.inv_inertia
    }
}

/// The caller's solver again, for one more part of a step.
fn reborrow<'a>(
    solver: &'a mut Option<&mut dyn FnMut(&Lcp) -> Solution>,
) -> Option<&'a mut dyn FnMut(&Lcp) -> Solution> {
    solver.as_mut().map(|f| &mut **f as &mut dyn FnMut(&Lcp) -> Solution)
}
