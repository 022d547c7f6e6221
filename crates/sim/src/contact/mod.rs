//! From contacts to the Stewart–Trinkle LCP.
//!
//! - [`params`]: the knobs of the formulation — friction-cone scale `s`,
//!   penetration stabilization, restitution, how μ is combined per pair.
//! - [`friction`]: the polyhedral friction basis `d_j`.
//! - [`assembly`]: Jacobian rows per contact, `A = J M_b⁻¹ Jᵀ`, and the LCP
//!   `(M, q)` with `z = [fn; fd; λ]`, plus the map back to physical units.
//! - [`body_space`]: the same LCP as an operator on the Jacobian rows, without
//!   the dense `M` (products and entries for a basis check).
//! - [`coupled_space`]: the LCP of an island solved on its dense `M` (a
//!   jointed island's `J P Jᵀ`, a torsion patch's cone) as an operator: the
//!   body-space products, minus the joints' coupling `E Yᵀ Y Eᵀ`, plus the virtual rows.
//! - [`body_factors`]: the same LCP as `G H + K` (body-space sparse factors) for the structured Lemke.
//! - [`torsion`]: a contact patch's torsional friction, one more contact whose
//!   cone row is bounded by the patch's normal load.
//! - [`body_rule`]: the acceptance rule judged in body space, each contact
//!   row on the scale of the velocities it relates (a heavy body on a light one).
//!
//! Assembly never solves and solvers never see bodies.

pub mod assembly;
pub mod body_factors;
pub mod body_rule;
pub mod body_space;
pub mod coupled_space;
pub mod friction;
pub mod params;
pub mod torsion;

pub use assembly::{ContactLcp, ContactRows};
pub use body_rule::BodyCheck;
pub use body_space::BodySpaceLcp;
pub use coupled_space::CoupledSpaceLcp;
pub use friction::{friction_directions, FrictionBasis};
pub use params::{ConeScale, MuCombine, Restitution, Stabilization};
