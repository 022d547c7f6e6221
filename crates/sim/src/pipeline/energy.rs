//! The step's energy audit and the policy for a failed solve.
//!
//! **Audit** ([`EnergyAudit`], in every `StepRecord`): the mechanical energy
//! `E = Σ ½ m v² + ½ ωᵀ I ω − m g·x` of the dynamic bodies before and after
//! the step, the work `W = h Σ (F·v⁺ + τ·ω⁺)` of the applied forces and
//! torques (gravity is in `E`), the work `S` of the penetration
//! correction (below) and the joints' terms (below). `E_after − E_before −
//! W − S − joints` is the energy the step created: semi-implicit Euler in
//! free fall loses `½ m h² g²` per step, inelastic contact only dissipates,
//! so a positive value comes from the contact impulses (a wrong answer).
//!
//! **Stabilization work.** A contact's normal impulse `fn` does the work
//! `fn·J_n v̄` on the bodies (`v̄` the mean of the velocities before and after
//! it), which is `fn·J_n v⁺ − ½ fn·J_n M⁻¹J_nᵀ fn`; complementarity
//! (`fn·w_n = 0` with `w_n = J_n v⁺ + b`) makes the first term `−fn·b`.
//! Friction (`−μ fn λ`) and the second term only dissipate, and the
//! speculative term `b = φ/h > 0` of an open gap too; the penetration term
//! `b = erp·(φ + slop)/h < 0` ([`crate::contact::Stabilization`]) pushes
//! the bodies apart with `S = Σ fn·|b|` that no force did: Baumgarte's
//! (ODE's ERP's) known energy gain, the price of removing a penetration
//! through the velocities. It is recorded, not called created: a sphere of
//! 1e7 kg sliding on a 1 kg cube (`tests/mass_ratio.rs`; μ = 0.5, the
//! cube's tipping limit) throws the cube into a tumble at its second step
//! (1.3e6 N·s, ω = 2.5 rad/s), and the contact on the turning face, exact
//! to first order, sinks by O(h²ω²r) a step, up to 4.7 µm; the correction
//! pushes it out with up to 6.8e-7 of E₀ in a step, 0.8 of that the
//! next, … — all of it `S`. (Split impulses or post-stabilization — a
//! position correction that does not touch the velocities — would not add
//! it; this simulator keeps Stewart–Trinkle's single velocity-level LCP.)
//!
//! **Joints** (`crate::joints`). The same argument, row by row: an impulse
//! `p` on a row `g` changes the kinetic energy by `p·g v⁺ − ½ p·g M⁻¹gᵀ p`
//! (the second term, summed over all the step's impulses, only dissipates),
//! so each kind of row is credited with `p·g v⁺`:
//! - a bilateral joint row asks `g v⁺ = −β C/h`: its work `λ·g v⁺ =
//!   −λ β C/h` is the joints' drift correction (either sign; 0 for an ideal
//!   joint, `C = 0`, which does no work), with a limit row pushed back past
//!   its limit (`fn·β|gap|/h`, as a contact's `S`): `joint_drift`;
//! - a motor's impulse `p` along the joint's rate row does `p·θ̇⁺`, the
//!   torque times the angle it turns in the step (`θ += h θ̇⁺`):
//!   `motor_work`;
//! - the position projections after the step (`JointParams::settle_passes`)
//!   move the bodies without touching their velocities: the energy they
//!   change, measured, is `joint_projection` (the potential of a pendulum
//!   bob pulled back onto its circle, `O(h²)` a step).
//!
//! With these, a frictionless pendulum's `created` is what semi-implicit
//! Euler with a velocity projection loses (`−½ p·g M⁻¹gᵀ p ≤ 0` a step).
//!
//! **Failed solves.** A solve that fails (any status but `solved`, or an
//! unusable `z`) does not apply the solver's answer: its last iterate can be
//! anything. It does not apply *nothing* either, which lets a heavy body sink
//! into a light one for a step and the stabilization throw it back up later.
//! Instead the island applies its answer made admissible — `fn, fd` clipped
//! at 0, `fd` scaled into the friction cone `Σ fd ≤ μ fn`, `λ` dropped — times
//! the factor `α ∈ [0, 1]` that minimizes the island's energy after the step
//! along that impulse (`α = min(1, −a/c)` for the energy change
//! `a α + ½ c α²`, `α = 0` when no positive `α` lowers it; in an island with
//! joints the velocity change along that impulse is the joint-projected
//! `P Jᵀ z`, the joint impulses it causes included). So a failed step
//! never has more energy than the same step with no impulse at all (which
//! itself creates none), and a nearly right answer is applied nearly whole.

use crate::contact::assembly::{dot6, row};
use crate::math::{Mat3, Vec3};
use crate::world::World;
use lcp::contact::ContactLayout;

/// Energies of one step (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyAudit {
    /// Kinetic + gravitational potential energy of the dynamic bodies at the start of the step.
    pub before: f64,
    /// The same at its end.
    pub after: f64,
    /// Work of the applied forces and torques over the step (gravity excluded: it is in the energies).
    pub external_work: f64,
    /// Work of the penetration correction: `Σ fn·|b|` over the contacts whose
    /// stabilization term `b` is negative (see the module docs); 0 when no
    /// contact penetrates.
    pub stabilization: f64,
    /// Work of the joint motors: each motor's impulse times its joint's rate after the step.
    pub motor_work: f64,
    /// Work of the joints' drift correction: `λ·G v⁺ = −λ·β C/h` of the
    /// bilateral rows, plus the limit rows past their limit (module docs);
    /// 0 without joints and for ideal joints.
    pub joint_drift: f64,
    /// Energy the joints' position projections after the step changed (module docs).
    pub joint_projection: f64,
}

