//! Python values → `sim` types (vectors, quaternions, cone scale, μ rule), and
//! `SimError` → `ValueError`. Every message names the argument and its value.

pub use crate::errors::repr;
use crate::errors::{py_float, value_error};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString};
use sim::math::{Mat3, Quat, Vec3};
use sim::{ConeScale, MuCombine, SimError};

/// A `SimError` (invalid input) as a `ValueError`; its message names the field and value.
pub fn sim_error(e: &SimError) -> PyErr {
    value_error(e.to_string())
}

/// `value` read by `read` unless it is missing or None, else `default` (the
/// Rust side's own default: the glue declares none).
pub fn or_default<'py, T>(
    value: Option<&Bound<'py, PyAny>>,
    field: &str,
    read: impl Fn(&Bound<'py, PyAny>, &str) -> PyResult<T>,
    default: T,
) -> PyResult<T> {
    match value.filter(|v| !v.is_none()) {
        Some(v) => read(v, field),
        None => Ok(default),
    }
}

/// A real number (bools and strings are refused). Finiteness is left to the
/// core, which names the field in its own message.
pub fn real(value: &Bound<'_, PyAny>, field: &str) -> PyResult<f64> {
    if value.is_instance_of::<PyBool>() || value.is_instance_of::<PyString>() {
        return Err(value_error(format!("{field} must be a real number, got {}", repr(value))));
    }
    value.extract::<f64>().map_err(|_| value_error(format!("{field} must be a real number, got {}", repr(value))))
}

/// True or False (numbers are refused: `speculative=1` is a mistake).
pub fn flag(value: &Bound<'_, PyAny>, field: &str) -> PyResult<bool> {
    if value.is_instance_of::<PyBool>() {
        return value.extract();
    }
    Err(value_error(format!("{field} must be True or False, got {}", repr(value))))
}

/// A string.
pub fn text(value: &Bound<'_, PyAny>, field: &str) -> PyResult<String> {
    value.extract().map_err(|_| value_error(format!("{field} must be a string, got {}", repr(value))))
}

/// `len` real numbers from any sequence (tuple, list, numpy array).
fn reals<const N: usize>(value: &Bound<'_, PyAny>, field: &str) -> PyResult<[f64; N]> {
    let bad = || value_error(format!("{field} must be a sequence of {N} real numbers, got {}", repr(value)));
    if value.is_instance_of::<PyString>() {
        return Err(bad());
    }
    let v: Vec<f64> = value.extract().map_err(|_| bad())?;
    let arr: [f64; N] = v.try_into().map_err(|_| bad())?;
    if let Some(x) = arr.iter().find(|x| !x.is_finite()) {
        return Err(value_error(format!("{field} must be finite, got {}", py_float(*x))));
    }
    Ok(arr)
}

/// A 3-vector.
pub fn vec3(value: &Bound<'_, PyAny>, field: &str) -> PyResult<Vec3> {
    Ok(Vec3::from_array(reals::<3>(value, field)?))
}

/// An optional 3-vector (`None` stays `None`).
pub fn opt_vec3(value: Option<&Bound<'_, PyAny>>, field: &str) -> PyResult<Option<Vec3>> {
    match value {
        Some(v) if !v.is_none() => Ok(Some(vec3(v, field)?)),
        _ => Ok(None),
    }
}

/// A quaternion (w, x, y, z); normalization (and the zero check) is the core's.
pub fn quat(value: &Bound<'_, PyAny>, field: &str) -> PyResult<Quat> {
    Ok(Quat::from_array(reals::<4>(value, field)?))
}

/// A 3×3 matrix from a nested sequence or a (3, 3) array.
pub fn mat3(value: &Bound<'_, PyAny>, field: &str) -> PyResult<Mat3> {
    let bad = || value_error(format!("{field} must be a 3x3 matrix of real numbers, got {}", repr(value)));
    let rows: Vec<Bound<'_, PyAny>> =
        value.try_iter().map_err(|_| bad())?.collect::<PyResult<_>>().map_err(|_| bad())?;
    if rows.len() != 3 {
        return Err(bad());
    }
    let mut m = [[0.0; 3]; 3];
    for (i, r) in rows.iter().enumerate() {
        m[i] = reals::<3>(r, field).map_err(|_| bad())?;
    }
    Ok(Mat3::from_rows(m))
}

