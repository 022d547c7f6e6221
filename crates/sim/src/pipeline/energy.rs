//! The step's energy audit and the policy for a failed solve.
//!
//! **Audit** ([`EnergyAudit`], in every `StepRecord`): the mechanical energy
//! `E = Σ ½ m v² + ½ ωᵀ I ω − m g·x` of the dynamic bodies before and after
//! the step, the work `W = h Σ (F·v⁺ + τ·ω⁺)` of the applied forces and
//! torques (gravity is in `E`), and the work `S` of the penetration
//! correction (below). `E_after − E_before − W − S` is the energy the step
//! created: semi-implicit Euler in free fall loses `½ m h² g²` per step,
//! inelastic contact only dissipates, so a positive value comes from the
//! contact impulses (a wrong answer).
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
//! **Failed solves.** A solve that fails (any status but `solved`, or an
//! unusable `z`) does not apply the solver's answer: its last iterate can be
//! anything. It does not apply *nothing* either, which lets a heavy body sink
//! into a light one for a step and the stabilization throw it back up later.
//! Instead the island applies its answer made admissible — `fn, fd` clipped
//! at 0, `fd` scaled into the friction cone `Σ fd ≤ μ fn`, `λ` dropped — times
//! the factor `α ∈ [0, 1]` that minimizes the island's energy after the step
//! along that impulse (`α = min(1, −a/c)` for the energy change
//! `a α + ½ c α²`, `α = 0` when no positive `α` lowers it). So a failed step
//! never has more energy than the same step with no impulse at all (which
//! itself creates none), and a nearly right answer is applied nearly whole.

use crate::math::{Mat3, Vec3};
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
        }
    }

    /// Energy the step created: `after − before − external_work − stabilization`
    /// (≤ 0 when it only dissipates).
    pub fn created(&self) -> f64 {
        self.after - self.before - self.external_work - self.stabilization
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
