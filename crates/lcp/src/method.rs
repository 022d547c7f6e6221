//! One entry point over all solvers: `solve(&Lcp, &Method) -> Solution`.
//!
//! Callers that do not care which algorithm runs (the simulator, the Python
//! glue, batch solves) hold a `Method` and call this; each solver also exposes
//! its own `solve(&Lcp, &Options)` with the same contract.

use crate::lemke::LemkeOptions;
use crate::newton_fb::NewtonFbOptions;
use crate::pgs::PgsOptions;
use crate::problem::Lcp;
use crate::solution::Solution;

/// A solver together with its options.
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    Lemke(LemkeOptions),
    Pgs(PgsOptions),
    NewtonFb(NewtonFbOptions),
}

impl Default for Method {
    /// The robust default: lexicographic Lemke with equilibration.
    fn default() -> Self {
        Method::Lemke(LemkeOptions::default())
    }
}

impl Method {
    /// Short name as used by the Python API and CLI (`"lemke"`, `"pgs"`, `"newton_fb"`).
    pub fn name(&self) -> &'static str {
        match self {
            Method::Lemke(_) => "lemke",
            Method::Pgs(_) => "pgs",
            Method::NewtonFb(_) => "newton_fb",
        }
    }
}

/// Solves `lcp` with `method`. Never panics on numerics; see `Solution::status`.
pub fn solve(lcp: &Lcp, method: &Method) -> Solution {
    solve_warm(lcp, method, None)
}

/// As [`solve`], starting Lemke from a guessed complementary basis (see
/// [`crate::lemke::solve_warm`]); the other methods ignore the guess.
pub fn solve_warm(lcp: &Lcp, method: &Method, basis: Option<&[bool]>) -> Solution {
    match method {
        Method::Lemke(o) => crate::lemke::solve_warm(lcp, o, basis),
        Method::Pgs(o) => crate::pgs::solve(lcp, o),
        Method::NewtonFb(o) => crate::newton_fb::solve(lcp, o),
    }
}
