//! The polyhedral friction cone's directions `d_j = cos(2πj/k)·t1 + sin(2πj/k)·t2`.
//!
//! `t1` is the contact's tangent (for a tilted plane its downhill direction,
//! otherwise a fixed world axis projected into the tangent plane: see
//! `geometry::Plane`), and `t2 = n × t1`, so `(t1, t2, n)` is right-handed.
//! With `k` even, `d_{j+k/2} = −d_j`: every direction has its opposite, and a
//! body sliding along `d_0` is resisted exactly along `d_{k/2}`.

use crate::math::Vec3;

/// Cosines and sines of `2πj/k`, exact where they should be (0, ±1), so that
/// the axis-aligned directions carry no 1e-17 noise.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionBasis {
    k: usize,
    trig: Vec<(f64, f64)>,
}

impl FrictionBasis {
    /// Basis with `k` directions (`k` even ≥ 2 is checked by the world).
    pub fn new(k: usize) -> Self {
        let trig = (0..k)
            .map(|j| {
                let a = 2.0 * std::f64::consts::PI * j as f64 / k as f64;
                let clean = |v: f64| {
                    if v.abs() < 1e-15 {
                        0.0
                    } else if (v.abs() - 1.0).abs() < 1e-15 {
                        v.signum()
                    } else {
                        v
                    }
                };
                (clean(a.cos()), clean(a.sin()))
            })
            .collect();
        FrictionBasis { k, trig }
    }

    pub fn k(&self) -> usize {
        self.k
    }

    /// `(cos 2πj/k, sin 2πj/k)`.
    #[inline]
    pub fn cos_sin(&self, j: usize) -> (f64, f64) {
        self.trig[j]
    }

    /// Direction `d_j` for normal `n` and tangent `t1` (unit, ⟂ n).
    #[inline]
    pub fn direction(&self, n: Vec3, t1: Vec3, j: usize) -> Vec3 {
        let t2 = n.cross(t1);
        let (c, s) = self.trig[j];
        t1 * c + t2 * s
    }
}

/// The most friction directions per contact `k` (an LCP of `k + 2` unknowns per
/// contact; 1024 already gives 134 MiB for one box's four contacts).
pub const MAX_FRICTION_DIRS: usize = 1024;

/// Fills `out` with the `k` directions for normal `n` and tangent `t1`.
pub fn friction_directions(n: Vec3, t1: Vec3, k: usize, out: &mut Vec<Vec3>) {
    let basis = FrictionBasis::new(k);
    out.clear();
    out.extend((0..k).map(|j| basis.direction(n, t1, j)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_directions_are_unit_tangent_and_opposed() {
        let mut d = Vec::new();
        friction_directions(Vec3::Z, Vec3::X, 8, &mut d);
        assert_eq!(d[0], Vec3::X);
        assert_eq!(d[2], Vec3::Y);
        assert_eq!(d[4], -Vec3::X);
        for j in 0..8 {
            assert!((d[j].norm() - 1.0).abs() < 1e-15);
            assert_eq!(d[j].z, 0.0);
            assert!((d[j] + d[(j + 4) % 8]).max_abs() < 1e-15);
        }
    }
}
