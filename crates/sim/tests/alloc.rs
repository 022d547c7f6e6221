//! The simulator's own stages do not allocate once their buffers are warm
//! (the LCP solver's answer is the solver's business).

use sim::scenes::{BoxStack, CubeOnSlope};
use sim::WorldParams;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn warm_stages_do_not_allocate() {
    for mut scene in [CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap(), BoxStack::new(3).build(WorldParams::default()).unwrap()] {
        let w = &mut scene.world;
        for _ in 0..3 {
            w.step().unwrap();
        }
        let before = ALLOCS.load(Ordering::Relaxed);
        for _ in 0..10 {
            w.forces_stage().unwrap();
            w.detect();
            w.assemble();
            w.integrate();
        }
        assert_eq!(ALLOCS.load(Ordering::Relaxed) - before, 0);
    }
}