impl EnergyAudit {
    /// The audit of this interval followed by `next` (from this one's start
    /// to `next`'s end): the parts of a retaken step as one step.
    pub fn then(self, next: EnergyAudit) -> EnergyAudit {
        EnergyAudit {
            before: self.before,
            after: next.after,
            external_work: self.external_work + next.external_work,
            stabilization: self.stabilization + next.stabilization,
            motor_work: self.motor_work + next.motor_work,
            joint_drift: self.joint_drift + next.joint_drift,
            joint_projection: self.joint_projection + next.joint_projection,
        }
    }

    /// Energy the step created: `after − before − external_work − stabilization
    /// − motor_work − joint_drift − joint_projection` (≤ 0 when it only dissipates).
    pub fn created(&self) -> f64 {
        self.after
            - self.before
            - self.external_work
            - self.stabilization
            - self.motor_work
            - self.joint_drift
            - self.joint_projection
    }
}

impl World {
    /// `(motor_work, joint_drift)` of the module docs for the step just
    /// integrated (the bodies hold `v⁺`); zeros without joints.
    pub(crate) fn joint_work(&self, h: f64) -> (f64, f64) {
        if self.joints.is_empty() {
            return (0.0, 0.0);
        }
        let (ws, bodies) = (&self.ws, &self.bodies);
        let vel = |b: usize| row(bodies[b].velocity, bodies[b].angular_velocity);
        // the bilateral rows: λ·g v⁺ (not a damper's: its −h d q̇⁺² is dissipation)
        let mut drift: f64 = (ws.joints.rows.iter().zip(&ws.joints.lambda))
            .filter(|(r, _)| r.compliance == 0.0)
            .map(|(r, &l)| l * (0..2).filter_map(|s| r.body[s].map(|b| dot6(&r.jac[s], &vel(b)))).sum::<f64>())
            .sum();
        let (first, beta, mut motor) = (ws.joints.first_limit, self.joint_params.drift, 0.0);
        for i in 0..ws.islands.len() {
            let isl = &ws.pool[i];
            if isl.z_apply.len() != isl.lcp.n() {
                continue;
            }
            for (c, &g) in ws.islands.contacts_of(i).iter().enumerate().filter(|(_, &g)| g >= first) {
                let (lim, p) = (&ws.joints.limits[g - first], isl.lcp.frame_impulse(c, &isl.z_apply));
                if lim.motor.is_some() {
                    // its impulse along its rate row (t1) times the rate
                    let rows = |s: usize| isl.lcp.side_rows(c, s).0[1];
                    let rate: f64 =
                        (0..2).filter_map(|s| isl.lcp.side_body(c, s).map(|b| dot6(&rows(s), &vel(b)))).sum();
                    motor += p[1] * rate;
                } else if lim.gap < 0.0 {
                    // pushed back past the limit with the joints' β, as a contact's `S`
                    drift += p[0] * beta * -lim.gap / h;
                }
            }
        }
        (motor, drift)
    }
}

/// `S` of the module docs for one island: its contacts, the impulses it
/// applied (physical `z`, island layout), the stabilization and `h`.
pub(crate) fn stabilization_work(
    contacts: &[crate::geometry::Contact],
    z_apply: &[f64],
    layout: ContactLayout,
    stabilization: &crate::contact::Stabilization,
    h: f64,
) -> f64 {
    if z_apply.len() != layout.n() {
        return 0.0;
    }
    contacts
        .iter()
        .enumerate()
        .map(|(c, ct)| z_apply[layout.fn_index(c)] * (-stabilization.bias(ct.gap, h)).max(0.0))
        .sum()
}

/// The admissible impulses of a failed answer `z` (physical units): `fn`, `fd`
/// clipped at 0, each contact's `fd` scaled so that `Σ fd ≤ μ fn`, `λ = 0`.
pub(crate) fn admissible(z: &[f64], layout: ContactLayout, mu: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.resize(z.len(), 0.0);
    if z.len() != layout.n() || !z.iter().all(|v| v.is_finite()) {
        return;
    }
    for c in 0..layout.nc {
        let f = z[layout.fn_index(c)].max(0.0);
        out[layout.fn_index(c)] = f;
        let fd = layout.fd_of(c);
        let sum: f64 = z[fd.clone()].iter().map(|v| v.max(0.0)).sum();
        let scale = if sum > mu[c] * f { mu[c] * f / sum } else { 1.0 };
        for j in fd {
            out[j] = z[j].max(0.0) * scale;
        }
    }
}

/// One body's share of the energy change along an impulse: its velocity
/// change `(dv, dw)` from `(v, w)` (both after the free step), mass, world
/// inertia, and `g·h` for the potential.
pub(crate) struct Share {
    pub v: Vec3,
    pub w: Vec3,
    pub dv: Vec3,
    pub dw: Vec3,
    pub mass: f64,
    pub inertia: Mat3,
}

/// The factor `α ∈ [0, 1]` minimizing `E(α) − E(0) = a α + ½ c α²` over the
/// bodies' shares, where `a = Σ m (v − h g)·dv + ω·I dω` (kinetic energy and
/// the potential of the position update `x += h v⁺`) and `c = Σ m dv² + dωᵀ I dω`.
pub(crate) fn fallback_scale(shares: impl Iterator<Item = Share>, gravity: Vec3, h: f64) -> f64 {
    let (mut a, mut c) = (0.0, 0.0);
    for s in shares {
        a += s.mass * (s.v - gravity * h).dot(s.dv) + s.w.dot(s.inertia * s.dw);
        c += s.mass * s.dv.norm_squared() + s.dw.dot(s.inertia * s.dw);
    }
    if a < 0.0 && c > 0.0 {
        (-a / c).min(1.0)
    } else {
        0.0
    }
}
