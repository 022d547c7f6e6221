//! LCP capture: every solved LCP can be handed to a sink (e.g. the Python
//! layer streaming them to HDF5). Nothing is copied when no sink is set.

use lcp::Status;
use std::sync::{Arc, Mutex};

/// One solved LCP, borrowed for the duration of the `capture` call.
/// `m`, `q`, `z`, `w` are exactly what the solver saw and returned — the
/// *scaled* problem (`D M D, D q` with `D = diag(I, I, s·I)`); the physical
/// answer is in the step record.
#[derive(Clone, Copy, Debug)]
pub struct CapturedLcp<'a> {
    /// Step index and time at its start (s).
    pub step: u64,
    pub time: f64,
    /// Island of the step this LCP belongs to (0 for the first; see `StepRecord::islands`).
    pub island: usize,
    /// Contacts and friction directions: `n = contacts·(friction_dirs + 2)`.
    pub contacts: usize,
    pub friction_dirs: usize,
    /// Friction-cone scale `s`.
    pub scale: f64,
    /// Row-major `M` (n·n) and `q` (n).
    pub m: &'a [f64],
    pub q: &'a [f64],
    /// The solver's `z` and `w` (length n).
    pub z: &'a [f64],
    pub w: &'a [f64],
    pub status: Status,
    pub pivots: usize,
    /// Solver name (`lcp::Method::name`, or "custom" for `step_with`).
    pub method: &'static str,
}

impl CapturedLcp<'_> {
    /// Problem size.
    pub fn n(&self) -> usize {
        self.q.len()
    }

    /// An owned copy.
    pub fn to_owned(&self) -> OwnedLcp {
        OwnedLcp {
            step: self.step,
            time: self.time,
            island: self.island,
            contacts: self.contacts,
            friction_dirs: self.friction_dirs,
            scale: self.scale,
            m: self.m.to_vec(),
            q: self.q.to_vec(),
            z: self.z.to_vec(),
            w: self.w.to_vec(),
            status: self.status,
            pivots: self.pivots,
            method: self.method,
        }
    }
}

/// An owned [`CapturedLcp`].
#[derive(Clone, Debug, PartialEq)]
pub struct OwnedLcp {
    pub step: u64,
    pub time: f64,
    pub island: usize,
    pub contacts: usize,
    pub friction_dirs: usize,
    pub scale: f64,
    pub m: Vec<f64>,
    pub q: Vec<f64>,
    pub z: Vec<f64>,
    pub w: Vec<f64>,
    pub status: Status,
    pub pivots: usize,
    pub method: &'static str,
}

/// Receives every LCP the world solves. `Send` so a world can move between threads.
pub trait LcpSink: Send {
    fn capture(&mut self, lcp: &CapturedLcp<'_>);
}

impl<F: FnMut(&CapturedLcp<'_>) + Send> LcpSink for F {
    fn capture(&mut self, lcp: &CapturedLcp<'_>) {
        self(lcp)
    }
}

/// A sink that keeps owned copies in a shared buffer; clone it, give one
/// clone to the world and `drain` the other (e.g. every N steps, to stream).
#[derive(Clone, Debug, Default)]
pub struct LcpBuffer {
    inner: Arc<Mutex<Vec<OwnedLcp>>>,
}

impl LcpBuffer {
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes everything captured so far.
    pub fn drain(&self) -> Vec<OwnedLcp> {
        std::mem::take(&mut *self.inner.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Number of LCPs waiting.
    pub fn len(&self) -> usize {
        self.inner.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl LcpSink for LcpBuffer {
    fn capture(&mut self, lcp: &CapturedLcp<'_>) {
        self.inner.lock().unwrap_or_else(|e| e.into_inner()).push(lcp.to_owned());
    }
}
