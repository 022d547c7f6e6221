//! Joint limits: a hinge's angle or a slider's displacement kept in
//! `[lower, upper]` by unilateral rows with complementarity — a hard stop,
//! not a spring.
//!
//! A limit that the joint may reach within the step enters the island's
//! contact LCP as one more contact, frictionless (μ = 0), whose normal row
//! is the limit's row instead of a point's: `w = g_lim v⁺ + gap/h ≥ 0 ⊥
//! fn ≥ 0` (a positive gap speculative, so the joint stops on the limit; a
//! negative one corrected with the joints' `β`). Its friction rows are zero,
//! so with μ = 0 its `fd` stay 0. In the step record it is a contact at B's
//! anchor with normal ± the axis (its `body_a` is `body_b` when side A is the
//! world); its `fn` is the limit's impulse.
//!
//! A velocity motor is the Stewart–Trinkle friction pattern with a constant
//! bound, as one more contact: its friction rows are the joint's rate row
//! `g` (`t1 = g`, `t2 = 0`) with `q = c_j (g v* − speed)`, so `fd_j ≥ 0` push
//! the rate towards `speed` and `λ` is the rate's miss; its normal is a
//! virtual unit row (`M_nn = 1`, `q_n = −F_max h`, no velocity), so `fn =
//! F_max h` exactly and the cone row `w = μ fn − Σ fd` (μ = 1) bounds the
//! motor's impulse by `F_max h`. In the record its `fn` is that bound and
//! its friction impulses the motor's.
//!
//! ```text
//! hinge   θ = angle of B about a from A      upper: gap = θ_u − θ, row A: [0, a],               B: −[0, a]
//! slider  d = a·(x_B − x_A)                  upper: gap = d_u − d, row A: [a, (x_B − p_A) × a], B: −[a, (x_B − p_B) × a]
//!         lower: gap = θ − θ_l (d − d_l), the rows negated
//! ```

use super::joint::{normal_to, pose, Joint, JointKind};
use crate::contact::assembly::{row, Row6};
use crate::dynamics::Body;
use crate::geometry::Contact;
use crate::math::Vec3;

/// One limit (or motor) in this step's LCP.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitRow {
    pub joint: usize,
    /// A motor's `(speed, max impulse F·h)`; `None` for a limit.
    pub motor: Option<(f64, f64)>,
    /// Dynamic body per side.
    pub body: [Option<usize>; 2],
    /// The row per side (`fn` along it).
    pub jac: [Row6; 2],
    /// Distance to the limit (rad or m), negative past it.
    pub gap: f64,
}

impl Joint {
    /// Appends the joint's motor, if it has one with a force, as a
    /// [`LimitRow`] (its row that of the coordinate's rate) and its contact.
    pub fn push_motor(&self, j: usize, bodies: &[Body], h: f64, rows: &mut Vec<LimitRow>, out: &mut Vec<Contact>) {
        let Some(m) = self.motor.filter(|m| m.max_force > 0.0) else { return };
        let (_, up, axis, point) = self.limit_rows(bodies);
        let body = [self.dynamic_side(bodies, 0), self.dynamic_side(bodies, 1)];
        let b = self.bodies[1].expect("side B is a body");
        // d/dt coordinate = −up·v: the rate row is −up.
        let jac = up.map(|r| r.map(|v| -v));
        rows.push(LimitRow { joint: j, motor: Some((m.speed, m.max_force * h)), body, jac, gap: 0.0 });
        out.push(Contact {
            body_a: self.bodies[0].unwrap_or(b),
            body_b: b,
            point,
            normal: axis,
            gap: 0.0,
            mu: 1.0,
            tangent: normal_to(axis),
        });
    }

    /// The joint's coordinate (hinge angle, slider displacement) and the rows
    /// of its rate `d/dt coordinate = −(row_A·v_A + row_B·v_B)` (the upper limit's rows).
    pub(super) fn limit_rows(&self, bodies: &[Body]) -> (f64, [Row6; 2], Vec3, Vec3) {
        let (pa, qa) = pose(bodies, self.bodies[0]);
        let pb = pose(bodies, self.bodies[1]).0;
        let a = qa.rotate(self.axis[0]);
        let xb = self.anchors_world(bodies)[1];
        match self.kind {
            JointKind::Slider => {
                let (ra, rb) = (xb - pa, xb - pb);
                let jac = [row(a, ra.cross(a)), row(-a, -rb.cross(a))];
                (self.displacement(bodies), jac, a, xb)
            }
            _ => (self.angle(bodies), [row(Vec3::ZERO, a), row(Vec3::ZERO, -a)], a, xb),
        }
    }

    /// Appends the limits the joint may reach within `reach` (rad or m) as
    /// [`LimitRow`]s and their contacts.
    pub fn push_limits(&self, j: usize, bodies: &[Body], reach: f64, rows: &mut Vec<LimitRow>, out: &mut Vec<Contact>) {
        let Some((lower, upper)) = self.limits else { return };
        let (x, up, axis, point) = self.limit_rows(bodies);
        let body = [self.dynamic_side(bodies, 0), self.dynamic_side(bodies, 1)];
        let b = self.bodies[1].expect("side B is a body");
        for (gap, sign) in [(upper - x, 1.0), (x - lower, -1.0)] {
            // (A NaN gap is out of reach.)
            if gap.is_nan() || gap > reach {
                continue;
            }
            let jac = up.map(|r| r.map(|v| v * sign));
            rows.push(LimitRow { joint: j, motor: None, body, jac, gap });
            let normal = axis * sign;
            out.push(Contact {
                body_a: self.bodies[0].unwrap_or(b),
                body_b: b,
                point,
                normal,
                gap,
                mu: 0.0,
                tangent: normal_to(normal),
            });
        }
    }
}
