//! Box–plane: every box corner within the margin of the plane is a contact.
//!
//! A box resting on a face gives its 4 bottom corners (the source note's 4-contact,
//! size-40 LCP); on an edge 2; on a corner 1.

use super::{BoxShape, GeomContact, Placement, Plane};

/// Appends one contact per corner of the box (A) with gap `≤ margin` above the plane (B).
/// Normal = plane normal (B → A); point = midway between the corner and the plane.
pub fn box_plane(b: &BoxShape, at: &Placement, plane: &Plane, margin: f64, out: &mut Vec<GeomContact>) {
    let n = plane.normal();
    for corner in b.corners() {
        let p = at.center + at.rotation * corner;
        let gap = plane.distance(p);
        if gap <= margin {
            // The corner is on A's surface; the plane point is gap below it.
            out.push(GeomContact { point: p - n * (0.5 * gap), normal: n, gap });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Quat, Vec3};

    #[test]
    fn resting_cube_has_four_corners() {
        let b = BoxShape::cube(1.0).unwrap();
        let at = Placement { center: Vec3::new(0.0, 0.0, 0.5), rotation: Mat3::IDENTITY };
        let mut out = Vec::new();
        box_plane(&b, &at, &Plane::ground(), 1e-3, &mut out);
        assert_eq!(out.len(), 4);
        assert!(out.iter().all(|c| c.gap == 0.0 && c.normal == Vec3::Z));
    }

    #[test]
    fn tilted_cube_on_edge_has_two() {
        let b = BoxShape::cube(1.0).unwrap();
        let q = Quat::from_axis_angle(Vec3::Y, std::f64::consts::FRAC_PI_4);
        let at = Placement { center: Vec3::new(0.0, 0.0, 0.5 * 2f64.sqrt()), rotation: q.to_mat3() };
        let mut out = Vec::new();
        box_plane(&b, &at, &Plane::ground(), 1e-6, &mut out);
        assert_eq!(out.len(), 2);
    }
}
