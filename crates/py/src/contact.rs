//! Bindings of `lcp::contact`: `lcpsim.ContactLayout`, the one place Python
//! reads where `fn`, `fd`, `λ` live in `z`, scales a contact LCP by the
//! friction cone and classifies sign patterns. Every array argument may carry
//! leading batch dimensions (`z` of shape `(..., n)`).

use crate::errors::{lcp_error, value_error};
use lcp::contact::{ContactLayout, Pattern, ZeroLevels};
use lcp::Lcp;
use numpy::{AllowTypeChange, PyArray, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PySlice;

/// `lcpsim.ContactLayout(nc, k)`: `z = [fn (nc); fd (nc·k); λ (nc)]`, `n = nc·(k + 2)`.
#[pyclass(module = "lcpsim._core", name = "ContactLayout", frozen, eq, hash)]
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct PyContactLayout(ContactLayout);

/// A float64 array whose last `tail.len()` dimensions are `tail`, as
/// row-major data and its leading (batch) shape.
fn batched(ob: &Bound<'_, PyAny>, field: &str, tail: &[usize]) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let a: PyArrayLikeDyn<'_, f64, AllowTypeChange> =
        ob.extract().map_err(|e| value_error(format!("{field} must be an array of real numbers: {e}")))?;
    let shape = a.shape().to_vec();
    let lead = shape.len().checked_sub(tail.len());
    match lead {
        Some(l) if shape[l..] == *tail => {
            let v = a.as_array();
            Ok((v.iter().copied().collect(), shape[..l].to_vec()))
        }
        _ => Err(value_error(format!("{field} must have shape (..., {tail:?}) for this layout, got {shape:?}"))),
    }
}

/// A threshold: one float for every row, or an array of the batch shape.
fn thresholds(ob: &Bound<'_, PyAny>, field: &str, batch: &[usize]) -> PyResult<Vec<f64>> {
    let rows: usize = batch.iter().product();
    if let Ok(v) = ob.extract::<f64>() {
        return Ok(vec![v; rows]);
    }
    let (v, lead) = batched(ob, field, &[])?;
    if lead != batch {
        return Err(value_error(format!("{field} must be a float or an array of shape {batch:?}, got {lead:?}")));
    }
    Ok(v)
}

fn new_array<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    v: Vec<T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray::from_vec(py, v).reshape(shape.to_vec())?.into_any())
}

#[pymethods]
impl PyContactLayout {
    #[new]
    fn new(nc: &Bound<'_, PyAny>, k: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (nc, k) = (crate::args::count(nc, "nc")?, crate::args::count(k, "k")?);
        if nc == 0 || k == 0 {
            return Err(value_error(format!("a contact layout needs nc >= 1 and k >= 1, got nc = {nc}, k = {k}")));
        }
        // n = nc·(k + 2) must be a size numpy can allocate.
        if nc.checked_mul(k.saturating_add(2)).is_none_or(|n| n > isize::MAX as usize / 8) {
            return Err(value_error(format!(
                "a contact layout of nc = {nc}, k = {k} is too large (n = nc·(k + 2) overflows)"
            )));
        }
        Ok(PyContactLayout(ContactLayout::new(nc, k)))
    }

