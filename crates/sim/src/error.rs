//! `SimError`: invalid input to the simulator, naming the offending field and value.
//!
//! Invalid parameters are errors (the Python layer turns them into
//! `ValueError`); solver trouble never is — that is a `Status` in the step
//! record (see `pipeline::StepRecord`).

use std::fmt;

/// Why a body, shape, force or world parameter was rejected.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// A quantity that must be `> 0` is not (mass, dt, box half extent, radius, inertia).
    NotPositive { field: &'static str, value: f64 },
    /// A quantity that must be `≥ 0` is negative (μ, margin, slop, …).
    Negative { field: &'static str, value: f64 },
    /// A quantity that must lie in a range does not (`range` says which, e.g. "[0, 1]").
    OutOfRange { field: &'static str, value: f64, range: &'static str },
    /// An input is NaN or infinite.
    NonFinite { field: &'static str, value: f64 },
    /// A quaternion (or a direction vector) of zero length cannot be normalized.
    ZeroLength { field: &'static str },
    /// The number of friction directions `k` must be even and ≥ 2.
    FrictionDirs { k: usize },
    /// A body index that the world does not hold.
    UnknownBody { index: usize, bodies: usize },
    /// A joint index that the world does not hold.
    UnknownJoint { index: usize, joints: usize },
    /// An operation that needs a dynamic body got a static one (forces on static bodies).
    StaticBody { index: usize },
    /// Planes are infinite: they can only be static.
    DynamicPlane,
    /// Shapes that can only be static (meshes), given a dynamic body.
    StaticOnly { kind: &'static str },
    /// Geometry data (hull points, mesh vertices and faces) that does not make its shape.
    BadGeometry { field: &'static str, reason: String },
    /// An inertia tensor that is not symmetric positive definite.
    BadInertia { reason: &'static str },
    /// The state or the external forces became non-finite during a step, so the
    /// contact LCP could not even be formed.
    NonFiniteState { body: usize },
    /// The assembled LCP was rejected by `lcp::Lcp::new` (non-finite data).
    Lcp(lcp::LcpError),
    /// A size (of a scene, an island's LCP, a trajectory) that would not fit in memory.
    TooLarge(lcp::limits::SizeError),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::NotPositive { field, value } => write!(f, "{field} must be > 0, got {}", num(*value)),
            SimError::Negative { field, value } => write!(f, "{field} must be >= 0, got {}", num(*value)),
            SimError::OutOfRange { field, value, range } => {
                write!(f, "{field} must be in {range}, got {}", num(*value))
            }
            SimError::NonFinite { field, value } => write!(f, "{field} must be finite, got {}", num(*value)),
            SimError::ZeroLength { field } => write!(f, "{field} has zero length and cannot be normalized"),
            SimError::FrictionDirs { k } if *k > crate::contact::friction::MAX_FRICTION_DIRS => {
                write!(
                    f,
                    "friction_dirs must be even and in [2, {}], got {k}",
                    crate::contact::friction::MAX_FRICTION_DIRS
                )
            }
            SimError::FrictionDirs { k } => write!(f, "friction_dirs must be even and >= 2, got {k}"),
            SimError::UnknownBody { index, bodies } => {
                write!(f, "body {index} does not exist (the world has {bodies} bodies)")
            }
            SimError::UnknownJoint { index, joints } => {
                write!(f, "joint {index} does not exist (the world has {joints} joints)")
            }
            SimError::StaticBody { index } => write!(f, "body {index} is static"),
            SimError::DynamicPlane => write!(f, "a plane must be static"),
            SimError::StaticOnly { kind } => write!(f, "a {kind} must be static"),
            SimError::BadGeometry { field, reason } => write!(f, "{field} {reason}"),
            SimError::BadInertia { reason } => write!(f, "inertia tensor {reason}"),
            SimError::NonFiniteState { body } => write!(f, "body {body} has a non-finite state"),
            SimError::Lcp(e) => write!(f, "contact LCP: {e}"),
            SimError::TooLarge(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SimError {}

/// A value for a message: plain decimals, exponent form for the very small
/// or very large (`1e-300`, not three hundred zeros).
fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

// Small checks shared by every constructor, so that each field is named once.

pub(crate) fn finite(field: &'static str, value: f64) -> Result<f64, SimError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SimError::NonFinite { field, value })
    }
}

pub(crate) fn positive(field: &'static str, value: f64) -> Result<f64, SimError> {
    finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(SimError::NotPositive { field, value })
    }
}

pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<f64, SimError> {
    finite(field, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(SimError::Negative { field, value })
    }
}

pub(crate) fn finite_vec(field: &'static str, v: crate::math::Vec3) -> Result<crate::math::Vec3, SimError> {
    for c in v.to_array() {
        finite(field, c)?;
    }
    Ok(v)
}

pub(crate) fn in_range(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<f64, SimError> {
    finite(field, value)?;
    if value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(SimError::OutOfRange { field, value, range })
    }
}
