//! The constraint rows of each joint kind at the current configuration:
//! `G` (one [`JointRow`] per row, a 6-vector per side) and the position
//! error `C` of each row, with `dC/dt = G v`.
//!
//! ```text
//! ball    C = x_A − x_B (world x, y, z)     A: [e, r_A × e]   B: −[e, r_B × e]     x = anchor as each side carries it
//! hinge   ball + C_i = −p_i·(a_A × a_B)     A: [0, p_i]       B: −[0, p_i]         p_1, p_2 ⊥ a_A
//! fixed   ball + C = θ(q_A q₀ q_B⁻¹)        A: [0, e]         B: −[0, e]           θ: the rotation vector
//! slider  rotation as fixed + C_i = p_i·(x_A − x_B), rows about x_B (the point of A at B's anchor)
//! ```
//!
//! A damped hinge or slider adds its rate row `q̇ = r·v` with compliance
//! `1/(h d)`: the row asks `r·v⁺ + λ/(h d) = 0`, so its impulse is
//! `λ = −h d q̇⁺`, the damper's force at the end of the step (implicit Euler,
//! stable for any `d`). Eliminating it with the others is, by Woodbury, the
//! step with the mass matrix `M + h d rrᵀ`.

use super::joint::{normal_to, pose, Joint, JointKind};
use crate::contact::assembly::{row, Row6};
use crate::dynamics::Body;
use crate::math::Vec3;

/// One bilateral row: per side its dynamic body (`None` for the world or a
/// static body) and its 6-vector, and the position error `C` of the row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRow {
    /// The joint it belongs to.
    pub joint: usize,
    pub body: [Option<usize>; 2],
    pub jac: [Row6; 2],
    /// Position error (m for a linear row, rad for an angular one).
    pub error: f64,
    /// Whether the row is angular (its error in rad).
    pub angular: bool,
    /// Added to the row's diagonal of `S`: `1/(h d)` for a damping row, 0 for a rigid one.
    pub compliance: f64,
}

/// The world's rotation vector of a unit quaternion (angle·axis, the short way round).
fn rotation_vector(q: crate::math::Quat) -> Vec3 {
    let (w, v) = if q.w < 0.0 { (-q.w, -q.vector()) } else { (q.w, q.vector()) };
    let s = v.norm();
    if s < 1e-12 {
        return v * 2.0;
    }
    v * (2.0 * s.atan2(w) / s)
}

impl Joint {
    /// Appends the joint's rows (joint index `j`) at the bodies' current poses.
    pub fn push_rows(&self, j: usize, bodies: &[Body], out: &mut Vec<JointRow>) {
        let body = [self.dynamic_side(bodies, 0), self.dynamic_side(bodies, 1)];
        let (pa, qa) = pose(bodies, self.bodies[0]);
        let (pb, qb) = pose(bodies, self.bodies[1]);
        let [xa, xb] = self.anchors_world(bodies);
        let mut push = |a: Row6, b: Row6, error: f64, angular: bool| {
            out.push(JointRow { joint: j, body, jac: [a, b.map(|x| -x)], error, angular, compliance: 0.0 });
        };
        let angular = |e: Vec3| row(Vec3::ZERO, e);
        // The anchors coincide (ball, hinge, fixed).
        if self.kind != JointKind::Slider {
            let (ra, rb, c) = (xa - pa, xb - pb, xa - xb);
            for (i, e) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().enumerate() {
                push(row(e, ra.cross(e)), row(e, rb.cross(e)), c[i], false);
            }
        }
        match self.kind {
            JointKind::Ball => {}
            JointKind::Hinge => {
                let (aa, ab) = (qa.rotate(self.axis[0]), qb.rotate(self.axis[1]));
                let p1 = normal_to(aa);
                let p2 = aa.cross(p1);
                let e = aa.cross(ab);
                for p in [p1, p2] {
                    push(angular(p), angular(p), -p.dot(e), true);
                }
            }
            JointKind::Fixed | JointKind::Slider => {
                let theta = rotation_vector(qa * self.rest * qb.conjugate());
                for (i, e) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().enumerate() {
                    push(angular(e), angular(e), theta[i], true);
                }
                if self.kind == JointKind::Slider {
                    let aa = qa.rotate(self.axis[0]);
                    let p1 = normal_to(aa);
                    let p2 = aa.cross(p1);
                    let (ra, rb) = (xb - pa, xb - pb);
                    for p in [p1, p2] {
                        push(row(p, ra.cross(p)), row(p, rb.cross(p)), p.dot(xa - xb), false);
                    }
                }
            }
        }
    }

    /// Appends the damping row of a damped hinge or slider for a step of `h`.
    pub fn push_damping(&self, j: usize, bodies: &[Body], h: f64, out: &mut Vec<JointRow>) {
        // (A NaN damping is none.)
        if self.damping.is_nan() || self.damping <= 0.0 {
            return;
        }
        let body = [self.dynamic_side(bodies, 0), self.dynamic_side(bodies, 1)];
        // The coordinate's rate is −(up_A·v_A + up_B·v_B).
        let up = self.limit_rows(bodies).1;
        let jac = up.map(|r| r.map(|v| -v));
        let angular = self.kind == JointKind::Hinge;
        out.push(JointRow { joint: j, body, jac, error: 0.0, angular, compliance: 1.0 / (h * self.damping) });
    }

    /// The joint's position error now: the largest linear (m) and angular (rad) row error.
    pub fn error(&self, bodies: &[Body]) -> (f64, f64) {
        let mut rows = Vec::with_capacity(6);
        self.push_rows(0, bodies, &mut rows);
        let worst = |ang: bool| rows.iter().filter(|r| r.angular == ang).fold(0.0f64, |m, r| m.max(r.error.abs()));
        (worst(false), worst(true))
    }
}