/// The friction-cone scale in the forms `lcpsim.scale.parse_cone_scale` hands
/// on (the one parser of its spellings): None or "none" → s = 1, "dt" → s = h,
/// a number → that s (> 0, checked by the core).
pub fn cone_scale(value: Option<&Bound<'_, PyAny>>) -> PyResult<ConeScale> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(ConeScale::Unscaled);
    };
    let bad = || value_error(format!("cone_scale must be None, \"none\", \"dt\" or a number > 0, got {}", repr(v)));
    if let Ok(s) = v.extract::<String>() {
        return match s.as_str() {
            "none" => Ok(ConeScale::Unscaled),
            "dt" => Ok(ConeScale::TimeStep),
            _ => Err(bad()),
        };
    }
    real(v, "cone_scale").map(ConeScale::Value).map_err(|_| bad())
}

/// How a cone scale is shown to Python: "none", "dt" or the number.
pub fn cone_scale_to_py(py: Python<'_>, s: ConeScale) -> PyResult<Py<PyAny>> {
    Ok(match s {
        ConeScale::Unscaled => "none".into_pyobject(py)?.into_any().unbind(),
        ConeScale::TimeStep => "dt".into_pyobject(py)?.into_any().unbind(),
        ConeScale::Value(x) => x.into_pyobject(py)?.into_any().unbind(),
    })
}

/// Names of the μ-combination rules.
pub const MU_COMBINE: [&str; 5] = ["min", "max", "product", "geometric_mean", "average"];

pub fn mu_combine(name: &str) -> PyResult<MuCombine> {
    Ok(match name {
        "min" => MuCombine::Min,
        "max" => MuCombine::Max,
        "product" => MuCombine::Product,
        "geometric_mean" => MuCombine::GeometricMean,
        "average" => MuCombine::Average,
        _ => return Err(value_error(format!("unknown mu_combine {name:?} (valid: {})", MU_COMBINE.join(", ")))),
    })
}

pub fn mu_combine_name(m: MuCombine) -> &'static str {
    match m {
        MuCombine::Min => "min",
        MuCombine::Max => "max",
        MuCombine::Product => "product",
        MuCombine::GeometricMean => "geometric_mean",
        MuCombine::Average => "average",
    }
}

/// A slope's downhill side: "+x" or "-x".
pub fn downhill(name: &str) -> PyResult<sim::Downhill> {
    match name {
        "+x" | "x" | "plus_x" => Ok(sim::Downhill::PlusX),
        "-x" | "minus_x" => Ok(sim::Downhill::MinusX),
        _ => Err(value_error(format!("downhill must be \"+x\" or \"-x\", got {name:?}"))),
    }
}

pub use crate::args::{at_most, count};

/// A slope angle in degrees, in [0, 90).
pub fn angle_deg(value: f64) -> PyResult<f64> {
    if !(value.is_finite() && (0.0..90.0).contains(&value)) {
        return Err(value_error(format!("angle_deg must be in [0, 90), got {}", py_float(value))));
    }
    Ok(value)
}

/// Named fields from a dict (the scene parameters, the world parameters):
/// None counts as not given, and unknown names are refused.
pub struct Fields<'a, 'py> {
    /// What the fields are of, for messages ("scene cube_drop", "World").
    pub of: &'a str,
    pub dict: Option<&'a Bound<'py, PyDict>>,
}

impl<'py> Fields<'_, 'py> {
    /// The value of `name`, unless missing or None.
    pub fn get(&self, name: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.dict {
            Some(d) => Ok(d.get_item(name)?.filter(|v| !v.is_none())),
            None => Ok(None),
        }
    }

    /// `name` read by `read`, else `default` (the Rust side's own: the glue declares none).
    pub fn or<T>(&self, name: &str, read: impl Fn(&Bound<'py, PyAny>, &str) -> PyResult<T>, default: T) -> PyResult<T> {
        self.get(name)?.map_or(Ok(default), |v| read(&v, name))
    }

    /// Refuses any name not in `valid`.
    pub fn check_names(&self, valid: &[&str]) -> PyResult<()> {
        for key in self.dict.into_iter().flat_map(|d| d.keys()) {
            let name: String = key.extract()?;
            if !valid.contains(&name.as_str()) {
                return Err(value_error(format!(
                    "unknown parameter {name:?} for {} (valid: {})",
                    self.of,
                    valid.join(", ")
                )));
            }
        }
        Ok(())
    }
}
