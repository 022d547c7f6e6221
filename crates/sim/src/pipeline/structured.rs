//! A large island's LCP solved by the structured Lemke (`lcp::structured`):
//! `M = J M_b⁻¹ Jᵀ + K` handed over as its sparse factors, never formed.
//!
//! The answer is accepted on the LCP as scaled (by the solver, with the
//! acceptance rule of `lcp::accept` evaluated on the sparse rows) and again
//! in physical units (cone scale 1), as the body-space basis check does.
//! `None` sends the island to the dense Lemke, unless `keep_failure` (the
//! dense `M` would not fit): then the failed answer is returned as it is.

use crate::contact::structured::structured_lcp;
use crate::contact::ContactLcp;
use lcp::structured::{self, StructuredOptions};
use lcp::{Solution, Status};

/// Solves `lcp` (its rows assembled) from the basis `warm`, at the acceptance tolerance `tol`.
pub fn solve(lcp: &ContactLcp, warm: Option<&[bool]>, tol: f64, keep_failure: bool) -> Option<Solution> {
    let op = structured_lcp(lcp, lcp.scale()).ok()?;
    let o = StructuredOptions { accept_tol: tol, ..Default::default() };
    let mut sol = structured::solve(&op, &o, warm);
    let physical_ok = sol.ok()
        && (lcp.scale() == 1.0
            || structured_lcp(lcp, 1.0).is_ok_and(|p| {
                let mut z = Vec::new();
                lcp.unscale_z(&sol.z, &mut z);
                let mut w = vec![0.0; z.len()];
                p.w_of(&z, &mut w);
                structured::accepts(&p, &z, &w, tol)
            }));
    if physical_ok {
        return Some(sol);
    }
    if sol.status == Status::Solved {
        sol.status = Status::Numerical;
    }
    keep_failure.then_some(sol)
}
