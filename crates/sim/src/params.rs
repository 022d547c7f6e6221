//! `WorldParams`: every knob of the simulation, with its default documented on the field.

use crate::contact::{ConeScale, MuCombine, Restitution, Stabilization};
use crate::error::{finite_vec, in_range, non_negative, positive, SimError};
use crate::math::Vec3;
use lcp::Method;

/// Simulation parameters (Rapier's `IntegrationParameters` in spirit).
/// Validated by `World::new` and `World::set_params`.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldParams {
    /// Time step `h` (s), > 0. Default 1e-3 (the source note's).
    pub dt: f64,
    /// Gravity (m/s²). Default (0, 0, −9.81).
    pub gravity: Vec3,
    /// Friction directions per contact `k`, even, in [2, `contact::friction::MAX_FRICTION_DIRS`].
    /// Default 8 (LCP size 10 per contact).
    pub friction_dirs: usize,
    /// Friction-cone scale `s` (`contact::ConeScale`). Default `Unscaled` (s = 1).
    pub cone_scale: ConeScale,
    /// Contacts with gap `φ ≤ margin` enter the LCP (m), ≥ 0. Default 1e-3.
    pub margin: f64,
    /// Widen the margin of each pair by how far its bodies can approach in one
    /// step (`h·(|v*| + |ω*|·r)` for both bodies), so fast bodies cannot pass
    /// through a surface between two detections. Default true.
    pub velocity_margin: bool,
    /// Penetration stabilization of `b0`. Default: ERP 0.2, no slop, speculative gaps.
    pub stabilization: Stabilization,
    /// Restitution. Default coefficient 0 (no bounce).
    pub restitution: Restitution,
    /// How two bodies' μ combine. Default `Min`.
    pub mu_combine: MuCombine,
    /// If set, every contact uses this μ instead of the combined one. Default `None`.
    pub mu_override: Option<f64>,
    /// LCP solver and its options. Default `Method::default()` (robust Lemke).
    pub method: Method,
    /// Threads for the contact islands' assembly and solves: 1 = this thread
    /// only, 0 = one per core, t = up to t. Results do not depend on it (each
    /// island is solved on its own, bit for bit the same on any thread); steps
    /// with little work stay on this thread anyway. Default 1.
    pub threads: usize,
    /// A step whose contact LCP fails is taken again from its start as two
    /// steps of `h/2`, each of which may be halved again, at most this many
    /// halvings deep (`pipeline::retake`); at the end of the halvings the
    /// failed-solve policy applies. Every part solves its own exact LCP. In
    /// `[0, limits::MAX_HALVINGS]`; default 0 (never: a failure is recorded as
    /// it happened, which the experiments that count failures rely on).
    pub max_halvings: u32,
}

impl Default for WorldParams {
    fn default() -> Self {
        WorldParams {
            dt: 1e-3,
            gravity: Vec3::new(0.0, 0.0, -9.81),
            friction_dirs: 8,
            cone_scale: ConeScale::Unscaled,
            margin: 1e-3,
            velocity_margin: true,
            stabilization: Stabilization::default(),
            restitution: Restitution::default(),
            mu_combine: MuCombine::Min,
            mu_override: None,
            method: Method::default(),
            threads: 1,
            max_halvings: 0,
        }
    }
}

impl WorldParams {
    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), SimError> {
        positive("dt", self.dt)?;
        finite_vec("gravity", self.gravity)?;
        if self.friction_dirs < 2
            || self.friction_dirs % 2 == 1
            || self.friction_dirs > crate::contact::friction::MAX_FRICTION_DIRS
        {
            return Err(SimError::FrictionDirs { k: self.friction_dirs });
        }
        self.cone_scale.validate()?;
        non_negative("margin", self.margin)?;
        self.stabilization.validate()?;
        self.restitution.validate()?;
        if let Some(mu) = self.mu_override {
            non_negative("mu_override", mu)?;
        }
        let (most, range) = (crate::limits::MAX_HALVINGS, crate::limits::HALVINGS_RANGE);
        in_range("max_halvings", f64::from(self.max_halvings), 0.0, f64::from(most), range)?;
        Ok(())
    }

    /// The numeric friction-cone scale `s` for this time step.
    pub fn scale(&self) -> f64 {
        self.cone_scale.value(self.dt)
    }
}
