//! LCP capture for Python: a sink that appends every solved LCP to flat
//! buffers (no Python call per LCP, so it works with the GIL released); the
//! Python side drains them into numpy arrays between chunks of a run.

use lcp::Status;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::{CapturedLcp, LcpSink};
use std::sync::{Arc, Mutex, MutexGuard};

/// Captured LCPs, concatenated: `m` holds the row-major `M` of each problem
/// one after the other (n_i² values), `q`, `z`, `w` n_i values each.
#[derive(Default)]
pub struct Captured {
    pub m: Vec<f64>,
    pub q: Vec<f64>,
    pub z: Vec<f64>,
    pub w: Vec<f64>,
    pub n: Vec<i64>,
    pub step: Vec<i64>,
    /// Island of the step (0, 1, …) each LCP belongs to.
    pub island: Vec<i64>,
    pub time: Vec<f64>,
    pub contacts: Vec<i64>,
    pub friction_dirs: Vec<i64>,
    pub scale: Vec<f64>,
    /// Index into `lcp::Status::ALL`.
    pub status: Vec<i8>,
    pub pivots: Vec<i64>,
    pub method: Vec<&'static str>,
}

impl Captured {
    /// Memory held (bytes), to decide when to drain.
    pub fn bytes(&self) -> usize {
        8 * (self.m.len() + self.q.len() + self.z.len() + self.w.len()) + 73 * self.n.len()
    }

    pub fn len(&self) -> usize {
        self.n.len()
    }
}

/// Index of a status in `Status::ALL` (the order of `_core.STATUSES`).
pub fn status_code(s: Status) -> i8 {
    Status::ALL.iter().position(|x| *x == s).map_or(-1, |i| i as i8)
}

/// The shared buffer, one clone in the world's sink and one in the Python object.
#[derive(Clone, Default)]
pub struct CaptureBuffer(Arc<Mutex<Captured>>);

impl CaptureBuffer {
    pub fn lock(&self) -> MutexGuard<'_, Captured> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Takes everything captured so far as a dict of numpy arrays.
    pub fn drain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = std::mem::take(&mut *self.lock());
        let d = PyDict::new(py);
        d.set_item("M", PyArray1::from_vec(py, c.m))?;
        d.set_item("q", PyArray1::from_vec(py, c.q))?;
        d.set_item("z", PyArray1::from_vec(py, c.z))?;
        d.set_item("w", PyArray1::from_vec(py, c.w))?;
        d.set_item("n", PyArray1::from_vec(py, c.n))?;
        d.set_item("step", PyArray1::from_vec(py, c.step))?;
        d.set_item("island", PyArray1::from_vec(py, c.island))?;
        d.set_item("time", PyArray1::from_vec(py, c.time))?;
        d.set_item("contacts", PyArray1::from_vec(py, c.contacts))?;
        d.set_item("friction_dirs", PyArray1::from_vec(py, c.friction_dirs))?;
        d.set_item("scale", PyArray1::from_vec(py, c.scale))?;
        d.set_item("status", PyArray1::from_vec(py, c.status))?;
        d.set_item("pivots", PyArray1::from_vec(py, c.pivots))?;
        d.set_item("method", c.method)?;
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
        let Captured { z, w, .. } = &mut *c;
        for (dst, src) in [(z, l.z), (w, l.w)] {
            let k = src.len().min(n);
            dst.extend_from_slice(&src[..k]);
            dst.resize(dst.len() + (n - k), f64::NAN);
        }
        c.n.push(l.n() as i64);
        c.step.push(l.step as i64);
        c.island.push(l.island as i64);
        c.time.push(l.time);
        c.contacts.push(l.contacts as i64);
        c.friction_dirs.push(l.friction_dirs as i64);
        c.scale.push(l.scale);
        c.status.push(status_code(l.status));
        c.pivots.push(l.pivots as i64);
        c.method.push(l.method);
    }
}
