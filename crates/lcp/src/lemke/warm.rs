//! Warm starts: the previous answer's complementary basis, made regular.
//!
//! A statically indeterminate answer (a resting stack: four corner contacts
//! per interface, three independent normal constraints) can leave a basis
//! whose block `M_αα` is singular, or becomes so at the next step's round-off.
//! Instead of a cold start, the warm start keeps a regular principal block on
//! the same support ([`super::subbasis`]): the same kind of answer, one of the
//! many exact solutions, with no change to the problem.

use super::basis::{Basis, BasisBuffers, Var};
use super::frame::Frame;
use super::run::{self, LoopBuffers, Run, RunSettings};
use super::subbasis::regular_subset;
use crate::problem::Lcp;
use crate::solution::{Solution, Status};

/// Block principal pivoting rounds tried from a warm basis before Lemke.
const SWAP_ROUNDS: usize = 3;

/// Scratch of a warm start, kept in the workspace.
#[derive(Default)]
pub(crate) struct WarmBuffers {
    /// The complementary set in use, reduced to a regular block if need be.
    beta: Vec<usize>,
    /// The next one, after a block principal pivot.
    next: Vec<usize>,
    /// The block during a reduction (see [`regular_subset`]).
    block: Vec<f64>,
    /// Membership mask of `beta`, for its covering vector.
    in_beta: Vec<bool>,
}

/// How a rung's pivoting starts.
pub(crate) enum Start<'a> {
    Run(Run<'a>),
    /// A warm basis that solves the problem as it stands, and the buffers.
    Done(Solution, BasisBuffers),
    /// A warm basis that could not be made regular: the buffers and the pivots made.
    Singular(BasisBuffers, usize),
}

/// The warm start of a rung from the complementary set `alpha` (see
/// `super::solve_warm`): a regular basis on its support, accepted as it
/// stands if its answer passes `frame`'s check, else after up to
/// [`SWAP_ROUNDS`] block principal pivots, else Lemke from the last basis.
#[allow(clippy::too_many_arguments)]
pub(crate) fn start<'a>(
    lcp: &Lcp,
    frame: &'a Frame,
    alpha: &[usize],
    set: &RunSettings,
    bufs: BasisBuffers,
    pivoting: &mut LoopBuffers,
    d: &'a mut Vec<f64>,
    z_work: &mut Vec<f64>,
    wb: &mut WarmBuffers,
) -> Start<'a> {
    let (n, work) = (lcp.n(), &frame.work);
    wb.beta.clear();
    wb.beta.extend_from_slice(alpha);
    let mut basis = match warm_basis(work, &mut wb.beta, &mut wb.block, bufs) {
        Ok(b) => b,
        Err(b) => return Start::Singular(b, 0),
    };
    // Exchanges made by block principal pivots (each counts as a pivot).
    let mut swaps = 0;
    for round in 0.. {
        if run::warm_feasible(&basis) {
            break;
        }
        // Its values, negatives clipped, may solve the problem as it stands
        // although round-off (or the step's small change) put some a hair
        // below zero: the residual check decides, in the units given.
        basis.z_into(z_work);
        let mut sol = frame.solution(lcp, z_work, Status::Solved, swaps);
        if !sol.accepted {
            super::snap_in_working_units(lcp, frame, &mut sol);
        }
        if sol.accepted {
            let mask = super::basic_mask(&basis.s, n);
            return Start::Done(Solution { basis: Some(mask), ..sol }, basis.into_buffers());
        }
        // Else exchange the negative basics for their complements.
        let k = swap_negatives(&basis, run::warm_tolerance(&basis), &mut wb.next);
        // (The exchanges spend the pivot budget too.)
        if round == SWAP_ROUNDS || k == 0 || swaps + k > set.max_pivots {
            break;
        }
        basis = match warm_basis(work, &mut wb.next, &mut wb.block, basis.into_buffers()) {
            Ok(b) => b,
            Err(b) => return Start::Singular(b, swaps),
        };
        swaps += k;
        std::mem::swap(&mut wb.beta, &mut wb.next);
    }
    run::warm_covering(work, &wb.beta, d, &mut wb.in_beta);
    let d: &'a Vec<f64> = d;
    basis.set_covering(d);
    // What the exchanges left of the budget.
    let set = RunSettings {
        max_pivots: set.max_pivots - swaps,
        rule: set.rule,
        trace: set.trace,
        refactor_every: set.refactor_every,
    };
    match run::run_warm(basis, &set, pivoting) {
        Ok(mut r) => {
            r.pivots += swaps;
            Start::Run(r)
        }
        Err(b) => Start::Singular(b.into_buffers(), swaps),
    }
}

/// The complementary basis on `alpha`, factored (without a covering vector,
/// see [`Basis::set_covering`]). If its block is singular, `alpha` is first
/// reduced in place to a regular principal subset; `Err` with the buffers
/// when no regular basis results. `scratch` holds the block during the reduction.
fn warm_basis<'a>(
    work: &'a Lcp,
    alpha: &mut Vec<usize>,
    scratch: &mut Vec<f64>,
    bufs: BasisBuffers,
) -> Result<Basis<'a>, BasisBuffers> {
    let bufs = match Basis::complementary(work, &[], alpha, bufs) {
        Ok(b) => return Ok(b),
        Err(b) => b.into_buffers(),
    };
    if regular_subset(|i, j| work.at(i, j), alpha, scratch) == 0 {
        return Err(bufs);
    }
    Basis::complementary(work, &[], alpha, bufs).map_err(Basis::into_buffers)
}

/// One block principal pivot: the complementary set with every basic below
/// `−thresh` exchanged for its complement (a negative `z_j` leaves, a
/// negative `w_i` makes `z_i` basic), written into `alpha`. Returns the
/// number of exchanges (0: nothing below `−thresh`).
fn swap_negatives(basis: &Basis, thresh: f64, alpha: &mut Vec<usize>) -> usize {
    alpha.clear();
    let mut swaps = 0;
    for (p, v) in basis.s.iter().enumerate() {
        if let Var::Z(j) = *v {
            if basis.val_s[p] >= -thresh {
                alpha.push(j);
            } else {
                swaps += 1;
            }
        }
    }
    for (i, &v) in basis.val_w.iter().enumerate() {
        if basis.w_basic(i) && v < -thresh {
            alpha.push(i);
            swaps += 1;
        }
    }
    alpha.sort_unstable();
    swaps
}
