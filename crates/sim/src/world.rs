//! `World`: bodies, constant forces, parameters, and the buffers the step reuses.
//!
//! Build a world, add bodies (`add_box`, `add_sphere`, `add_plane`, or
//! `add_body` with a [`BodyDesc`]), apply forces, then `step()` or `run(n)`.
//! The stages of a step live in `pipeline`.

use crate::broad_phase::BroadPhase;
use crate::contact::ContactLcp;
use crate::dynamics::{AppliedForce, AppliedTorque, Body, BodyDesc, BodyId};
use crate::error::{finite_vec, non_negative, SimError};
use crate::geometry::{Contact, GeomContact, Plane, Shape};
use crate::islands::Islands;
use crate::math::{Mat3, Quat, Vec3};
use crate::params::WorldParams;
use crate::pipeline::capture::LcpSink;
use crate::pipeline::island::IslandLcp;
use crate::pipeline::record::StepRecord;
use crate::pipeline::retake::Parts;
use crate::solve_chain::warm_starts::WarmStarts;

/// A rigid-body world stepped with the Stewart–Trinkle contact LCP.
pub struct World {
    pub(crate) params: WorldParams,
    pub(crate) bodies: Vec<Body>,
    pub(crate) forces: Vec<AppliedForce>,
    pub(crate) torques: Vec<AppliedTorque>,
    /// Time at the start of the next step (s).
    pub(crate) time: f64,
    /// Steps taken so far.
    pub(crate) steps: u64,
    pub(crate) sink: Option<Box<dyn LcpSink>>,
    pub(crate) ws: Workspace,
    pub(crate) record: StepRecord,
    /// Joints between bodies (`joints`), and their parameters.
    pub(crate) joints: Vec<crate::joints::Joint>,
    pub(crate) joint_params: crate::joints::JointParams,
    /// Pairs of bodies kept apart whatever their collision bits (`exclude_pair`).
    pub(crate) excluded: crate::ExcludedPairs,
    /// Pairs of bodies that touch past bits and exclusions, with their own μ (`add_contact_pair`).
    pub(crate) contact_pairs: crate::ContactPairs,
}

impl Clone for World {
    /// A copy of the state, parameters, forces and last record — without the
    /// LCP sink (a sink is a one-way stream; give the copy its own).
    fn clone(&self) -> Self {
        World {
            params: self.params.clone(),
            bodies: self.bodies.clone(),
            forces: self.forces.clone(),
            torques: self.torques.clone(),
            time: self.time,
            steps: self.steps,
            sink: None,
            // The warm starts go along, and the islands' kept factorizations
            // (`IslandLcp::basis_ws`): the copy steps as the original would.
            ws: Workspace { warm: self.ws.warm.clone(), pool: self.ws.pool.clone(), ..Workspace::default() },
            record: self.record.clone(),
            joints: self.joints.clone(),
            joint_params: self.joint_params,
            excluded: self.excluded.clone(),
            contact_pairs: self.contact_pairs.clone(),
        }
    }
}

