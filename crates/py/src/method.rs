//! Method name + keyword options → `lcp::Method`. Unknown names, wrong types and
//! out-of-range values are `ValueError`s that name the option and the value.

use crate::errors::{repr, value_error};
use lcp::{LemkeOptions, Method, NewtonFbOptions, PgsOptions, Pivoting};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString};

/// Method names accepted by `method=`.
pub const METHODS: [&str; 3] = ["lemke", "pgs", "newton_fb"];
/// Pivoting rules accepted by Lemke's `pivoting=`.
pub const PIVOTINGS: [&str; 2] = ["lexicographic", "classic"];

const LEMKE_OPTIONS: [&str; 8] =
    ["pivoting", "piv_tol", "zero_tol", "max_pivots", "accept_tol", "equilibrate", "fallback", "warm_start"];
const PGS_OPTIONS: [&str; 3] = ["omega", "max_iterations", "tol"];
const NEWTON_FB_OPTIONS: [&str; 6] =
    ["max_iterations", "tol", "armijo_sigma", "backtrack", "max_backtracks", "descent_rho"];

/// A finite real number (bools are refused: `piv_tol=True` is a mistake).
fn real(name: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    let bad = || value_error(format!("option {name} must be a real number, got {}", repr(value)));
    if value.is_instance_of::<PyBool>() || value.is_instance_of::<PyString>() {
        return Err(bad());
    }
    let x: f64 = value.extract().map_err(|_| bad())?;
    if !x.is_finite() {
        return Err(value_error(format!("option {name} must be finite, got {}", repr(value))));
    }
    Ok(x)
}

/// A tolerance: finite and ≥ 0.
fn tolerance(name: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    let x = real(name, value)?;
    if x < 0.0 {
        return Err(value_error(format!("option {name} must be >= 0, got {}", repr(value))));
    }
    Ok(x)
}

/// A real number in the open interval `(lo, hi)`.
fn open_interval(name: &str, value: &Bound<'_, PyAny>, lo: f64, hi: f64) -> PyResult<f64> {
    let x = real(name, value)?;
    if !(x > lo && x < hi) {
        return Err(value_error(format!("option {name} must lie in ({lo}, {hi}), got {}", repr(value))));
    }
    Ok(x)
}

/// A count ≥ 0 (Python int or numpy integer; floats and bools are refused).
fn count(name: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    if value.is_instance_of::<PyBool>() {
        return Err(value_error(format!("option {name} must be a non-negative integer, got {}", repr(value))));
    }
    value
        .extract::<usize>()
        .map_err(|_| value_error(format!("option {name} must be a non-negative integer, got {}", repr(value))))
}

fn boolean(name: &str, value: &Bound<'_, PyAny>) -> PyResult<bool> {
    value
        .extract::<bool>()
        .map_err(|_| value_error(format!("option {name} must be True or False, got {}", repr(value))))
}

