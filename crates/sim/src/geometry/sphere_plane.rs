//! Sphere–plane: one contact at the sphere's lowest point along the normal.

use super::{GeomContact, Plane};
use crate::math::Vec3;

/// Appends the contact of a sphere (A, centre `c`, radius `r`) with a plane (B) if its gap `≤ margin`.
pub fn sphere_plane(c: Vec3, r: f64, plane: &Plane, margin: f64, out: &mut Vec<GeomContact>) {
    let n = plane.normal();
    let gap = plane.distance(c) - r;
    if gap <= margin {
        out.push(GeomContact { point: c - n * (r + 0.5 * gap), normal: n, gap });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gap_and_point() {
        let mut out = Vec::new();
        sphere_plane(Vec3::new(1.0, 2.0, 0.6), 0.5, &Plane::ground(), 0.2, &mut out);
        assert_eq!(out.len(), 1);
        assert!((out[0].gap - 0.1).abs() < 1e-15);
        assert!((out[0].point - Vec3::new(1.0, 2.0, 0.05)).max_abs() < 1e-15);
        out.clear();
        sphere_plane(Vec3::new(0.0, 0.0, 1.0), 0.5, &Plane::ground(), 0.2, &mut out);
        assert!(out.is_empty());
    }
}
