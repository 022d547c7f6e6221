//! Parameters of the contact formulation, each with its documented default.

use crate::error::{in_range, non_negative, positive, SimError};

/// The friction-cone scale `s`: the LCP solved is `D M D, D q`
/// with `D = diag(I, I, s·I)` — `fn`, `fd` unchanged, `λ_scaled = λ / s`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ConeScale {
    /// `s = 1`: the problem in physical units (default).
    #[default]
    Unscaled,
    /// A fixed `s > 0`.
    Value(f64),
    /// `s = h`, the time step (the source note's choice).
    TimeStep,
}

impl ConeScale {
    /// The numeric `s` for time step `h`.
    pub fn value(self, h: f64) -> f64 {
        match self {
            ConeScale::Unscaled => 1.0,
            ConeScale::Value(s) => s,
            ConeScale::TimeStep => h,
        }
    }

    pub fn validate(self) -> Result<(), SimError> {
        if let ConeScale::Value(s) = self {
            positive("cone_scale", s)?;
        }
        Ok(())
    }
}

/// Penetration stabilization: the term added to `b0 = J_n v*` per contact.
///
/// With gap `φ`:
/// - `φ > 0` and `speculative`: `+ φ/h` — the contact may close during the
///   step but not overshoot (`φ + h·v⁺_n ≥ 0`); this adds no energy and lets a
///   falling body land exactly on the surface.
/// - `φ ≤ 0`: `+ erp · min(0, φ + slop) / h` — remove the fraction `erp` of
///   the penetration beyond `slop` per step (Baumgarte / ODE's ERP).
///
/// A body resting at `φ = 0` gets no term at all, so stabilization cannot add
/// energy to it. Gaps within `±gap_floor` count as `φ = 0`: they are the
/// round-off of the contact geometry, not a distance (see [`GAP_FLOOR`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stabilization {
    /// Fraction of the penetration removed per step, in [0, 1]. Default 0.2.
    pub erp: f64,
    /// Penetration depth left uncorrected (m), ≥ 0. Default 0.
    pub slop: f64,
    /// Use the positive gap of contacts within the margin (`+φ/h`). Default true;
    /// when false a contact within the margin acts as if touching.
    pub speculative: bool,
    /// Gaps with `|φ| ≤ gap_floor` (m) get no term. Default [`GAP_FLOOR`]; 0
    /// turns it off.
    pub gap_floor: f64,
}

/// Default [`Stabilization::gap_floor`]: 1e-12 m. Box–box and box–plane
/// gaps of bodies at rest come out of the contact geometry as round-off of
/// about 1e-14–1e-13 m (positions of O(1–10) m), a different value at each
/// corner and each step. Divided by `h = 1e-3` that is 1e-11 m/s of noise in
/// `q`, which moves a statically indeterminate stack's LCP off its previous
/// vertex: with no floor, 636 of 2,000 steps of a resting 10-box stack pivot
/// (about 260 pivots each), with 1e-12 m a few dozen do (`stack_steps`
/// example: 22 when the floor came, 40 under the componentwise acceptance). A
/// picometre is far below any physical tolerance of a rigid-body contact.
pub const GAP_FLOOR: f64 = 1e-12;

impl Default for Stabilization {
    fn default() -> Self {
        Stabilization { erp: 0.2, slop: 0.0, speculative: true, gap_floor: GAP_FLOOR }
    }
}

impl Stabilization {
    /// No correction at all: `b0 = J_n v*` (positive gaps treated as touching).
    pub fn none() -> Self {
        Stabilization { erp: 0.0, slop: 0.0, speculative: false, gap_floor: 0.0 }
    }

    /// The term added to `b0` for a contact of gap `phi` at time step `h`.
    #[inline]
    pub fn bias(&self, phi: f64, h: f64) -> f64 {
        if phi.abs() <= self.gap_floor {
            return 0.0;
        }
        if phi > 0.0 {
            if self.speculative {
                phi / h
            } else {
                0.0
            }
        } else {
            self.erp * (phi + self.slop).min(0.0) / h
        }
    }

    pub fn validate(&self) -> Result<(), SimError> {
        in_range("stabilization.erp", self.erp, 0.0, 1.0, "[0, 1]")?;
        non_negative("stabilization.slop", self.slop)?;
        non_negative("stabilization.gap_floor", self.gap_floor)?;
        Ok(())
    }
}

/// Newton restitution on the normal velocity: `w0 = v⁺_n + e·v⁻_n ≥ 0`, i.e.
/// a contact approaching at `v⁻_n < 0` leaves at `≥ e·|v⁻_n|`.
///
/// Applied to a contact only when it approaches faster than `threshold` and
/// would reach the surface within this step (`φ + h·v⁻_n ≤ 0`); `v⁻` is the
/// velocity at the start of the step (before external forces). Where it
/// applies, the stricter of the bounce and the stabilization term is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// Coefficient `e` in [0, 1]. Default 0 (perfectly inelastic, no bounce).
    pub coefficient: f64,
    /// Approach speed (m/s) below which there is no bounce, so resting
    /// contacts do not jitter. Default 1e-2.
    pub threshold: f64,
}

impl Default for Restitution {
    fn default() -> Self {
        Restitution { coefficient: 0.0, threshold: 1e-2 }
    }
}

impl Restitution {
    /// Restitution `e` with the default threshold.
    pub fn new(coefficient: f64) -> Self {
        Restitution { coefficient, ..Default::default() }
    }

    pub fn validate(&self) -> Result<(), SimError> {
        in_range("restitution", self.coefficient, 0.0, 1.0, "[0, 1]")?;
        non_negative("restitution.threshold", self.threshold)?;
        Ok(())
    }
}

/// How the friction coefficients of two bodies combine into the contact's μ.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MuCombine {
    /// `min(μ_a, μ_b)` (default): the slipperier surface decides, and giving
    /// a ground a large μ makes every body's own μ count.
    #[default]
    Min,
    /// `max(μ_a, μ_b)`.
    Max,
    /// `μ_a · μ_b` (Bullet's default).
    Product,
    /// `√(μ_a μ_b)` (ODE/PhysX-style average).
    GeometricMean,
    /// `(μ_a + μ_b)/2`.
    Average,
}

impl MuCombine {
    #[inline]
    pub fn combine(self, a: f64, b: f64) -> f64 {
        match self {
            MuCombine::Min => a.min(b),
            MuCombine::Max => a.max(b),
            MuCombine::Product => a * b,
            MuCombine::GeometricMean => (a * b).sqrt(),
            MuCombine::Average => 0.5 * (a + b),
        }
    }
}
