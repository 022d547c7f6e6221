//! `Quat`: rotation quaternions stored as (w, x, y, z), rotating body → world.

use super::{Mat3, Vec3};
use std::ops::Mul;

/// A quaternion `w + x i + y j + z k`. Orientations are unit quaternions that
/// rotate body-frame vectors into the world frame: `v_world = q ⊗ v_body ⊗ q*`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quat {
    pub w: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl Default for Quat {
    /// The identity rotation.
    fn default() -> Self {
        Quat::IDENTITY
    }
}

impl Quat {
    pub const IDENTITY: Quat = Quat { w: 1.0, x: 0.0, y: 0.0, z: 0.0 };

    #[inline]
    pub const fn new(w: f64, x: f64, y: f64, z: f64) -> Self {
        Quat { w, x, y, z }
    }

    /// From `[w, x, y, z]`.
    #[inline]
    pub fn from_array(a: [f64; 4]) -> Self {
        Quat::new(a[0], a[1], a[2], a[3])
    }

    /// As `[w, x, y, z]`.
    #[inline]
    pub fn to_array(self) -> [f64; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// Rotation by `angle` (rad) about `axis` (need not be unit; identity when zero).
    pub fn from_axis_angle(axis: Vec3, angle: f64) -> Quat {
        match axis.try_normalize() {
            Some(a) => {
                let (s, c) = (0.5 * angle).sin_cos();
                Quat::new(c, a.x * s, a.y * s, a.z * s)
            }
            None => Quat::IDENTITY,
        }
    }

    /// The rotation vector `θ·axis` as a quaternion (exponential map).
    pub fn from_rotation_vector(r: Vec3) -> Quat {
        Quat::from_axis_angle(r, r.norm())
    }

    #[inline]
    pub fn vector(self) -> Vec3 {
        Vec3::new(self.x, self.y, self.z)
    }

    #[inline]
    pub fn norm(self) -> f64 {
        (self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    #[inline]
    pub fn conjugate(self) -> Quat {
        Quat::new(self.w, -self.x, -self.y, -self.z)
    }

    /// Unit quaternion along `self`, or `None` for a zero or non-finite quaternion.
    #[inline]
    pub fn try_normalize(self) -> Option<Quat> {
        let n = self.norm();
        if n > 0.0 && n.is_finite() {
            Some(Quat::new(self.w / n, self.x / n, self.y / n, self.z / n))
        } else {
            None
        }
    }

    #[inline]
    pub fn is_finite(self) -> bool {
        self.w.is_finite() && self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// Rotates `v` (assumes a unit quaternion): `v + 2w (u×v) + 2 u×(u×v)`.
    #[inline]
    pub fn rotate(self, v: Vec3) -> Vec3 {
        let u = self.vector();
        let t = u.cross(v) * 2.0;
        v + t * self.w + u.cross(t)
    }

    /// Rotates `v` by the inverse rotation (world → body).
    #[inline]
    pub fn inverse_rotate(self, v: Vec3) -> Vec3 {
        self.conjugate().rotate(v)
    }

    /// The rotation matrix `R` with `R v = self.rotate(v)`; its columns are the body axes in world.
    pub fn to_mat3(self) -> Mat3 {
        let Quat { w, x, y, z } = self;
        Mat3::from_rows([
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
            [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
            [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
        ])
    }

    /// The unit quaternion of a rotation matrix (Shepperd's method: the
    /// largest of `w`, `x`, `y`, `z` is taken from the diagonal, the others
    /// from sums and differences of the off-diagonal entries), with `w ≥ 0`
    /// when the trace is positive. Inverse of [`Quat::to_mat3`] up to sign.
    pub fn from_mat3(r: &Mat3) -> Quat {
        let m = &r.m;
        let t = m[0][0] + m[1][1] + m[2][2];
        let q = if t > 0.0 {
            let s = (t + 1.0).sqrt() * 2.0;
            Quat::new(0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s)
        } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
            let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
            Quat::new((m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s)
        } else if m[1][1] > m[2][2] {
            let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
            Quat::new((m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s)
        } else {
            let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
            Quat::new((m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s)
        };
        q.try_normalize().unwrap_or(Quat::IDENTITY)
    }

    /// Rotation angle in [0, π] of the relative rotation between `self` and `other`.
    pub fn angle_to(self, other: Quat) -> f64 {
        let d = (self.conjugate() * other).w.abs().min(1.0);
        2.0 * d.acos()
    }

    /// One explicit step `q + h/2·(0, ω) ⊗ q` for a world-frame angular velocity,
    /// renormalized (the renormalization is what keeps the integrator stable).
    /// Returns `self` unchanged if the result cannot be normalized.
    pub fn integrate(self, omega: Vec3, h: f64) -> Quat {
        let dq = Quat::new(0.0, omega.x, omega.y, omega.z) * self;
        let q = Quat::new(
            self.w + 0.5 * h * dq.w,
            self.x + 0.5 * h * dq.x,
            self.y + 0.5 * h * dq.y,
            self.z + 0.5 * h * dq.z,
        );
        q.try_normalize().unwrap_or(self)
    }
}

impl Mul for Quat {
    type Output = Quat;
    /// Hamilton product: `(a * b).rotate(v) == a.rotate(b.rotate(v))`.
    #[inline]
    fn mul(self, b: Quat) -> Quat {
        let a = self;
        Quat::new(
            a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).max_abs() < 1e-14
    }

    #[test]
    fn rotate_matches_matrix_and_composition() {
        let a = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0), 0.7);
        let b = Quat::from_axis_angle(Vec3::new(-1.0, 0.5, 0.2), -1.3);
        let v = Vec3::new(0.3, -2.0, 1.1);
        assert!(close(a.rotate(v), a.to_mat3() * v));
        assert!(close((a * b).rotate(v), a.rotate(b.rotate(v))));
        assert!(close(a.inverse_rotate(a.rotate(v)), v));
    }

    #[test]
    fn from_mat3_inverts_to_mat3() {
        for (axis, angle) in
            [(Vec3::X, 0.3), (Vec3::new(1.0, 2.0, 3.0), 2.9), (Vec3::Y, -3.0), (Vec3::Z, 3.1), (Vec3::X, 3.14)]
        {
            let q = Quat::from_axis_angle(axis, angle);
            let back = Quat::from_mat3(&q.to_mat3());
            // q and −q are the same rotation.
            let sign = if back.w * q.w + back.x * q.x + back.y * q.y + back.z * q.z < 0.0 { -1.0 } else { 1.0 };
            for (a, b) in back.to_array().iter().zip(q.to_array()) {
                assert!((sign * a - b).abs() < 1e-14, "{axis:?} {angle}: {back:?} vs {q:?}");
            }
        }
        assert_eq!(Quat::from_mat3(&Mat3::IDENTITY), Quat::IDENTITY);
    }

    #[test]
    fn quarter_turn_about_z() {
        let q = Quat::from_axis_angle(Vec3::Z, std::f64::consts::FRAC_PI_2);
        assert!(close(q.rotate(Vec3::X), Vec3::Y));
    }

    #[test]
    fn integrate_spins_at_omega() {
        // 1000 steps of 1 rad/s about z for 1 s turn by ~1 rad.
        let mut q = Quat::IDENTITY;
        for _ in 0..1000 {
            q = q.integrate(Vec3::new(0.0, 0.0, 1.0), 1e-3);
        }
        assert!((q.angle_to(Quat::IDENTITY) - 1.0).abs() < 1e-6);
        assert!((q.norm() - 1.0).abs() < 1e-15);
    }
}
