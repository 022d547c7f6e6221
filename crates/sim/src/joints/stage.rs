//! The world's side of the joints: adding them, and the three places the
//! step calls on them (`pipeline`):
//!
//! ```text
//! forces     … then the rows G at this step's poses, S = G M⁻¹ Gᵀ factored, v* projected (`joints_project`)
//! detect     bodies joined by a joint get no contact between them, nor a contact whose normal they hold (`held_contacts`)
//! islands    bodies joined by a joint share an island
//! assemble   … then each island with a jointed body gets its coupling Y = L⁻¹ Πᵀ B (`joints_couple`)
//! integrate  … the joint impulses of the contact impulses added to Δv, the reactions recorded (`joints_apply`);
//!            after the positions, their joint error projected away (`joints_settle`)
//! ```
//!
//! An island with a joint is solved on `J P Jᵀ` (the body-space stages of the
//! solve chain assume the block-diagonal `M_b⁻¹` and decline it): its
//! previous basis through `contact::CoupledSpaceLcp`, which reads `Y`, and
//! the Lemke on the dense `M`, formed with `−Yᵀ Y` only then
//! (`IslandLcp::form_matrix`). Its answer is accepted by the same rule as
//! every other.

use super::joint::{Joint, JointDesc, JointId, JointParams};
use crate::contact::assembly::{dot6, row};
use crate::error::SimError;
use crate::math::Vec3;
use crate::world::World;

impl World {
    /// Adds a joint after validating it (bodies exist, one is dynamic, they
    /// differ; a finite anchor; a finite, non-zero axis for hinges and sliders).
    pub fn add_joint(&mut self, desc: JointDesc) -> Result<JointId, SimError> {
        let joint = Joint::new(&desc, &self.bodies)?;
        self.joints.push(joint);
        Ok(JointId(self.joints.len() - 1))
    }

    /// The joints, in `JointId` order.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The joints' parameters.
    pub fn joint_params(&self) -> JointParams {
        self.joint_params
    }

    /// Replaces the joints' parameters (validated first).
    pub fn set_joint_params(&mut self, p: JointParams) -> Result<(), SimError> {
        p.validate()?;
        self.joint_params = p;
        Ok(())
    }

    /// Joint `j`'s position error now: the largest linear (m) and angular (rad) row error.
    pub fn joint_error(&self, j: JointId) -> Result<(f64, f64), SimError> {
        let joint = self.joints.get(j.0).ok_or(SimError::UnknownJoint { index: j.0, joints: self.joints.len() })?;
        Ok(joint.error(&self.bodies))
    }

    /// After the free velocities: the rows at this step's poses, `S` factored,
    /// and `v*` projected onto the joints (nothing without joints).
    pub(crate) fn joints_project(&mut self) {
        let ws = &mut self.ws;
        if self.joints.is_empty() {
            if !ws.joints.is_empty() || !ws.joints.pairs.is_empty() {
                ws.joints = Default::default();
            }
            return;
        }
        let h = self.ws.part_h.unwrap_or(self.params.dt);
        let ws = &mut self.ws;
        ws.joints.build(&self.joints, &self.bodies, &ws.inv_inertia, self.joint_params.rank_tol, Some(h));
        ws.joints.project(&mut ws.v_free, &mut ws.w_free, h, self.joint_params.drift);
    }

    /// Limits of joint `j` (`None`: free), checked as `add_joint` checks them.
    pub fn set_joint_limits(&mut self, j: JointId, limits: Option<(f64, f64)>) -> Result<(), SimError> {
        let n = self.joints.len();
        let joint = self.joints.get_mut(j.0).ok_or(SimError::UnknownJoint { index: j.0, joints: n })?;
        joint.limits = super::joint::check_limits(joint.kind, limits)?;
        Ok(())
    }

    /// A velocity motor on joint `j` (a hinge or slider): its rate driven to
    /// `speed` (rad/s, m/s) with at most `max_force` (N·m, N); 0 turns it off.
    pub fn set_motor(&mut self, j: JointId, speed: f64, max_force: f64) -> Result<(), SimError> {
        let n = self.joints.len();
        let joint = self.joints.get_mut(j.0).ok_or(SimError::UnknownJoint { index: j.0, joints: n })?;
        joint.motor = Some(super::joint::check_motor(joint.kind, speed, max_force)?);
        Ok(())
    }

    /// Viscous damping `d` (N·m·s/rad, N·s/m) of hinge or slider `j`'s rate: a
    /// force `−d·q̇` integrated implicitly (`rows`); 0 turns it off.
    pub fn set_joint_damping(&mut self, j: JointId, damping: f64) -> Result<(), SimError> {
        let n = self.joints.len();
        let joint = self.joints.get_mut(j.0).ok_or(SimError::UnknownJoint { index: j.0, joints: n })?;
        joint.damping = super::joint::check_damping(joint.kind, damping)?;
        Ok(())
    }