/// Per-step buffers, kept between steps so that a warm step does not allocate
/// (apart from what the LCP solver itself allocates for its answer).
#[derive(Default)]
pub(crate) struct Workspace {
    /// Free velocities `v*`, `ω*` per body.
    pub v_free: Vec<Vec3>,
    pub w_free: Vec<Vec3>,
    /// Net external force and torque per body this step.
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// World-frame inverse inertia per body.
    pub inv_inertia: Vec<Mat3>,
    /// Sweep and prune, and how far each body can move this step (m/s).
    pub broad: BroadPhase,
    pub reach: Vec<f64>,
    /// Narrow-phase output for one pair.
    pub geom: Vec<GeomContact>,
    /// Contacts of this step.
    pub contacts: Vec<Contact>,
    /// Contact islands, and one LCP slot per island (slots are kept, never shrunk).
    pub islands: Islands,
    pub pool: Vec<IslandLcp>,
    /// The LCP solver's buffers, one per solving thread (Lemke's basis inverse, working problem, …).
    pub solvers: Vec<lcp::Workspace>,
    /// Bases of the previous step's islands.
    pub warm: WarmStarts,
    /// The record's basis buffer while the record holds none (its next basis is written into it).
    pub record_basis: Vec<bool>,
    /// What `contact_lcp` shows without contacts.
    pub no_lcp: ContactLcp,
    /// Velocity changes from the contact impulses.
    pub dv: Vec<Vec3>,
    pub dw: Vec<Vec3>,
    /// The `h` of the part being taken while a failed step is retaken in
    /// parts (`pipeline::retake`); `None` otherwise (`h = dt`).
    pub part_h: Option<f64>,
    /// The parts of the step being taken.
    pub parts: Parts,
    /// This step's joint rows, their factorization and impulses (`joints`).
    pub joints: crate::joints::JointSystem,
    /// This step's contact patches with torsional friction (`contact::torsion`).
    pub torsion: crate::contact::torsion::TorsionPatches,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World")
            .field("params", &self.params)
            .field("bodies", &self.bodies)
            .field("time", &self.time)
            .field("steps", &self.steps)
            .finish_non_exhaustive()
    }
}

impl World {
    /// An empty world with validated parameters.
    pub fn new(params: WorldParams) -> Result<World, SimError> {
        params.validate()?;
        Ok(World {
            params,
            bodies: Vec::new(),
            forces: Vec::new(),
            torques: Vec::new(),
            time: 0.0,
            steps: 0,
            sink: None,
            ws: Workspace::default(),
            record: StepRecord::default(),
            joints: Vec::new(),
            joint_params: Default::default(),
            excluded: Default::default(),
            contact_pairs: Default::default(),
        })
    }

    /// Parameters in force.
    pub fn params(&self) -> &WorldParams {
        &self.params
    }

    /// Replaces the parameters (validated first; on error nothing changes).
    pub fn set_params(&mut self, params: WorldParams) -> Result<(), SimError> {
        params.validate()?;
        self.params = params;
        Ok(())
    }

    /// Changes only the solver.
    pub fn set_method(&mut self, method: lcp::Method) {
        self.params.method = method;
    }

    /// Time at the start of the next step (s): `steps · dt` for a constant dt.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    // ----- bodies -----

