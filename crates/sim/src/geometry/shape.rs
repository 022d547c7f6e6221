//! Collision shapes, described in the body frame (centred at the centre of mass).

use super::compound::{CompoundPart, CompoundShape};
use super::convex::{ConvexHull, TriMeshShape};
use super::heightfield::HeightFieldShape;
use super::Plane;
use crate::error::{positive, SimError};
use crate::math::{Mat3, Vec3};

/// A box given by its half extents along the body axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxShape {
    pub half_extents: Vec3,
}

impl BoxShape {
    /// Validates that all half extents are finite and `> 0`.
    pub fn new(half_extents: Vec3) -> Result<Self, SimError> {
        positive("half_extents.x", half_extents.x)?;
        positive("half_extents.y", half_extents.y)?;
        positive("half_extents.z", half_extents.z)?;
        Ok(BoxShape { half_extents })
    }

    /// A cube of edge length `size`.
    pub fn cube(size: f64) -> Result<Self, SimError> {
        positive("size", size)?;
        BoxShape::new(Vec3::splat(0.5 * size))
    }

    /// The 8 corners in the body frame; corner `i` has sign `+` on axis `a` iff bit `a` of `i` is set.
    pub fn corners(&self) -> [Vec3; 8] {
        let h = self.half_extents;
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 != 0 { h.x } else { -h.x },
                if i & 2 != 0 { h.y } else { -h.y },
                if i & 4 != 0 { h.z } else { -h.z },
            )
        })
    }
}

/// A collision shape. Solids are centred on their body's centre of mass; a
/// plane is given in world coordinates and its body must be static, as must a
/// mesh's (in its body's frame). Capsules and cylinders have their axis along
/// the body's local z (as in MJCF).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Box(BoxShape),
    Sphere {
        radius: f64,
    },
    Plane(Plane),
    /// A segment of half length `half_length` along z, swept by a sphere of `radius`.
    Capsule {
        radius: f64,
        half_length: f64,
    },
    /// A solid cylinder: radius, half its length along z.
    Cylinder {
        radius: f64,
        half_length: f64,
    },
    /// The convex hull of points, recentred at its centre of mass.
    Convex(ConvexHull),
    /// A triangle mesh (static bodies only).
    Mesh(TriMeshShape),
    /// Several solid parts at poses in the body frame, recentred at their centre of mass.
    Compound(CompoundShape),
    /// Heights on a regular grid (static bodies only): terrain.
    HeightField(HeightFieldShape),
}

impl Shape {
    /// A box with the given half extents (validated).
    pub fn cuboid(half_extents: Vec3) -> Result<Shape, SimError> {
        Ok(Shape::Box(BoxShape::new(half_extents)?))
    }

    /// A sphere of the given radius (validated).
    pub fn sphere(radius: f64) -> Result<Shape, SimError> {
        positive("radius", radius)?;
        Ok(Shape::Sphere { radius })
    }

    /// A capsule (axis z) of the given radius and half length of its segment (validated).
    pub fn capsule(radius: f64, half_length: f64) -> Result<Shape, SimError> {
        let s = Shape::Capsule { radius, half_length };
        s.validate()?;
        Ok(s)
    }

    /// A solid cylinder (axis z) of the given radius and half length (validated).
    pub fn cylinder(radius: f64, half_length: f64) -> Result<Shape, SimError> {
        let s = Shape::Cylinder { radius, half_length };
        s.validate()?;
        Ok(s)
    }

    /// The convex hull of `points` (see [`ConvexHull::new`]).
    pub fn convex(points: &[Vec3]) -> Result<Shape, SimError> {
        Ok(Shape::Convex(ConvexHull::new(points)?))
    }

    /// A triangle mesh (see [`TriMeshShape::new`]).
    pub fn mesh(vertices: &[Vec3], faces: &[[u32; 3]]) -> Result<Shape, SimError> {
        Ok(Shape::Mesh(TriMeshShape::new(vertices, faces)?))
    }

    /// A compound of `parts` (see [`CompoundShape::new`]).
    pub fn compound(parts: &[CompoundPart]) -> Result<Shape, SimError> {
        Ok(Shape::Compound(CompoundShape::new(parts)?))
    }

    /// A compound of `parts` about a given centre of mass (see [`CompoundShape::about`]).
    pub fn compound_about(parts: &[CompoundPart], com: Vec3) -> Result<Shape, SimError> {
        Ok(Shape::Compound(CompoundShape::about(parts, Some(com))?))
    }

