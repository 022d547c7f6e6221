//! A large island's LCP solved by the structured Lemke (`lcp::structured`):
//! `M = J M_b⁻¹ Jᵀ + K` handed over as its sparse factors, never formed.
//!
//! The solver first sees the sub-LCP with friction unknowns only for the
//! contacts loaded on the previous step or about to touch (`q_fn < 0`),
//! grown as contacts take load, and its answer extended exactly to the full
//! LCP (`pipeline::loaded_friction`); the full LCP is solved when that fails.
//! The answer is accepted on the LCP as scaled (by the solver, with the
//! acceptance rule of `lcp::accept` evaluated on the sparse rows) and again
//! in physical units (cone scale 1), as the body-space basis check does.
//! `None` sends the island to the dense Lemke, unless `keep_failure` (the
//! dense `M` would not fit): then the failed answer is returned as it is.

use super::replay::{self, StructuredProblem};
use crate::contact::structured::structured_lcp;
use crate::contact::ContactLcp;
use lcp::contact::ContactLayout;
use lcp::structured::guess::{self, GuessOptions};
use lcp::structured::{self, StructuredOptions};
use lcp::{Solution, Status};

/// Where the structured path starts pivoting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// From the warm basis handed over (the previous step's), if any.
    Previous,
    /// From the basis guessed by `sweeps` sweeps of body-space projected Gauss–Seidel (`lcp::structured::guess`).
    Guess { sweeps: usize },
    /// The warm basis for the contacts it has loaded, the guess's for the others.
    Merged { sweeps: usize },
    /// Cold.
    Cold,
}

/// Solves `lcp` (its rows assembled) from the basis `warm`, at the acceptance tolerance `tol`.
pub fn solve(lcp: &ContactLcp, warm: Option<&[bool]>, tol: f64, keep_failure: bool) -> Option<Solution> {
    let op = structured_lcp(lcp, lcp.scale()).ok()?;
    let physical = if lcp.scale() == 1.0 { None } else { Some(structured_lcp(lcp, 1.0).ok()?) };
    let warm = warm.map(|b| sliding_contacts_seeded(lcp, b));
    let problem = StructuredProblem { op, physical, scale: lcp.scale(), layout: lcp.layout(), warm, tol };
    replay::dump(&problem);
    let sol = solve_problem(&problem, Start::Previous);
    (sol.ok() || keep_failure).then_some(sol)
}

/// Solves `p` from `start`; a `Solved` answer is one accepted on the LCP as
/// scaled and in physical units (else `Numerical`).
pub(crate) fn solve_problem(p: &StructuredProblem, start: Start) -> Solution {
    let o = StructuredOptions { accept_tol: p.tol, ..Default::default() };
    let basis = match start {
        Start::Previous => p.warm.clone(),
        Start::Guess { sweeps } => {
            Some(guess::guess_basis(&p.op, p.layout, &GuessOptions { sweeps, ..Default::default() }, None))
        }
        Start::Merged { sweeps } => {
            let g = guess::guess_basis(&p.op, p.layout, &GuessOptions { sweeps, ..Default::default() }, None);
            p.warm.as_ref().map(|w| merged(p.layout, w, g))
        }
        Start::Cold => None,
    };
    let mut sol = solve_from(p, &o, basis.as_deref());
    let physical_ok = sol.ok()
        && p.physical.as_ref().is_none_or(|phys| {
            let mut z = sol.z.clone();
            p.layout.unscale_z(&mut z, p.scale);
            let mut w = vec![0.0; z.len()];
            phys.w_of(&z, &mut w);
            structured::accepts(phys, &z, &w, p.tol)
        });
    if !physical_ok && sol.status == Status::Solved {
        sol.status = Status::Numerical;
    }
    sol
}

/// `warm`'s flags for the contacts loaded in it, `guess`'s for the others.
fn merged(lay: ContactLayout, warm: &[bool], mut guess: Vec<bool>) -> Vec<bool> {
    for c in (0..lay.nc).filter(|&c| warm[lay.fn_index(c)]) {
        guess[lay.fn_index(c)] = true;
        guess[lay.fd_of(c)].copy_from_slice(&warm[lay.fd_of(c)]);
        guess[lay.lambda_index(c)] = warm[lay.lambda_index(c)];
    }
    guess
}

/// The loaded-friction sub-LCPs from `warm`, then the full LCP when they fail.
fn solve_from(p: &StructuredProblem, o: &StructuredOptions, warm: Option<&[bool]>) -> Solution {
    let (op, lay) = (&p.op, p.layout);
    // Friction first for the contacts loaded on the previous step or about to touch (q_fn < 0).
    let active = (0..lay.nc).map(|c| warm.is_some_and(|b| b[lay.fn_index(c)]) || op.q()[lay.fn_index(c)] < 0.0);
    match super::loaded_friction::solve(op, lay, o, warm, active.collect()) {
        Ok(sol) if sol.ok() => sol,
        Ok(Solution { pivots, .. }) | Err(pivots) => {
            let sol = structured::solve(op, o, warm);
            Solution { pivots: sol.pivots + pivots, ..sol }
        }
    }
}

/// `warm` with the friction of each contact that has no flag set (a new
/// contact, or one that neither pushed nor slid) chosen as a separating
/// contact's answer: if its free tangential velocity has a component against
/// some friction direction, `λ` and the `fd` of the most opposed direction
/// `j*` basic (then `fd_j* = 0` from the cone row, `λ = −d_j*ᵀv_t` and every
/// other `w_fd ≥ 0`, up to the coupling with other contacts). Such a pair
/// keeps a regular basis regular: the cone row of the contact has its one
/// basic entry in `fd_j*`, its `λ` column its one in `fd_j*`'s row.
///
/// Measured on a forming 200-cube heap (`many_bodies heap:200`, steps
/// 141–150): most of the warm basis's negative values were such contacts'
/// `w_fd` (800 of 1,100 at n = 7,100), each costing Lemke pivots.
fn sliding_contacts_seeded(lcp: &ContactLcp, warm: &[bool]) -> Vec<bool> {
    let lay = lcp.layout();
    let mut mask = warm.to_vec();
    if mask.len() != lay.n() {
        return mask;
    }
    let q = lcp.q();
    for c in 0..lay.nc {
        let (f, l) = (lay.fd_of(c), lay.lambda_index(c));
        if mask[lay.fn_index(c)] {
            continue;
        }
        mask[f.clone()].iter_mut().for_each(|b| *b = false);
        mask[l] = false;
        let Some(j) = f.clone().min_by(|&a, &b| q[a].total_cmp(&q[b])) else { continue };
        if q[j] < 0.0 {
            mask[j] = true;
            mask[l] = true;
        }
    }
    mask
}
