//! Lemke's complementary pivoting method.
//!
//! - [`basis`]: the basis in block form, `C⁻¹` kept and updated in O(m²).
//! - [`ratio`]: the lexicographic and the classic (seed) ratio tests.
//! - [`run`]: the pivoting loop with its cycle guard and pivot limit.
//! - [`refine`]: re-solving the final complementary basis.
//!
//! `Lexicographic` (default) equilibrates `M` (Ruiz, power-of-two factors, so
//! the scaling itself adds no round-off) and normalizes `q`, pivots, re-solves
//! the final basis, maps `z` back and accepts it only if its natural residual
//! in the units given is small. `Classic` pivots on the problem as given with
//! absolute tolerances and trusts its own values, as the seed note's did.

mod basis;
mod options;
mod ratio;
mod refine;
mod run;

pub use options::{LemkeOptions, Pivoting};

use crate::problem::Lcp;
use crate::scaling::Scaling;
use crate::solution::{Solution, Status};
use basis::Var;
use ratio::Rule;
use run::{run, RunSettings};

/// Ruiz sweeps used by the default equilibration.
const RUIZ_ITERATIONS: usize = 8;

/// Solves `lcp` by Lemke's method. Never panics on numerics.
pub fn solve(lcp: &Lcp, o: &LemkeOptions) -> Solution {
    match o.pivoting {
        Pivoting::Classic => solve_classic(lcp, o),
        Pivoting::Lexicographic => solve_lexicographic(lcp, o),
    }
}

/// Refactor often enough to bound drift, rarely enough to stay O(n²) per pivot.
fn refactor_every(n: usize) -> usize {
    n.max(50)
}

fn solve_classic(lcp: &Lcp, o: &LemkeOptions) -> Solution {
    let d = vec![1.0; lcp.n()];
    let set = RunSettings {
        rule: Rule::Classic { piv_tol: o.piv_tol, zero_tol: o.zero_tol },
        max_pivots: o.pivot_limit(lcp.n()),
        refactor_every: refactor_every(lcp.n()),
    };
    let r = run(lcp, &d, &set);
    let (z, _) = r.basis.z();
    let mut sol = Solution::from_z(lcp, z, r.status, r.pivots);
    sol.basis = Some(basic_mask(&r.basis.s, lcp.n()));
    sol
}

fn solve_lexicographic(lcp: &Lcp, o: &LemkeOptions) -> Solution {
    let n = lcp.n();
    // Equilibrate M and bring q to unit size: z scales linearly with q.
    let scaling = if o.equilibrate { Scaling::ruiz(lcp, RUIZ_ITERATIONS) } else { Scaling::identity(n) };
    let qmax = lcp.q().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let qscale = if qmax > 0.0 { pow2_near(1.0 / qmax) } else { 1.0 };
    let mut work = scaling.apply(lcp);
    if qscale != 1.0 {
        let (m, q) = work.into_parts();
        work = Lcp::new(m, q.into_iter().map(|v| v * qscale).collect()).expect("scaling keeps the LCP valid");
    }
    let d = vec![1.0; n];
    let set = RunSettings {
        rule: Rule::Lexicographic { piv_tol: o.piv_tol, tie_tol: o.zero_tol.min(1e-9) },
        max_pivots: o.pivot_limit(n),
        refactor_every: refactor_every(n),
    };
    let r = run(&work, &d, &set);
    let mask = basic_mask(&r.basis.s, n);
    // The final complementary basis, re-solved; the loop's values as a fallback.
    let z_work = match r.status {
        Status::Solved => {
            let alpha: Vec<usize> = (0..n).filter(|&j| mask[j]).collect();
            refine::resolve_basis(&work, &alpha).unwrap_or_else(|| r.basis.z().0)
        }
        _ => r.basis.z().0,
    };
    let z: Vec<f64> = scaling.z_back(&z_work).into_iter().map(|v| (v / qscale).max(0.0)).collect();
    let mut sol = Solution::from_z(lcp, z, r.status, r.pivots);
    if sol.status == Status::Solved && !(sol.residuals.natural <= o.accept_tol * (1.0 + qmax)) {
        sol.status = Status::Numerical;
    }
    sol.basis = Some(mask);
    sol
}

/// Which `z_j` are basic.
fn basic_mask(s: &[Var], n: usize) -> Vec<bool> {
    let mut mask = vec![false; n];
    for v in s {
        if let Var::Z(j) = *v {
            mask[j] = true;
        }
    }
    mask
}

/// The power of two nearest to `x > 0`, so scaling by it is exact.
fn pow2_near(x: f64) -> f64 {
    2f64.powi(x.log2().round() as i32)
}
