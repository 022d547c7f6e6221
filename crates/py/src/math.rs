//! Bindings of the quaternion helpers of `sim::math` that Python code needs
//! to place bodies (one home for rotations): quaternions are `[w, x, y, z]`
//! lists, matrices `(3, 3)` arrays.

use numpy::PyArray2;
use pyo3::prelude::*;
use sim::math::{Mat3, Quat, Vec3};

/// Rotation by `angle` (rad) about `axis` (need not be unit; identity for a zero axis).
#[pyfunction]
pub fn quat_from_axis_angle(axis: [f64; 3], angle: f64) -> [f64; 4] {
    Quat::from_axis_angle(Vec3::from_array(axis), angle).to_array()
}

/// Hamilton product `p ⊗ q` (rotate by `q`, then by `p`).
#[pyfunction]
pub fn quat_mul(p: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    (Quat::from_array(p) * Quat::from_array(q)).to_array()
}

/// The rotation matrix of a unit quaternion (columns: the body axes in world).
#[pyfunction]
pub fn quat_to_matrix(py: Python<'_>, q: [f64; 4]) -> Bound<'_, PyArray2<f64>> {
    let m = Quat::from_array(q).to_mat3().m;
    PyArray2::from_vec2(py, &m.iter().map(|r| r.to_vec()).collect::<Vec<_>>()).expect("3 rows of 3")
}

/// The unit quaternion of a rotation matrix.
#[pyfunction]
pub fn quat_from_matrix(r: [[f64; 3]; 3]) -> [f64; 4] {
    Quat::from_mat3(&Mat3::from_rows(r)).to_array()
}
