//! Integer arguments from Python: a `ValueError` naming the field and the
//! value for anything that is not a non-negative int that fits (never an
//! `OverflowError` or a `TypeError` for `2**64`, `-1`, `1.5` or `True`).

use crate::errors::{repr, value_error};
use pyo3::prelude::*;
use pyo3::types::PyBool;

/// A non-negative int (Python or numpy) of at most `max`.
fn bounded(value: &Bound<'_, PyAny>, field: &str, max: u64) -> PyResult<u64> {
    let bad = || value_error(format!("{field} must be a non-negative integer (at most {max}), got {}", repr(value)));
    if value.is_instance_of::<PyBool>() {
        return Err(bad());
    }
    // Through __index__ so that numpy integers pass and floats do not.
    let index = value.call_method0("__index__").map_err(|_| bad())?;
    index.extract::<u64>().ok().filter(|&v| v <= max).ok_or_else(bad)
}

/// A count or index ≥ 0 that fits in `usize`.
pub fn count(value: &Bound<'_, PyAny>, field: &str) -> PyResult<usize> {
    Ok(bounded(value, field, usize::MAX as u64)? as usize)
}
