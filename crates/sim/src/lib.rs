//! Rigid bodies with the Stewart–Trinkle / Anitescu–Potra contact LCP ([`contact`]).
//!
//! A [`World`] holds bodies (boxes, spheres, static planes), constant
//! external forces and [`WorldParams`]. Each step runs named stages
//! (`pipeline`): external forces → `detect` ([`broad_phase`], then the
//! narrow phase) → `islands` ([`islands`]) → `assemble` → `solve` (any
//! `lcp::Method`, one LCP per contact island, on `WorldParams::threads`
//! threads) → `integrate`, and leaves a [`StepRecord`] with the contacts,
//! the islands, the LCP's size and status, residuals in physical units and
//! the impulses `fn`, `fd`, `λ` per contact. Every solved LCP can be
//! streamed to an [`LcpSink`].
//!
//! ```
//! use sim::{World, WorldParams, math::Vec3};
//! let mut world = World::new(WorldParams::default()).unwrap();
//! world.add_ground(1.0).unwrap();
//! let cube = world.add_box(Vec3::splat(0.5), 1.0, Vec3::new(0.0, 0.0, 0.5), 0.5).unwrap();
//! let record = world.step().unwrap();
//! assert_eq!(record.lcp_size, 40); // 4 contacts × (1 + 8 + 1)
//! ```
//!
//! Conventions: SI units, gravity (0, 0, −9.81), quaternions
//! (w, x, y, z) rotating body → world, velocities `[v; ω]` in the world
//! frame, contact normals from body B to body A, `z = [fn; fd; λ]`.
//!
//! Modules: [`math`] (Vec3/Quat/Mat3), [`dynamics`] (bodies, integration),
//! [`geometry`] (shapes, one file per shape pair), [`contact`] (friction
//! basis, assembly, formulation parameters), [`pipeline`] (the step),
//! [`solve_chain`] (how one island's LCP is solved, stage after stage),
//! [`scenes`] (the analytic test scenes), [`generate`] (seeded
//! contact scenes and their LCPs for tests and benchmarks).

pub mod broad_phase;
pub mod contact;
pub mod dynamics;
pub mod error;
pub mod generate;
pub mod geometry;
pub mod islands;
pub mod joints;
pub mod limits;
pub mod math;
pub mod parallel;
pub mod params;
pub mod pipeline;
pub mod scenes;
pub mod solve_chain;
pub mod world;

pub use contact::{ConeScale, MuCombine, Restitution, Stabilization};
pub use dynamics::{Body, BodyDesc, BodyId, CollisionFilter, ContactPairs, ExcludedPairs, PairMap};
pub use error::SimError;
pub use geometry::{
    CompoundPart, CompoundShape, Contact, ConvexHull, Downhill, HeightFieldShape, Plane, Shape, TriMeshShape,
};
pub use joints::{Joint, JointDesc, JointId, JointKind, JointParams, JointReaction};
pub use params::WorldParams;
pub use pipeline::{
    Captured, CapturedLcp, EnergyAudit, IslandRecord, LcpBuffer, LcpSink, OwnedLcp, Retake, StepRecord, Trajectory,
};
pub use solve_chain::stage_name::SolveStage;
pub use world::World;

/// The LCP core this crate builds on (re-exported for `Method`, `Status`, …).
pub use lcp;
