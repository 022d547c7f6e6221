//! Large islands' structured LCPs saved to files and solved again, to work on
//! the hard steps of a run (a forming heap's, minutes into it) in seconds.
//!
//! With the environment variable `LCPSIM_DUMP_DIR` set, every island solved
//! by the structured Lemke ([`super::structured_lemke`]) is written there as
//! `lcp_NNNNN_nN.bin` (a counter over the process's structured solves) before
//! it is solved: its sparse factors, `q`, cone scale, layout, acceptance
//! tolerance and the warm basis it was handed. [`StructuredProblem::read`]
//! loads one; [`StructuredProblem::solve`] (in `structured_lemke`) solves it as the step does.
//! Nothing is written, and nothing costs, without the variable.
//! [`set_dump_dir`] sets or clears the directory while a run goes on (to save
//! a few steps of a long run).

use lcp::contact::ContactLayout;
use lcp::structured::{Entry, StructuredLcp};
use std::io::{self, Read, Write};
use std::path::Path;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{OnceLock, RwLock};

/// A large island's LCP as the structured path sees it.
#[derive(Clone, Debug)]
pub struct StructuredProblem {
    /// The LCP at the cone scale `scale` (the one solved).
    pub op: StructuredLcp,
    /// The same at scale 1 (the physical one), when `scale ≠ 1`.
    pub physical: Option<StructuredLcp>,
    pub scale: f64,
    pub layout: ContactLayout,
    /// The warm basis handed over (with the sliding contacts' friction set), if any.
    pub warm: Option<Vec<bool>>,
    /// Acceptance tolerance.
    pub tol: f64,
}

const MAGIC: &[u8; 8] = b"LCPSTR01";

impl StructuredProblem {
    /// Writes it to `path` (binary, little-endian).
    pub fn write(&self, path: &Path) -> io::Result<()> {
        let (p, g, h, k) = lcp::structured::parts(&self.op);
        let mut b = Vec::new();
        b.extend_from_slice(MAGIC);
        for v in [self.op.n(), p, self.layout.nc, self.layout.k, g.len(), h.len(), k.len()] {
            b.extend_from_slice(&(v as u64).to_le_bytes());
        }
        for v in [self.scale, self.tol] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for e in [&g, &h, &k] {
            for &(r, c, v) in e.iter() {
                b.extend_from_slice(&(r as u32).to_le_bytes());
                b.extend_from_slice(&(c as u32).to_le_bytes());
                b.extend_from_slice(&v.to_le_bytes());
            }
        }
        self.op.q().iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        b.push(self.warm.is_some() as u8);
        if let Some(w) = &self.warm {
            b.extend(w.iter().map(|&x| x as u8));
        }
        std::fs::File::create(path)?.write_all(&b)
    }

    /// Reads a problem written by [`StructuredProblem::write`].
    pub fn read(path: &Path) -> io::Result<Self> {
        let mut b = Vec::new();
        std::fs::File::open(path)?.read_to_end(&mut b)?;
        let bad = |m: &str| io::Error::new(io::ErrorKind::InvalidData, m.to_string());
        if b.get(..8) != Some(&MAGIC[..]) {
            return Err(bad("not a structured LCP file"));
        }
        let mut at = 8;
        let mut take = |len: usize| -> io::Result<&[u8]> {
            let s = b.get(at..at + len).ok_or_else(|| bad("truncated"))?;
            at += len;
            Ok(s)
        };
        let mut u64s = [0usize; 7];
        for v in u64s.iter_mut() {
            *v = u64::from_le_bytes(take(8)?.try_into().expect("8 bytes")) as usize;
        }
        let [n, p, nc, kd, ng, nh, nk] = u64s;
        let f64_of = |s: &[u8]| f64::from_le_bytes(s.try_into().expect("8 bytes"));
        let scale = f64_of(take(8)?);
        let tol = f64_of(take(8)?);
        let mut entries = |len: usize| -> io::Result<Vec<Entry>> {
            let s = take(16 * len)?;
            Ok(s.chunks_exact(16)
                .map(|e| {
                    let r = u32::from_le_bytes(e[0..4].try_into().expect("4 bytes")) as usize;
                    let c = u32::from_le_bytes(e[4..8].try_into().expect("4 bytes")) as usize;
                    (r, c, f64_of(&e[8..16]))
                })
                .collect())
        };
        let (g, h, k) = (entries(ng)?, entries(nh)?, entries(nk)?);
        let q: Vec<f64> = take(8 * n)?.chunks_exact(8).map(f64_of).collect();
        let warm = match take(1)?[0] {
            0 => None,
            _ => Some(take(n)?.iter().map(|&x| x != 0).collect()),
        };
        let layout = ContactLayout::new(nc, kd);
        if layout.n() != n {
            return Err(bad("layout and n disagree"));
        }
        let invalid = |e: lcp::LcpError| bad(&e.to_string());
        let op = StructuredLcp::new(p, &g, &h, &k, q.clone()).map_err(invalid)?;
        let physical = if scale != 1.0 {
            let k1: Vec<Entry> = k.iter().map(|&(r, c, v)| (r, c, v / scale)).collect();
            Some(StructuredLcp::new(p, &g, &h, &k1, q).map_err(invalid)?)
        } else {
            None
        };
        Ok(StructuredProblem { op, physical, scale, layout, warm, tol })
    }
}

/// The dump directory: `LCPSIM_DUMP_DIR` until [`set_dump_dir`] changes it.
fn dump_dir() -> &'static RwLock<Option<PathBuf>> {
    static DIR: OnceLock<RwLock<Option<PathBuf>>> = OnceLock::new();
    DIR.get_or_init(|| RwLock::new(std::env::var_os("LCPSIM_DUMP_DIR").map(Into::into)))
}

/// Islands solved from now on are written to `dir` (`None`: not written).
pub fn set_dump_dir(dir: Option<PathBuf>) {
    *dump_dir().write().unwrap_or_else(|e| e.into_inner()) = dir;
}

/// Writes `problem` to the dump directory when one is set (module docs).
pub(crate) fn dump(problem: &StructuredProblem) {
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let guard = dump_dir().read().unwrap_or_else(|e| e.into_inner());
    let Some(dir) = guard.as_deref() else { return };
    let i = COUNT.fetch_add(1, Ordering::Relaxed);
    let path = dir.join(format!("lcp_{i:05}_n{}.bin", problem.op.n()));
    if let Err(e) = problem.write(&path) {
        eprintln!("LCPSIM_DUMP_DIR: {}: {e}", path.display());
    }
}
