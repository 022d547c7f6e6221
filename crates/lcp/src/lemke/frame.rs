//! A rung's working problem: `M` Ruiz-equilibrated or not, `q` brought to
//! unit size (`z` scales linearly with `q`), and how its answers map back.
//! They are judged in the units given by the rule of [`crate::accept`],
//! which the scaling does not change (it is invariant under diagonal scaling).

use crate::problem::Lcp;
use crate::scaling::{RuizBuffers, Scaling};
use crate::solution::{Solution, Status};

/// Ruiz sweeps used by the default equilibration.
const RUIZ_ITERATIONS: usize = 8;

/// The working problem of one rung, rebuilt in place by [`Frame::reset`].
pub(crate) struct Frame {
    /// `D_r`, `D_c`: Ruiz factors (powers of two) or all ones.
    pub scaling: Scaling,
    /// Exponent buffers of the Ruiz equilibration.
    ruiz: RuizBuffers,
    /// The power of two that brings `‖q‖∞` near 1.
    pub qscale: f64,
    /// `(D_r M D_c, qscale·D_r q)`: the problem the rung pivots on.
    pub work: Lcp,
    /// The acceptance rule's tolerance (Lemke's `accept_tol`).
    pub accept_tol: f64,
    /// `accept_tol·(1 + ‖q‖∞)`: the natural-residual target of the Newton–FB polish.
    pub tol: f64,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            scaling: Scaling { row: Vec::new(), col: Vec::new() },
            ruiz: RuizBuffers::default(),
            qscale: 1.0,
            work: Lcp::from_parts_unchecked(Vec::new(), Vec::new()),
            accept_tol: 0.0,
            tol: 0.0,
        }
    }
}

impl Frame {
    /// Rebuilds the working problem of `lcp`, equilibrated or not, in this frame's buffers.
    pub fn reset(&mut self, lcp: &Lcp, equilibrate: bool, accept_tol: f64) {
        if equilibrate {
            self.scaling.ruiz_in(lcp, RUIZ_ITERATIONS, &mut self.ruiz);
        } else {
            self.scaling.identity_in(lcp.n());
        }
        let qmax = lcp.q_norm_inf();
        self.qscale = if qmax > 0.0 { pow2_inverse(qmax) } else { 1.0 };
        self.scaling.apply_pow2_into(lcp, self.qscale, &mut self.work);
        self.accept_tol = accept_tol;
        self.tol = accept_tol * (1.0 + qmax);
    }

    /// `z` in the units given (rounded-off negatives clipped) from working units.
    pub fn unscale(&self, z_work: &[f64]) -> Vec<f64> {
        z_work.iter().zip(&self.scaling.col).map(|(z, c)| (c * z / self.qscale).max(0.0)).collect()
    }

    /// The answer `z_work` (working units) as a `Solution` of `lcp`, judged by the acceptance rule.
    pub fn solution(&self, lcp: &Lcp, z_work: &[f64], status: Status, pivots: usize) -> Solution {
        Solution::from_z_tol(lcp, self.unscale(z_work), status, pivots, self.accept_tol)
    }
}

/// A power of two near `1/x` for `x > 0`, kept normal so that scaling by it is
/// exact and finite even for a subnormal `x` (where `1/x` overflows).
fn pow2_inverse(x: f64) -> f64 {
    2f64.powi((-x.log2().round()).clamp(-1000.0, 1000.0) as i32)
}
