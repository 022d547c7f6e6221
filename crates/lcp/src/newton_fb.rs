//! Damped Newton on the Fischer–Burmeister function (placeholder being written).
use crate::{Lcp, Solution, Status};

/// Options of the damped Newton–Fischer–Burmeister method.
#[derive(Clone, Debug, PartialEq)]
pub struct NewtonFbOptions {
    /// Newton step limit. Default 100.
    pub max_iterations: usize,
    /// Stop when the natural residual ‖min(z, w)‖∞ ≤ tol. Default 1e-12.
    pub tol: f64,
}

impl Default for NewtonFbOptions {
    fn default() -> Self {
        NewtonFbOptions { max_iterations: 100, tol: 1e-12 }
    }
}

pub fn solve(lcp: &Lcp, _o: &NewtonFbOptions) -> Solution {
    Solution::from_z(lcp, vec![0.0; lcp.n()], Status::MaxIterations, 0)
}
