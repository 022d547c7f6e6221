//! Contacts of any pair that involves a capsule, a cylinder, a convex hull,
//! a triangle mesh, a compound or a height field, from parry's contact manifolds
//! (`PersistentQueryDispatcher::contact_manifolds`: several points per pair,
//! each with its gap), in this module's convention: normal from B to A, the
//! point midway between the two surfaces, points with `φ ≤ margin`.
//!
//! Each call starts from an empty manifold list and workspace, so the result
//! depends only on the two placements (a world and its copy step alike). Each
//! manifold is cut to the points that hold the shape (`support_points`:
//! parry's copies of one point and the points inside the others' polygon go),
//! unless `LCPSIM_MANIFOLD=parry` is in the environment (every point of
//! parry's manifolds kept, to compare the two; read once per process).
//! Cylinders and capsules have their axis along the body's local z (as in
//! MJCF); parry's cylinder axis is y, turned onto z here.

use super::support_points::keep_support_points;
use super::{GeomContact, Placement, Shape};
use crate::geometry::convex::{pvec, svec};
use crate::math::Quat;
use parry3d_f64::math::{Pose, Rot3, Vector as PVec};
use parry3d_f64::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, HalfSpace, Shape as PShape};
use std::sync::OnceLock;

/// Whether `LCPSIM_MANIFOLD=parry` keeps every point of parry's manifolds.
fn keep_parry_points() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var("LCPSIM_MANIFOLD").is_ok_and(|v| v == "parry"))
}

/// A parry shape for one of ours: the simple ones built on the spot, a hull's
/// or a mesh's borrowed (never copied).
pub(crate) enum ParryShape<'a> {
    Cuboid(Cuboid),
    Ball(Ball),
    Capsule(Capsule),
    Cylinder(Cylinder),
    HalfSpace(HalfSpace),
    Borrowed(&'a dyn PShape),
}

impl ParryShape<'_> {
    pub(crate) fn get(&self) -> &dyn PShape {
        match self {
            ParryShape::Cuboid(s) => s,
            ParryShape::Ball(s) => s,
            ParryShape::Capsule(s) => s,
            ParryShape::Cylinder(s) => s,
            ParryShape::HalfSpace(s) => s,
            ParryShape::Borrowed(s) => *s,
        }
    }
}

/// parry's axis y onto the body's z: a quarter turn about x.
fn y_to_z() -> Rot3 {
    Rot3::from_axis_angle(PVec::X, std::f64::consts::FRAC_PI_2)
}

/// The parry shape of `shape` at `place`, and its pose.
pub(crate) fn parry_shape<'a>(shape: &'a Shape, place: &Placement) -> (ParryShape<'a>, Pose) {
    let q = Quat::from_mat3(&place.rotation);
    let rot = Rot3::from_xyzw(q.x, q.y, q.z, q.w).normalize();
    let pose = Pose::from_parts(pvec(place.center), rot);
    match shape {
        Shape::Box(b) => (ParryShape::Cuboid(Cuboid::new(pvec(b.half_extents))), pose),
        Shape::Sphere { radius } => (ParryShape::Ball(Ball::new(*radius)), pose),
        Shape::Capsule { radius, half_length } => (ParryShape::Capsule(Capsule::new_z(*half_length, *radius)), pose),
        Shape::Cylinder { radius, half_length } => (
            ParryShape::Cylinder(Cylinder::new(*half_length, *radius)),
            Pose::from_parts(pose.translation, rot * y_to_z()),
        ),
        Shape::Convex(h) => (ParryShape::Borrowed(h.parry()), pose),
        Shape::Mesh(m) => (ParryShape::Borrowed(m.parry()), pose),
        Shape::Compound(c) => (ParryShape::Borrowed(c.parry()), pose),
        // parry's y-up field onto the body's z, as the cylinder.
        Shape::HeightField(h) => (ParryShape::Borrowed(h.parry()), Pose::from_parts(pose.translation, rot * y_to_z())),
        Shape::Plane(p) => (
            ParryShape::HalfSpace(HalfSpace::new(pvec(p.normal()))),
            Pose::from_translation(pvec(p.normal() * p.offset())),
        ),
    }
}

/// Reusable buffers for [`parry_pair`].
#[derive(Default)]
pub struct ParryScratch {
    manifolds: Vec<ContactManifold<(), ()>>,
}

impl std::fmt::Debug for ParryScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ParryScratch")
    }
}

/// Appends the contacts of shape A at `pa` and shape B at `pb` with `φ ≤ margin`
/// (normal from B to A). Pairs parry cannot take (plane–plane, mesh–plane,
/// mesh–mesh) give none.
pub fn parry_pair(
    a: &Shape,
    pa: &Placement,
    b: &Shape,
    pb: &Placement,
    margin: f64,
    scratch: &mut ParryScratch,
    out: &mut Vec<GeomContact>,
) {
    let (ga, posa) = parry_shape(a, pa);
    let (gb, posb) = parry_shape(b, pb);
    // Points this close (relative to the smaller shape) are one point.
    let tol = 1e-6 * a.bounding_radius().min(b.bounding_radius());
    parry_pair_shapes(ga.get(), &posa, gb.get(), &posb, margin, if tol.is_finite() { tol } else { 0.0 }, scratch, out);
}

/// [`parry_pair`] on shapes already made; points of a manifold closer than `tol` are one.
#[allow(clippy::too_many_arguments)]
pub(crate) fn parry_pair_shapes(
    ga: &dyn PShape,
    posa: &Pose,
    gb: &dyn PShape,
    posb: &Pose,
    margin: f64,
    tol: f64,
    scratch: &mut ParryScratch,
    out: &mut Vec<GeomContact>,
) {
    let pos12 = posa.inverse() * *posb;
    scratch.manifolds.clear();
    let mut workspace = None;
    if DefaultQueryDispatcher.contact_manifolds(&pos12, ga, gb, margin, &mut scratch.manifolds, &mut workspace).is_err()
    {
        return;
    }
    for m in &scratch.manifolds {
        // Sub-shapes of a composite (a mesh's triangles) may carry their own poses.
        let (sa, sb) = match &m.subshape_poses {
            Some(s) => (s.pos1.map_or(*posa, |p| *posa * p), s.pos2.map_or(*posb, |p| *posb * p)),
            None => (*posa, *posb),
        };
        let n1 = sa.transform_vector(m.local_n1);
        let normal = -svec(n1);
        let Some(normal) = normal.try_normalize() else { continue };
        let first = out.len();
        for c in &m.points {
            if !(c.dist <= margin) {
                continue;
            }
            let p1 = svec(sa.transform_point(c.local_p1));
            let p2 = svec(sb.transform_point(c.local_p2));
            out.push(GeomContact { point: (p1 + p2) * 0.5, normal, gap: c.dist });
        }
        if !keep_parry_points() {
            keep_support_points(out, first, tol);
        }
    }
}
