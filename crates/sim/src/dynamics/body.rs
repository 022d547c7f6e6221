//! `Body` (validated, owned by the world) and `BodyDesc` (what a user fills in).

use super::collision_filter::CollisionFilter;
use crate::error::{finite_vec, non_negative, positive, SimError};
use crate::geometry::{Placement, Shape};
use crate::math::{Mat3, Quat, Vec3};

/// Index of a body in its world (the order of `add_*` calls, from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);

impl BodyId {
    #[inline]
    pub fn index(self) -> usize {
        self.0
    }
}

impl From<BodyId> for usize {
    fn from(b: BodyId) -> usize {
        b.0
    }
}

/// Everything needed to create a body; validated by `World::add_body`.
///
/// ```
/// use sim::{BodyDesc, math::Vec3};
/// let cube = BodyDesc::cuboid(Vec3::splat(0.5)).mass(2.0).position(Vec3::new(0.0, 0.0, 0.5)).mu(0.8);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDesc {
    /// Collision shape (body frame; a plane is in world coordinates).
    pub shape: Shape,
    /// Mass (kg), must be > 0 for a dynamic body; ignored when static. Default 1.
    pub mass: f64,
    /// Inertia tensor about the centre of mass in the body frame (kg·m²);
    /// `None` (default) takes the solid shape's own with `mass`.
    pub inertia: Option<Mat3>,
    /// Centre of mass in the world (m). Default origin.
    pub position: Vec3,
    /// Orientation (w, x, y, z), normalized on creation; a zero quaternion is an error. Default identity.
    pub orientation: Quat,
    /// Linear velocity of the centre of mass, world frame (m/s). Default 0.
    pub velocity: Vec3,
    /// Angular velocity, world frame (rad/s). Default 0.
    pub angular_velocity: Vec3,
    /// Friction coefficient (≥ 0), combined per pair by the world's `MuCombine`. Default 0.5.
    pub mu: f64,
    /// A static body never moves (infinite mass). Planes must be static. Default false.
    pub is_static: bool,
    /// Which other bodies this one may touch (MuJoCo's contype/conaffinity). Default 1, 1: all.
    pub filter: CollisionFilter,
}

/// Builder methods `field(self, value) -> Self`, one per field named.
macro_rules! setters {
    ($($field:ident: $t:ty),* $(,)?) => {
        $(
            pub fn $field(mut self, $field: $t) -> Self {
                self.$field = $field;
                self
            }
        )*
    };
}

impl BodyDesc {
    /// A dynamic body of the given shape with the defaults above.
    pub fn new(shape: Shape) -> Self {
        BodyDesc {
            mass: 1.0,
            inertia: None,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            mu: 0.5,
            is_static: shape.is_static_only(),
            filter: CollisionFilter::default(),
            shape,
        }
    }

    /// A dynamic box with the given half extents (validated when added).
    pub fn cuboid(half_extents: Vec3) -> Self {
        BodyDesc::new(Shape::Box(crate::geometry::BoxShape { half_extents }))
    }

    /// A dynamic sphere (validated when added).
    pub fn sphere(radius: f64) -> Self {
        BodyDesc::new(Shape::Sphere { radius })
    }

    /// A static plane.
    pub fn plane(plane: crate::geometry::Plane) -> Self {
        BodyDesc::new(Shape::Plane(plane))
    }

    /// A dynamic capsule: a segment of half length `half_length` along the body's z,
    /// swept by a sphere of `radius` (validated when added).
    pub fn capsule(radius: f64, half_length: f64) -> Self {
        BodyDesc::new(Shape::Capsule { radius, half_length })
    }

    /// A dynamic solid cylinder, axis along the body's z (validated when added).
    pub fn cylinder(radius: f64, half_length: f64) -> Self {
        BodyDesc::new(Shape::Cylinder { radius, half_length })
    }

    /// A dynamic convex hull of `points`; the body frame is at the hull's centre
    /// of mass (uniform density), axes as the points' (`ConvexHull::com_offset`
    /// says where that centre was), inertia the full tensor of the solid.
    pub fn convex(points: &[Vec3]) -> Result<Self, SimError> {
        Ok(BodyDesc::new(Shape::convex(points)?))
    }

    /// A static triangle mesh (vertices in the body frame; the pose places it).
    pub fn mesh(vertices: &[Vec3], faces: &[[u32; 3]]) -> Result<Self, SimError> {
        Ok(BodyDesc::new(Shape::mesh(vertices, faces)?))
    }

    /// A static height field (see [`crate::HeightFieldShape::new`]; the pose places its grid).
    pub fn heightfield(nrow: usize, ncol: usize, half_x: f64, half_y: f64, heights: &[f64]) -> Result<Self, SimError> {
        Ok(BodyDesc::new(Shape::HeightField(crate::HeightFieldShape::new(nrow, ncol, half_x, half_y, heights)?)))
    }

