//! One entry point over all solvers: `solve(&Lcp, &Method) -> Solution`.
//!
//! Callers that do not care which algorithm runs (the simulator, the Python
//! glue, batch solves) hold a `Method` and call this; each solver also exposes
//! its own `solve(&Lcp, &Options)` with the same contract. Callers that solve
//! often also hold a [`Workspace`] per thread and call [`solve_in`].

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

/// The buffers of a solve by any [`Method`], owned by the caller (one per
/// thread) and reused from solve to solve with [`solve_in`]. Answers do not
/// depend on what a workspace saw before.
#[derive(Debug, Default)]
pub struct Workspace {
    /// Lemke's buffers: working problem, basis inverse and columns, pivoting
    /// scratch (see [`crate::lemke::Workspace`]).
    pub lemke: crate::lemke::Workspace,
    // PGS and Newton–FB keep nothing here: their iterates are their answer,
    // and neither runs on a per-step hot path (PGS cannot solve the contact
    // LCP; Newton–FB polishes Lemke's rare failures).
}

impl Workspace {
    /// An empty workspace; its buffers grow at the first solves.
    pub fn new() -> Self {
        Self::default()
    }
}

/// Solves `lcp` with `method`. Never panics on numerics; see `Solution::status`.
pub fn solve(lcp: &Lcp, method: &Method) -> Solution {
    solve_warm(lcp, method, None)
}

/// As [`solve`], starting Lemke from a guessed complementary basis (see
/// [`crate::lemke::solve_warm`]); the other methods ignore the guess.
pub fn solve_warm(lcp: &Lcp, method: &Method, basis: Option<&[bool]>) -> Solution {
    solve_in(lcp, method, basis, &mut Workspace::new())
}

/// As [`solve_warm`], in the caller's workspace `ws` (see [`crate::lemke::solve_in`]).
pub fn solve_in(lcp: &Lcp, method: &Method, basis: Option<&[bool]>, ws: &mut Workspace) -> Solution {
    match method {
        Method::Lemke(o) => crate::lemke::solve_in(lcp, o, basis, &mut ws.lemke),
        Method::Pgs(o) => crate::pgs::solve(lcp, o),
        Method::NewtonFb(o) => crate::newton_fb::solve(lcp, o),
    }
}
