//! Errors crossing into Python: invalid input becomes `ValueError`, naming the
//! field and the offending value; a solver panic (a bug) becomes `RuntimeError`.

use lcp::LcpError;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::any::Any;

/// `repr(value)`, for messages.
pub fn repr(value: &Bound<'_, PyAny>) -> String {
    value.repr().map(|r| r.to_string()).unwrap_or_else(|_| "<unprintable>".to_string())
}

/// `ValueError(msg)`.
pub fn value_error(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

/// Maps an `LcpError` to a `ValueError`; `n` is the problem size, used to print
/// a flat index of `M` as `M[i, j]`. `prefix` names the problem in a batch.
pub fn lcp_error(err: &LcpError, n: usize, prefix: &str) -> PyErr {
    let msg = match err {
        LcpError::NonFinite { field: "M", index, value } if n > 0 => {
            format!("M[{}, {}] = {} is not finite", index / n, index % n, py_float(*value))
        }
        LcpError::NonFinite { field, index, value } => format!("{field}[{index}] = {} is not finite", py_float(*value)),
        other => other.to_string(),
    };
    value_error(format!("{prefix}{msg}"))
}

/// Turns the payload of a caught panic into a `RuntimeError`: a solver must never
/// panic, so this is a bug to report, but it must not abort the interpreter.
pub fn panic_error(payload: Box<dyn Any + Send>) -> PyErr {
    let msg = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string());
    PyRuntimeError::new_err(format!("internal error in the LCP solver (please report this bug): {msg}"))
}

/// A float as Python prints it (`nan`, `inf`, `-inf`, `1.5`).
pub fn py_float(v: f64) -> String {
    if v.is_nan() {
        "nan".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{v:?}")
    }
}
