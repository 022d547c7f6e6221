//! Stage 4, the last word: the method's own solver on the dense `M`, formed
//! here if assembly left it out. For Lemke that is its repair ladder, ending
//! in the double-double and exact rungs inside `lcp::lemke`. A jointed
//! island first tries its loaded contacts' sub-LCP ([`super::dense_loaded`]).

use crate::pipeline::island::{IslandLcp, IslandSolver};
use lcp::{LcpError, Solution};

/// Solves `isl`'s LCP with `solver`, from `warm`; an error when the LCP
/// cannot be handed to it (non-finite data).
pub(super) fn solve(
    isl: &mut IslandLcp,
    solver: &mut IslandSolver<'_>,
    warm: Option<&[bool]>,
) -> Result<Solution, LcpError> {
    isl.form_matrix();
    // Lend the buffers to an Lcp, solve, and take them back.
    let lcp = isl.lcp.take_lcp()?;
    let loaded = if isl.dense_only() { super::dense_loaded::solve(&lcp, isl.lcp.layout(), solver, warm) } else { None };
    let sol = loaded.unwrap_or_else(|| solver(&lcp, warm));
    isl.lcp.restore(lcp);
    Ok(sol)
}