    /// Validates the shape's own parameters (hulls, meshes and compounds were on construction).
    pub fn validate(&self) -> Result<(), SimError> {
        match self {
            Shape::Box(b) => BoxShape::new(b.half_extents).map(|_| ()),
            Shape::Sphere { radius } => positive("radius", *radius).map(|_| ()),
            Shape::Plane(p) => Plane::new(p.normal(), p.offset()).map(|_| ()),
            Shape::Capsule { radius, half_length } | Shape::Cylinder { radius, half_length } => {
                positive("radius", *radius)?;
                positive("half_length", *half_length).map(|_| ())
            }
            Shape::Convex(_) | Shape::Mesh(_) | Shape::Compound(_) | Shape::HeightField(_) => Ok(()),
        }
    }

    /// Volume of the solid (m³); `None` for the shapes without one (plane, mesh).
    pub fn volume(&self) -> Option<f64> {
        use std::f64::consts::PI;
        match self {
            Shape::Box(b) => Some(8.0 * b.half_extents.x * b.half_extents.y * b.half_extents.z),
            Shape::Sphere { radius: r } => Some(4.0 / 3.0 * PI * r * r * r),
            Shape::Capsule { radius: r, half_length: h } => Some(PI * r * r * (2.0 * h + 4.0 / 3.0 * r)),
            Shape::Cylinder { radius: r, half_length: h } => Some(PI * r * r * 2.0 * h),
            Shape::Convex(c) => Some(c.volume()),
            Shape::Compound(c) => Some(c.volume()),
            Shape::Plane(_) | Shape::Mesh(_) | Shape::HeightField(_) => None,
        }
    }

    /// Whether the shape is one of the three with hand-written pair routines
    /// (box, sphere, plane); any pair with another shape goes to parry.
    pub fn is_primitive(&self) -> bool {
        matches!(self, Shape::Box(_) | Shape::Sphere { .. } | Shape::Plane(_))
    }

    /// Whether bodies of this shape must be static (planes, meshes and height fields).
    pub fn is_static_only(&self) -> bool {
        matches!(self, Shape::Plane(_) | Shape::Mesh(_) | Shape::HeightField(_))
    }

    /// Inertia tensor of a solid of this shape and `mass`, in the body frame.
    /// `None` for a plane (it has none; planes are static).
    pub fn inertia(&self, mass: f64) -> Option<Mat3> {
        match self {
            Shape::Box(b) => {
                let h = b.half_extents;
                let (x2, y2, z2) = (h.x * h.x, h.y * h.y, h.z * h.z);
                Some(Mat3::diagonal(Vec3::new(y2 + z2, x2 + z2, x2 + y2) * (mass / 3.0)))
            }
            Shape::Sphere { radius } => Some(Mat3::diagonal(Vec3::splat(0.4 * mass * radius * radius))),
            Shape::Capsule { radius: r, half_length: h } => {
                // Cylinder of length 2h and two hemispheres, by volume.
                let (vc, vs) = (2.0 * h * r * r, 4.0 / 3.0 * r * r * r);
                let (mc, ms) = (mass * vc / (vc + vs), mass * vs / (vc + vs));
                let axial = mc * r * r / 2.0 + ms * 0.4 * r * r;
                let across = mc * (r * r / 4.0 + h * h / 3.0) + ms * (0.4 * r * r + h * h + 0.75 * h * r);
                Some(Mat3::diagonal(Vec3::new(across, across, axial)))
            }
            Shape::Cylinder { radius: r, half_length: h } => {
                let across = mass * (r * r / 4.0 + h * h / 3.0);
                Some(Mat3::diagonal(Vec3::new(across, across, mass * r * r / 2.0)))
            }
            Shape::Convex(c) => Some(c.inertia(mass)),
            Shape::Compound(c) => Some(c.inertia(mass)),
            Shape::Plane(_) | Shape::Mesh(_) | Shape::HeightField(_) => None,
        }
    }

    /// Radius of a sphere around the centre that holds the shape (∞ for a plane).
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Shape::Box(b) => b.half_extents.norm(),
            Shape::Sphere { radius } => *radius,
            Shape::Plane(_) => f64::INFINITY,
            Shape::Capsule { radius, half_length } => radius + half_length,
            Shape::Cylinder { radius, half_length } => radius.hypot(*half_length),
            Shape::Convex(c) => c.radius(),
            Shape::Mesh(m) => m.radius(),
            Shape::Compound(c) => c.radius(),
            Shape::HeightField(h) => h.radius(),
        }
    }

    /// Short name (`"box"`, `"sphere"`, `"plane"`, `"capsule"`, `"cylinder"`, `"convex"`, `"mesh"`, `"compound"`, `"hfield"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box(_) => "box",
            Shape::Sphere { .. } => "sphere",
            Shape::Plane(_) => "plane",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Convex(_) => "convex",
            Shape::Mesh(_) => "mesh",
            Shape::Compound(_) => "compound",
            Shape::HeightField(_) => "hfield",
        }
    }
}