    setters!(mass: f64, position: Vec3, orientation: Quat, velocity: Vec3, angular_velocity: Vec3, mu: f64);

    pub fn inertia(mut self, inertia: Mat3) -> Self {
        self.inertia = Some(inertia);
        self
    }
    pub fn fixed(mut self, is_static: bool) -> Self {
        self.is_static = is_static;
        self
    }
    /// The collision bits `contype`, `conaffinity` (see [`CollisionFilter`]).
    pub fn collision_filter(mut self, contype: u32, conaffinity: u32) -> Self {
        self.filter = CollisionFilter::new(contype, conaffinity);
        self
    }
}

/// A validated rigid body. Read it through `World::body`; change it through
/// the world's setters, which validate.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub(crate) shape: Shape,
    pub(crate) mass: f64,
    pub(crate) inv_mass: f64,
    pub(crate) inertia: Mat3,
    pub(crate) inv_inertia: Mat3,
    pub(crate) position: Vec3,
    pub(crate) orientation: Quat,
    pub(crate) velocity: Vec3,
    pub(crate) angular_velocity: Vec3,
    pub(crate) mu: f64,
    /// Torsional friction μ_t (m): a contact patch's friction about its
    /// normal is bounded by μ_t times its normal load (`contact::torsion`); 0 by default.
    pub(crate) mu_torsion: f64,
    pub(crate) is_static: bool,
    pub(crate) filter: CollisionFilter,
}

impl Body {
    /// Validates a description: shape, mass > 0 (dynamic), SPD inertia, finite
    /// pose and velocity, non-zero quaternion (normalized here), μ ≥ 0.
    pub fn from_desc(d: &BodyDesc) -> Result<Body, SimError> {
        d.shape.validate()?;
        let is_plane = matches!(d.shape, Shape::Plane(_));
        if is_plane && !d.is_static {
            return Err(SimError::DynamicPlane);
        }
        if d.shape.is_static_only() && !d.is_static {
            return Err(SimError::StaticOnly { kind: d.shape.kind() });
        }
        non_negative("mu", d.mu)?;
        finite_vec("position", d.position)?;
        finite_vec("velocity", d.velocity)?;
        finite_vec("angular_velocity", d.angular_velocity)?;
        let orientation = normalize_quat(d.orientation)?;
        if d.is_static {
            // Static bodies: infinite mass, zero velocity; a plane lives in world coordinates.
            let (position, orientation) =
                if is_plane { (Vec3::ZERO, Quat::IDENTITY) } else { (d.position, orientation) };
            return Ok(Body {
                shape: d.shape.clone(),
                mass: f64::INFINITY,
                inv_mass: 0.0,
                inertia: Mat3::ZERO,
                inv_inertia: Mat3::ZERO,
                position,
                orientation,
                velocity: Vec3::ZERO,
                angular_velocity: Vec3::ZERO,
                mu: d.mu,
                mu_torsion: 0.0,
                is_static: true,
                filter: d.filter,
            });
        }
        positive("mass", d.mass)?;
        let (inertia, inv_inertia) = match d.inertia {
            Some(i) => (i, check_inertia(&i)?),
            None => {
                let i = d.shape.inertia(d.mass).ok_or(SimError::DynamicPlane)?;
                // The shape's own inertia is valid unless the mass makes it under- or overflow.
                let inv = check_inertia(&i).map_err(|_| SimError::OutOfRange {
                    field: "mass",
                    value: d.mass,
                    range: "a range where this shape's inertia (∝ mass) and its inverse are finite and nonzero",
                })?;
                (i, inv)
            }
        };
        Ok(Body {
            shape: d.shape.clone(),
            mass: d.mass,
            inv_mass: 1.0 / d.mass,
            inertia,
            inv_inertia,
            position: d.position,
            orientation,
            velocity: d.velocity,
            angular_velocity: d.angular_velocity,
            mu: d.mu,
            mu_torsion: 0.0,
            is_static: false,
            filter: d.filter,
        })
    }

