//! Every buffer a Lemke solve needs, owned by the caller and reused.
//!
//! A small solve (n = 40, ~10 µs) needs some twenty buffers: the
//! equilibrated copy of `M` and the Ruiz exponents, `C⁻¹` and the basic
//! columns `G[:, S]` (a few KiB to tens of KiB each), and a dozen vectors of
//! length n. Allocating them per solve costs ~8 % of it (glibc's large bins
//! and its small thread cache), so, as in faer's `*_in` kernels, the caller
//! owns a [`Workspace`] and hands it to [`super::solve_in`]: one per thread
//! (a simulator island, a batch worker, the Python glue), reused from solve to
//! solve. Buffers grow to the largest problem seen and are never shrunk; drop
//! the workspace to free them. A solve on a workspace that has seen a problem
//! of the same size allocates only its answer (`Solution`), except on rare
//! paths: a basis of more than 48 z-columns refactored by faer's LU, the
//! final-basis re-solve, the repair ladder's failed rungs and its Newton
//! polish, and the pivot trace of a traced solve.
//!
//! The contents between solves mean nothing: every solve rebuilds what it
//! reads, so answers are the same whatever the workspace saw before.

use super::basis::BasisBuffers;
use super::frame::Frame;
use super::run::LoopBuffers;
use super::warm::WarmBuffers;

/// The buffers of a Lemke solve (see the module documentation).
#[derive(Default)]
pub struct Workspace {
    /// The rung's working problem: Ruiz factors and their exponent buffers,
    /// the equilibrated copy of `M` and the normalized `q`.
    pub(super) frame: Frame,
    /// The basis: `C⁻¹`, the basic columns `G[:, S]`, the index sets `R`,
    /// `S`, basic values, tableau rows and the refactorization's scratch.
    pub(super) basis: BasisBuffers,
    /// The pivoting loop's entering column, ratio-test candidates and the set
    /// of bases seen (cycle guard).
    pub(super) pivoting: LoopBuffers,
    /// The covering vector `d`.
    pub(super) d: Vec<f64>,
    /// A warm start's complementary set `α` (indices of basic `z_j`).
    pub(super) alpha: Vec<usize>,
    /// The final basis' `z` in working units, before it is mapped back.
    pub(super) z_work: Vec<f64>,
    /// The warm start's complementary sets and block (see `warm::WarmBuffers`).
    pub(super) warm: WarmBuffers,
}

impl Workspace {
    /// An empty workspace; its buffers grow at the first solves.
    pub fn new() -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("lemke::Workspace").field("n", &self.frame.work.n()).finish_non_exhaustive()
    }
}
