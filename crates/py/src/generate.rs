//! Bindings of the seeded test-LCP generators — `lcp::generate` (matrices) and
//! `sim::generate` (contact scenes) — each returning
//! `(M, q, label)` with `M` an `(n, n)` and `q` an `(n,)` float64 array, and
//! the label a string that names the generator and its arguments. The
//! contact generators also return `(nc, k)` so that Python can undo the
//! friction-cone scaling (`lcp::contact`). Arguments the Rust generators would panic
//! on, and sizes whose matrices could not fit in memory, are rejected here with
//! a `ValueError` (saying how much memory the request needs); integer arguments
//! (sizes ≥ 1, seeds and counts ≥ 0, below 2⁶⁴) by `args::integer`, naming the field.

use crate::args::integer;
use crate::errors::value_error;
use lcp::generate;
use lcp::Lcp;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use sim::generate::{self as scenes, HardKind};

/// Every hard-contact family by its snake_case name.
pub fn hard_kinds() -> Vec<&'static str> {
    HardKind::ALL.iter().map(|k| k.as_str()).collect()
}

/// `(M, q, label, nc, k)`: what every contact generator returns.
type ContactTuple<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>, String, usize, usize);
/// `(M, q, label)`.
type PlainTuple<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>, String);
/// `(M, q)`.
type Arrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// An `Lcp` as numpy `(M (n, n), q (n,))`.
fn to_numpy(py: Python<'_>, lcp: Lcp) -> PyResult<Arrays<'_>> {
    let n = lcp.n();
    let (m, q) = lcp.into_parts();
    let m = PyArray1::from_vec(py, m).reshape([n, n])?;
    Ok((m, PyArray1::from_vec(py, q)))
}

fn check_scale(scale: f64) -> PyResult<()> {
    if scale >= 0.0 && scale.is_finite() {
        Ok(())
    } else {
        Err(value_error(format!("scale = {scale} must be finite and >= 0")))
    }
}

/// Friction directions of a generated contact LCP: in [1, `sim::contact::friction::MAX_FRICTION_DIRS`].
fn check_dirs(k: usize) -> PyResult<()> {
    let max = sim::contact::friction::MAX_FRICTION_DIRS;
    if k > max {
        return Err(value_error(format!("k must be at most {max} friction directions, got {k}")));
    }
    Ok(())
}

/// A size or count ≥ 1 (`n`, `nc`, `k`).
fn size(value: &Bound<'_, PyAny>, field: &str) -> PyResult<usize> {
    Ok(integer(value, field, 1)? as usize)
}

/// Refuses a generator call whose `copies` dense `n × n` matrices could not fit in memory.
fn check_size(what: impl FnOnce() -> String, n: usize, copies: u32) -> PyResult<()> {
    lcp::limits::check_dense(what, n, copies).map_err(|e| value_error(e.to_string()))
}

fn hard_kind(name: &str) -> PyResult<HardKind> {
    HardKind::ALL
        .into_iter()
        .find(|k| k.as_str() == name)
        .ok_or_else(|| value_error(format!("unknown hard-contact kind {name:?}; expected one of {:?}", hard_kinds())))
}

/// The contact LCP of one unit cube on a random slope (`sim::generate::contact_lcp`).
#[pyfunction]
pub fn contact_lcp<'py>(
    py: Python<'py>,
    nc: &Bound<'py, PyAny>,
    k: &Bound<'py, PyAny>,
    scale: f64,
    seed: &Bound<'py, PyAny>,
) -> PyResult<ContactTuple<'py>> {
    let (nc, k, seed) = (size(nc, "nc")?, size(k, "k")?, integer(seed, "seed", 0)?);
    check_dirs(k)?;
    check_scale(scale)?;
    let n = sim::limits::lcp_size(nc, k).unwrap_or(usize::MAX);
    check_size(|| format!("contact_lcp(nc={nc}, k={k}): an LCP of n = {n} unknowns"), n, 2)?;
    let lcp = scenes::contact_lcp(nc, k, scale, seed);
    let (m, q) = to_numpy(py, lcp)?;
    Ok((m, q, format!("contact/nc{nc}/k{k}/seed{seed}"), nc, k))
}

