//! Joints: ball, hinge, slider and fixed joints between two bodies (or a body
//! and the world), solved in the same step as the contacts.
//!
//! A joint is a set of bilateral velocity rows `G v⁺ = −β C / h` (`C` the
//! joint's position error, `β` [`JointParams::drift`]). The rows are not
//! unknowns of the contact LCP: they are eliminated, as Drake's
//! `ConstraintSolver` does. With `S = G M⁻¹ Gᵀ` (factored by a pivoted
//! Cholesky that stops at its numerical rank, so dependent rows — a closed
//! loop, two hinges on one axis — are dropped, not inverted):
//!
//! ```text
//! v*ₚ = v* + M⁻¹ Gᵀ λ₀,   λ₀ = −S⁺ (G v* + β C / h)    the free velocity, projected (`elimination`)
//! P   = M⁻¹ − M⁻¹ Gᵀ S⁺ G M⁻¹                           the joint-projected inverse mass
//! M_c = J P Jᵀ (+ the cone rows),  q = J v*ₚ + …        the contact LCP of an island with joints
//! v⁺  = v*ₚ + P Jᵀ z                                     (so G v⁺ = −β C / h exactly)
//! ```
//!
//! so the contact LCP keeps its Stewart–Trinkle structure `[fn; fd; λ]` (only
//! the impulse block of `M` changes, by `−Bᵀ S⁺ B` with `B = G M⁻¹ J_frameᵀ`),
//! `J P Jᵀ` stays positive semidefinite and cold Lemke keeps its guarantee.
//!
//! - [`joint`]: the joint kinds, their anchors and axes in each body's frame, validation.
//! - [`rows`]: the constraint rows `G` and position errors `C` of each kind.
//! - [`pivoted_cholesky`]: the rank-revealing factorization of `S`.
//! - [`limits`]: a hinge's or slider's limits as frictionless contact rows of the LCP.
//! - [`elimination`]: `S`, the projection of the free velocity, the coupling of
//!   an island's contacts, the joint impulses.
//! - [`held_contacts`]: contacts whose normal the joints already hold, dropped before the LCP.
//! - [`scenes`]: `benchmarks/joints.py`'s chain and gripper, for the example and tests.
//! - [`stage`]: the world's side (adding joints, the step's three calls).

pub mod elimination;
pub mod held_contacts;
pub mod joint;
pub mod limits;
pub mod pivoted_cholesky;
pub mod rows;
pub mod scenes;
pub mod stage;

pub use elimination::{JointCoupling, JointSystem};
pub use joint::{Joint, JointDesc, JointId, JointKind, JointParams, JointReaction, Motor};
