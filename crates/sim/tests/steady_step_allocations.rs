//! Heap allocations of a steady step, counted by this test binary's own
//! global allocator (its own file, so no other test shares the counter).
//!
//! A resting scene's step after warm-up reuses every buffer of the last one
//! (island pool, solver workspaces, record, the body-space operator's
//! buffers, and the last answer's vectors, handed back to `lcp::on_basis`
//! for the next answer's): what it allocates is a cost paid on every step
//! of every run.

use sim::scenes::{BoxStack, CubeOnSlope, Scene};
use sim::solve_chain::stage_name::SolveStage;
use sim::WorldParams;
use std::sync::atomic::Ordering::Relaxed;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{by_stage, Counting, ALLOCATIONS};

#[global_allocator]
static COUNTING: Counting = Counting;

/// Over `steps` steps of `s`, after `warm` steps: of the steps whose
/// islands all kept their previous basis at 0 pivots (the steady steps), how
/// many allocated and how many there were, and the largest speed of any
/// body at the end (the scene must be at rest).
fn steady_allocations(s: &mut Scene, warm: usize, steps: usize) -> (usize, usize, f64) {
    for _ in 0..warm {
        s.world.step().unwrap();
    }
    let (mut allocating, mut steady) = (0, 0);
    for _ in 0..steps {
        let before = ALLOCATIONS.load(Relaxed);
        let r = s.world.step().unwrap();
        let after = ALLOCATIONS.load(Relaxed);
        assert!(r.ok(), "every step solved");
        if r.islands.iter().all(|i| i.pivots == 0 && i.stage == Some(SolveStage::PreviousBasis)) {
            allocating += usize::from(after > before);
            steady += 1;
        }
    }
    let speed = s.world.bodies().iter().map(|b| b.velocity().norm()).fold(0.0, f64::max);
    (allocating, steady, speed)
}

/// One test, so that no other test's allocations land in the counter.
/// (A step that pivots allocates Lemke's answer: the stack's few such steps
/// are left out. A steady step whose exchange rounds meet a basic block
/// larger than any before grows their buffers, once per such size: on this
/// stack 2 of its 995 steady steps from step 3,000.)
#[test]
fn a_steady_step_allocates_nothing() {
    let mut cube = CubeOnSlope::new(30.0, 0.7).build(WorldParams::default()).unwrap();
    let (per_cube, steady_cube, v) = steady_allocations(&mut cube, 200, 500);
    assert!(v < 1e-6, "the cube rests on the 30° slope at μ 0.7 (speed {v:e} m/s)");
    let mut stack = BoxStack::new(10).build(WorldParams::default()).unwrap();
    let (per_stack, steady_stack, v) = steady_allocations(&mut stack, 3000, 1000);
    assert!(v < 1e-6, "the 10-box stack rests (speed {v:e} m/s)");
    let (cube_stages, stack_stages) = (by_stage(&mut cube.world), by_stage(&mut stack.world));
    println!(
        "steady steps that allocated: cube {per_cube} of {steady_cube} {cube_stages:?}, \
         stack {per_stack} of {steady_stack} {stack_stages:?}"
    );
    assert_eq!(steady_cube, 500, "every step of the resting cube keeps its basis");
    assert!(steady_stack > 900, "most steps of the resting stack keep their basis ({steady_stack} of 1,000)");
    for (name, n) in cube_stages.iter().chain(&stack_stages) {
        assert_eq!(*n, 0, "allocations of stage {name} ({cube_stages:?}, {stack_stages:?})");
    }
    assert_eq!(per_cube, 0, "resting cube: steps that allocated, of {steady_cube} steady steps");
    assert!(
        per_stack * 100 <= steady_stack,
        "resting 10-box stack: {per_stack} of {steady_stack} steady steps allocated"
    );
}
