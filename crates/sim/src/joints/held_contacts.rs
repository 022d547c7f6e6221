//! Contacts whose normal the joints hold: dropped before the LCP.
//!
//! A contact's normal row `n` sees the bodies through the joints as `n P nᵀ
//! = n M⁻¹ nᵀ − bᵀ S⁺ b` (`b = G M⁻¹ nᵀ`). Where the joints already fix that
//! direction — the contacts under a hinge's axle, every contact of a body
//! welded to the world or held level by a slider — it is 0 for the exact
//! data, and as computed its row of `J P Jᵀ` is round-off (±1e-16 of the
//! row) and its `q` the round-off of a velocity the joints set. Such a row
//! says `w_n = q_n` whatever the impulses: the LCP is then solvable only
//! when `q_n ≥ 0` to the last bit, `M` is copositive but not copositive-plus
//! and Lemke may end on a ray; and no answer's `w_n` passes the acceptance
//! rule's relative test on a row of round-off. The contact can add nothing
//! the joints do not (its load is shared with the joint in any split, and
//! the joint's taking all of it is one of the step's answers), so it is
//! dropped at detection, as the contacts of two joined bodies are: it is not
//! in the step record. With a normal mobility left above [`HELD_NORMAL`] of
//! its free one, a contact stays (its row is then the joints' geometry, not
//! round-off).

use super::elimination::JointSystem;
use crate::contact::assembly::{dot6, row};
use crate::dynamics::Body;
use crate::geometry::Contact;
use crate::math::Mat3;

/// The normal mobility through the joints, relative to the free one, at or
/// below which the joints hold a contact's normal (round-off is ~1e-16; a
/// contact point 10 µm off a 1 m bar's hinge axis keeps 1e-10).
pub const HELD_NORMAL: f64 = 1e-10;

impl JointSystem {
    /// Drops the contacts whose normal the joints hold (module docs) from
    /// `contacts`; only contacts with a jointed dynamic body are looked at.
    pub fn drop_held_contacts(&mut self, contacts: &mut Vec<Contact>, bodies: &[Body], inv_inertia: &[Mat3]) {
        if self.is_empty() {
            return;
        }
        // (The coupling's scratch serves: a step's coupling comes after detection.)
        let (mut b, mut y) = (std::mem::take(&mut self.b), std::mem::take(&mut self.y));
        contacts.retain(|ct| !self.holds_normal(ct, bodies, inv_inertia, &mut b, &mut y));
        (self.b, self.y) = (b, y);
    }

    /// Whether `n P nᵀ ≤ HELD_NORMAL · n M⁻¹ nᵀ` for `ct`'s normal row.
    fn holds_normal(
        &self,
        ct: &Contact,
        bodies: &[Body],
        inv_inertia: &[Mat3],
        b: &mut Vec<f64>,
        y: &mut Vec<f64>,
    ) -> bool {
        let sides = [(ct.body_a, 1.0), (ct.body_b, -1.0)];
        if !sides.iter().any(|&(b, _)| self.jointed.get(b).copied().unwrap_or(false) && !bodies[b].is_static()) {
            return false;
        }
        // The normal row and its M⁻¹nᵀ on each dynamic side.
        let mut free = 0.0;
        let rows = sides.map(|(body, sign)| {
            (!bodies[body].is_static()).then(|| {
                let d = ct.normal * sign;
                let ang = (ct.point - bodies[body].position()).cross(d);
                let minv = row(d * bodies[body].inv_mass(), inv_inertia[body] * ang);
                free += dot6(&row(d, ang), &minv);
                (body, minv)
            })
        });
        if free <= 0.0 {
            return false;
        }
        // b = G M⁻¹ nᵀ over the bodies a joint row and the contact share; bᵀ S⁺ b = |L⁻¹ Πᵀ b|².
        b.clear();
        b.extend(self.rows.iter().map(|jr| {
            rows.iter()
                .flatten()
                .map(|(body, minv)| {
                    (0..2).filter(|&s| jr.body[s] == Some(*body)).map(|s| dot6(&jr.jac[s], minv)).sum::<f64>()
                })
                .sum::<f64>()
        }));
        self.factor.forward(b, 1, y);
        let coupled: f64 = y.iter().map(|v| v * v).sum();
        free - coupled <= HELD_NORMAL * free
    }
}
