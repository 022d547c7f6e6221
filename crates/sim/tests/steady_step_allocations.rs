//! Heap allocations of a steady step, counted by this test binary's own
//! global allocator (its own file, so no other test shares the counter).
//!
//! A resting scene's step after warm-up reuses every buffer of the last one
//! (island pool, solver workspaces, record, the body-space operator's
//! buffers): what it allocates is a cost paid on every step of every run.

use sim::scenes::{BoxStack, CubeOnSlope, Scene};
use sim::WorldParams;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

/// The system allocator, counting allocations and reallocations.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

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

#[global_allocator]
static COUNTING: Counting = Counting;

/// Allocations per step over `steps` steps of `s`, after `warm` steps; also
/// the largest speed of any body at the end (the scene must be at rest).
fn allocations_per_step(s: &mut Scene, warm: usize, steps: usize) -> (f64, f64) {
    for _ in 0..warm {
        s.world.step().unwrap();
    }
    let before = ALLOCATIONS.load(Relaxed);
    for _ in 0..steps {
        let r = s.world.step().unwrap();
        assert!(r.ok(), "every step solved");
    }
    let per_step = (ALLOCATIONS.load(Relaxed) - before) as f64 / steps as f64;
    let speed = s.world.bodies().iter().map(|b| b.velocity().norm()).fold(0.0, f64::max);
    (per_step, speed)
}

/// Allocations of one step taken stage by stage (the stages `step` runs,
/// as `examples/step_budget.rs` times them): where a count comes from.
fn by_stage(s: &mut Scene) -> Vec<(&'static str, usize)> {
    let w = &mut s.world;
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

/// What the solve of a steady island still allocates: the vectors of the
/// answer `lcp::on_basis` returns (`z` and `w` moved out of its workspace,
/// which grows new ones on the next call, and a copy of the basis), which
/// the island keeps as its answer and the next step's warm start. Every
/// other stage allocates nothing.
const SOLVE_ALLOCATIONS: usize = 4;

/// One test, so that no other test's allocations land in the counter.
#[test]
fn a_steady_step_allocates_only_its_lcp_answer() {
    let mut cube = CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap();
    let (per_cube, v) = allocations_per_step(&mut cube, 200, 500);
    assert!(v < 1e-6, "the cube rests on the 30° slope at μ 0.7 (speed {v:e} m/s)");
    let mut stack = BoxStack::new(10).build(WorldParams::default()).unwrap();
    let (per_stack, v) = allocations_per_step(&mut stack, 200, 500);
    assert!(v < 1e-6, "the 10-box stack rests (speed {v:e} m/s)");
    let (cube_stages, stack_stages) = (by_stage(&mut cube), by_stage(&mut stack));
    println!("allocations per steady step: cube {per_cube} {cube_stages:?}, stack {per_stack} {stack_stages:?}");
    for (name, n) in cube_stages.iter().chain(&stack_stages) {
        let expected = if *name == "solve" { SOLVE_ALLOCATIONS } else { 0 };
        assert_eq!(*n, expected, "allocations of stage {name} ({cube_stages:?}, {stack_stages:?})");
    }
    assert_eq!(per_cube, SOLVE_ALLOCATIONS as f64, "resting cube: allocations per step");
    // (The stack's few steps that pivot allocate Lemke's answer besides.)
    assert!(per_stack < SOLVE_ALLOCATIONS as f64 + 0.5, "resting 10-box stack: {per_stack} allocations per step");
}
