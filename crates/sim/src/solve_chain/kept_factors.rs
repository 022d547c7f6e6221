//! What the structured stage keeps of an island from one step to the next:
//! its sparse operator, refilled in place while the island's contacts join
//! the same bodies, and the factorization of its last basis, reused while
//! the basis stays (`lcp::structured::kept`).
//!
//! A settled heap's large island (n ≈ 2,000) is answered at 0 pivots every
//! step by the basis of the step before; building its operator and basis
//! afresh (compressed matrices sorted, COLAMD, a numeric LU) was two thirds
//! of such a step. With the operator refilled and the basis's factors kept,
//! the step costs a few sparse solves and the acceptance rule. The answer
//! is the same basis's answer to round-off, judged by the same rule on the
//! LCP as scaled and in physical units; a basis that fails goes on to the
//! structured Lemke as before.
//!
//! `LCPSIM_KEPT_FACTORS=off` (or [`set_enabled`]) builds everything afresh
//! each step, as before: for measuring the difference.

use super::structured_lemke::accepted_physical;
use crate::contact::body_factors::Factors;
use crate::contact::ContactLcp;
use lcp::structured::kept::{KeptBasis, KeptOptions};
use lcp::structured::{self, StructuredLcp};
use lcp::{Residuals, Solution, Status};
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};

/// A basis whose least value is `≥ −WARM_TOL·`(its largest, at least 1) is
/// taken as it stands, as the structured Lemke's warm run takes it at 0
/// pivots (`lcp::structured`'s tolerance of the same name); below, the
/// island goes on to that run.
const WARM_TOL: f64 = 1e-12;

/// 0: not read yet; 1: on; 2: off.
static ENABLED: AtomicU8 = AtomicU8::new(0);

/// Whether islands keep their operator and factors (default on; off with
/// `LCPSIM_KEPT_FACTORS=off`).
pub fn enabled() -> bool {
    match ENABLED.load(Ordering::Relaxed) {
        0 => {
            let on = std::env::var("LCPSIM_KEPT_FACTORS").map_or(true, |v| v != "off");
            ENABLED.store(if on { 1 } else { 2 }, Ordering::Relaxed);
            on
        }
        v => v == 1,
    }
}

/// Islands answered on kept factors so far in this process (all worlds).
static ANSWERS: AtomicUsize = AtomicUsize::new(0);

/// How many islands the kept factors have answered in this process (for tests and measurements).
pub fn answers() -> usize {
    ANSWERS.load(Ordering::Relaxed)
}

/// Turns the keeping on or off for the whole process (measurements, tests).
pub fn set_enabled(on: bool) {
    ENABLED.store(if on { 1 } else { 2 }, Ordering::Relaxed);
}

/// An island slot's operators and basis factors from its last structured solve.
#[derive(Default)]
pub struct KeptFactors {
    /// The bodies of each contact's two sides (`usize::MAX`: static), the
    /// friction directions and the cone scale the operators were built for.
    sides: Vec<[usize; 2]>,
    k: usize,
    scale: f64,
    /// The operator at the island's scale and, when that is not 1, at scale 1.
    op: Option<StructuredLcp>,
    physical: Option<StructuredLcp>,
    basis: Option<KeptBasis>,
    entries: Factors,
}

impl Clone for KeptFactors {
    /// A copy keeps nothing: it builds afresh on its first solve.
    fn clone(&self) -> Self {
        KeptFactors::default()
    }
}

impl std::fmt::Debug for KeptFactors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KeptFactors")
            .field("contacts", &self.sides.len())
            .field("operator", &self.op.is_some())
            .field("basis", &self.basis.is_some())
            .finish()
    }
}

impl KeptFactors {
    /// The operators of `lcp` (see [`KeptFactors::take`]) made ready: refilled
    /// in place when its contacts join the same bodies as on the last call
    /// (`Some(true)`), else built afresh (`Some(false)`, the kept basis
    /// dropped); `None` when they cannot be built (non-finite data).
    pub(crate) fn prepare(&mut self, lcp: &ContactLcp) -> Option<bool> {
        let lay = lcp.layout();
        let side = |c: usize, s: usize| lcp.side_body(c, s).unwrap_or(usize::MAX);
        let same = self.op.is_some()
            && self.k == lay.k
            && self.scale == lcp.scale()
            && self.sides.len() == lay.nc
            && self.sides.iter().enumerate().all(|(c, s)| *s == [side(c, 0), side(c, 1)]);
        if same && self.refill(lcp)? {
            return Some(true);
        }
        self.basis = None;
        let p = self.entries.fill(lcp, lcp.scale());
        let Factors { g, h, k } = &self.entries;
        self.op = Some(StructuredLcp::refillable(p, g, h, k, lcp.q().to_vec()).ok()?);
        self.physical = None;
        if lcp.scale() != 1.0 {
            self.entries.fill(lcp, 1.0);
            let Factors { g, h, k } = &self.entries;
            self.physical = Some(StructuredLcp::refillable(p, g, h, k, lcp.q().to_vec()).ok()?);
        }
        self.sides.clear();
        self.sides.extend((0..lay.nc).map(|c| [side(c, 0), side(c, 1)]));
        (self.k, self.scale) = (lay.k, lcp.scale());
        Some(false)
    }