    pub fn shape(&self) -> &Shape {
        &self.shape
    }
    /// Mass (kg); infinite for a static body.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// `1/m`; 0 for a static body.
    pub fn inv_mass(&self) -> f64 {
        self.inv_mass
    }
    /// Inertia tensor in the body frame (zero for a static body).
    pub fn inertia(&self) -> Mat3 {
        self.inertia
    }
    /// Centre of mass (world).
    pub fn position(&self) -> Vec3 {
        self.position
    }
    /// Orientation body → world (unit, w-x-y-z).
    pub fn orientation(&self) -> Quat {
        self.orientation
    }
    /// Linear velocity (world).
    pub fn velocity(&self) -> Vec3 {
        self.velocity
    }
    /// Angular velocity (world).
    pub fn angular_velocity(&self) -> Vec3 {
        self.angular_velocity
    }
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Torsional friction coefficient μ_t (m), set by `World::set_torsional_friction`.
    pub fn mu_torsion(&self) -> f64 {
        self.mu_torsion
    }
    pub fn is_static(&self) -> bool {
        self.is_static
    }
    /// Its collision bits (MuJoCo's contype/conaffinity).
    pub fn collision_filter(&self) -> CollisionFilter {
        self.filter
    }

    /// Rotation matrix body → world.
    pub fn rotation(&self) -> Mat3 {
        self.orientation.to_mat3()
    }

    /// Inverse inertia in the world frame, `R I⁻¹ Rᵀ` (zero for a static body).
    pub fn inv_inertia_world(&self) -> Mat3 {
        if self.is_static {
            return Mat3::ZERO;
        }
        let r = self.rotation();
        r * self.inv_inertia * r.transpose()
    }

    /// Inertia in the world frame, `R I Rᵀ`.
    pub fn inertia_world(&self) -> Mat3 {
        let r = self.rotation();
        r * self.inertia * r.transpose()
    }

    /// Body-frame point (relative to the centre of mass) in world coordinates.
    pub fn point_to_world(&self, p_body: Vec3) -> Vec3 {
        self.position + self.orientation.rotate(p_body)
    }

    /// Velocity of the material point at world position `p`: `v + ω × (p − x)`.
    pub fn point_velocity(&self, p: Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(p - self.position)
    }

    /// Kinetic energy `½ m v² + ½ ωᵀ I_world ω` (0 for a static body).
    pub fn kinetic_energy(&self) -> f64 {
        if self.is_static {
            return 0.0;
        }
        // ωᵀ R I Rᵀ ω with Rᵀω computed once (no world-frame inertia formed).
        let wb = self.orientation.inverse_rotate(self.angular_velocity);
        0.5 * self.mass * self.velocity.norm_squared() + 0.5 * wb.dot(self.inertia * wb)
    }

    /// Where the shape is, for the narrow phase.
    pub(crate) fn placement(&self) -> Placement {
        Placement { center: self.position, rotation: self.rotation() }
    }
}

/// Normalizes a quaternion, rejecting non-finite and zero ones. One already of
/// unit length to round-off (‖q‖² within 4ε of 1, as a normalized one is) is kept
/// bit for bit: normalizing again can move its last bits, so a body's orientation
/// read back and given to another body (a scene written to MJCF and read again)
/// would not be the same.
pub(crate) fn normalize_quat(q: Quat) -> Result<Quat, SimError> {
    for (name, c) in [("orientation.w", q.w), ("orientation.x", q.x), ("orientation.y", q.y), ("orientation.z", q.z)] {
        crate::error::finite(name, c)?;
    }
    let n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (n2 - 1.0).abs() <= 4.0 * f64::EPSILON {
        return Ok(q);
    }
    q.try_normalize().ok_or(SimError::ZeroLength { field: "orientation" })
}

/// Checks that an inertia tensor is finite, symmetric and positive definite; returns its inverse.
fn check_inertia(i: &Mat3) -> Result<Mat3, SimError> {
    if !i.is_finite() {
        return Err(SimError::BadInertia { reason: "is not finite" });
    }
    let scale = i.m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    if i.asymmetry() > 1e-12 * scale {
        return Err(SimError::BadInertia { reason: "is not symmetric" });
    }
    // Sylvester's criterion on the leading principal minors.
    let m = &i.m;
    let d1 = m[0][0];
    let d2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let d3 = i.determinant();
    if !(d1 > 0.0 && d2 > 0.0 && d3 > 0.0) {
        return Err(SimError::BadInertia { reason: "is not positive definite" });
    }
    // A rigid body's principal moments obey the triangle inequality
    // (I₁ + I₂ ≥ I₃: I₃ = ∫(x² + y²) ≤ ∫(y² + z²) + ∫(x² + z²)); equality is a flat plate.
    let trace = m[0][0] + m[1][1] + m[2][2];
    if 2.0 * i.symmetric_max_eigenvalue() > trace * (1.0 + 1e-9) {
        return Err(SimError::BadInertia {
            reason: "violates the triangle inequality of principal moments (I₁ + I₂ ≥ I₃): no rigid body has it",
        });
    }
    let inv = i.try_inverse().ok_or(SimError::BadInertia { reason: "is singular" })?;
    if !inv.is_finite() {
        return Err(SimError::BadInertia { reason: "has an inverse that overflows" });
    }
    Ok(inv)
}
