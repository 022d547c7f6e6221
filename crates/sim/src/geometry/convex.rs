//! Shapes with data: the convex hull of points ([`ConvexHull`]) and a static
//! triangle mesh ([`TriMeshShape`]). Both are validated on construction
//! (finite vertices, sizes within [`MAX_HULL_POINTS`] / [`MAX_MESH_VERTICES`]
//! / [`MAX_MESH_FACES`], a hull of positive volume, faces in range and not
//! degenerate) and shared (`Arc`): cloning a body or a world copies a pointer.
//!
//! A hull is recentred at the centre of mass of the solid it bounds (uniform
//! density): its vertices are in the body frame, whose axes are those of the
//! points given; `com_offset` is where that centre was in the points' frame.
//! Its inertia per unit mass is the full tensor about that centre.

use crate::error::SimError;
use crate::math::{Mat3, Vec3};
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::shape::{ConvexPolyhedron, TriMesh, TriMeshFlags};
use std::sync::Arc;

/// The most points a convex hull is built from.
pub const MAX_HULL_POINTS: usize = 100_000;
/// The most vertices of a triangle mesh.
pub const MAX_MESH_VERTICES: usize = 1_000_000;
/// The most triangles of a triangle mesh.
pub const MAX_MESH_FACES: usize = 2_000_000;

fn bad(field: &'static str, reason: String) -> SimError {
    SimError::BadGeometry { field, reason }
}

pub(crate) fn pvec(v: Vec3) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

pub(crate) fn svec(v: PVec) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// Checks that every coordinate is finite and the count is within `max`.
fn check_points(field: &'static str, points: &[Vec3], max: usize) -> Result<(), SimError> {
    if points.len() > max {
        return Err(bad(field, format!("has {} points, more than the limit of {max}", points.len())));
    }
    for (i, p) in points.iter().enumerate() {
        for c in p.to_array() {
            if !c.is_finite() {
                return Err(bad(field, format!("point {i} has a non-finite coordinate {c}")));
            }
        }
    }
    Ok(())
}

/// The convex hull of a set of points, recentred at its centre of mass.
#[derive(Clone, Debug)]
pub struct ConvexHull {
    inner: Arc<HullData>,
}

#[derive(Debug)]
struct HullData {
    /// Hull vertices in the body frame (centre of mass at the origin).
    vertices: Vec<Vec3>,
    /// Hull triangles (outward), indices into `vertices`.
    faces: Vec<[u32; 3]>,
    volume: f64,
    /// Inertia about the centre of mass per unit mass (body frame).
    unit_inertia: Mat3,
    /// Where the centre of mass was in the frame of the points given.
    com_offset: Vec3,
    radius: f64,
    parry: ConvexPolyhedron,
}

impl PartialEq for ConvexHull {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.inner, &o.inner)
            || (self.inner.vertices == o.inner.vertices && self.inner.faces == o.inner.faces)
    }
}

impl ConvexHull {
    /// The hull of `points` (at least 4 not in one plane, finite, at most [`MAX_HULL_POINTS`]).
    pub fn new(points: &[Vec3]) -> Result<ConvexHull, SimError> {
        check_points("vertices", points, MAX_HULL_POINTS)?;
        let few =
            || bad("vertices", format!("must hold at least 4 points not in one plane, got {} points", points.len()));
        if points.len() < 4 {
            return Err(few());
        }
        // Affine rank: farthest point from p0, from the line, from the plane.
        let p0 = points[0];
        let far = |f: &dyn Fn(Vec3) -> f64| {
            points.iter().copied().fold((p0, 0.0), |(bp, bd), p| {
                let d = f(p);
                if d > bd {
                    (p, d)
                } else {
                    (bp, bd)
                }
            })
        };
        let (p1, d1) = far(&|p| (p - p0).norm());
        if d1 == 0.0 {
            return Err(few());
        }
        let u = (p1 - p0) * (1.0 / d1);
        let (p2, d2) = far(&|p| (p - p0).cross(u).norm());
        if d2 <= 1e-9 * d1 {
            return Err(few());
        }
        let n = (p2 - p0).cross(u);
        let n = n * (1.0 / n.norm());
        let (_, d3) = far(&|p| (p - p0).dot(n).abs());
        if d3 <= 1e-9 * d1 {
            return Err(few());
        }
        let pts: Vec<PVec> = points.iter().map(|&p| pvec(p)).collect();
        let hull = ConvexPolyhedron::from_convex_hull(&pts).ok_or_else(few)?;
        let (hv, faces) = hull.to_trimesh();
        let mp = parry3d_f64::mass_properties::MassProperties::from_convex_polyhedron(1.0, &hv, &faces);
        let volume = mp.mass();
        if !(volume > 0.0 && volume.is_finite()) {
            return Err(few());
        }
        let com = svec(mp.local_com);
        let im = mp.reconstruct_inertia_matrix();
        let mut rows = [[0.0; 3]; 3];
        for (c, col) in [im.x_axis, im.y_axis, im.z_axis].into_iter().enumerate() {
            for (r, v) in [col.x, col.y, col.z].into_iter().enumerate() {
                rows[r][c] = v / volume;
            }
        }
        // Exactly symmetric (the reconstruction rounds).
        for r in 0..3 {
            for c in (r + 1)..3 {
                let s = 0.5 * (rows[r][c] + rows[c][r]);
                rows[r][c] = s;
                rows[c][r] = s;
            }
        }
        let vertices: Vec<Vec3> = hv.iter().map(|&p| svec(p) - com).collect();
        let centred: Vec<PVec> = vertices.iter().map(|&p| pvec(p)).collect();
        let parry = ConvexPolyhedron::from_convex_hull(&centred).ok_or_else(few)?;
        let radius = vertices.iter().fold(0.0f64, |r, v| r.max(v.norm()));
        Ok(ConvexHull {
            inner: Arc::new(HullData {
                vertices,
                faces,
                volume,
                unit_inertia: Mat3::from_rows(rows),
                com_offset: com,
                radius,
                parry,
            }),
        })
    }