    /// Adds a body after validating it.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyId, SimError> {
        let body = Body::from_desc(&desc)?;
        self.bodies.push(body);
        Ok(BodyId(self.bodies.len() - 1))
    }

    /// Adds a dynamic box (half extents in m, mass in kg) at `position`, upright, at rest.
    pub fn add_box(&mut self, half_extents: Vec3, mass: f64, position: Vec3, mu: f64) -> Result<BodyId, SimError> {
        self.add_body(BodyDesc::cuboid(half_extents).mass(mass).position(position).mu(mu))
    }

    /// Adds a dynamic solid sphere at `position`, at rest.
    pub fn add_sphere(&mut self, radius: f64, mass: f64, position: Vec3, mu: f64) -> Result<BodyId, SimError> {
        self.add_body(BodyDesc::sphere(radius).mass(mass).position(position).mu(mu))
    }

    /// Adds a static plane.
    pub fn add_plane(&mut self, plane: Plane, mu: f64) -> Result<BodyId, SimError> {
        self.add_body(BodyDesc::plane(plane).mu(mu))
    }

    /// Adds the static level ground `z = 0`.
    pub fn add_ground(&mut self, mu: f64) -> Result<BodyId, SimError> {
        self.add_plane(Plane::ground(), mu)
    }

    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// All bodies, in `BodyId` order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// One body.
    pub fn body(&self, id: BodyId) -> Result<&Body, SimError> {
        self.bodies.get(id.0).ok_or(SimError::UnknownBody { index: id.0, bodies: self.bodies.len() })
    }

    fn body_mut(&mut self, id: BodyId) -> Result<&mut Body, SimError> {
        let n = self.bodies.len();
        self.bodies.get_mut(id.0).ok_or(SimError::UnknownBody { index: id.0, bodies: n })
    }

    fn dynamic_mut(&mut self, id: BodyId) -> Result<&mut Body, SimError> {
        let b = self.body_mut(id)?;
        if b.is_static {
            return Err(SimError::StaticBody { index: id.0 });
        }
        Ok(b)
    }

    /// A body that can be placed: any but a plane (static boxes and spheres too).
    fn placeable_mut(&mut self, id: BodyId) -> Result<&mut Body, SimError> {
        let b = self.body_mut(id)?;
        if matches!(b.shape, Shape::Plane(_)) {
            return Err(SimError::StaticBody { index: id.0 });
        }
        Ok(b)
    }

    /// Moves a body (static boxes and spheres too; planes cannot move).
    pub fn set_position(&mut self, id: BodyId, p: Vec3) -> Result<(), SimError> {
        finite_vec("position", p)?;
        self.placeable_mut(id)?.position = p;
        Ok(())
    }

    /// Sets the orientation (normalized; a zero quaternion is an error).
    pub fn set_orientation(&mut self, id: BodyId, q: Quat) -> Result<(), SimError> {
        let q = crate::dynamics::body::normalize_quat(q)?;
        self.placeable_mut(id)?.orientation = q;
        Ok(())
    }

    /// Sets the linear velocity of a dynamic body.
    pub fn set_velocity(&mut self, id: BodyId, v: Vec3) -> Result<(), SimError> {
        finite_vec("velocity", v)?;
        self.dynamic_mut(id)?.velocity = v;
        Ok(())
    }

    /// Sets the angular velocity (world frame) of a dynamic body.
    pub fn set_angular_velocity(&mut self, id: BodyId, w: Vec3) -> Result<(), SimError> {
        finite_vec("angular_velocity", w)?;
        self.dynamic_mut(id)?.angular_velocity = w;
        Ok(())
    }

    /// How the broad phase finds its candidate pairs (`BroadMethod::Auto` by
    /// default, and in a copy; every method gives the same pairs, so the same trajectory).
    pub fn set_broad_method(&mut self, method: crate::broad_phase::BroadMethod) {
        self.ws.broad.method = method;
    }

    /// Sets a body's friction coefficient.
    pub fn set_mu(&mut self, id: BodyId, mu: f64) -> Result<(), SimError> {
        non_negative("mu", mu)?;
        self.body_mut(id)?.mu = mu;
        Ok(())
    }

    /// Sets a body's torsional friction coefficient μ_t (m, ≥ 0; MuJoCo's
    /// `friction[1]` with condim 4): each contact patch of two or more points
    /// it makes gets friction about its normal bounded by μ_t (the larger of
    /// the pair's) times the patch's normal load (`contact::torsion`).
    pub fn set_torsional_friction(&mut self, id: BodyId, mu_torsion: f64) -> Result<(), SimError> {
        non_negative("torsional_friction", mu_torsion)?;
        self.body_mut(id)?.mu_torsion = mu_torsion;
        Ok(())
    }

    /// Sets which bodies this one may touch (MuJoCo's contype/conaffinity rule,
    /// [`crate::CollisionFilter`]); any body, static ones and planes too.
    pub fn set_collision_filter(&mut self, id: BodyId, contype: u32, conaffinity: u32) -> Result<(), SimError> {
        self.body_mut(id)?.filter = crate::CollisionFilter::new(contype, conaffinity);
        Ok(())
    }

    /// Keeps bodies `a` and `b` from touching whatever their collision bits
    /// (MJCF's `<contact><exclude>`; MuJoCo's parent filter). Two different bodies.
    pub fn exclude_pair(&mut self, a: BodyId, b: BodyId) -> Result<(), SimError> {
        self.two_bodies(a, b)?;
        self.excluded.insert(a.0, b.0, ());
        Ok(())
    }

    /// Makes bodies `a` and `b` touch whatever their collision bits and
    /// exclusions, their contacts with friction coefficient `mu` (≥ 0; 0 is
    /// frictionless) in place of the bodies' combined one (MJCF's
    /// `<contact><pair>`; `WorldParams::mu_override` still wins). Two different
    /// bodies, not both static; bodies joined by a joint still never touch.
    /// Given again, the pair takes the new `mu`.
    pub fn add_contact_pair(&mut self, a: BodyId, b: BodyId, mu: f64) -> Result<(), SimError> {
        self.two_bodies(a, b)?;
        non_negative("mu", mu)?;
        if self.bodies[a.0].is_static && self.bodies[b.0].is_static {
            return Err(SimError::OutOfRange {
                field: "body_b",
                value: b.0 as f64,
                range: "the moving bodies (two static bodies never touch)",
            });
        }
        self.contact_pairs.insert(a.0, b.0, mu);
        Ok(())
    }

    /// The pairs [`World::add_contact_pair`] makes touch (lower index first,
    /// sorted) and their μ, in the same order.
    pub fn contact_pairs(&self) -> (&[(usize, usize)], &[f64]) {
        (self.contact_pairs.as_slice(), self.contact_pairs.values())
    }

    /// Checks that `a` and `b` are two different bodies of this world.
    fn two_bodies(&self, a: BodyId, b: BodyId) -> Result<(), SimError> {
        self.body(a)?;
        self.body(b)?;
        if a == b {
            return Err(SimError::OutOfRange {
                field: "body_b",
                value: b.0 as f64,
                range: "the bodies other than body_a",
            });
        }
        Ok(())
    }

    /// The pairs [`World::exclude_pair`] keeps apart, lower index first, sorted.
    pub fn excluded_pairs(&self) -> &[(usize, usize)] {
        self.excluded.as_slice()
    }

    // ----- external forces -----

    /// Applies a constant force (world frame, N) every step until
    /// [`World::clear_forces`]. `point` is relative to the centre of mass in
    /// the body frame (it moves with the body); `None` acts at the centre of
    /// mass. Gravity is separate (`WorldParams::gravity`).
    pub fn apply_force(&mut self, id: BodyId, force: Vec3, point: Option<Vec3>) -> Result<(), SimError> {
        finite_vec("force", force)?;
        if let Some(p) = point {
            finite_vec("point", p)?;
        }
        self.dynamic_mut(id)?;
        self.forces.push(AppliedForce { body: id.0, force, point });
        Ok(())
    }

    /// Applies a constant torque (world frame, N·m) every step until cleared.
    pub fn apply_torque(&mut self, id: BodyId, torque: Vec3) -> Result<(), SimError> {
        finite_vec("torque", torque)?;
        self.dynamic_mut(id)?;
        self.torques.push(AppliedTorque { body: id.0, torque });
        Ok(())
    }

    /// Removes all applied forces and torques.
    pub fn clear_forces(&mut self) {
        self.forces.clear();
        self.torques.clear();
    }

    /// Forces currently applied.
    pub fn applied_forces(&self) -> &[AppliedForce] {
        &self.forces
    }

    /// Torques currently applied.
    pub fn applied_torques(&self) -> &[AppliedTorque] {
        &self.torques
    }

    // ----- LCP capture -----

    /// Hands every solved LCP to `sink` from now on (replacing any previous one).
    pub fn set_sink(&mut self, sink: Box<dyn LcpSink>) {
        self.sink = Some(sink);
    }

    /// Stops capturing and returns the sink.
    pub fn take_sink(&mut self) -> Option<Box<dyn LcpSink>> {
        self.sink.take()
    }

    // ----- observation -----

    /// The record of the last step (empty before the first).
    pub fn last_record(&self) -> &StepRecord {
        &self.record
    }

    /// Total mechanical energy: kinetic + gravitational potential `−m g·x` (J).
    pub fn energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| !b.is_static)
            .map(|b| b.kinetic_energy() - b.mass * self.params.gravity.dot(b.position))
            .sum()
    }
}
