//! Integer arguments from Python: a `ValueError` naming the field and the
//! value for anything that is not a non-negative int that fits (never an
//! `OverflowError` or a `TypeError` for `2**64`, `-1`, `1.5` or `True`).

use crate::errors::{repr, value_error};
use pyo3::prelude::*;
use pyo3::types::PyBool;

/// `value` as an integer through `__index__` (Python and numpy integers pass;
/// floats, bools and strings do not), when it fits in `u64`.
fn as_u64(value: &Bound<'_, PyAny>) -> Option<u64> {
    if value.is_instance_of::<PyBool>() {
        return None;
    }
    value.call_method0("__index__").ok()?.extract::<u64>().ok()
}

/// A non-negative int (Python or numpy) of at most `max`.
fn bounded(value: &Bound<'_, PyAny>, field: &str, max: u64) -> PyResult<u64> {
    as_u64(value).filter(|&v| v <= max).ok_or_else(|| {
        value_error(format!("{field} must be a non-negative integer (at most {max}), got {}", repr(value)))
    })
}

/// A non-negative int of at most `max` (a small setting such as `max_halvings`).
pub fn at_most(value: &Bound<'_, PyAny>, field: &str, max: u32) -> PyResult<u32> {
    Ok(bounded(value, field, u64::from(max))? as u32)
}

/// A count or index ≥ 0 that fits in `usize`.
pub fn count(value: &Bound<'_, PyAny>, field: &str) -> PyResult<usize> {
    Ok(bounded(value, field, usize::MAX as u64)? as usize)
}

/// An integer in `[lo, 2⁶⁴)`: the generators' sizes, counts and seeds.
pub fn integer(value: &Bound<'_, PyAny>, field: &str, lo: u64) -> PyResult<u64> {
    as_u64(value)
        .filter(|&v| v >= lo)
        .ok_or_else(|| value_error(format!("{field} must be an integer in [{lo}, 2**64), got {}", repr(value))))
}
