//! Rigid bodies, external forces and the semi-implicit Euler integrator.
//!
//! State per body: pose (position of the centre of mass, unit quaternion
//! body → world) and velocity `[v; ω]`, both in the world frame.
//! Static bodies never move and have infinite mass: they contribute nothing
//! to the contact LCP's `A = J M_b⁻¹ Jᵀ`.

pub(crate) mod body;
mod collision_filter;
mod forces;
mod integrate;

pub use body::{Body, BodyDesc, BodyId};
pub use collision_filter::{CollisionFilter, ContactPairs, ExcludedPairs, PairMap};
pub use forces::{AppliedForce, AppliedTorque};
pub use integrate::{free_velocity, integrate_positions};
