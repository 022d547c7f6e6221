//! The acceptance rule judged in body space: each contact row on the scale
//! of the velocities it relates, not of the impulses that pass through it.
//!
//! The LCP's rule (`lcp::accept`) judges row `i` of `w = M z + q` against
//! `s_i = |q_i| + Σ_j |M_ij| z_j`, i.e. it lets `M` vary by `τ = 1e-9` of each
//! entry. A contact row's `M_ij = Σ_b J_ib M_b⁻¹ J_jbᵀ` sums the mobilities of
//! the bodies it touches, so with a 1e8 kg box on a 1 kg one the light box's
//! mobility times impulses of ~1e7 N·s sets the scale (~1e8 m/s) and the heavy
//! box's share of the row (1e-8 of it) is below the rule: answers at
//! η ~ 1e-10 leave the heavy box rising at mm/s (1.6 % off in `Σ fn`).
//!
//! In body space the same LCP is `Δv_b = M_b⁻¹ Σ_c J_cbᵀ z_c` (momentum, per
//! body) and `w = J Δv + q` (contact velocities). Row `i` of a contact's
//! normal or friction direction gets the *velocity scale* and *round-off floor*
//!
//! ```text
//! V_i = |q_i| + Σ_b (‖J_ib,lin‖∞‖Δv_b‖₁ + ‖J_ib,ang‖∞‖Δω_b‖₁) (+ λ_c for a friction row)
//! F_i = ρ·Σ_b |J_ib|·U_b,   U_b = Σ_c |M_b⁻¹ J_cbᵀ|·|z_c|   (ρ = lcp::accept::ROUND_OFF)
//! ```
//!
//! and the violation `v_i` of `lcp::accept` (`|w_i|` where `z_i > 0`, else
//! `max(−w_i, 0)`); `η_body = max_i max(v_i − F_i, 0)/V_i`. `z` passes iff
//! `η_body ≤ τ`: it is the exact answer of a problem whose contact rows (`J`
//! in `w = J Δv + q`, and `q`) differ by at most `τ` of each row's largest
//! entry (of its linear and its angular part: the contact frame turned by
//! `τ` rad) and whose momentum rows (`M_b⁻¹ J_cbᵀ`) by round-off. (Judged
//! entry by entry, a friction row across a body moving along the normal
//! would see none of that motion: answers exact to 1e-12 m/s failed.) The momentum rows get no more
//! than round-off because perturbing them contact by contact breaks Newton's
//! third law: a light box squeezed by 1e7 N·s from above and below would
//! move at `τ·U_b` ~ 0.1 m/s. A cone row (`λ`) touches no body; the LCP rule
//! judges it.
//!
//! The rule is stricter than the LCP's only where `U_b ≫ |Δv_b|` — impulses
//! that nearly cancel on a body, as on a light body under a heavy one (by the
//! mass ratio) or at the bottom of a stack (by its height). Its bite is the
//! first: an answer is judged only where a contact joins two bodies whose
//! mobilities along its normal differ [`MOBILITY_RATIO`]-fold or more
//! ([`BodyCheck::applies`]); bodies of like mass differ by at most ~4 (lever
//! arms), and on the benchmark scenes (a 10-box stack, a 3×3×3 pile, a cube
//! on a slope; 300 steps) no answer failed the check, which cost up to 45 %
//! of a resting stack's step when run on every island.

use super::assembly::{dot6, ContactLcp, Row6};
use lcp::accept::ROUND_OFF;

/// Contacts whose two bodies' mobilities `J_n M_b⁻¹ J_nᵀ` differ by this
/// factor or more put their island under the check.
pub const MOBILITY_RATIO: f64 = 100.0;

/// Per-body scratch of the check (island body slots), kept between calls.
#[derive(Clone, Debug, Default)]
pub struct BodyCheck {
    /// `Δv_b` (linear, angular) of the impulses.
    dv: Vec<Row6>,
    /// `U_b`: the same with every term's absolute value.
    u: Vec<Row6>,
}

/// `Σ_m |a_m|·|b_m|`.
#[inline]
fn abs_dot(a: &Row6, b: &Row6) -> f64 {
    a.iter().zip(b).map(|(x, y)| x.abs() * y.abs()).sum()
}

/// `‖a_lin‖∞‖v_lin‖₁ + ‖a_ang‖∞‖v_ang‖₁`: the most a turn of the row by one
/// unit of its largest entry can change `a·v`.
#[inline]
fn norm_dot(a: &Row6, v: &Row6) -> f64 {
    let part = |r: std::ops::Range<usize>| {
        let amax = a[r.clone()].iter().fold(0.0f64, |m, x| m.max(x.abs()));
        amax * v[r].iter().map(|x| x.abs()).sum::<f64>()
    };
    part(0..3) + part(3..6)
}

