//! Semi-implicit (symplectic) Euler: velocities first, then positions from the new velocities.
//!
//! `v* = v + h M⁻¹ f_ext` (before contacts), the contact impulses give
//! `v⁺ = v* + M⁻¹ Jᵀ z`, and then `x⁺ = x + h v⁺`, `q⁺ = normalize(q + h/2 (0, ω⁺) ⊗ q)`.
//! There is no gyroscopic term `ω × Iω`: ω changes only through torques and
//! impulses, the usual choice for this time-stepping scheme (it cannot add
//! energy, and cubes and spheres are unaffected).

use super::Body;
use crate::math::Vec3;

/// Free velocity of a dynamic body over one step of length `h` under a total
/// force `f` (including gravity) and torque `tau`: `(v*, ω*)`.
#[inline]
pub fn free_velocity(body: &Body, f: Vec3, tau: Vec3, h: f64) -> (Vec3, Vec3) {
    let v = body.velocity + f * (h * body.inv_mass);
    let w = body.angular_velocity + body.inv_inertia_world() * tau * h;
    (v, w)
}

/// Moves a dynamic body with its (new) velocity for one step; the quaternion is renormalized.
#[inline]
pub fn integrate_positions(body: &mut Body, h: f64) {
    if body.is_static {
        return;
    }
    body.position += body.velocity * h;
    body.orientation = body.orientation.integrate(body.angular_velocity, h);
}
