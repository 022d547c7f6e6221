//! A joint's kind, its bodies, and its anchor and axes kept in each body's
//! frame (so they move with the bodies); validation of what a user gives.

use crate::dynamics::Body;
use crate::error::{finite_vec, in_range, SimError};
use crate::math::{Quat, Vec3};

/// Index of a joint in its world (the order of `add_joint` calls, from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

/// What a joint leaves free between its two bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// The anchor points coincide: 3 rows, rotation free.
    Ball,
    /// A ball joint whose axis stays aligned: 5 rows, rotation about the axis free.
    Hinge,
    /// Relative rotation locked and the anchors on one line along the axis:
    /// 5 rows, translation along the axis free.
    Slider,
    /// Nothing free: 6 rows.
    Fixed,
}

impl JointKind {
    /// Constraint rows of this kind.
    pub fn rows(self) -> usize {
        match self {
            JointKind::Ball => 3,
            JointKind::Hinge | JointKind::Slider => 5,
            JointKind::Fixed => 6,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            JointKind::Ball => "ball",
            JointKind::Hinge => "hinge",
            JointKind::Slider => "slider",
            JointKind::Fixed => "fixed",
        }
    }
}

/// Everything needed to add a joint; checked by `World::add_joint`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointDesc {
    pub kind: JointKind,
    /// The first body; `None` is the world (a static body works as the world does).
    pub body_a: Option<usize>,
    /// The second body (a dynamic body unless `body_a` is one).
    pub body_b: usize,
    /// The joint's anchor in the world at creation (m).
    pub anchor: Vec3,
    /// The hinge or slider axis in the world at creation (any length > 0;
    /// ignored by ball and fixed joints).
    pub axis: Vec3,
    /// `(lower, upper)` of a hinge's angle (rad) or a slider's displacement
    /// (m) from where it was created (`joints::limits`); `None`: free.
    pub limits: Option<(f64, f64)>,
}

/// A validated joint, its geometry in each body's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub kind: JointKind,
    /// The bodies of sides A and B (`None`: the world).
    pub bodies: [Option<usize>; 2],
    /// The anchor relative to each side's centre of mass, in its frame (the
    /// world's: the anchor itself).
    pub anchor: [Vec3; 2],
    /// The unit axis in each side's frame.
    pub axis: [Vec3; 2],
    /// A unit vector normal to the axis in each side's frame: the hinge angle's zero.
    pub reference: [Vec3; 2],
    /// `q_A⁻¹ q_B` at creation: the relative orientation fixed and slider joints keep.
    pub rest: Quat,
    /// The hinge's or slider's `(lower, upper)`, if limited.
    pub limits: Option<(f64, f64)>,
    /// A velocity motor on the hinge or slider (`joints::limits`), if any.
    pub motor: Option<Motor>,
    /// Viscous damping of a hinge's or slider's rate (N·m·s/rad, N·s/m): a
    /// force `−d·q̇`, integrated implicitly (`rows`); 0: none.
    pub damping: f64,
}

/// A velocity motor: drives the joint's rate (rad/s, m/s) to `speed` with at
/// most `max_force` (N·m, N) either way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    pub speed: f64,
    pub max_force: f64,
}

/// A joint's reaction over the last step: what side A exerted on side B,
/// as a mean force at the anchor and a mean torque about it (N, N·m; the
/// impulses divided by the step).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointReaction {
    pub force: Vec3,
    pub torque: Vec3,
}

