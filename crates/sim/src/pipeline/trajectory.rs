//! `Trajectory`: the state after every step of a run, in flat arrays ready
//! for numpy (`(steps, bodies, 3)` and `(steps, bodies, 4)`, row-major), and
//! each step's contact physics and LCP outcome, and its joints' reactions,
//! coordinates and errors (`(steps, joints, …)`).

use super::record::StepRecord;
use crate::contact::FrictionBasis;
use crate::math::{Quat, Vec3};
use crate::solve_chain::stage_name::SolveStage;
use crate::world::World;
use lcp::Status;

/// States and per-step LCP statistics of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// Bodies per step.
    pub bodies: usize,
    /// Time after each step (s).
    pub time: Vec<f64>,
    /// Positions, `(steps, bodies, 3)`.
    pub position: Vec<f64>,
    /// Orientations (w, x, y, z), `(steps, bodies, 4)`.
    pub orientation: Vec<f64>,
    /// Linear velocities, `(steps, bodies, 3)`.
    pub velocity: Vec<f64>,
    /// Angular velocities, `(steps, bodies, 3)`.
    pub angular_velocity: Vec<f64>,
    /// Contacts per step.
    pub contacts: Vec<usize>,
    /// LCP size per step (0 without contacts).
    pub lcp_size: Vec<usize>,
    /// Solver status per step (`None` without contacts).
    pub status: Vec<Option<Status>>,
    /// Pivots (Lemke) or iterations (iterative solvers) per step.
    pub pivots: Vec<usize>,
    /// Natural residual `‖min(z, w)‖∞` in physical units per step.
    pub residual: Vec<f64>,
    /// Natural residual as the solver reported it (scaled LCP; worst island) per step.
    pub solver_residual: Vec<f64>,
    /// `Σ fn` per step (N·s); 0 when the solver's `z` was unusable.
    pub normal_impulse: Vec<f64>,
    /// `Σ_contacts Σ_j fd_j d_j` per step, the friction impulse on the A
    /// bodies (world frame, N·s), `(steps, 3)`.
    pub friction_impulse: Vec<f64>,
    /// Largest physical `λ` per step (m/s; 0 without contacts).
    pub max_lambda: Vec<f64>,
    /// Contact islands (LCPs solved) per step.
    pub islands: Vec<usize>,
    /// Largest island LCP per step (0 without contacts).
    pub max_island_size: Vec<usize>,
    /// Parts each step was taken in: 1, or more where a failed LCP had a
    /// part taken again in halves (`WorldParams::max_halvings`).
    pub parts: Vec<usize>,
    /// Islands answered by each stage of the solve chain per step, `(steps, 4)`
    /// in the order of [`SolveStage::ALL`].
    pub stage_counts: Vec<usize>,
    /// Joints per step.
    pub joints: usize,
    /// Each joint's reaction over the step, what side A exerted on side B
    /// ([`crate::joints::JointReaction`]): mean forces (N) and torques about
    /// the anchor (N·m), `(steps, joints, 3)` each.
    pub joint_force: Vec<f64>,
    pub joint_torque: Vec<f64>,
    /// Each joint's coordinate after the step ([`crate::joints::Joint::coordinate`]:
    /// a hinge's angle in rad, a slider's displacement in m), `(steps, joints)`.
    pub joint_position: Vec<f64>,
    /// Each joint's position error after the step, its largest linear (m) and
    /// angular (rad) row error, `(steps, joints, 2)`.
    pub joint_error: Vec<f64>,
    /// The friction directions' cosines and sines, built once per run.
    basis: Option<FrictionBasis>,
}

impl Trajectory {
    pub fn with_capacity(steps: usize, bodies: usize) -> Self {
        Trajectory {
            bodies,
            time: Vec::with_capacity(steps),
            position: Vec::with_capacity(steps * bodies * 3),
            orientation: Vec::with_capacity(steps * bodies * 4),
            velocity: Vec::with_capacity(steps * bodies * 3),
            angular_velocity: Vec::with_capacity(steps * bodies * 3),
            contacts: Vec::with_capacity(steps),
            lcp_size: Vec::with_capacity(steps),
            status: Vec::with_capacity(steps),
            pivots: Vec::with_capacity(steps),
            residual: Vec::with_capacity(steps),
            solver_residual: Vec::with_capacity(steps),
            normal_impulse: Vec::with_capacity(steps),
            friction_impulse: Vec::with_capacity(3 * steps),
            max_lambda: Vec::with_capacity(steps),
            islands: Vec::with_capacity(steps),
            max_island_size: Vec::with_capacity(steps),
            parts: Vec::with_capacity(steps),
            stage_counts: Vec::with_capacity(SolveStage::ALL.len() * steps),
            joints: 0,
            joint_force: Vec::new(),
            joint_torque: Vec::new(),
            joint_position: Vec::new(),
            joint_error: Vec::new(),
            basis: None,
        }
    }

