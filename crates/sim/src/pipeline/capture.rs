//! LCP capture: every solved LCP can be handed to a sink (e.g. the Python
//! layer streaming them to HDF5). Nothing is copied when no sink is set.

use lcp::Status;
use std::sync::{Arc, Mutex};

/// One solved LCP with its arrays of type `D`: borrowed slices in
/// [`CapturedLcp`] (for the duration of the `capture` call), owned vectors in
/// [`OwnedLcp`]. `m`, `q`, `z`, `w` are the *scaled* problem (`D M D, D q`
/// with `D = diag(I, I, s·I)`) and the answer the world applied, as the
/// solver returned it; the physical answer is in the step record. An island
/// a body-space stage answered never formed `M`: it is formed for the sink
/// after the solve, so a captured run steps exactly as an uncaptured one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Captured<D> {
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
    pub m: D,
    pub q: D,
    /// The solver's `z` and `w` (length n).
    pub z: D,
    pub w: D,
    pub status: Status,
    pub pivots: usize,
    /// Solver name (`lcp::Method::name`, or "custom" for `step_with`).
    pub method: &'static str,
}

/// A solved LCP as the sink sees it (arrays borrowed).
pub type CapturedLcp<'a> = Captured<&'a [f64]>;
/// An owned [`CapturedLcp`].
pub type OwnedLcp = Captured<Vec<f64>>;

impl<D: AsRef<[f64]>> Captured<D> {
    /// Problem size.
    pub fn n(&self) -> usize {
        self.q.as_ref().len()
    }

    /// The same record with each array mapped by `f` (e.g. `to_vec`).
    pub fn map<E>(&self, f: impl Fn(&[f64]) -> E) -> Captured<E> {
        Captured {
            step: self.step,
            time: self.time,
            island: self.island,
            contacts: self.contacts,
            friction_dirs: self.friction_dirs,
            scale: self.scale,
            m: f(self.m.as_ref()),
            q: f(self.q.as_ref()),
            z: f(self.z.as_ref()),
            w: f(self.w.as_ref()),
            status: self.status,
            pivots: self.pivots,
            method: self.method,
        }
    }
}

impl CapturedLcp<'_> {
    /// An owned copy.
    pub fn to_owned(&self) -> OwnedLcp {
        self.map(<[f64]>::to_vec)
    }
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
