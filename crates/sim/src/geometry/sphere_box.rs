//! Sphere–box: closest point of the box to the sphere centre.

use super::{BoxShape, GeomContact, Placement};
use crate::math::Vec3;

/// Appends the contact of a sphere (A, centre `c`, radius `r`) with a box (B) if the gap `≤ margin`.
///
/// Outside the box the normal runs from the closest box point to the centre;
/// a centre inside the box is pushed out through the nearest face.
pub fn sphere_box(c: Vec3, r: f64, b: &BoxShape, at: &Placement, margin: f64, out: &mut Vec<GeomContact>) {
    let h = b.half_extents;
    // Sphere centre in the box frame.
    let p = at.rotation.transpose_mul_vec(c - at.center);
    let q = Vec3::new(p.x.clamp(-h.x, h.x), p.y.clamp(-h.y, h.y), p.z.clamp(-h.z, h.z));
    let diff = p - q;
    let dist = diff.norm();
    let (n_local, gap, surface) = if dist > 0.0 {
        (diff / dist, dist - r, q)
    } else {
        // Inside: leave through the face with the least depth (first axis on ties).
        let depth = h - p.abs();
        let axis = if depth.x <= depth.y && depth.x <= depth.z {
            0
        } else if depth.y <= depth.z {
            1
        } else {
            2
        };
        let mut n = Vec3::ZERO;
        n[axis] = if p[axis] >= 0.0 { 1.0 } else { -1.0 };
        let mut s = p;
        s[axis] = n[axis] * h[axis];
        (n, -depth[axis] - r, s)
    };
    if gap > margin {
        return;
    }
    let n = at.rotation * n_local;
    let surface_world = at.center + at.rotation * surface;
    out.push(GeomContact { point: surface_world + n * (0.5 * gap), normal: n, gap });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    #[test]
    fn sphere_on_top_face_and_corner() {
        let b = BoxShape::cube(2.0).unwrap();
        let at = Placement { center: Vec3::ZERO, rotation: Mat3::IDENTITY };
        let mut out = Vec::new();
        sphere_box(Vec3::new(0.2, 0.3, 1.5), 0.5, &b, &at, 1e-3, &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].normal, Vec3::Z);
        assert!(out[0].gap.abs() < 1e-15);
        out.clear();
        sphere_box(Vec3::new(0.0, 0.0, 0.9), 0.5, &b, &at, 1e-3, &mut out);
        assert_eq!(out[0].normal, Vec3::Z);
        assert!((out[0].gap + 0.6).abs() < 1e-15);
        out.clear();
        let c = Vec3::splat(1.0 + 0.5 / 3f64.sqrt());
        sphere_box(c, 0.5, &b, &at, 1e-3, &mut out);
        assert!(out[0].gap.abs() < 1e-12);
        assert!((out[0].normal - Vec3::splat(1.0 / 3f64.sqrt())).max_abs() < 1e-12);
    }
}
