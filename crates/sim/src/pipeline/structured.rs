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
    let t0 = std::time::Instant::now();
    let mut sol = structured::solve(&op, &o, warm);
    let physical_ok = sol.ok() && {
        let physical = if lcp.scale() == 1.0 { None } else { structured_lcp(lcp, 1.0).ok() };
        match physical {
            None => true,
            Some(p) => {
                let mut z = Vec::new();
                lcp.unscale_z(&sol.z, &mut z);
                let mut w = vec![0.0; z.len()];
                p.w_of(&z, &mut w);
                structured::accepts(&p, &z, &w, tol)
            }
        }
    };
    if std::env::var("TRACE_STRUCTURED").is_ok() {
        eprintln!("structured n {} warm {} status {:?} ok {} physical {} pivots {} {:.3} s", op.n(), warm.is_some(), sol.status, sol.ok(), physical_ok, sol.pivots, t0.elapsed().as_secs_f64());
    }
    if !physical_ok {
        if let Ok(dir) = std::env::var("DUMP_STRUCTURED") {
            let (g, h, k) = op.entries();
            let mut t = format!("{} {} {} {} {}\n", op.n(), op.p(), g.len(), h.len(), k.len());
            for (a, b, v) in g.iter().chain(&h).chain(&k) {
                t += &format!("{a} {b} {v:e}\n");
            }
            for v in op.q() {
                t += &format!("{v:e}\n");
            }
            let _ = std::fs::write(format!("{dir}/fail_{}.txt", op.n()), t);
        }
    }
    if physical_ok {
        return Some(sol);
    }
    if sol.status == Status::Solved {
        sol.status = Status::Numerical;
    }
    keep_failure.then_some(sol)
}
