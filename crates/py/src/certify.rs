//! Bindings of `lcp::certify` (exact check of a complementary basis) and of
//! `lcp::lemke::solve_traced` (the pivot trace of a failure dump).
//!
//! `certify_lcp` / `certify_lcp_batch` return the certificate as a dict:
//! `status` ("certified", "violated", "singular"), `basis`, `z`, `w` (the
//! exact basis solution rounded to nearest; empty when singular),
//! `violations`, `violation` (the first one: `{index, kind, value}` or None),
//! `det_bits`, `natural_residual`, `backward_error`, `z_error` (float or None).
//! The batch form releases the GIL and splits the work over threads.

use crate::errors::{panic_error, value_error};
use crate::method::method_from_py;
use crate::problem::{array1, array2, array3, lcp_from_py, lcp_from_views};
use crate::solution::solution_to_dict;
use lcp::certify::{certify, certify_against, certify_z, CertStatus, Certificate, ViolationKind};
use lcp::{Lcp, Method};
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::panic::{catch_unwind, AssertUnwindSafe};

fn kind_str(k: ViolationKind) -> &'static str {
    match k {
        ViolationKind::NegativeZ => "negative_z",
        ViolationKind::NegativeW => "negative_w",
        ViolationKind::Complementarity => "complementarity",
    }
}

fn certificate_to_dict<'py>(py: Python<'py>, c: Certificate) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (status, violation) = match c.status {
        CertStatus::Certified => ("certified", None),
        CertStatus::Violated(v) => ("violated", Some(v)),
        CertStatus::Singular => ("singular", None),
    };
    d.set_item("status", status)?;
    d.set_item("basis", PyArray1::from_vec(py, c.basis))?;
    d.set_item("z", PyArray1::from_vec(py, c.z))?;
    d.set_item("w", PyArray1::from_vec(py, c.w))?;
    d.set_item("violations", c.violations)?;
    match violation {
        Some(v) => {
            let vd = PyDict::new(py);
            vd.set_item("index", v.index)?;
            vd.set_item("kind", kind_str(v.kind))?;
            vd.set_item("value", v.value)?;
            d.set_item("violation", vd)?;
        }
        None => d.set_item("violation", py.None())?,
    }
    d.set_item("det_bits", c.det_bits)?;
    d.set_item("natural_residual", c.natural_residual)?;
    d.set_item("backward_error", c.backward_error)?;
    d.set_item("z_error", c.z_error)?;
    Ok(d)
}

/// The certificate of `basis` (and `z`, if given) or of the support of `z`.
fn certify_one(lcp: &Lcp, basis: Option<&[bool]>, z: Option<&[f64]>) -> Certificate {
    match (basis, z) {
        (Some(b), Some(z)) => certify_against(lcp, b, z),
        (Some(b), None) => certify(lcp, b),
        (None, Some(z)) => certify_z(lcp, z),
        (None, None) => unreachable!("checked by the callers"),
    }
}

fn check_len(what: &str, len: usize, n: usize) -> PyResult<()> {
    if len != n {
        return Err(value_error(format!("{what} has {len} entries for an LCP of size {n}")));
    }
    Ok(())
}

/// Exact certificate of a complementary basis for `(M, q)`: `basis` (bool
/// array, `basis[j]`: `z_j` basic), optionally compared with a float `z`; or,
/// without a basis, of the support `{j : z_j > 0}` of `z`.
#[pyfunction]
#[pyo3(signature = (m, q, basis = None, z = None))]
pub fn certify_lcp<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    basis: Option<PyReadonlyArray1<'py, bool>>,
    z: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let lcp = lcp_from_py(m, q)?;
    let n = lcp.n();
    let basis: Option<Vec<bool>> = basis.map(|b| b.as_array().to_vec());
    let z: Option<Vec<f64>> = match z {
        Some(z) => Some(array1(z, "z")?.as_array().to_vec()),
        None => None,
    };
    if basis.is_none() && z.is_none() {
        return Err(value_error("certify: give a basis, a z, or both"));
    }
    if let Some(b) = &basis {
        check_len("basis", b.len(), n)?;
    }
    if let Some(z) = &z {
        check_len("z", z.len(), n)?;
        if let Some(i) = z.iter().position(|v| v.is_nan()) {
            return Err(value_error(format!("z[{i}] = nan is not a number")));
        }
    }
    let cert = py
        .detach(|| catch_unwind(AssertUnwindSafe(|| certify_one(&lcp, basis.as_deref(), z.as_deref()))))
        .map_err(panic_error)?;
    certificate_to_dict(py, cert)
}

