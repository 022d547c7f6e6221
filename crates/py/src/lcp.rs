//! Bindings of the `lcp` crate: `solve_lcp`, `solve_lcp_batch` (GIL released,
//! optionally threaded), `lcp_residual` and `lcp_residuals`.
//!
//! Solves run in an `lcp::Workspace` owned here: single solves in one per
//! thread ([`WORKSPACE`]), a batch in one per worker thread.

use crate::errors::panic_error;
use crate::method::method_from_py;
use crate::problem::{lcp_from_py, lcps_from_py, vector_of_len};
use crate::solution::{batch_to_dict, residuals_into, solution_to_dict};
use lcp::{Lcp, Method, Residuals, Solution, Workspace};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The payload of a caught panic.
type Panic = Box<dyn std::any::Any + Send>;

thread_local! {
    /// The solver workspace of `solve_lcp` on this thread (the GIL is
    /// released on the calling thread, so one per thread suffices). A solve
    /// rebuilds whatever it reads, so one interrupted by a panic leaves
    /// nothing behind that matters.
    static WORKSPACE: RefCell<Workspace> = RefCell::new(Workspace::new());
}

/// Solves one LCP in `ws`; a panic (a solver bug) is caught and returned as the payload.
fn solve_guarded(lcp: &Lcp, method: &Method, ws: &mut Workspace) -> Result<Solution, Panic> {
    catch_unwind(AssertUnwindSafe(|| lcp::solve_in(lcp, method, None, ws)))
}

/// [`solve_guarded`] in this thread's [`WORKSPACE`].
fn solve_here(lcp: &Lcp, method: &Method) -> Result<Solution, Panic> {
    WORKSPACE.with(|ws| solve_guarded(lcp, method, &mut ws.borrow_mut()))
}

/// Solves the LCP `(M, q)`: find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0.
///
/// `method` is "lemke", "pgs" or "newton_fb"; keyword options are passed to
/// that method (a value of None means its default). Returns a dict, see
/// `solution_to_dict`. Raises ValueError on invalid input.
#[pyfunction]
#[pyo3(signature = (m, q, method = "lemke", **options))]
pub fn solve_lcp<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    method: &str,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let method_v = method_from_py(method, options)?;
    let lcp = lcp_from_py(m, q)?;
    // Small problems are solved in microseconds: releasing the GIL would cost
    // more than it frees, so only large ones are solved detached.
    let sol = if lcp.n() >= 64 { py.detach(|| solve_here(&lcp, &method_v)) } else { solve_here(&lcp, &method_v) }
        .map_err(panic_error)?;
    solution_to_dict(py, sol, method_v.name())
}

/// Solves `b` LCPs `(Ms[i], qs[i])` of one size n with one method, with the
/// GIL released. `threads` worker threads (0 = one per core) split the batch.
#[pyfunction]
#[pyo3(signature = (ms, qs, method, threads, **options))]
pub fn solve_lcp_batch<'py>(
    py: Python<'py>,
    ms: &Bound<'py, PyAny>,
    qs: &Bound<'py, PyAny>,
    method: &str,
    threads: &Bound<'py, PyAny>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let threads = crate::args::count(threads, "threads")?;
    let method_v = method_from_py(method, options)?;
    let lcps = lcps_from_py(ms, qs)?;
    let n = match lcps.first() {
        Some(l) => l.n(),
        None => ms.getattr("shape").and_then(|s| s.get_item(1)).and_then(|x| x.extract()).unwrap_or(0),
    };
    let threads = match threads {
        0 => std::thread::available_parallelism().map(|t| t.get()).unwrap_or(1),
        t => t,
    }
    .min(lcps.len().max(1));
    let results: Vec<Result<Solution, (usize, Panic)>> = py.detach(|| {
        if threads <= 1 {
            let mut ws = Workspace::new();
            lcps.iter().enumerate().map(|(i, l)| solve_guarded(l, &method_v, &mut ws).map_err(|p| (i, p))).collect()
        } else {
            let chunk = lcps.len().div_ceil(threads);
            std::thread::scope(|scope| {
                let handles: Vec<_> = lcps
                    .chunks(chunk)
                    .enumerate()
                    .map(|(c, part)| {
                        let method_v = &method_v;
                        scope.spawn(move || {
                            let mut ws = Workspace::new();
                            part.iter()
                                .enumerate()
                                .map(|(i, l)| solve_guarded(l, method_v, &mut ws).map_err(|p| (c * chunk + i, p)))
                                .collect::<Vec<_>>()
                        })
                    })
                    .collect();
                handles.into_iter().flat_map(|h| h.join().unwrap_or_default()).collect()
            })
        }
    });
    let mut sols = Vec::with_capacity(results.len());
    for r in results {
        match r {
            Ok(s) => sols.push(s),
            Err((i, payload)) => {
                let err = panic_error(payload);
                return Err(pyo3::exceptions::PyRuntimeError::new_err(format!("problem {i}: {}", err.value(py))));
            }
        }
    }
    if sols.len() != lcps.len() {
        return Err(pyo3::exceptions::PyRuntimeError::new_err("internal error: a batch worker thread died"));
    }
    batch_to_dict(py, sols, n, method_v.name())
}

/// Natural residual ‖min(z, M z + q)‖∞ of `z` for `(M, q)`, in the units given.
#[pyfunction]
#[pyo3(signature = (m, q, z))]
pub fn lcp_residual(m: &Bound<'_, PyAny>, q: &Bound<'_, PyAny>, z: &Bound<'_, PyAny>) -> PyResult<f64> {
    let lcp = lcp_from_py(m, q)?;
    let z = vector_of_len(z, "z", lcp.n())?;
    Ok(Residuals::compute(&lcp, &z).1.residual)
}

/// All residuals of `z` for `(M, q)`: a dict with `w`, `residual`, `min_z`,
/// `min_w` and `max_complementarity`.
#[pyfunction]
#[pyo3(signature = (m, q, z))]
pub fn lcp_residuals<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    z: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let lcp = lcp_from_py(m, q)?;
    let z = vector_of_len(z, "z", lcp.n())?;
    let (w, r) = Residuals::compute(&lcp, &z);
    let d = PyDict::new(py);
    d.set_item("w", numpy::PyArray1::from_vec(py, w))?;
    residuals_into(&d, &r)?;
    Ok(d)
}