    /// Room for `steps` steps of `world`'s bodies and joints.
    pub fn for_world(steps: usize, world: &World) -> Self {
        let mut t = Trajectory::with_capacity(steps, world.bodies().len());
        let joints = world.joints().len();
        t.joints = joints;
        t.joint_force.reserve(steps * joints * 3);
        t.joint_torque.reserve(steps * joints * 3);
        t.joint_position.reserve(steps * joints);
        t.joint_error.reserve(steps * joints * 2);
        t
    }

    /// Appends the world's current state and its last step record.
    pub fn push(&mut self, world: &World) {
        self.time.push(world.time());
        for b in world.bodies() {
            self.position.extend_from_slice(&b.position().to_array());
            self.orientation.extend_from_slice(&b.orientation().to_array());
            self.velocity.extend_from_slice(&b.velocity().to_array());
            self.angular_velocity.extend_from_slice(&b.angular_velocity().to_array());
        }
        let r = world.last_record();
        self.contacts.push(r.nc());
        self.lcp_size.push(r.lcp_size);
        self.status.push(r.status);
        self.pivots.push(r.pivots);
        self.residual.push(r.residuals.residual);
        self.solver_residual.push(r.solver_residuals.residual);
        self.islands.push(r.islands.len());
        self.max_island_size.push(r.islands.iter().map(|i| i.lcp_size).max().unwrap_or(0));
        self.parts.push(r.parts);
        let mut counts = [0; SolveStage::ALL.len()];
        r.islands.iter().filter_map(|i| i.stage).for_each(|s| counts[s.index()] += 1);
        self.stage_counts.extend(counts);
        self.push_impulses(r);
        self.push_joints(world);
    }

    /// The joints' reactions (from the last record), coordinates and errors.
    fn push_joints(&mut self, world: &World) {
        let (joints, bodies) = (world.joints(), world.bodies());
        self.joints = joints.len();
        let r = world.last_record();
        for (j, joint) in joints.iter().enumerate() {
            let reaction = r.joints.get(j).copied().unwrap_or_default();
            self.joint_force.extend_from_slice(&reaction.force.to_array());
            self.joint_torque.extend_from_slice(&reaction.torque.to_array());
            self.joint_position.push(joint.coordinate(bodies));
            let (lin, ang) = joint.error(bodies);
            self.joint_error.extend([lin, ang]);
        }
    }

    /// Σ fn, the friction impulse vector and the largest λ of a step.
    fn push_impulses(&mut self, r: &StepRecord) {
        let (nc, k) = (r.nc(), r.friction_dirs);
        let (mut fnsum, mut fric, mut lam) = (0.0, Vec3::ZERO, 0.0);
        if nc > 0 && r.z.len() == r.layout().n() {
            if !matches!(&self.basis, Some(b) if b.k() == k) {
                self.basis = Some(FrictionBasis::new(k));
            }
            let basis = self.basis.as_ref().expect("set above");
            fnsum = r.total_normal_impulse();
            for (i, c) in r.contacts.iter().enumerate() {
                for (j, &f) in r.friction_of(i).iter().enumerate() {
                    if f != 0.0 {
                        fric += basis.direction(c.normal, c.tangent, j) * f;
                    }
                }
            }
            lam = r.lambdas().iter().copied().fold(0.0, f64::max);
        }
        self.normal_impulse.push(fnsum);
        self.friction_impulse.extend_from_slice(&fric.to_array());
        self.max_lambda.push(lam);
    }

    /// Steps recorded.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Position of `body` after step `step`.
    pub fn position_at(&self, step: usize, body: usize) -> Vec3 {
        let i = (step * self.bodies + body) * 3;
        Vec3::new(self.position[i], self.position[i + 1], self.position[i + 2])
    }

    /// Orientation of `body` after step `step`.
    pub fn orientation_at(&self, step: usize, body: usize) -> Quat {
        let i = (step * self.bodies + body) * 4;
        Quat::new(self.orientation[i], self.orientation[i + 1], self.orientation[i + 2], self.orientation[i + 3])
    }

    /// Velocity of `body` after step `step`.
    pub fn velocity_at(&self, step: usize, body: usize) -> Vec3 {
        let i = (step * self.bodies + body) * 3;
        Vec3::new(self.velocity[i], self.velocity[i + 1], self.velocity[i + 2])
    }

    /// Steps whose LCP was not solved.
    pub fn failures(&self) -> usize {
        self.status.iter().filter(|s| matches!(s, Some(st) if *st != Status::Solved)).count()
    }
}
