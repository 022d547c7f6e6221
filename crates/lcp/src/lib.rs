//! Dense linear complementarity problems and their solvers.
//!
//! Find `z ≥ 0` with `w = M z + q ≥ 0` and `zᵀw = 0`. Every solver has the same
//! contract, `solve(&Lcp, &Options) -> Solution`, never panics on numerics and
//! reports how it ended in `Solution::status` together with residuals
//! recomputed from its answer (`Residuals`). `method::solve` dispatches on a
//! `Method` value; `method::solve_in` does so in a caller-owned [`Workspace`]
//! (one per thread, reused), which spares Lemke its per-solve allocations.
//!
//! - [`lemke`]: Lemke's complementary pivoting — `Lexicographic` (robust
//!   default: equilibration, relative tie tolerance, O(n²) block-inverse
//!   updates, cycle guard, final-basis refinement) or `Classic` (the source
//!   note's absolute tolerances, kept to reproduce its findings).
//! - [`pgs`]: projected Gauss–Seidel with relaxation.
//! - [`newton_fb`]: damped semismooth Newton on the Fischer–Burmeister function.
//! - [`scaling`]: diagonal scaling `D_r M D_c, D_r q` and the map back.
//! - [`contact`]: the layout of a contact LCP's `z = [fn; fd; λ]`, its cone scaling and sign patterns.
//! - [`accept`]: the one acceptance rule (componentwise backward error, each row on its own scale).
//! - [`certify`]: exact (rational) check that a complementary basis solves the LCP of the floats given.
//! - [`structured`]: Lemke on `M = G H + K` with sparse `G`, `H`, `K` (a contact
//!   LCP in body space): sparse LU of the basis with eta updates, no dense `M`.
//! - [`operator`]: an LCP reached through products and blocks ([`operator::LcpOperator`]), `M` never formed.
//! - [`on_basis`]: solving on a given (guessed) complementary basis through an operator: the
//!   zero-pivot step of a simulator.
//! - [`enumerate`]: brute-force enumeration of complementary bases (small n; tests).
//! - [`limits`]: sizes checked before allocating (memory a dense LCP needs, `try_reserve`).
//! - [`generate`]: seeded generators of test LCPs (P-matrix, SPD, Murty, infeasible); contact
//!   LCPs are generated from bodies by `sim::generate`.

pub mod accept;
pub mod certify;
pub mod contact;
mod ddouble;
pub mod enumerate;
pub mod generate;
mod kernels;
pub mod lemke;
pub mod limits;
pub mod method;
pub mod newton_fb;
pub mod on_basis;
pub mod operator;
pub mod pgs;
pub mod problem;
pub mod scaling;
pub mod solution;
pub mod structured;

pub use contact::ContactLayout;
pub use lemke::{LemkeOptions, Pivoting};
pub use method::{solve, solve_in, solve_warm, Method, Workspace};
pub use newton_fb::NewtonFbOptions;
pub use pgs::PgsOptions;
pub use problem::{Lcp, LcpError};
pub use scaling::Scaling;
pub use solution::{Residuals, Solution, Status};