impl BodyCheck {
    /// Whether some contact of `lcp` joins two dynamic bodies whose
    /// mobilities along its normal differ [`MOBILITY_RATIO`]-fold or more.
    pub fn applies(lcp: &ContactLcp) -> bool {
        (0..lcp.nc()).any(|c| {
            if lcp.side_slot(c, 0).is_none() || lcp.side_slot(c, 1).is_none() {
                return false;
            }
            let mobility = |side| {
                let (j, minv) = lcp.side_rows(c, side);
                dot6(&j[0], &minv[0])
            };
            let (a, b) = (mobility(0), mobility(1));
            a.max(b) >= MOBILITY_RATIO * a.min(b)
        })
    }

    /// `η_body` of the module docs for the physical `z` (`λ` unscaled) and its
    /// `w` on the unscaled LCP; infinite when `z` has a negative or
    /// non-finite entry or a violated row has no scale.
    pub fn eta(&mut self, lcp: &ContactLcp, z: &[f64], w: &[f64]) -> f64 {
        let lay = lcp.layout();
        let n = lay.n();
        if z.len() != n || w.len() != n || !z.iter().all(|v| *v >= 0.0 && v.is_finite()) {
            return f64::INFINITY;
        }
        self.impulses(lcp, z);
        let q = lcp.q();
        let mut eta = 0.0f64;
        let mut judge = |i: usize, scale: f64, floor: f64| {
            let v = if z[i] > 0.0 { w[i].abs() } else { (-w[i]).max(0.0) };
            let excess = v - floor;
            if !v.is_finite() {
                eta = f64::INFINITY;
            } else if excess > 0.0 {
                eta = eta.max(if scale > 0.0 { excess / scale } else { f64::INFINITY });
            }
        };
        for c in 0..lay.nc {
            // Σ over the dynamic sides of (V's and F's terms) for the normal row, then each direction's.
            let sides = |row: &dyn Fn(&[Row6; 3]) -> Row6| {
                let mut acc = (0.0, 0.0);
                for side in 0..2 {
                    let Some(b) = lcp.side_slot(c, side) else { continue };
                    let j = row(lcp.side_rows(c, side).0);
                    acc.0 += norm_dot(&j, &self.dv[b]);
                    acc.1 += abs_dot(&j, &self.u[b]);
                }
                acc
            };
            let (dv, u) = sides(&|r| r[0]);
            judge(c, q[c].abs() + dv, ROUND_OFF * u);
            let lambda = z[lay.lambda_index(c)];
            for (j, f) in lay.fd_of(c).enumerate() {
                let (cj, sj) = lcp.cos_sin(j);
                let (dv, u) = sides(&|r| std::array::from_fn(|m| cj * r[1][m] + sj * r[2][m]));
                judge(f, q[f].abs() + dv + lambda, ROUND_OFF * (u + lambda));
            }
        }
        if eta.is_nan() {
            f64::INFINITY
        } else {
            eta
        }
    }

    /// `Δv_b` and `U_b` of every dynamic body of the island.
    fn impulses(&mut self, lcp: &ContactLcp, z: &[f64]) {
        let lay = lcp.layout();
        let nb = lcp.dynamic_body_count();
        self.dv.clear();
        self.dv.resize(nb, [0.0; 6]);
        self.u.clear();
        self.u.resize(nb, [0.0; 6]);
        for c in 0..lay.nc {
            let imp = lcp.frame_impulse(c, z);
            // |Σ_j fd_j d_j| ≤ (|t1| + |t2|)·Σ_j fd_j componentwise.
            let fd: f64 = z[lay.fd_of(c)].iter().sum();
            for side in 0..2 {
                let Some(b) = lcp.side_slot(c, side) else { continue };
                let minv = lcp.side_rows(c, side).1;
                let (dv, u) = (&mut self.dv[b], &mut self.u[b]);
                for (m, (dv, u)) in dv.iter_mut().zip(u.iter_mut()).enumerate() {
                    let (n, t1, t2) = (minv[0][m], minv[1][m], minv[2][m]);
                    *dv += n * imp[0] + t1 * imp[1] + t2 * imp[2];
                    *u += n.abs() * z[c] + (t1.abs() + t2.abs()) * fd;
                }
            }
        }
    }
}
