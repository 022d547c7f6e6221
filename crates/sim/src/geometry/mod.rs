//! Shapes and narrow-phase contact detection: one file per pair of the
//! primitives (box, sphere, plane), and parry's contact manifolds
//! (`parry_pair.rs`) for every pair with a capsule, cylinder, convex hull,
//! triangle mesh, compound or height field (`convex.rs` holds the hull's and
//! the mesh's data, `compound.rs` the compound's parts and mass properties,
//! `heightfield.rs` the terrain grid).
//!
//! Every pair function takes the two shapes in the order of its name
//! (`box_plane(box, plane)`, `sphere_box(sphere, box)`, …) and appends
//! [`GeomContact`]s whose normal points **from the second shape (B) to the
//! first (A)**: a positive normal impulse pushes A along `+normal`. The gap
//! `φ` is the signed distance between the surfaces along the normal
//! (negative = penetration). Points with `φ ≤ margin` are reported, so a
//! contact enters the LCP a little before the surfaces touch.
//!
//! The world's `detect` stage (pipeline) runs the pairs and fills in bodies,
//! the combined μ and the friction tangent to make full [`Contact`]s.

mod box_box;
mod box_plane;
mod compound;
mod contact;
mod convex;
mod heightfield;
mod parry_pair;
mod plane;
mod shape;
mod sphere_box;
mod sphere_plane;
mod sphere_sphere;
mod support_points;

pub use box_box::box_box;
pub use box_plane::box_plane;
pub use compound::{CompoundPart, CompoundShape, MAX_COMPOUND_PARTS};
pub use contact::{Contact, GeomContact};
pub use convex::{ConvexHull, TriMeshShape, MAX_HULL_POINTS, MAX_MESH_FACES, MAX_MESH_VERTICES};
pub use heightfield::{HeightFieldShape, MAX_HFIELD_POINTS};
pub use parry_pair::{parry_pair, ParryScratch};
pub use plane::{fixed_tangent, Downhill, Plane};
pub use shape::{BoxShape, Shape};
pub use sphere_box::sphere_box;
pub use sphere_plane::sphere_plane;
pub use sphere_sphere::sphere_sphere;

use crate::math::{Mat3, Vec3};

/// A shape placed in the world: position of its centre and rotation matrix
/// (columns = body axes in world coordinates).
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    pub center: Vec3,
    pub rotation: Mat3,
}
