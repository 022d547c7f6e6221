//! Contact records: the geometric part from the pair functions, the full
//! contact (bodies, μ, friction tangent) from the world's detect stage.

use crate::math::Vec3;

/// What a pair function finds: a point, a normal from B to A, a gap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomContact {
    /// Contact point in world coordinates (midway between the two surfaces).
    pub point: Vec3,
    /// Unit normal pointing from body B to body A.
    pub normal: Vec3,
    /// Signed gap φ along `normal` (m); negative means penetration.
    pub gap: f64,
}

/// A contact as it enters the LCP.
///
/// Sign convention: the normal impulse `fn ≥ 0` acts on `body_a` along
/// `+normal` at `point` and on `body_b` along `−normal`; friction impulses
/// `fd_j ≥ 0` act on A along `+d_j` and on B along `−d_j`, where
/// `d_j = cos(2πj/k)·tangent + sin(2πj/k)·(normal × tangent)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Body pushed along `+normal` (index into the world's bodies).
    pub body_a: usize,
    /// Body pushed along `−normal`.
    pub body_b: usize,
    /// Contact point (world frame).
    pub point: Vec3,
    /// Unit normal from B to A.
    pub normal: Vec3,
    /// Signed gap φ (m), negative = penetration.
    pub gap: f64,
    /// Friction coefficient of the pair (see `contact::MuCombine`).
    pub mu: f64,
    /// First friction direction `t1 = d_0`: unit, orthogonal to `normal`.
    /// For contacts with a tilted plane it is the plane's downhill direction.
    pub tangent: Vec3,
}