/// `O::default()` with each option given in `options` set by `set`, which says
/// false for a name that is not one of the method's (`valid`, listed in the
/// error). `None` values are skipped (they mean "the default") except for the
/// options in `nullable`.
fn options_of<O: Default>(
    method: &str,
    valid: &[&str],
    nullable: &[&str],
    options: Option<&Bound<'_, PyDict>>,
    set: impl Fn(&mut O, &str, &Bound<'_, PyAny>) -> PyResult<bool>,
) -> PyResult<O> {
    let mut o = O::default();
    for (key, value) in options.into_iter().flat_map(|d| d.iter()) {
        let name: &str = key.extract()?;
        if (!value.is_none() || nullable.contains(&name)) && !set(&mut o, name, &value)? {
            return Err(value_error(format!(
                "unknown option {name:?} for method {method:?} (valid options: {})",
                valid.join(", ")
            )));
        }
    }
    Ok(o)
}

fn lemke_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<LemkeOptions> {
    options_of("lemke", &LEMKE_OPTIONS, &["max_pivots"], options, |o: &mut LemkeOptions, name, value| {
        match name {
            "pivoting" => o.pivoting = pivoting(value)?,
            "piv_tol" => o.piv_tol = tolerance(name, value)?,
            "zero_tol" => o.zero_tol = tolerance(name, value)?,
            "accept_tol" => o.accept_tol = tolerance(name, value)?,
            "max_pivots" => o.max_pivots = if value.is_none() { None } else { Some(count(name, value)?) },
            "equilibrate" => o.equilibrate = boolean(name, value)?,
            "fallback" => o.fallback = boolean(name, value)?,
            "warm_start" => o.warm_start = boolean(name, value)?,
            _ => return Ok(false),
        }
        Ok(true)
    })
}

fn pivoting(value: &Bound<'_, PyAny>) -> PyResult<Pivoting> {
    let s: &str =
        value.extract().map_err(|_| value_error(format!("option pivoting must be a string, got {}", repr(value))))?;
    match s {
        "lexicographic" => Ok(Pivoting::Lexicographic),
        "classic" => Ok(Pivoting::Classic),
        _ => Err(value_error(format!("unknown pivoting {s:?} (valid: {})", PIVOTINGS.join(", ")))),
    }
}

fn pgs_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<PgsOptions> {
    options_of("pgs", &PGS_OPTIONS, &[], options, |o: &mut PgsOptions, name, value| {
        match name {
            "omega" => o.omega = open_interval(name, value, 0.0, 2.0)?,
            "max_iterations" => o.max_iterations = count(name, value)?,
            "tol" => o.tol = tolerance(name, value)?,
            _ => return Ok(false),
        }
        Ok(true)
    })
}

fn newton_fb_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<NewtonFbOptions> {
    options_of("newton_fb", &NEWTON_FB_OPTIONS, &[], options, |o: &mut NewtonFbOptions, name, value| {
        match name {
            "max_iterations" => o.max_iterations = count(name, value)?,
            "tol" => o.tol = tolerance(name, value)?,
            "armijo_sigma" => o.armijo_sigma = open_interval(name, value, 0.0, 0.5)?,
            "backtrack" => o.backtrack = open_interval(name, value, 0.0, 1.0)?,
            "max_backtracks" => o.max_backtracks = count(name, value)?,
            "descent_rho" => o.descent_rho = positive(name, value)?,
            _ => return Ok(false),
        }
        Ok(true)
    })
}

/// A tolerance > 0.
fn positive(name: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    let x = tolerance(name, value)?;
    if x == 0.0 {
        return Err(value_error(format!("option {name} must be > 0, got {}", repr(value))));
    }
    Ok(x)
}

/// Builds the `Method` named `method` from keyword `options` (`None` values mean the default).
pub fn method_from_py(method: &str, options: Option<&Bound<'_, PyDict>>) -> PyResult<Method> {
    match method {
        "lemke" => Ok(Method::Lemke(lemke_options(options)?)),
        "pgs" => Ok(Method::Pgs(pgs_options(options)?)),
        "newton_fb" => Ok(Method::NewtonFb(newton_fb_options(options)?)),
        _ => Err(value_error(format!("unknown method {method:?} (valid: {})", METHODS.join(", ")))),
    }
}

/// `LemkeOptions::default()` by option name, for `_core.LEMKE_DEFAULTS`: the
/// wrapper passes no options when given none, so its keyword defaults must be
/// these (a test compares them).
pub fn lemke_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let o = LemkeOptions::default();
    let d = PyDict::new(py);
    let pivoting = match o.pivoting {
        Pivoting::Lexicographic => "lexicographic",
        Pivoting::Classic => "classic",
    };
    d.set_item("pivoting", pivoting)?;
    d.set_item("piv_tol", o.piv_tol)?;
    d.set_item("zero_tol", o.zero_tol)?;
    d.set_item("max_pivots", o.max_pivots)?;
    d.set_item("accept_tol", o.accept_tol)?;
    d.set_item("equilibrate", o.equilibrate)?;
    d.set_item("fallback", o.fallback)?;
    d.set_item("warm_start", o.warm_start)?;
    Ok(d)
}

/// The option names each method accepts, for `_core.METHOD_OPTIONS`.
pub fn method_options() -> [(&'static str, &'static [&'static str]); 3] {
    [("lemke", &LEMKE_OPTIONS), ("pgs", &PGS_OPTIONS), ("newton_fb", &NEWTON_FB_OPTIONS)]
}
