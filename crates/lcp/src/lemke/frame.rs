//! A rung's working problem: `M` Ruiz-equilibrated or not, `q` brought to
//! unit size (`z` scales linearly with `q`), and how its answers map back and
//! are judged.

use crate::problem::Lcp;
use crate::scaling::{RuizBuffers, Scaling};
use crate::solution::Solution;

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
    /// Bounds on the natural residual in the units given and in the working units.
    pub tol: f64,
    pub tol_work: f64,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            scaling: Scaling { row: Vec::new(), col: Vec::new() },
            ruiz: RuizBuffers::default(),
            qscale: 1.0,
            work: Lcp::from_parts_unchecked(Vec::new(), Vec::new()),
            tol: 0.0,
            tol_work: 0.0,
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
        self.tol_work = accept_tol * (1.0 + self.work.q_norm_inf());
        self.tol = accept_tol * (1.0 + qmax);
    }

    /// `z` in the units given (rounded-off negatives clipped) from working units.
    pub fn unscale(&self, z_work: &[f64]) -> Vec<f64> {
        z_work.iter().zip(&self.scaling.col).map(|(z, c)| (c * z / self.qscale).max(0.0)).collect()
    }

    /// Accepted in the units given and in the working ones, where
    /// z' = qs·D_c⁻¹·z and w' = qs·D_r·w: a cone-scaled problem's λ rows are
    /// divided by s on the way back to physical units, and the equilibration
    /// undoes that scaling, so its units are the ones that matter.
    pub fn accept(&self, s: &Solution) -> bool {
        let (qs, sc) = (self.qscale, &self.scaling);
        let work_residual = (0..s.z.len()).fold(0.0f64, |a, i| {
            let (zw, ww) = (qs * s.z[i] / sc.col[i], qs * sc.row[i] * s.w[i]);
            a.max(zw.min(ww).abs())
        });
        s.residuals.residual <= self.tol && work_residual <= self.tol_work
    }
}

/// A power of two near `1/x` for `x > 0`, kept normal so that scaling by it is
/// exact and finite even for a subnormal `x` (where `1/x` overflows).
fn pow2_inverse(x: f64) -> f64 {
    2f64.powi((-x.log2().round()).clamp(-1000.0, 1000.0) as i32)
}