/// The knobs of the joint rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointParams {
    /// Baumgarte factor `β` of the joints' drift correction: each step asks
    /// `G v⁺ = −β C / h`, removing the fraction `β` of the position error `C`
    /// (to first order) in one step. Separate from the contacts'
    /// stabilization. In `[0, 1]`; default 1 (the whole error: what is left
    /// after a step is the second-order term of the motion, `~h²ω²r`).
    pub drift: f64,
    /// Relative pivot below which the pivoted Cholesky of `S = G M⁻¹ Gᵀ`
    /// stops (a row whose remaining pivot is below `rank_tol · max diag S`
    /// depends on the rows before it and is dropped). Default 1e-9.
    pub rank_tol: f64,
    /// Position projections after each step (post-stabilization, Cline and
    /// Pai 2003): `Δx = M⁻¹ Gᵀ S⁺ (−C)` at the new poses, repeated while a
    /// row's error exceeds [`JointParams::settle_tol`]. The velocity rows are
    /// linear in the step: a link turning at ω leaves an error `~h²ω²r`
    /// (0.13 mm on a whipping 5-link chain at h = 1 ms) that the next step's
    /// `β` would only chase. Velocities are not changed. Default 3; 0 turns it off.
    pub settle_passes: u32,
    /// Error (m, rad) below which no more projection is made. Default 1e-10.
    pub settle_tol: f64,
}

impl Default for JointParams {
    fn default() -> Self {
        JointParams { drift: 1.0, rank_tol: 1e-9, settle_passes: 3, settle_tol: 1e-10 }
    }
}

impl JointParams {
    pub fn validate(&self) -> Result<(), SimError> {
        in_range("joint_drift", self.drift, 0.0, 1.0, "[0, 1]")?;
        in_range("joint_rank_tol", self.rank_tol, 0.0, 1.0, "[0, 1]")?;
        in_range("joint_settle_tol", self.settle_tol, 0.0, 1.0, "[0, 1]")?;
        Ok(())
    }
}

/// Limits of a hinge or slider: not NaN, `lower ≤ upper` (infinite ends allowed).
pub(crate) fn check_limits(kind: JointKind, limits: Option<(f64, f64)>) -> Result<Option<(f64, f64)>, SimError> {
    let Some((lo, hi)) = limits else { return Ok(None) };
    if !matches!(kind, JointKind::Hinge | JointKind::Slider) {
        return Err(SimError::BadGeometry {
            field: "limits",
            reason: format!("are for hinges and sliders, not a {} joint", kind.name()),
        });
    }
    for (field, v) in [("limits.lower", lo), ("limits.upper", hi)] {
        if v.is_nan() {
            return Err(SimError::NonFinite { field, value: v });
        }
    }
    if lo > hi {
        return Err(SimError::BadGeometry {
            field: "limits",
            reason: format!("must have lower <= upper, got ({lo}, {hi})"),
        });
    }
    Ok(Some((lo, hi)))
}

/// A motor for a joint of `kind`: a hinge or slider, a finite speed, a finite `max_force ≥ 0`.
pub(crate) fn check_motor(kind: JointKind, speed: f64, max_force: f64) -> Result<Motor, SimError> {
    if !matches!(kind, JointKind::Hinge | JointKind::Slider) {
        return Err(SimError::BadGeometry {
            field: "motor",
            reason: format!("is for hinges and sliders, not a {} joint", kind.name()),
        });
    }
    crate::error::finite("speed", speed)?;
    crate::error::non_negative("max_force", max_force)?;
    Ok(Motor { speed, max_force })
}

/// Damping for a joint of `kind`: a hinge or slider, a finite `d ≥ 0`.
pub(crate) fn check_damping(kind: JointKind, d: f64) -> Result<f64, SimError> {
    if !matches!(kind, JointKind::Hinge | JointKind::Slider) {
        return Err(SimError::BadGeometry {
            field: "damping",
            reason: format!("is for hinges and sliders, not a {} joint", kind.name()),
        });
    }
    crate::error::non_negative("damping", d)?;
    Ok(d)
}

/// Where a side is: `(position, orientation)`; the world's is the origin.
pub(crate) fn pose(bodies: &[Body], side: Option<usize>) -> (Vec3, Quat) {
    side.map_or((Vec3::ZERO, Quat::IDENTITY), |b| (bodies[b].position, bodies[b].orientation))
}

/// A unit vector normal to the unit `a`.
pub(crate) fn normal_to(a: Vec3) -> Vec3 {
    let t = if a.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    (t - a * t.dot(a)).try_normalize().unwrap_or(Vec3::Z)
}

