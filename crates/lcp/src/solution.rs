//! What every solver returns: one `Solution` type, one set of statuses and one
//! error measure shared by all of them (as Siconos does with its `lcp_compute_error`).

use crate::problem::Lcp;

/// How a solve ended. Every status comes with correctly sized `z` and `w` (the
/// last iterate). `Solution::ok()` — `Solved` *and* accepted by the rule of
/// [`crate::accept`] — is what says `z` solves the LCP: every method's
/// `Solved` passes that rule except classic Lemke's, which keeps the source note's
/// own check as its word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// Complementary solution found and accepted by the solver's check (the
    /// rule of [`crate::accept`] for every method but classic Lemke).
    Solved,
    /// Lemke: the entering column had no positive entry (a secondary ray).
    /// For a copositive-plus `M` this proves the LCP has no solution.
    RayTermination,
    /// Lemke: pivot limit reached.
    MaxPivots,
    /// Iterative solvers (PGS, Newton–FB): iteration limit reached without convergence.
    MaxIterations,
    /// A basis matrix could not be factored.
    SingularBasis,
    /// A basis repeated: the pivoting cycled.
    Cycling,
    /// The method ended but its answer fails the residual check (round-off won).
    Numerical,
    /// The answer solves a regularized problem `M + αI`, not `M` itself.
    Regularized,
}

impl Status {
    /// Stable snake_case name used by the Python API, the CLI and result files.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Solved => "solved",
            Status::RayTermination => "ray_termination",
            Status::MaxPivots => "max_pivots",
            Status::MaxIterations => "max_iterations",
            Status::SingularBasis => "singular_basis",
            Status::Cycling => "cycling",
            Status::Numerical => "numerical",
            Status::Regularized => "regularized",
        }
    }

    /// All statuses, in declaration order.
    pub const ALL: [Status; 8] = [
        Status::Solved,
        Status::RayTermination,
        Status::MaxPivots,
        Status::MaxIterations,
        Status::SingularBasis,
        Status::Cycling,
        Status::Numerical,
        Status::Regularized,
    ];
}

/// Error measures of a candidate `z` for `(M, q)`, with `w = M z + q` recomputed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Residuals {
    /// Natural residual `‖min(z, w)‖∞`: the one measure shared by all solvers.
    pub residual: f64,
    /// `min_i z_i` (negative means infeasible).
    pub min_z: f64,
    /// `min_i w_i` (negative means infeasible).
    pub min_w: f64,
    /// `max_i |z_i w_i|`.
    pub max_complementarity: f64,
}

impl Residuals {
    /// Residuals of `z` and `w` (which should be `M z + q`). A non-finite
    /// `z_i` or `w_i` makes the natural residual and the complementarity
    /// infinite (`f64::max` would skip a NaN), so that no rule accepts it.
    ///
    /// One sweep over four lanes with `if`-selects (as the kernels of
    /// Lemke's scans): a NaN entry is skipped by each max and min as
    /// `f64::max` and `f64::min` skip it, and the infinities are set after,
    /// so the measures are those of the plain loop (on a resting 10-box
    /// stack that loop was 4 % of its step).
    pub fn of(z: &[f64], w: &[f64]) -> Self {
        use crate::kernels::{pick_max, pick_min, LANES};
        let n = z.len().min(w.len());
        let (z, w) = (&z[..n], &w[..n]);
        let (mut res, mut comp) = ([0.0f64; LANES], [0.0f64; LANES]);
        let (mut min_z, mut min_w) = ([f64::INFINITY; LANES], [f64::INFINITY; LANES]);
        // `x·0` is NaN for a NaN or infinite `x`, 0 otherwise.
        let mut nan = [0.0f64; LANES];
        let mut lane = |k: usize, zi: f64, wi: f64| {
            res[k] = pick_max(res[k], pick_min(zi, wi).abs());
            min_z[k] = pick_min(min_z[k], zi);
            min_w[k] = pick_min(min_w[k], wi);
            comp[k] = pick_max(comp[k], (zi * wi).abs());
            nan[k] += zi * 0.0 + wi * 0.0;
        };
        let (mut cz, mut cw) = (z.chunks_exact(LANES), w.chunks_exact(LANES));
        for (a, b) in (&mut cz).zip(&mut cw) {
            for k in 0..LANES {
                lane(k, a[k], b[k]);
            }
        }
        for (&zi, &wi) in cz.remainder().iter().zip(cw.remainder()) {
            lane(0, zi, wi);
        }
        let fold = |v: [f64; LANES], init: f64, f: fn(f64, f64) -> f64| v.iter().fold(init, |m, &x| f(m, x));
        let finite = nan.iter().sum::<f64>() == 0.0;
        let inf_unless = |v: f64| if finite { v } else { f64::INFINITY };
        Residuals {
            residual: inf_unless(fold(res, 0.0, pick_max)),
            min_z: if n == 0 { 0.0 } else { fold(min_z, f64::INFINITY, pick_min) },
            min_w: if n == 0 { 0.0 } else { fold(min_w, f64::INFINITY, pick_min) },
            max_complementarity: inf_unless(fold(comp, 0.0, pick_max)),
        }
    }

    /// Recomputes `w = M z + q` and returns `(w, residuals)`.
    pub fn compute(lcp: &Lcp, z: &[f64]) -> (Vec<f64>, Self) {
        let w = lcp.w_of(z);
        let r = Residuals::of(z, &w);
        (w, r)
    }
}

/// The result of any solver: `z`, `w = M z + q`, status, work done and residuals.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Unknowns, length n (the last iterate when not solved).
    pub z: Vec<f64>,
    /// `M z + q`, recomputed from `z` in the units of the problem as given.
    pub w: Vec<f64>,
    pub status: Status,
    /// Pivots (Lemke) or iterations (PGS sweeps, Newton steps).
    pub pivots: usize,
    /// Residuals of `(z, w)` for the problem as given.
    pub residuals: Residuals,
    /// Lemke only: which `z_j` were basic at the end (the complementary basis),
    /// usable as a warm start for a similar problem.
    pub basis: Option<Vec<bool>>,
    /// `(z, w)` passes the acceptance rule ([`crate::accept::accepts`]) at the
    /// solver's tolerance (Lemke's `accept_tol`, else [`crate::accept::DEFAULT_TOL`]).
    pub accepted: bool,
}

impl Solution {
    /// Wraps a final `z`, recomputing `w` and the residuals from the problem,
    /// judged by the acceptance rule at [`crate::accept::DEFAULT_TOL`].
    pub fn from_z(lcp: &Lcp, z: Vec<f64>, status: Status, pivots: usize) -> Self {
        Self::from_z_tol(lcp, z, status, pivots, crate::accept::DEFAULT_TOL)
    }

    /// As [`Solution::from_z`], judged at `tol`.
    pub fn from_z_tol(lcp: &Lcp, z: Vec<f64>, status: Status, pivots: usize, tol: f64) -> Self {
        let (w, residuals) = Residuals::compute(lcp, &z);
        let accepted = crate::accept::accepts(lcp, &z, &w, tol);
        Solution { z, w, status, pivots, residuals, basis: None, accepted }
    }

    /// `true` only for `Status::Solved` with an answer the acceptance rule accepts.
    pub fn ok(&self) -> bool {
        self.status == Status::Solved && self.accepted
    }
}
