//! numpy arrays → `lcp::Lcp`: any float-convertible array (int dtype, Fortran
//! order, strided views) is accepted; shapes are checked here so that every
//! message names the field and its shape.

use crate::errors::{lcp_error, value_error};
use lcp::Lcp;
use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayLike2, PyArrayLike3, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// Extracts a float64 array of a fixed number of dimensions; any failure
/// (wrong ndim, non-numeric data) is a `ValueError` naming `field`.
macro_rules! extract_array {
    ($ob:expr, $ty:ty, $field:expr, $ndim:expr) => {
        $ob.extract::<$ty>().map_err(|e| {
            let shape = describe_shape($ob);
            value_error(format!("{} must be a {}-D array of real numbers, got {}: {}", $field, $ndim, shape, e))
        })
    };
}

pub type Array1<'py> = PyArrayLike1<'py, f64, AllowTypeChange>;
pub type Array2<'py> = PyArrayLike2<'py, f64, AllowTypeChange>;
pub type Array3<'py> = PyArrayLike3<'py, f64, AllowTypeChange>;

/// A short description of what was passed: its numpy shape if it has one, else its type.
fn describe_shape(ob: &Bound<'_, PyAny>) -> String {
    if let Ok(shape) = ob.getattr("shape") {
        if let Ok(s) = shape.repr() {
            return format!("shape {s}");
        }
    }
    match ob.get_type().name() {
        Ok(name) => format!("an object of type {name}"),
        Err(_) => "an object".to_string(),
    }
}

pub fn array1<'py>(ob: &Bound<'py, PyAny>, field: &str) -> PyResult<Array1<'py>> {
    extract_array!(ob, Array1<'py>, field, 1)
}

pub fn array2<'py>(ob: &Bound<'py, PyAny>, field: &str) -> PyResult<Array2<'py>> {
    extract_array!(ob, Array2<'py>, field, 2)
}

pub fn array3<'py>(ob: &Bound<'py, PyAny>, field: &str) -> PyResult<Array3<'py>> {
    extract_array!(ob, Array3<'py>, field, 3)
}

/// Checks that `m` is n×n and `q` has length n, then builds the validated `Lcp`
/// (finiteness is checked by `Lcp::new`). `prefix` names the problem in a batch.
pub fn lcp_from_views(m: ArrayView2<'_, f64>, q: ArrayView1<'_, f64>, prefix: &str) -> PyResult<Lcp> {
    let (rows, cols) = m.dim();
    if rows != cols {
        return Err(value_error(format!("{prefix}M must be square, got shape ({rows}, {cols})")));
    }
    if q.len() != rows {
        return Err(value_error(format!("{prefix}q has length {} but M has shape ({rows}, {cols})", q.len())));
    }
    if rows == 0 {
        return Err(value_error(format!("{prefix}the LCP is empty: M has shape (0, 0) and q has length 0")));
    }
    // A C-contiguous array is copied as is; otherwise `iter()` walks in
    // logical (row-major) order whatever the memory layout.
    let m_rowmajor: Vec<f64> = m.as_slice().map_or_else(|| m.iter().copied().collect(), <[f64]>::to_vec);
    let q_vec: Vec<f64> = q.as_slice().map_or_else(|| q.iter().copied().collect(), <[f64]>::to_vec);
    Lcp::new(m_rowmajor, q_vec).map_err(|e| lcp_error(&e, rows, prefix))
}

/// `(M, q)` from Python objects.
pub fn lcp_from_py(m: &Bound<'_, PyAny>, q: &Bound<'_, PyAny>) -> PyResult<Lcp> {
    let m = array2(m, "M")?;
    let q = array1(q, "q")?;
    lcp_from_views(m.as_array(), q.as_array(), "")
}

/// A batch `(Ms[b], qs[b])` from a (b, n, n) and a (b, n) array.
pub fn lcps_from_py(ms: &Bound<'_, PyAny>, qs: &Bound<'_, PyAny>) -> PyResult<Vec<Lcp>> {
    let ms = array3(ms, "Ms")?;
    let qs = array2(qs, "qs")?;
    let (ms_shape, qs_shape) = (ms.shape().to_vec(), qs.shape().to_vec());
    if ms_shape[0] != qs_shape[0] {
        return Err(value_error(format!(
            "Ms and qs hold different numbers of problems: Ms has shape {:?}, qs has shape {:?}",
            ms_shape, qs_shape
        )));
    }
    let (ms, qs) = (ms.as_array(), qs.as_array());
    (0..ms_shape[0])
        .map(|b| {
            let prefix = format!("problem {b}: ");
            lcp_from_views(
                ms.index_axis(numpy::ndarray::Axis(0), b),
                qs.index_axis(numpy::ndarray::Axis(0), b),
                &prefix,
            )
        })
        .collect()
}

/// `z` of length `n`.
pub fn vector_of_len(ob: &Bound<'_, PyAny>, field: &str, n: usize) -> PyResult<Vec<f64>> {
    let a = array1(ob, field)?;
    let a = a.as_array();
    if a.len() != n {
        return Err(value_error(format!("{field} has length {} but M has shape ({n}, {n})", a.len())));
    }
    if let Some((i, v)) = a.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(value_error(format!("{field}[{i}] = {} is not finite", crate::errors::py_float(*v))));
    }
    Ok(a.to_vec())
}
