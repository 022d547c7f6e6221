//! `Mat3`: a row-major 3×3 matrix (inertia tensors, rotation matrices).

use super::Vec3;
use std::ops::{Add, Mul};

/// A 3×3 matrix stored by rows: `m[i][j]` is row `i`, column `j`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Mat3 {
    pub m: [[f64; 3]; 3],
}

impl Mat3 {
    pub const ZERO: Mat3 = Mat3 { m: [[0.0; 3]; 3] };
    pub const IDENTITY: Mat3 = Mat3 { m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] };

    #[inline]
    pub const fn from_rows(m: [[f64; 3]; 3]) -> Self {
        Mat3 { m }
    }

    #[inline]
    pub fn diagonal(d: Vec3) -> Self {
        Mat3 { m: [[d.x, 0.0, 0.0], [0.0, d.y, 0.0], [0.0, 0.0, d.z]] }
    }

    /// Matrix with the given columns.
    #[inline]
    pub fn from_cols(c0: Vec3, c1: Vec3, c2: Vec3) -> Self {
        Mat3 { m: [[c0.x, c1.x, c2.x], [c0.y, c1.y, c2.y], [c0.z, c1.z, c2.z]] }
    }

    #[inline]
    pub fn row(&self, i: usize) -> Vec3 {
        Vec3::from_array(self.m[i])
    }

    #[inline]
    pub fn col(&self, j: usize) -> Vec3 {
        Vec3::new(self.m[0][j], self.m[1][j], self.m[2][j])
    }

    #[inline]
    pub fn transpose(&self) -> Mat3 {
        Mat3::from_cols(self.row(0), self.row(1), self.row(2))
    }

    /// `Aᵀ v` without forming the transpose.
    #[inline]
    pub fn transpose_mul_vec(&self, v: Vec3) -> Vec3 {
        Vec3::new(self.col(0).dot(v), self.col(1).dot(v), self.col(2).dot(v))
    }

    pub fn determinant(&self) -> f64 {
        let m = &self.m;
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    /// Inverse by the adjugate, or `None` when singular or not finite.
    pub fn try_inverse(&self) -> Option<Mat3> {
        let det = self.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let (r0, r1, r2) = (self.row(0), self.row(1), self.row(2));
        // Columns of the inverse are the cross products of the rows over det.
        let inv = Mat3::from_cols(r1.cross(r2), r2.cross(r0), r0.cross(r1));
        Some(inv * (1.0 / det))
    }

    /// Largest eigenvalue of a symmetric matrix (closed form, Smith 1961):
    /// for an inertia tensor, the largest principal moment.
    pub fn symmetric_max_eigenvalue(&self) -> f64 {
        let m = &self.m;
        let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        let q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
        let dev = (m[0][0] - q).powi(2) + (m[1][1] - q).powi(2) + (m[2][2] - q).powi(2) + 2.0 * off;
        let p = (dev / 6.0).sqrt();
        if p == 0.0 {
            return q;
        }
        let mut b = *self;
        for (i, row) in b.m.iter_mut().enumerate() {
            row[i] -= q;
            row.iter_mut().for_each(|v| *v /= p);
        }
        let r = (0.5 * b.determinant()).clamp(-1.0, 1.0);
        q + 2.0 * p * (r.acos() / 3.0).cos()
    }

    /// `true` when all entries are finite.
    pub fn is_finite(&self) -> bool {
        self.m.iter().flatten().all(|v| v.is_finite())
    }

    /// Largest `|a_ij − a_ji|`.
    pub fn asymmetry(&self) -> f64 {
        let m = &self.m;
        (m[0][1] - m[1][0]).abs().max((m[0][2] - m[2][0]).abs()).max((m[1][2] - m[2][1]).abs())
    }
}

impl Mul<Vec3> for Mat3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, v: Vec3) -> Vec3 {
        Vec3::new(self.row(0).dot(v), self.row(1).dot(v), self.row(2).dot(v))
    }
}

impl Mul<Mat3> for Mat3 {
    type Output = Mat3;
    #[inline]
    fn mul(self, o: Mat3) -> Mat3 {
        let mut r = [[0.0; 3]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = self.m[i][0] * o.m[0][j] + self.m[i][1] * o.m[1][j] + self.m[i][2] * o.m[2][j];
            }
        }
        Mat3 { m: r }
    }
}

impl Mul<f64> for Mat3 {
    type Output = Mat3;
    #[inline]
    fn mul(self, s: f64) -> Mat3 {
        let mut r = self;
        r.m.iter_mut().flatten().for_each(|e| *e *= s);
        r
    }
}

impl Add for Mat3 {
    type Output = Mat3;
    #[inline]
    fn add(self, o: Mat3) -> Mat3 {
        let mut r = self;
        for i in 0..3 {
            for j in 0..3 {
                r.m[i][j] += o.m[i][j];
            }
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_roundtrip() {
        let a = Mat3::from_rows([[2.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 4.0]]);
        let p = a * a.try_inverse().unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((p.m[i][j] - e).abs() < 1e-14);
            }
        }
        assert!(Mat3::ZERO.try_inverse().is_none());
    }
}
