//! Collision shapes, described in the body frame (centred at the centre of mass).

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

/// A collision shape. Boxes and spheres are centred on their body's centre of
/// mass; a plane is given in world coordinates and its body must be static.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Box(BoxShape),
    Sphere { radius: f64 },
    Plane(Plane),
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

    /// Validates the shape's own parameters.
    pub fn validate(&self) -> Result<(), SimError> {
        match self {
            Shape::Box(b) => BoxShape::new(b.half_extents).map(|_| ()),
            Shape::Sphere { radius } => positive("radius", *radius).map(|_| ()),
            Shape::Plane(p) => Plane::new(p.normal(), p.offset()).map(|_| ()),
        }
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
            Shape::Plane(_) => None,
        }
    }

    /// Radius of a sphere around the centre that holds the shape (∞ for a plane).
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Shape::Box(b) => b.half_extents.norm(),
            Shape::Sphere { radius } => *radius,
            Shape::Plane(_) => f64::INFINITY,
        }
    }

    /// Short name (`"box"`, `"sphere"`, `"plane"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box(_) => "box",
            Shape::Sphere { .. } => "sphere",
            Shape::Plane(_) => "plane",
        }
    }
}
