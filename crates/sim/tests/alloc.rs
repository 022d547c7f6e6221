//! The simulator's own stages do not allocate once their buffers are warm
//! (the LCP solver's answer is the solver's business). Only the test
//! thread's allocations count: libtest's main thread allocates now and then
//! while it waits (4 allocations seen under load, a spurious failure).

use sim::scenes::{BoxStack, CubeOnSlope};
use sim::WorldParams;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    /// Allocations made by this thread (a const-initialized `Cell`: reading
    /// it never allocates, so the allocator may use it).
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    ALLOCS.with(|a| a.set(a.get() + 1));
}

fn allocs() -> usize {
    ALLOCS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn warm_stages_do_not_allocate() {
    for mut scene in [
        CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap(),
        BoxStack::new(3).build(WorldParams::default()).unwrap(),
    ] {
        let w = &mut scene.world;
        for _ in 0..3 {
            w.step().unwrap();
        }
        let before = allocs();
        for _ in 0..10 {
            w.forces_stage().unwrap();
            w.detect();
            w.assemble();
            w.integrate();
        }
        assert_eq!(allocs() - before, 0);
    }
}