/// `certify_lcp` over a stack: `ms` (b, n, n), `qs` (b, n), `bases` (b, n)
/// bool and optionally `zs` (b, n). Returns a list of certificate dicts. The
/// GIL is released; `threads` workers (0 = one per core) split the batch.
#[pyfunction]
#[pyo3(signature = (ms, qs, bases, zs, threads))]
pub fn certify_lcp_batch<'py>(
    py: Python<'py>,
    ms: &Bound<'py, PyAny>,
    qs: &Bound<'py, PyAny>,
    bases: PyReadonlyArray2<'py, bool>,
    zs: Option<&Bound<'py, PyAny>>,
    threads: &Bound<'py, PyAny>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let threads = crate::args::count(threads, "threads")?;
    let ms = array3(ms, "Ms")?;
    let qs = array2(qs, "qs")?;
    let (ms_v, qs_v, b_v) = (ms.as_array(), qs.as_array(), bases.as_array());
    let b = ms_v.shape()[0];
    let n = ms_v.shape()[1];
    if qs_v.shape() != [b, n] || b_v.shape() != [b, n] {
        return Err(value_error(format!(
            "shapes differ: Ms {:?}, qs {:?}, bases {:?}",
            ms_v.shape(),
            qs_v.shape(),
            b_v.shape()
        )));
    }
    let zs = match zs {
        Some(z) => {
            let z = array2(z, "zs")?;
            let zv = z.as_array();
            if zv.shape() != [b, n] {
                return Err(value_error(format!("zs has shape {:?}, expected ({b}, {n})", zv.shape())));
            }
            Some(zv.rows().into_iter().map(|r| r.to_vec()).collect::<Vec<_>>())
        }
        None => None,
    };
    let mut lcps = Vec::with_capacity(b);
    for i in 0..b {
        lcps.push(lcp_from_views(ms_v.index_axis(numpy::ndarray::Axis(0), i), qs_v.row(i), &format!("problem {i}: "))?);
    }
    let basis_rows: Vec<Vec<bool>> = b_v.rows().into_iter().map(|r| r.to_vec()).collect();
    let threads = match threads {
        0 => std::thread::available_parallelism().map(|t| t.get()).unwrap_or(1),
        t => t,
    }
    .clamp(1, b.max(1));
    let work = |i: usize| certify_one(&lcps[i], Some(&basis_rows[i]), zs.as_ref().map(|z| z[i].as_slice()));
    let certs: Result<Vec<Certificate>, _> = py.detach(|| {
        catch_unwind(AssertUnwindSafe(|| {
            if threads <= 1 {
                (0..b).map(work).collect::<Vec<_>>()
            } else {
                let chunk = b.div_ceil(threads);
                std::thread::scope(|scope| {
                    let handles: Vec<_> = (0..b)
                        .step_by(chunk)
                        .map(|start| {
                            let work = &work;
                            scope.spawn(move || (start..(start + chunk).min(b)).map(work).collect::<Vec<_>>())
                        })
                        .collect();
                    handles.into_iter().flat_map(|h| h.join().expect("certify worker panicked")).collect()
                })
            }
        }))
    });
    let certs = certs.map_err(panic_error)?;
    certs.into_iter().map(|c| certificate_to_dict(py, c)).collect()
}

/// Solves `(M, q)` with Lemke (`method` must be "lemke") and returns
/// `(solution dict, trace dict)`; the trace holds one entry per pivot over
/// every rung of the repair ladder: arrays `rung`, `entering`, `leaving`
/// (variables numbered w_i → i, z_j → n + j, z0 → 2n), `theta`, `pivot`,
/// `column_max`. `warm` is an optional starting basis (bool array).
#[pyfunction]
#[pyo3(signature = (m, q, method = "lemke", warm = None, **options))]
pub fn solve_lcp_traced<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    method: &str,
    warm: Option<PyReadonlyArray1<'py, bool>>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
    let method_v = method_from_py(method, options)?;
    let Method::Lemke(o) = &method_v else {
        return Err(value_error(format!("a pivot trace needs method 'lemke', not {method:?}")));
    };
    let lcp = lcp_from_py(m, q)?;
    let warm: Option<Vec<bool>> = warm.map(|w| w.as_array().to_vec());
    if let Some(w) = &warm {
        check_len("warm", w.len(), lcp.n())?;
    }
    let (sol, trace) = py
        .detach(|| catch_unwind(AssertUnwindSafe(|| lcp::lemke::solve_traced(&lcp, o, warm.as_deref()))))
        .map_err(panic_error)?;
    let t = PyDict::new(py);
    t.set_item("rung", PyArray1::from_vec(py, trace.iter().map(|r| r.rung as i64).collect()))?;
    t.set_item("entering", PyArray1::from_vec(py, trace.iter().map(|r| r.entering as i64).collect()))?;
    t.set_item("leaving", PyArray1::from_vec(py, trace.iter().map(|r| r.leaving as i64).collect()))?;
    t.set_item("theta", PyArray1::from_vec(py, trace.iter().map(|r| r.theta).collect()))?;
    t.set_item("pivot", PyArray1::from_vec(py, trace.iter().map(|r| r.pivot).collect()))?;
    t.set_item("column_max", PyArray1::from_vec(py, trace.iter().map(|r| r.column_max).collect()))?;
    Ok((solution_to_dict(py, sol, method_v.name())?, t))
}
