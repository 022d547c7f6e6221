//! Sizes checked before allocating: what a request needs, refused with a
//! [`SizeError`] that says how much memory, instead of an allocation that
//! aborts the process.
//!
//! A size that comes from a user or a file (an LCP size, a count of contacts or
//! friction directions, a generator's `n`) is checked with [`check_bytes`]
//! before anything is allocated: a request larger than the machine's physical
//! memory can never succeed, so it is refused up front. The large buffers are
//! then reserved with [`try_reserve`] (`Vec::try_reserve_exact`), so that an
//! allocation the system refuses is an error, not an abort.

use std::fmt;

/// Bytes of one `f64`.
pub const F64_BYTES: u128 = 8;

/// A request refused because of its size.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SizeError {
    /// What was asked for, e.g. "a contact LCP of n = 4000000 unknowns".
    pub what: String,
    /// Bytes it needs (saturated at `u128::MAX` when the size itself overflows).
    pub bytes: u128,
    /// The limit it exceeds (the machine's physical memory), when known; `None`
    /// when the allocator refused it.
    pub limit: Option<u128>,
}

impl fmt::Display for SizeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} needs {}", self.what, human_bytes(self.bytes))?;
        match self.limit {
            Some(l) => write!(f, ", more than this machine's {} of memory", human_bytes(l)),
            None => write!(f, "; the allocation failed (out of memory)"),
        }
    }
}

impl std::error::Error for SizeError {}

/// `8·n²·copies`: the bytes of `copies` dense `n × n` float64 matrices (saturating).
pub fn dense_bytes(n: usize, copies: u32) -> u128 {
    let n = n as u128;
    n.checked_mul(n).and_then(|v| v.checked_mul(F64_BYTES * copies as u128)).unwrap_or(u128::MAX)
}

/// A byte count for people: `1.5 GiB`, `116 TiB`, `800 B`.
pub fn human_bytes(bytes: u128) -> String {
    if bytes == u128::MAX {
        return "more bytes than any machine can address".to_string();
    }
    const UNITS: [&str; 9] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB", "ZiB", "YiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{} {}", three_digits(v), UNITS[u])
    }
}

/// `v` with three significant digits (`7.28`, `116`, `1.5e6` past the last unit).
fn three_digits(v: f64) -> String {
    if v >= 1e4 {
        format!("{v:.2e}")
    } else if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// The machine's physical memory in bytes (Linux: `MemTotal` of
/// `/proc/meminfo`); `None` where it cannot be read. Read once per process:
/// the simulator checks sizes on every step of every island, and reading the
/// file each time was 14 % of a 1,000-body step.
pub fn physical_memory() -> Option<u128> {
    static MEM: std::sync::OnceLock<Option<u128>> = std::sync::OnceLock::new();
    *MEM.get_or_init(read_physical_memory)
}

fn read_physical_memory() -> Option<u128> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u128 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses `bytes` for `what` if it exceeds the physical memory (or `isize::MAX`,
/// the most one allocation can hold).
pub fn check_bytes(what: impl FnOnce() -> String, bytes: u128) -> Result<(), SizeError> {
    let limit = physical_memory().unwrap_or(isize::MAX as u128).min(isize::MAX as u128);
    if bytes > limit {
        return Err(SizeError { what: what(), bytes, limit: Some(limit) });
    }
    Ok(())
}

/// Refuses a dense LCP of size `n` whose `copies` matrices would not fit.
pub fn check_dense(what: impl FnOnce() -> String, n: usize, copies: u32) -> Result<(), SizeError> {
    check_bytes(what, dense_bytes(n, copies))
}

/// Makes room for `len` elements in `v` (its length becomes at most `len`
/// without reallocating), or says how much memory that needed.
pub fn try_reserve<T>(v: &mut Vec<T>, len: usize, what: impl FnOnce() -> String) -> Result<(), SizeError> {
    let extra = len.saturating_sub(v.len());
    v.try_reserve_exact(extra).map_err(|_| SizeError {
        what: what(),
        bytes: (len as u128).saturating_mul(std::mem::size_of::<T>() as u128),
        limit: None,
    })
}
