//! Per-thread reuse of the buffers of a Lemke solve.
//!
//! A small solve (n = 40, ~10 µs) allocates some twenty buffers: the
//! equilibrated copy of `M` and the Ruiz exponents, `C⁻¹` and the basic
//! columns `G[:, S]` (a few KiB to tens of KiB each), and a dozen vectors of
//! length n. glibc serves the large ones from its large bins after
//! consolidating its fast bins, keeps only seven chunks per size in its
//! thread cache and takes `calloc` past that cache: together ~8 % of the solve
//! (profile_contact with mimalloc instead: −0.8 µs). The solver's structures
//! hand their buffers back here when dropped and take them at the next solve.
//! Only buffers up to [`KEEP_MAX`] elements are kept, at most [`KEEP_COUNT`]
//! per type and thread, so an occasional large problem does not pin memory.

use std::cell::RefCell;

/// Largest buffer kept (elements): `M` of n = 128, far past where
/// allocation matters against the O(n³) work.
pub(crate) const KEEP_MAX: usize = 1 << 14;

/// Buffers kept per element type and thread (a solve holds up to ten f64
/// buffers at once).
pub(crate) const KEEP_COUNT: usize = 16;

thread_local! {
    static F64: RefCell<Vec<Vec<f64>>> = const { RefCell::new(Vec::new()) };
    static I16: RefCell<Vec<Vec<i16>>> = const { RefCell::new(Vec::new()) };
    static USIZE: RefCell<Vec<Vec<usize>>> = const { RefCell::new(Vec::new()) };
}

/// Element types with a per-thread pool.
pub(crate) trait Recycled: Sized + 'static {
    fn with_pool<R>(f: impl FnOnce(&mut Vec<Vec<Self>>) -> R) -> R;
}

impl Recycled for f64 {
    fn with_pool<R>(f: impl FnOnce(&mut Vec<Vec<f64>>) -> R) -> R {
        F64.with(|p| f(&mut p.borrow_mut()))
    }
}

impl Recycled for i16 {
    fn with_pool<R>(f: impl FnOnce(&mut Vec<Vec<i16>>) -> R) -> R {
        I16.with(|p| f(&mut p.borrow_mut()))
    }
}

impl Recycled for usize {
    fn with_pool<R>(f: impl FnOnce(&mut Vec<Vec<usize>>) -> R) -> R {
        USIZE.with(|p| f(&mut p.borrow_mut()))
    }
}

/// An empty vector with capacity at least `cap`: a kept one if there is one
/// large enough, else a new one.
pub(crate) fn take<T: Recycled>(cap: usize) -> Vec<T> {
    if cap > KEEP_MAX {
        return Vec::with_capacity(cap);
    }
    let kept = T::with_pool(|pool| pool.iter().position(|v| v.capacity() >= cap).map(|k| pool.swap_remove(k)));
    kept.unwrap_or_else(|| Vec::with_capacity(cap))
}

/// `len` copies of `value` in a [`take`]n vector.
pub(crate) fn filled<T: Recycled + Clone>(len: usize, value: T) -> Vec<T> {
    let mut v = take(len);
    v.resize(len, value);
    v
}

/// Hands `v` back for a later [`take`] on this thread (or frees it).
pub(crate) fn give<T: Recycled>(mut v: Vec<T>) {
    if v.capacity() == 0 || v.capacity() > KEEP_MAX {
        return;
    }
    v.clear();
    T::with_pool(|pool| {
        if pool.len() < KEEP_COUNT {
            pool.push(v);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_buffer_is_taken_again_empty() {
        let mut v: Vec<f64> = take(100);
        v.extend([1.0, 2.0]);
        let ptr = v.as_ptr();
        give(v);
        let w: Vec<f64> = take(50);
        assert!(w.is_empty() && w.capacity() >= 100);
        assert_eq!(w.as_ptr(), ptr);
        // Too small for the request: a new buffer.
        give(w);
        let big: Vec<f64> = take(1000);
        assert!(big.capacity() >= 1000);
        assert_ne!(big.as_ptr(), ptr);
    }

    #[test]
    fn large_buffers_are_not_kept() {
        let v: Vec<i16> = Vec::with_capacity(KEEP_MAX + 1);
        give(v);
        I16.with(|p| assert!(p.borrow().iter().all(|v| v.capacity() <= KEEP_MAX)));
    }
}
