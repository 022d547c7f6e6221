//! Sphere–sphere: one contact on the line of centres.

use super::GeomContact;
use crate::math::Vec3;

/// Appends the contact of spheres A (`ca`, `ra`) and B (`cb`, `rb`) if their gap `≤ margin`.
/// Coincident centres get the normal `+z` (any unit vector would do; this one is deterministic).
pub fn sphere_sphere(ca: Vec3, ra: f64, cb: Vec3, rb: f64, margin: f64, out: &mut Vec<GeomContact>) {
    let d = ca - cb;
    let dist = d.norm();
    let gap = dist - ra - rb;
    if gap > margin {
        return;
    }
    let n = d.try_normalize().unwrap_or(Vec3::Z);
    out.push(GeomContact { point: cb + n * (rb + 0.5 * gap), normal: n, gap });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_spheres() {
        let mut out = Vec::new();
        sphere_sphere(Vec3::new(0.0, 0.0, 2.0), 1.0, Vec3::ZERO, 1.0, 1e-3, &mut out);
        assert_eq!(out[0].normal, Vec3::Z);
        assert_eq!(out[0].gap, 0.0);
        assert_eq!(out[0].point, Vec3::new(0.0, 0.0, 1.0));
    }
}