    /// Hull vertices in the body frame (centre of mass at the origin).
    pub fn vertices(&self) -> &[Vec3] {
        &self.inner.vertices
    }
    /// Hull triangles, outward, indices into [`ConvexHull::vertices`].
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.inner.faces
    }
    /// Volume (m³).
    pub fn volume(&self) -> f64 {
        self.inner.volume
    }
    /// Inertia about the centre of mass of a solid of this hull and `mass` (uniform density).
    pub fn inertia(&self, mass: f64) -> Mat3 {
        Mat3::from_rows(self.inner.unit_inertia.m.map(|r| r.map(|v| v * mass)))
    }
    /// The centre of mass in the frame of the points given (the body frame is there).
    pub fn com_offset(&self) -> Vec3 {
        self.inner.com_offset
    }
    /// Largest distance of a vertex from the centre of mass.
    pub fn radius(&self) -> f64 {
        self.inner.radius
    }
    pub(crate) fn parry(&self) -> &ConvexPolyhedron {
        &self.inner.parry
    }
}

/// A triangle mesh (static bodies only: terrain, bins), in its body's frame.
#[derive(Clone, Debug)]
pub struct TriMeshShape {
    inner: Arc<MeshData>,
}

#[derive(Debug)]
struct MeshData {
    vertices: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    radius: f64,
    parry: TriMesh,
}

impl PartialEq for TriMeshShape {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.inner, &o.inner)
            || (self.inner.vertices == o.inner.vertices && self.inner.faces == o.inner.faces)
    }
}

impl TriMeshShape {
    /// A mesh of `vertices` and triangles `faces` (indices into `vertices`):
    /// finite vertices, at least one face, every index in range, no face with a
    /// repeated vertex or zero area, sizes within the limits.
    pub fn new(vertices: &[Vec3], faces: &[[u32; 3]]) -> Result<TriMeshShape, SimError> {
        check_points("vertices", vertices, MAX_MESH_VERTICES)?;
        if faces.is_empty() {
            return Err(bad("faces", "must hold at least one triangle, got none".into()));
        }
        if faces.len() > MAX_MESH_FACES {
            return Err(bad(
                "faces",
                format!("has {} triangles, more than the limit of {MAX_MESH_FACES}", faces.len()),
            ));
        }
        let scale = vertices.iter().fold(0.0f64, |r, v| r.max(v.max_abs()));
        for (f, tri) in faces.iter().enumerate() {
            for &i in tri {
                if i as usize >= vertices.len() {
                    return Err(bad(
                        "faces",
                        format!("face {f} has vertex index {i}, out of range for {} vertices", vertices.len()),
                    ));
                }
            }
            let [a, b, c] = tri.map(|i| vertices[i as usize]);
            let area2 = (b - a).cross(c - a).norm();
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || !(area2 > 1e-12 * scale * scale) {
                return Err(bad("faces", format!("face {f} {tri:?} is degenerate (repeated vertex or zero area)")));
            }
        }
        let pv: Vec<PVec> = vertices.iter().map(|&p| pvec(p)).collect();
        let parry = TriMesh::with_flags(pv, faces.to_vec(), TriMeshFlags::FIX_INTERNAL_EDGES_TWO_SIDED)
            .or_else(|_| TriMesh::new(vertices.iter().map(|&p| pvec(p)).collect(), faces.to_vec()))
            .map_err(|e| bad("faces", format!("do not make a triangle mesh: {e:?}")))?;
        let radius = vertices.iter().fold(0.0f64, |r, v| r.max(v.norm()));
        Ok(TriMeshShape {
            inner: Arc::new(MeshData { vertices: vertices.to_vec(), faces: faces.to_vec(), radius, parry }),
        })
    }

    pub fn vertices(&self) -> &[Vec3] {
        &self.inner.vertices
    }
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.inner.faces
    }
    /// Largest distance of a vertex from the body's origin.
    pub fn radius(&self) -> f64 {
        self.inner.radius
    }
    pub(crate) fn parry(&self) -> &TriMesh {
        &self.inner.parry
    }
}
