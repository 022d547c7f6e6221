//! Planes: `n·x = offset`, solid on the side `n·x ≤ offset`, with the
//! friction tangent that contacts with the plane use.

use crate::error::{finite, finite_vec, SimError};
use crate::math::Vec3;

/// Which way a slope goes down, for [`Plane::slope`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Downhill {
    /// The surface descends towards `+x`: normal `(sin θ, 0, cos θ)`.
    PlusX,
    /// The surface descends towards `−x`: normal `(−sin θ, 0, cos θ)`.
    MinusX,
}

/// An infinite plane `{x : n·x = offset}` with unit normal `n` pointing out of
/// the solid (the solid is `n·x ≤ offset`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    normal: Vec3,
    offset: f64,
    tangent: Vec3,
}

/// Below this horizontal component of the normal a plane counts as level
/// (no downhill direction); a deliberate slope is far steeper.
const LEVEL_TOL: f64 = 1e-12;

impl Plane {
    /// Plane with normal along `normal` (normalized here) and `n·x = offset`.
    /// Its friction tangent defaults to [`Plane::downhill`] when tilted, else
    /// to the world x axis projected into the plane (`y` for a vertical x-wall).
    pub fn new(normal: Vec3, offset: f64) -> Result<Plane, SimError> {
        finite_vec("normal", normal)?;
        finite("offset", offset)?;
        let n = normal.try_normalize().ok_or(SimError::ZeroLength { field: "normal" })?;
        let tangent = downhill_of(n).unwrap_or_else(|| fixed_tangent(n));
        Ok(Plane { normal: n, offset, tangent })
    }

    /// The level ground `z = 0`.
    pub fn ground() -> Plane {
        Plane { normal: Vec3::Z, offset: 0.0, tangent: Vec3::X }
    }

    /// Horizontal plane `z = height`.
    pub fn horizontal(height: f64) -> Result<Plane, SimError> {
        Plane::new(Vec3::Z, height)
    }

    /// A slope through the origin at `angle` (rad, in [0, π/2)) from the
    /// horizontal, descending towards `toward`; its friction tangent is the
    /// downhill direction `(±cos θ, 0, −sin θ)` so that a body sliding down it
    /// moves along a friction direction.
    pub fn slope(angle: f64, toward: Downhill) -> Result<Plane, SimError> {
        crate::error::in_range("angle", angle, 0.0, std::f64::consts::FRAC_PI_2 - 1e-12, "[0, pi/2)")?;
        let (s, c) = angle.sin_cos();
        let sign = match toward {
            Downhill::PlusX => 1.0,
            Downhill::MinusX => -1.0,
        };
        Plane::new(Vec3::new(sign * s, 0.0, c), 0.0)
    }

    /// [`Plane::slope`] with the angle in degrees.
    pub fn slope_deg(angle_deg: f64, toward: Downhill) -> Result<Plane, SimError> {
        Plane::slope(finite("angle_deg", angle_deg)?.to_radians(), toward)
    }

    /// The same plane moved so that `n·x = offset`.
    pub fn with_offset(mut self, offset: f64) -> Result<Plane, SimError> {
        self.offset = finite("offset", offset)?;
        Ok(self)
    }

    /// The same plane with another friction tangent (projected into the plane
    /// and normalized) — e.g. to put the downhill direction between two
    /// friction directions.
    pub fn with_friction_tangent(mut self, t: Vec3) -> Result<Plane, SimError> {
        finite_vec("tangent", t)?;
        let n = self.normal;
        self.tangent = (t - n * n.dot(t)).try_normalize().ok_or(SimError::ZeroLength { field: "tangent" })?;
        Ok(self)
    }

    /// Unit outward normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Offset: the plane is `normal·x = offset`.
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// First friction direction `d_0` of contacts with this plane.
    pub fn friction_tangent(&self) -> Vec3 {
        self.tangent
    }

    /// Direction of steepest descent in the plane (unit, the projection of
    /// `−z` onto the plane), or `None` for a level plane. For
    /// `slope(θ, PlusX)` this is `(cos θ, 0, −sin θ)`.
    pub fn downhill(&self) -> Option<Vec3> {
        downhill_of(self.normal)
    }

    /// Signed distance of `x` from the plane (positive outside the solid).
    pub fn distance(&self, x: Vec3) -> f64 {
        self.normal.dot(x) - self.offset
    }
}

fn downhill_of(n: Vec3) -> Option<Vec3> {
    if (n.x * n.x + n.y * n.y).sqrt() <= LEVEL_TOL {
        return None;
    }
    (-Vec3::Z + n * n.z).try_normalize()
}

/// Deterministic tangent for contacts without a preferred one: the world x
/// axis projected into the tangent plane, or y when the normal is close to x.
pub fn fixed_tangent(n: Vec3) -> Vec3 {
    let e = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    (e - n * n.dot(e)).try_normalize().unwrap_or(Vec3::Y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_downhill_is_along_x() {
        let th = 30f64.to_radians();
        let p = Plane::slope(th, Downhill::PlusX).unwrap();
        let d = p.downhill().unwrap();
        assert!((d - Vec3::new(th.cos(), 0.0, -th.sin())).max_abs() < 1e-15);
        assert!(p.normal().dot(d).abs() < 1e-15);
        assert_eq!(p.friction_tangent(), d);
        let m = Plane::slope(th, Downhill::MinusX).unwrap();
        assert!((m.downhill().unwrap() - Vec3::new(-th.cos(), 0.0, -th.sin())).max_abs() < 1e-15);
        assert!(Plane::ground().downhill().is_none());
    }

    #[test]
    fn zero_normal_is_rejected() {
        assert_eq!(Plane::new(Vec3::ZERO, 0.0), Err(SimError::ZeroLength { field: "normal" }));
    }
}
