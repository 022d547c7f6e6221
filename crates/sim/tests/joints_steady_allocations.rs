//! Heap allocations of the gripper's held steps (`examples/joint_scenes.rs`,
//! `benchmarks/joints.py`), counted by this test binary's own global
//! allocator (its own file and one test, so nothing else lands in the
//! counter). A held step answered by its previous basis reuses every buffer
//! of the last one: the joints' rows and factor, the island's coupling `Y`,
//! the coupled operator's buffers, the last answer's vectors.

use sim::joints::scenes::gripper;
use sim::solve_chain::stage_name::SolveStage;
use std::sync::atomic::Ordering::Relaxed;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{by_stage, Counting, ALLOCATIONS};

#[global_allocator]
static COUNTING: Counting = Counting;

#[test]
fn a_held_gripper_step_allocates_nothing() {
    let (mut w, lift) = gripper();
    w.set_motor(lift, 0.0, 200.0).unwrap();
    // The fingers close in about 0.6 s; then every step holds.
    for _ in 0..1000 {
        assert!(w.step().unwrap().ok());
    }
    let (mut allocating, mut held) = (0, 0);
    for _ in 0..500 {
        let before = ALLOCATIONS.load(Relaxed);
        let r = w.step().unwrap();
        let after = ALLOCATIONS.load(Relaxed);
        assert!(r.ok(), "every step solved");
        if r.islands.iter().all(|i| i.pivots == 0 && i.stage == Some(SolveStage::PreviousBasis)) {
            allocating += usize::from(after > before);
            held += 1;
        }
    }
    // One more held step taken stage by stage: where a count would come from.
    let stages = by_stage(&mut w);
    assert!(held > 490, "the held gripper's steps keep their basis ({held} of 500)");
    assert_eq!(allocating, 0, "held steps that allocated, of {held} (by stage: {stages:?})");
    assert!(stages.iter().all(|&(_, n)| n == 0), "allocations by stage: {stages:?}");
}