    /// New values into the kept operators; `Some(false)` when their pattern differs.
    fn refill(&mut self, lcp: &ContactLcp) -> Option<bool> {
        let q = lcp.q();
        self.entries.fill(lcp, lcp.scale());
        let Factors { g, h, k } = &self.entries;
        let op = self.op.as_mut()?;
        if !op.refill(g, h, k, q).ok()? {
            return Some(false);
        }
        if let Some(phys) = self.physical.as_mut() {
            self.entries.fill(lcp, 1.0);
            let Factors { g, h, k } = &self.entries;
            if !phys.refill(g, h, k, q).ok()? {
                return Some(false);
            }
        }
        Some(true)
    }

    /// The operators prepared by [`KeptFactors::prepare`], lent out; give
    /// them back with [`KeptFactors::give_back`] (else the next step builds afresh).
    pub(crate) fn take(&mut self) -> Option<(StructuredLcp, Option<StructuredLcp>)> {
        Some((self.op.take()?, self.physical.take()))
    }

    /// The operators lent by [`KeptFactors::take`].
    pub(crate) fn give_back(&mut self, op: StructuredLcp, physical: Option<StructuredLcp>) {
        (self.op, self.physical) = (Some(op), physical);
    }

    /// The complementary basis `alpha` (`alpha[j]`: `z_j` basic) solved on
    /// `op`: an answer at 0 pivots when its values are those a warm run
    /// takes as they stand and the acceptance rule accepts it on `op` and on
    /// `physical` (if any: the LCP at scale 1, `z` unscaled by `lay`)
    /// within Lemke's bound on the natural residual; `None` otherwise.
    ///
    /// The kept basis (the last answer's, when this path gave it) is tried
    /// first, on its kept factors: on a resting heap the warm basis differs
    /// from it only in the friction flags of unloaded contacts, which
    /// `with_sliding_friction` picks each step from free tangential
    /// velocities of round-off size, so the warm basis changes every step
    /// while the answer does not. Then `alpha`, factored afresh and kept —
    /// only where the island `stood` (its last answer did not pivot away
    /// from its warm basis). Where it pivoted, the structured Lemke's warm
    /// run factors its start anyway (on the loaded-friction sub-LCP first)
    /// and answers at 0 pivots what this would: the fresh factorization
    /// here was a second one, paid on every pivoting step of a forming pile.
    /// Measured (`World.run`, user time): the mixed bin (seed 7, 2,500
    /// steps) 1.43–1.44 → 1.28–1.34 s; from its saved states (seeds 1, 2, 3,
    /// 7, 50 steps from every 250th, 2 rounds) 13.1 → 12.6 s; a 90-cube pour
    /// (3,000 steps) 23.9–24.8 → 21.2–21.7 s; 0 failures.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn answer(
        &mut self,
        op: &StructuredLcp,
        physical: Option<&StructuredLcp>,
        lay: lcp::ContactLayout,
        scale: f64,
        alpha: &[bool],
        tol: f64,
        stood: bool,
    ) -> Option<Solution> {
        let o = KeptOptions::default();
        if let Some(b) = self.basis.as_mut() {
            let found = b.solve(op, &o).and_then(|f| judged(op, physical, lay, scale, b.alpha(), &f.values, tol));
            if found.is_some() || b.is(alpha) {
                return counted(found);
            }
        }
        if !stood {
            return None;
        }
        self.basis = KeptBasis::new(op, alpha);
        let found = self.basis.as_mut()?.solve(op, &o)?;
        counted(judged(op, physical, lay, scale, alpha, &found.values, tol))
    }
}

/// `found`, counted in [`answers`] if it is an answer.
fn counted(found: Option<Solution>) -> Option<Solution> {
    if found.is_some() {
        ANSWERS.fetch_add(1, Ordering::Relaxed);
    }
    found
}

/// The answer of the basis `alpha` whose basic values are `v`, if it is one
/// (see [`KeptFactors::answer`]).
fn judged(
    op: &StructuredLcp,
    physical: Option<&StructuredLcp>,
    lay: lcp::ContactLayout,
    scale: f64,
    alpha: &[bool],
    v: &[f64],
    tol: f64,
) -> Option<Solution> {
    let top = v.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    if v.iter().any(|&x| !(x >= -WARM_TOL * top)) {
        return None;
    }
    let n = op.n();
    let z: Vec<f64> = (0..n).map(|j| if alpha[j] { v[j].max(0.0) } else { 0.0 }).collect();
    let mut w = vec![0.0; n];
    op.w_of(&z, &mut w);
    let residuals = Residuals::of(&z, &w);
    if !(residuals.residual <= tol * (1.0 + op.q_norm_inf())) || !structured::accepts(op, &z, &w, tol) {
        return None;
    }
    if physical.is_some_and(|phys| !accepted_physical(phys, lay, scale, &z, tol)) {
        return None;
    }
    Some(Solution { z, w, status: Status::Solved, pivots: 0, residuals, basis: Some(alpha.to_vec()), accepted: true })
}