    /// The source note's sign patterns in table order (`ContactLayout.patterns` codes index it).
    #[classattr]
    const PATTERNS: [&'static str; 8] = Pattern::ALL;

    #[getter]
    fn nc(&self) -> usize {
        self.0.nc
    }
    #[getter]
    fn k(&self) -> usize {
        self.0.k
    }
    /// LCP size `nc·(k + 2)`.
    #[getter]
    fn n(&self) -> usize {
        self.0.n()
    }
    /// `nc·(k + 1)`: the `[fn; fd]` part (rows and columns of `A`).
    #[getter]
    fn impulses(&self) -> usize {
        self.0.impulses()
    }
    /// Slice of `fn` in `z`.
    #[getter(r#fn)]
    fn fn_slice<'py>(&self, py: Python<'py>) -> Bound<'py, PySlice> {
        slice(py, self.0.fn_range())
    }
    /// Slice of `fd` in `z` (reshape to `(nc, k)`: contact-major).
    #[getter]
    fn fd<'py>(&self, py: Python<'py>) -> Bound<'py, PySlice> {
        slice(py, self.0.fd_range())
    }
    /// Slice of `λ` in `z`.
    #[getter]
    fn lam<'py>(&self, py: Python<'py>) -> Bound<'py, PySlice> {
        slice(py, self.0.lambda_range())
    }
    /// Slice of the `[fn; fd]` part.
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> Bound<'py, PySlice> {
        slice(py, 0..self.0.impulses())
    }
    /// Slice of contact `c`'s `fd`.
    fn fd_of<'py>(&self, py: Python<'py>, c: usize) -> PyResult<Bound<'py, PySlice>> {
        self.check_contact(c)?;
        Ok(slice(py, self.0.fd_of(c)))
    }
    /// Index of `fd` along direction `j` at contact `c`.
    fn fd_index(&self, c: usize, j: usize) -> PyResult<usize> {
        self.check_contact(c)?;
        if j >= self.0.k {
            return Err(value_error(format!("j = {j} out of range for k = {}", self.0.k)));
        }
        Ok(self.0.fd_index(c, j))
    }
    /// Index of `λ` of contact `c`.
    fn lambda_index(&self, c: usize) -> PyResult<usize> {
        self.check_contact(c)?;
        Ok(self.0.lambda_index(c))
    }

    /// The diagonal of the cone scaling `D = diag(I, I, s·I)`.
    fn cone_diagonal<'py>(&self, py: Python<'py>, s: f64) -> PyResult<Bound<'py, PyAny>> {
        new_array(py, self.0.cone_diagonal(s), &[self.0.n()])
    }
    /// `(D M D, D q)` of an unscaled contact LCP (`M` of shape `(..., n, n)`, `q` `(..., n)`).
    fn scale_lcp<'py>(
        &self,
        py: Python<'py>,
        m: &Bound<'py, PyAny>,
        q: &Bound<'py, PyAny>,
        s: f64,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let n = self.0.n();
        let (mv, qv, mb) = self.lcps(m, q)?;
        let (mut ms, mut qs) = (Vec::with_capacity(mv.len()), Vec::with_capacity(qv.len()));
        for (m, q) in mv.chunks_exact(n * n).zip(qv.chunks_exact(n)) {
            let lcp = Lcp::new(m.to_vec(), q.to_vec()).map_err(|e| lcp_error(&e, n, ""))?;
            let scaled = self.0.scale_lcp(&lcp, s).map_err(|e| lcp_error(&e, n, &format!("s = {s}: ")))?;
            let (m, q) = scaled.into_parts();
            ms.extend(m);
            qs.extend(q);
        }
        let mshape: Vec<usize> = mb.iter().copied().chain([n, n]).collect();
        let qshape: Vec<usize> = mb.iter().copied().chain([n]).collect();
        Ok((new_array(py, ms, &mshape)?, new_array(py, qs, &qshape)?))
    }
    /// The physical `z` of a scaled problem's answer (`λ = s·λ_scaled`), `z` of shape `(..., n)`.
    fn unscale_z<'py>(&self, py: Python<'py>, z: &Bound<'py, PyAny>, s: f64) -> PyResult<Bound<'py, PyAny>> {
        let n = self.0.n();
        let (mut zv, b) = batched(z, "z", &[n])?;
        for row in zv.chunks_exact_mut(n) {
            self.0.unscale_z(row, s);
        }
        new_array(py, zv, &b.iter().copied().chain([n]).collect::<Vec<_>>())
    }

    /// Thresholds `(impulse, velocity)` of the zero rule relative to each
    /// LCP's scales (`rel` × max(‖[fn; fd]‖∞, ‖q‖∞/max|A|), `rel` × ‖q‖∞);
    /// `M`, `q` of the unscaled problem, `z` physical, all with the same batch shape.
    fn zero_levels<'py>(
        &self,
        py: Python<'py>,
        m: &Bound<'py, PyAny>,
        q: &Bound<'py, PyAny>,
        z: &Bound<'py, PyAny>,
        rel: f64,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let n = self.0.n();
        let (mv, qv, mb) = self.lcps(m, q)?;
        let (zv, zb) = batched(z, "z", &[n])?;
        if mb != zb {
            return Err(value_error(format!("M, q and z have batch shapes {mb:?} and {zb:?}")));
        }
        let levels: Vec<ZeroLevels> = mv
            .chunks_exact(n * n)
            .zip(qv.chunks_exact(n))
            .zip(zv.chunks_exact(n))
            .map(|((m, q), z)| ZeroLevels::relative(&self.0, m, q, z, rel))
            .collect();
        let imp = levels.iter().map(|l| l.impulse).collect();
        let vel = levels.iter().map(|l| l.velocity).collect();
        Ok((new_array(py, imp, &mb)?, new_array(py, vel, &mb)?))
    }

    /// Sign-pattern codes (index into `PATTERNS`, `4·fn + 2·Σfd + λ`) of the
    /// physical `z` `(..., n)`, shape `(..., nc)`. A value is positive when it
    /// is strictly greater than its threshold: `impulse_zero` for `fn` and
    /// `Σ fd`, `velocity_zero` (default: `impulse_zero`) for `λ`; each a float
    /// or an array of `z`'s batch shape (from `zero_levels`).
    #[pyo3(signature = (z, impulse_zero = None, velocity_zero = None))]
    fn patterns<'py>(
        &self,
        py: Python<'py>,
        z: &Bound<'py, PyAny>,
        impulse_zero: Option<Bound<'py, PyAny>>,
        velocity_zero: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (n, nc) = (self.0.n(), self.0.nc);
        let (zv, b) = batched(z, "z", &[n])?;
        let imp = match &impulse_zero {
            Some(v) => thresholds(v, "impulse_zero", &b)?,
            None => vec![0.0; b.iter().product()],
        };
        let vel = match &velocity_zero {
            Some(v) => thresholds(v, "velocity_zero", &b)?,
            None => imp.clone(),
        };
        let mut codes = Vec::with_capacity(imp.len() * nc);
        for ((row, &i), &v) in zv.chunks_exact(n).zip(&imp).zip(&vel) {
            let zero = ZeroLevels { impulse: i, velocity: v };
            codes.extend((0..nc).map(|c| self.0.pattern(row, c, zero).code() as i8));
        }
        new_array(py, codes, &b.iter().copied().chain([nc]).collect::<Vec<_>>())
    }

    fn __repr__(&self) -> String {
        format!("ContactLayout(nc={}, k={})", self.0.nc, self.0.k)
    }
}

impl PyContactLayout {
    /// `M (..., n, n)` and `q (..., n)` of one batch shape: their data and that shape.
    fn lcps(&self, m: &Bound<'_, PyAny>, q: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, Vec<f64>, Vec<usize>)> {
        let n = self.0.n();
        let (mv, mb) = batched(m, "M", &[n, n])?;
        let (qv, qb) = batched(q, "q", &[n])?;
        if mb != qb {
            return Err(value_error(format!("M and q have batch shapes {mb:?} and {qb:?}")));
        }
        Ok((mv, qv, mb))
    }

    fn check_contact(&self, c: usize) -> PyResult<()> {
        if c < self.0.nc {
            Ok(())
        } else {
            Err(value_error(format!("contact c = {c} out of range for nc = {}", self.0.nc)))
        }
    }
}

/// A Python `slice` of `r`.
fn slice(py: Python<'_>, r: std::ops::Range<usize>) -> Bound<'_, PySlice> {
    PySlice::new(py, r.start as isize, r.end as isize, 1)
}