/// A random LCP with a symmetric positive definite `M` (`generate::spd_lcp`).
#[pyfunction]
pub fn spd_lcp<'py>(py: Python<'py>, n: &Bound<'py, PyAny>, seed: &Bound<'py, PyAny>) -> PyResult<PlainTuple<'py>> {
    matrix_lcp(py, "spd", n, seed, generate::spd_lcp)
}

/// A random LCP with a nonsymmetric positive definite (P) `M` (`generate::p_matrix_lcp`).
#[pyfunction]
pub fn p_matrix_lcp<'py>(
    py: Python<'py>,
    n: &Bound<'py, PyAny>,
    seed: &Bound<'py, PyAny>,
) -> PyResult<PlainTuple<'py>> {
    matrix_lcp(py, "p_matrix", n, seed, generate::p_matrix_lcp)
}

/// A seeded matrix generator's LCP of size `n`, labelled `family/nN/seedS`.
fn matrix_lcp<'py>(
    py: Python<'py>,
    family: &str,
    n: &Bound<'py, PyAny>,
    seed: &Bound<'py, PyAny>,
    make: fn(usize, u64) -> Lcp,
) -> PyResult<PlainTuple<'py>> {
    let (n, seed) = (size(n, "n")?, integer(seed, "seed", 0)?);
    check_size(|| format!("{family}_lcp(n={n})"), n, 4)?;
    let lcp = py.detach(|| make(n, seed));
    let (m, q) = to_numpy(py, lcp)?;
    Ok((m, q, format!("{family}/n{n}/seed{seed}")))
}

/// A hard contact LCP of family `kind` (`sim::generate::hard_contact_lcp_k`); the
/// label is the scene's own (`kind/kK/ncN/seedS`).
#[pyfunction]
pub fn hard_contact_lcp<'py>(
    py: Python<'py>,
    kind: &str,
    scale: f64,
    seed: &Bound<'py, PyAny>,
    k: &Bound<'py, PyAny>,
) -> PyResult<ContactTuple<'py>> {
    let kind = hard_kind(kind)?;
    let (seed, k) = (integer(seed, "seed", 0)?, size(k, "k")?);
    check_dirs(k)?;
    check_scale(scale)?;
    let scene = scenes::HardScene::random(kind, k, seed);
    let (label, nc) = (scene.label(seed), scene.nc);
    let (m, q) = to_numpy(py, scene.lcp(scale))?;
    Ok((m, q, label, nc, k))
}

/// `count` hard contact LCPs (`sim::generate::hard_corpus`), each `(M, q, label, nc, k)`.
#[pyfunction]
pub fn hard_corpus<'py>(
    py: Python<'py>,
    seed: &Bound<'py, PyAny>,
    count: &Bound<'py, PyAny>,
    scale: f64,
) -> PyResult<Vec<ContactTuple<'py>>> {
    let (seed, count) = (integer(seed, "seed", 0)?, integer(count, "count", 0)? as usize);
    check_scale(scale)?;
    // Every item is at least one contact with k = 4 (an LCP of 6 unknowns).
    let bytes = (count as u128).saturating_mul(lcp::limits::dense_bytes(6, 1) + 64);
    lcp::limits::check_bytes(|| format!("hard_corpus(count={count})"), bytes)
        .map_err(|e| value_error(e.to_string()))?;
    let items = py.detach(|| scenes::hard_corpus(seed, count, scale));
    items
        .into_iter()
        .enumerate()
        .map(|(i, (label, lcp))| {
            let (_, k, _) = scenes::hard_corpus_item(seed, i);
            let nc = lcp.n() / (k + 2);
            let (m, q) = to_numpy(py, lcp)?;
            Ok((m, q, label, nc, k))
        })
        .collect()
}
