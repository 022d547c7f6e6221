//! The system allocator, counting allocations and reallocations: a test
//! binary that declares it its `#[global_allocator]` counts its own heap
//! allocations (`steady_step_allocations.rs`, `joints_steady_allocations.rs`).

use sim::World;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

pub struct Counting;

/// Allocations and reallocations so far.
pub static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded unchanged to the system allocator.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Allocations of one step of `w` taken stage by stage (the stages `step`
/// runs, as `examples/step_budget.rs` times them): where a count comes from.
pub fn by_stage(w: &mut World) -> Vec<(&'static str, usize)> {
    let mut out = Vec::new();
    let mut count = |name: &'static str, f: &mut dyn FnMut()| {
        let before = ALLOCATIONS.load(Relaxed);
        f();
        out.push((name, ALLOCATIONS.load(Relaxed) - before));
    };
    count("forces", &mut || w.forces_stage().unwrap());
    count("detect", &mut || w.detect());
    count("islands", &mut || w.islands());
    count("assemble", &mut || w.assemble_for_solve().unwrap());
    count("solve", &mut || w.solve(None).unwrap());
    count("integrate", &mut || w.integrate());
    out
}
