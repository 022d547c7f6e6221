//! Constant external forces and torques, kept by the world until cleared.

use crate::math::Vec3;

/// A constant force on a body, applied every step until `World::clear_forces`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppliedForce {
    /// Body index.
    pub body: usize,
    /// Force in the world frame (N).
    pub force: Vec3,
    /// Point of application relative to the centre of mass **in the body
    /// frame** (so it moves with the body); `None` = at the centre of mass
    /// (no torque).
    pub point: Option<Vec3>,
}

/// A constant torque on a body (world frame, N·m), applied every step until cleared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppliedTorque {
    pub body: usize,
    pub torque: Vec3,
}
