//! The double-double rungs on demand, for an answer the caller doubts.
//!
//! The acceptance rule judges each row of `w = M z + q` on its own scale,
//! but a caller may know more than `M`: the simulator sees that a row's
//! scale can be one body's mobility times impulses that cancel on it, and
//! judges the same answer in body space (`sim::contact::body_rule`). An
//! answer the rule accepts from an `f64` basis of cond ~1e17 can fail there
//! (a 1e8 kg box on a 1 kg one: the heavy box pushed up at mm/s).
//! [`solve_dd`] then tries, in double-double: the caller's bases (say the
//! answer's and the previous step's) re-solved with refinement (`dd_solve`:
//! the values, where a basis was right), then
//! Lemke from the all-slack basis (`extended`: the path too) on the working
//! problem equilibrated as `o` says, then on the other one; and returns the
//! first answer that the rule and the caller's `accept` both accept.
//!
//! Measured on 2,000 steps each of a 1e7 and a 1e8 kg box resting on a 1 kg
//! box (n = 80), with the answer's basis alone: of 131 answers the
//! body-space check rejected, 9 were right in their basis, 115 needed the
//! double-double path, 3 the other scaling (the first run ended on a ray or
//! cycled); for 4 no run passed (3 with the previous step's basis too).

use super::extended::{self, ExtEnd};
use super::frame::Frame;
use super::LemkeOptions;
use crate::problem::Lcp;
use crate::solution::{Solution, Status};

/// Largest LCP [`solve_dd`] tries (the double-double tableau's limit).
pub const DD_MAX_N: usize = extended::MAX_N;

/// The first of (each basis of `bases` re-solved in double-double, Lemke in
/// double-double from scratch on each scaling) that the acceptance rule at
/// `o.accept_tol` and `accept` accept; `None` when none is, or `n` is above
/// the double-double rung's limit. Pivots of the answer: those of its
/// double-double runs (0 for the re-solved basis).
pub fn solve_dd(
    lcp: &Lcp,
    o: &LemkeOptions,
    bases: &[&[bool]],
    mut accept: impl FnMut(&Solution) -> bool,
) -> Option<Solution> {
    let n = lcp.n();
    if n > DD_MAX_N {
        return None;
    }
    let mut frame = Frame::default();
    let mut take = |frame: &Frame, z: Vec<f64>, mask: Vec<bool>, pivots: usize| {
        let sol = frame.solution(lcp, &z, Status::Solved, pivots);
        (sol.accepted && accept(&sol)).then_some(Solution { basis: Some(mask), ..sol })
    };
    frame.reset(lcp, o.equilibrate, o.accept_tol);
    for &mask in bases.iter().filter(|b| b.len() == n) {
        if let Some(sol) = extended::resolve(&frame.work, mask).and_then(|z| take(&frame, z, mask.to_vec(), 0)) {
            return Some(sol);
        }
    }
    let mut pivots = 0;
    for equilibrate in [o.equilibrate, !o.equilibrate] {
        frame.reset(lcp, equilibrate, o.accept_tol);
        let budget = o.pivot_limit(n).saturating_sub(pivots);
        let (end, taken) = extended::solve(&frame.work, budget, super::EXTENDED_OPS);
        pivots += taken;
        if let ExtEnd::Solved(z, mask) = end {
            if let Some(sol) = take(&frame, z, mask, pivots) {
                return Some(sol);
            }
        }
    }
    None
}
