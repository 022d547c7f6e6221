//! `lcp::Solution` → Python dicts of numpy arrays (one solve, or a stacked batch).
//! A solve at n = 40 takes microseconds, so per-call costs show: keys are
//! interned, and `z`, `w`, `basis` are copied into numpy-owned arrays (a copy
//! of n floats is cheaper than the Python object that would own a `Vec`).

use lcp::{Residuals, Solution};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One solution as a dict keyed by the fields of `lcpsim.LcpResult` that a
/// solve determines: `z`, `w` (float64 arrays), `status` (str), `ok` (bool),
/// `pivots` (int), `residual`, `min_z`, `min_w`, `max_complementarity`
/// (floats), `method` (str), `basis` (bool array or None). The wrapper makes
/// this dict the result's `__dict__`, so these keys are exactly those fields.
pub fn solution_to_dict<'py>(py: Python<'py>, s: Solution, method: &str) -> PyResult<Bound<'py, PyDict>> {
    let r = &s.residuals;
    let d = PyDict::new(py);
    d.set_item(intern!(py, "z"), PyArray1::from_slice(py, &s.z))?;
    d.set_item(intern!(py, "w"), PyArray1::from_slice(py, &s.w))?;
    d.set_item(intern!(py, "status"), s.status.as_str())?;
    d.set_item(intern!(py, "ok"), s.ok())?;
    d.set_item(intern!(py, "pivots"), s.pivots)?;
    d.set_item(intern!(py, "residual"), r.residual)?;
    d.set_item(intern!(py, "min_z"), r.min_z)?;
    d.set_item(intern!(py, "min_w"), r.min_w)?;
    d.set_item(intern!(py, "max_complementarity"), r.max_complementarity)?;
    d.set_item(intern!(py, "method"), method)?;
    match &s.basis {
        Some(b) => d.set_item(intern!(py, "basis"), PyArray1::from_slice(py, b))?,
        None => d.set_item(intern!(py, "basis"), py.None())?,
    }
    Ok(d)
}

/// The residual fields of a dict.
pub fn residuals_into(d: &Bound<'_, PyDict>, r: &Residuals) -> PyResult<()> {
    let py = d.py();
    d.set_item(intern!(py, "residual"), r.residual)?;
    d.set_item(intern!(py, "min_z"), r.min_z)?;
    d.set_item(intern!(py, "min_w"), r.min_w)?;
    d.set_item(intern!(py, "max_complementarity"), r.max_complementarity)?;
    Ok(())
}

/// A batch of `b` solutions of size `n`, stacked: `z`, `w` of shape (b, n);
/// `status` a list of str; `ok` (solved and accepted by `lcp::accept`); `pivots`, residuals of shape (b,); `basis` a
/// (b, n) bool array when every solution has one, else None.
pub fn batch_to_dict<'py>(
    py: Python<'py>,
    sols: Vec<Solution>,
    n: usize,
    method: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let b = sols.len();
    let mut z = Vec::with_capacity(b * n);
    let mut w = Vec::with_capacity(b * n);
    let mut pivots = Vec::with_capacity(b);
    let (mut residual, mut min_z, mut min_w, mut max_c) =
        (Vec::with_capacity(b), Vec::with_capacity(b), Vec::with_capacity(b), Vec::with_capacity(b));
    let all_basis = b > 0 && sols.iter().all(|s| s.basis.is_some());
    let mut basis = Vec::with_capacity(if all_basis { b * n } else { 0 });
    let mut status = Vec::with_capacity(b);
    let mut ok = Vec::with_capacity(b);
    for s in sols {
        ok.push(s.ok());
        z.extend_from_slice(&s.z);
        w.extend_from_slice(&s.w);
        pivots.push(s.pivots as i64);
        residual.push(s.residuals.residual);
        min_z.push(s.residuals.min_z);
        min_w.push(s.residuals.min_w);
        max_c.push(s.residuals.max_complementarity);
        status.push(s.status.as_str());
        if all_basis {
            basis.extend_from_slice(s.basis.as_deref().unwrap_or(&[]));
        }
    }
    let d = PyDict::new(py);
    d.set_item("z", PyArray1::from_vec(py, z).reshape([b, n])?)?;
    d.set_item("w", PyArray1::from_vec(py, w).reshape([b, n])?)?;
    d.set_item("status", status)?;
    d.set_item("ok", PyArray1::from_vec(py, ok))?;
    d.set_item("pivots", PyArray1::from_vec(py, pivots))?;
    d.set_item("residual", PyArray1::from_vec(py, residual))?;
    d.set_item("min_z", PyArray1::from_vec(py, min_z))?;
    d.set_item("min_w", PyArray1::from_vec(py, min_w))?;
    d.set_item("max_complementarity", PyArray1::from_vec(py, max_c))?;
    if all_basis && basis.len() == b * n {
        let arr: Bound<'py, PyArray2<bool>> = PyArray1::from_vec(py, basis).reshape([b, n])?;
        d.set_item("basis", arr)?;
    } else {
        d.set_item("basis", py.None())?;
    }
    d.set_item("method", method)?;
    Ok(d)
}
