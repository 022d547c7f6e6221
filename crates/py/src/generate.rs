//! Bindings of the seeded test-LCP generators — `lcp::generate` (matrices) and
//! `sim::generate` (contact scenes) — each returning
//! `(M, q, label)` with `M` an `(n, n)` and `q` an `(n,)` float64 array, and
//! the label a string that names the generator and its arguments. The
//! contact generators also return `(nc, k)` so that Python can undo the
//! friction-cone scaling (DESIGN §1). Arguments the Rust generators would panic
//! on are rejected here with a `ValueError`.

use crate::errors::value_error;
use lcp::generate;
use sim::generate::{self as scenes, HardKind};
use lcp::Lcp;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

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

fn check_positive(value: usize, name: &str) -> PyResult<()> {
    if value == 0 {
        return Err(value_error(format!("{name} must be >= 1, got 0")));
    }
    Ok(())
}

fn hard_kind(name: &str) -> PyResult<HardKind> {
    HardKind::ALL
        .into_iter()
        .find(|k| k.as_str() == name)
        .ok_or_else(|| value_error(format!("unknown hard-contact kind {name:?}; expected one of {:?}", hard_kinds())))
}

/// The contact LCP of one unit cube on a random slope (`sim::generate::contact_lcp`).
#[pyfunction]
#[pyo3(signature = (nc, k = 8, scale = 1.0, seed = 0))]
pub fn contact_lcp(py: Python<'_>, nc: usize, k: usize, scale: f64, seed: u64) -> PyResult<ContactTuple<'_>> {
    check_positive(nc, "nc")?;
    check_positive(k, "k")?;
    check_scale(scale)?;
    let lcp = scenes::contact_lcp(nc, k, scale, seed);
    let (m, q) = to_numpy(py, lcp)?;
    Ok((m, q, format!("contact/nc{nc}/k{k}/seed{seed}"), nc, k))
}

/// A random LCP with a symmetric positive definite `M` (`generate::spd_lcp`).
#[pyfunction]
#[pyo3(signature = (n, seed = 0))]
pub fn spd_lcp(py: Python<'_>, n: usize, seed: u64) -> PyResult<PlainTuple<'_>> {
    matrix_lcp(py, "spd", n, seed, generate::spd_lcp)
}

/// A random LCP with a nonsymmetric positive definite (P) `M` (`generate::p_matrix_lcp`).
#[pyfunction]
#[pyo3(signature = (n, seed = 0))]
pub fn p_matrix_lcp(py: Python<'_>, n: usize, seed: u64) -> PyResult<PlainTuple<'_>> {
    matrix_lcp(py, "p_matrix", n, seed, generate::p_matrix_lcp)
}

/// A seeded matrix generator's LCP of size `n`, labelled `family/nN/seedS`.
fn matrix_lcp<'py>(
    py: Python<'py>,
    family: &str,
    n: usize,
    seed: u64,
    make: fn(usize, u64) -> Lcp,
) -> PyResult<PlainTuple<'py>> {
    check_positive(n, "n")?;
    let lcp = py.detach(|| make(n, seed));
    let (m, q) = to_numpy(py, lcp)?;
    Ok((m, q, format!("{family}/n{n}/seed{seed}")))
}

/// A hard contact LCP of family `kind` (`sim::generate::hard_contact_lcp_k`); the
/// label is the scene's own (`kind/kK/ncN/seedS`).
#[pyfunction]
#[pyo3(signature = (kind, scale = 1.0, seed = 0, k = 8))]
pub fn hard_contact_lcp<'py>(
    py: Python<'py>,
    kind: &str,
    scale: f64,
    seed: u64,
    k: usize,
) -> PyResult<ContactTuple<'py>> {
    let kind = hard_kind(kind)?;
    check_positive(k, "k")?;
    check_scale(scale)?;
    let scene = scenes::HardScene::random(kind, k, seed);
    let (label, nc) = (scene.label(seed), scene.nc);
    let (m, q) = to_numpy(py, scene.lcp(scale))?;
    Ok((m, q, label, nc, k))
}

/// `count` hard contact LCPs (`sim::generate::hard_corpus`), each `(M, q, label, nc, k)`.
#[pyfunction]
#[pyo3(signature = (seed, count, scale = 1.0))]
pub fn hard_corpus(py: Python<'_>, seed: u64, count: usize, scale: f64) -> PyResult<Vec<ContactTuple<'_>>> {
    check_scale(scale)?;
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
