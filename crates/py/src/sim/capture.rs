//! LCP capture for Python: a sink that appends every solved LCP to flat
//! buffers (no Python call per LCP, so it works with the GIL released); the
//! Python side drains them into numpy arrays between chunks of a run.

use lcp::Status;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::{Captured, CapturedLcp, LcpSink};
use std::sync::{Arc, Mutex, MutexGuard};

/// Captured LCPs: `m` holds the row-major `M` of each problem one after the
/// other (n_i² values), `q`, `z`, `w` n_i values each; `records` the rest of
/// each record, its arrays replaced by the number of values kept (n_i², n_i).
#[derive(Default)]
pub struct CaptureLog {
    pub m: Vec<f64>,
    pub q: Vec<f64>,
    pub z: Vec<f64>,
    pub w: Vec<f64>,
    pub records: Vec<Captured<usize>>,
}

impl CaptureLog {
    /// Memory held (bytes), to decide when to drain.
    pub fn bytes(&self) -> usize {
        8 * (self.m.len() + self.q.len() + self.z.len() + self.w.len()) + 73 * self.records.len()
    }

    pub fn len(&self) -> usize {
        self.records.len()
    }
}

/// Index of a status in `Status::ALL` (the order of `_core.STATUSES`).
pub fn status_code(s: Status) -> i8 {
    Status::ALL.iter().position(|x| *x == s).map_or(-1, |i| i as i8)
}

/// The shared buffer, one clone in the world's sink and one in the Python object.
#[derive(Clone, Default)]
pub struct CaptureBuffer(Arc<Mutex<CaptureLog>>);

impl CaptureBuffer {
    pub fn lock(&self) -> MutexGuard<'_, CaptureLog> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Takes everything captured so far as a dict of numpy arrays.
    pub fn drain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = std::mem::take(&mut *self.lock());
        let r = &c.records;
        let ints = |f: fn(&Captured<usize>) -> i64| PyArray1::from_vec(py, r.iter().map(f).collect());
        let reals = |f: fn(&Captured<usize>) -> f64| PyArray1::from_vec(py, r.iter().map(f).collect());
        let d = PyDict::new(py);
        d.set_item("n", ints(|l| l.q as i64))?;
        d.set_item("step", ints(|l| l.step as i64))?;
        d.set_item("island", ints(|l| l.island as i64))?;
        d.set_item("time", reals(|l| l.time))?;
        d.set_item("contacts", ints(|l| l.contacts as i64))?;
        d.set_item("friction_dirs", ints(|l| l.friction_dirs as i64))?;
        d.set_item("scale", reals(|l| l.scale))?;
        d.set_item("status", PyArray1::from_vec(py, r.iter().map(|l| status_code(l.status)).collect()))?;
        d.set_item("pivots", ints(|l| l.pivots as i64))?;
        d.set_item("method", r.iter().map(|l| l.method).collect::<Vec<_>>())?;
        d.set_item("M", PyArray1::from_vec(py, c.m))?;
        d.set_item("q", PyArray1::from_vec(py, c.q))?;
        d.set_item("z", PyArray1::from_vec(py, c.z))?;
        d.set_item("w", PyArray1::from_vec(py, c.w))?;
        Ok(d)
    }
}

impl LcpSink for CaptureBuffer {
    fn capture(&mut self, l: &CapturedLcp<'_>) {
        let mut c = self.lock();
        c.m.extend_from_slice(l.m);
        c.q.extend_from_slice(l.q);
        // z and w are n long by the solver contract; pad with NaN otherwise so
        // that the offsets of the next problems stay right.
        let n = l.n();
        let CaptureLog { z, w, .. } = &mut *c;
        for (dst, src) in [(z, l.z), (w, l.w)] {
            let k = src.len().min(n);
            dst.extend_from_slice(&src[..k]);
            dst.resize(dst.len() + (n - k), f64::NAN);
        }
        c.records.push(l.map(|a| a.len()));
    }
}