    /// At the end of `detect`: the limits each joint may reach this step
    /// (within its rate times `2h` plus the margin) appended to the contacts.
    pub(crate) fn joint_limit_contacts(&mut self) {
        let ws = &mut self.ws;
        ws.joints.limits.clear();
        ws.joints.first_limit = ws.contacts.len();
        if self.joints.iter().all(|j| j.limits.is_none() && j.motor.is_none()) {
            return;
        }
        let h = ws.part_h.unwrap_or(self.params.dt);
        for (j, joint) in self.joints.iter().enumerate().filter(|(_, j)| j.limits.is_some()) {
            // How fast the coordinate can change: the free velocities' speeds.
            let sides = [joint.dynamic_side(&self.bodies, 0), joint.dynamic_side(&self.bodies, 1)];
            let rate: f64 = sides.iter().flatten().map(|&b| ws.w_free[b].norm() + ws.v_free[b].norm()).sum();
            let reach = 2.0 * h * rate + self.params.margin;
            joint.push_limits(j, &self.bodies, reach, &mut ws.joints.limits, &mut ws.contacts);
        }
        for (j, joint) in self.joints.iter().enumerate() {
            joint.push_motor(j, &self.bodies, h, &mut ws.joints.limits, &mut ws.contacts);
        }
    }

    /// After assembly: each island holding a jointed body gets its coupling
    /// through the joints (and, with `matrix`, its dense `M` formed with it),
    /// and is marked so that the solve chain takes it on the dense path.
    pub(crate) fn joints_couple(&mut self, matrix: bool) {
        let h = self.ws.part_h.unwrap_or(self.params.dt);
        let ws = &mut self.ws;
        let count = ws.islands.len();
        for (i, isl) in ws.pool[..count].iter_mut().enumerate() {
            isl.jointed = ws.joints.holds_jointed(ws.islands.bodies_of(i));
            if !isl.jointed {
                isl.coupling.clear();
                continue;
            }
            // Its limits' rows in place of the contacts' point rows.
            let first = ws.joints.first_limit;
            for (c, &g) in ws.islands.contacts_of(i).iter().enumerate().filter(|(_, &g)| g >= first) {
                let lim = &ws.joints.limits[g - first];
                let minv = [0, 1].map(|s| {
                    lim.body[s].map_or([0.0; 6], |b| {
                        let r = &lim.jac[s];
                        let (l, a) = (Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]));
                        row(l * self.bodies[b].inv_mass(), ws.inv_inertia[b] * a)
                    })
                });
                let jv: f64 = (0..2)
                    .filter_map(|s| lim.body[s].map(|b| dot6(&lim.jac[s], &row(ws.v_free[b], ws.w_free[b]))))
                    .sum();
                if let Some((speed, _)) = lim.motor {
                    // The rate row as the first friction direction, driven to `speed`.
                    let z = [0.0; 6];
                    let (jac, minv) = (lim.jac.map(|r| [z, r, z]), minv.map(|r| [z, r, z]));
                    isl.lcp.set_generalized_rows(c, lim.body, jac, minv, [0.0, jv - speed, 0.0]);
                    continue;
                }
                // Speculative before the limit (stop on it), β of the joints past it.
                let bias = if lim.gap > 0.0 { lim.gap / h } else { self.joint_params.drift * lim.gap / h };
                isl.lcp.set_generalized_row(c, lim.body, lim.jac, minv, jv + bias);
            }
            ws.joints.couple(&isl.lcp, &mut isl.coupling);
            if matrix {
                // (Formed at assembly unless a limit's rows replaced a contact's since.)
                if !isl.lcp.has_matrix() {
                    isl.lcp.assemble_matrix();
                }
                isl.coupling.subtract_from(&mut isl.lcp);
            }
            // Motors: their normal pinned at the force bound.
            for (c, &g) in ws.islands.contacts_of(i).iter().enumerate().filter(|(_, &g)| g >= first) {
                if let Some((_, bound)) = ws.joints.limits[g - first].motor {
                    isl.lcp.pin_normal(c, bound);
                }
            }
        }
    }

    /// After the positions: the joints' remaining position error projected
    /// away ([`JointParams::settle_passes`]); velocities unchanged.
    pub(crate) fn joints_settle(&mut self) {
        let p = self.joint_params;
        if self.joints.is_empty() || p.settle_passes == 0 {
            return;
        }
        let mut st = self.ws.joints.settling.take().unwrap_or_default();
        for _ in 0..p.settle_passes {
            // The errors first (rows only): S is formed and factored only for a projection.
            st.rows.clear();
            for (j, joint) in self.joints.iter().enumerate() {
                joint.push_rows(j, &self.bodies, &mut st.rows);
            }
            if st.rows.iter().all(|r| r.error.abs() <= p.settle_tol) {
                break;
            }
            st.inv_inertia.clear();
            st.inv_inertia.extend(self.bodies.iter().map(|b| b.inv_inertia_world()));
            let mut sys = std::mem::take(&mut st.sys);
            sys.build(&self.joints, &self.bodies, &st.inv_inertia, p.rank_tol, None);
            sys.settle(&mut self.bodies, &mut st);
            st.sys = sys;
        }
        self.ws.joints.settling = Some(st);
    }

    /// In `integrate`, after the contact impulses: the joint impulses they
    /// cause, into `Δv`, and every joint's reaction into the record.
    pub(crate) fn joints_apply(&mut self) {
        if self.joints.is_empty() {
            self.record.joints.clear();
            return;
        }
        let h = self.ws.part_h.unwrap_or(self.params.dt);
        let ws = &mut self.ws;
        for isl in &ws.pool[..ws.islands.len()] {
            if isl.jointed && isl.z_apply.len() == isl.lcp.n() {
                ws.joints.add_contact_response(&isl.coupling, &isl.lcp, &isl.z_apply, &mut ws.dv, &mut ws.dw);
            }
        }
        ws.joints.reactions(&self.joints, &self.bodies, h, &mut self.record.joints);
    }
}