impl Joint {
    /// Checks `d` against `bodies` and keeps its geometry in the bodies' frames.
    pub fn new(d: &JointDesc, bodies: &[Body]) -> Result<Joint, SimError> {
        let nb = bodies.len();
        for b in d.body_a.into_iter().chain([d.body_b]) {
            if b >= nb {
                return Err(SimError::UnknownBody { index: b, bodies: nb });
            }
        }
        if d.body_a == Some(d.body_b) {
            return Err(SimError::BadGeometry {
                field: "body_b",
                reason: format!("is body_a ({}): a joint needs two bodies", d.body_b),
            });
        }
        let dynamic = |b: Option<usize>| b.is_some_and(|b| !bodies[b].is_static);
        if !dynamic(Some(d.body_b)) && !dynamic(d.body_a) {
            return Err(SimError::StaticBody { index: d.body_b });
        }
        finite_vec("anchor", d.anchor)?;
        finite_vec("axis", d.axis)?;
        let axis = match d.kind {
            JointKind::Ball | JointKind::Fixed => d.axis.try_normalize().unwrap_or(Vec3::Z),
            _ => d.axis.try_normalize().ok_or(SimError::ZeroLength { field: "axis" })?,
        };
        let reference = normal_to(axis);
        let limits = check_limits(d.kind, d.limits)?;
        let sides = [d.body_a, Some(d.body_b)];
        let local = |f: &dyn Fn(Vec3, Quat) -> Vec3| {
            sides.map(|s| {
                let (p, q) = pose(bodies, s);
                f(p, q)
            })
        };
        let anchor = local(&|p, q| q.inverse_rotate(d.anchor - p));
        let axis_local = local(&|_, q| q.inverse_rotate(axis));
        let reference_local = local(&|_, q| q.inverse_rotate(reference));
        let (qa, qb) = (pose(bodies, sides[0]).1, pose(bodies, sides[1]).1);
        Ok(Joint {
            kind: d.kind,
            bodies: sides,
            anchor,
            axis: axis_local,
            reference: reference_local,
            rest: qa.conjugate() * qb,
            limits,
            motor: None,
            damping: 0.0,
        })
    }

    /// The dynamic bodies of the joint (a static body's side is like the world's).
    pub fn dynamic_side(&self, bodies: &[Body], side: usize) -> Option<usize> {
        self.bodies[side].filter(|&b| !bodies[b].is_static)
    }

    /// The anchor in the world as each side carries it.
    pub fn anchors_world(&self, bodies: &[Body]) -> [Vec3; 2] {
        [0, 1].map(|s| {
            let (p, q) = pose(bodies, self.bodies[s]);
            p + q.rotate(self.anchor[s])
        })
    }

    /// The hinge angle of B relative to A about the axis (rad, 0 at creation).
    pub fn angle(&self, bodies: &[Body]) -> f64 {
        let (qa, qb) = (pose(bodies, self.bodies[0]).1, pose(bodies, self.bodies[1]).1);
        let a = qa.rotate(self.axis[0]);
        let (ua, ub) = (qa.rotate(self.reference[0]), qb.rotate(self.reference[1]));
        ua.cross(ub).dot(a).atan2(ua.dot(ub))
    }

    /// The slider's displacement of B's anchor from A's along the axis (m, 0 at creation).
    pub fn displacement(&self, bodies: &[Body]) -> f64 {
        let [xa, xb] = self.anchors_world(bodies);
        let a = pose(bodies, self.bodies[0]).1.rotate(self.axis[0]);
        a.dot(xb - xa)
    }

    /// The joint's coordinate: a slider's [`Joint::displacement`], any other's [`Joint::angle`].
    pub fn coordinate(&self, bodies: &[Body]) -> f64 {
        match self.kind {
            JointKind::Slider => self.displacement(bodies),
            _ => self.angle(bodies),
        }
    }
}
