//! Projected Gauss–Seidel (placeholder being written).
use crate::{Lcp, Solution, Status};

/// Options of projected Gauss–Seidel.
#[derive(Clone, Debug, PartialEq)]
pub struct PgsOptions {
    /// Relaxation factor ω in (0, 2). Default 1.0.
    pub omega: f64,
    /// Sweep limit. Default 10 000.
    pub max_iterations: usize,
    /// Stop when the natural residual ‖min(z, w)‖∞ ≤ tol. Default 1e-10.
    pub tol: f64,
}

impl Default for PgsOptions {
    fn default() -> Self {
        PgsOptions { omega: 1.0, max_iterations: 10_000, tol: 1e-10 }
    }
}

pub fn solve(lcp: &Lcp, _o: &PgsOptions) -> Solution {
    Solution::from_z(lcp, vec![0.0; lcp.n()], Status::MaxIterations, 0)
}
