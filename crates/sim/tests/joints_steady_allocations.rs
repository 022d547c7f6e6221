//! Heap allocations of the gripper's held steps (`examples/joint_scenes.rs`,
//! `benchmarks/joints.py`), counted by this test binary's own global
//! allocator (its own file and one test, so nothing else lands in the
//! counter). A held step answered by its previous basis reuses every buffer
//! of the last one: the joints' rows and factor, the island's coupling `Y`,
//! the coupled operator's buffers, the last answer's vectors.

use sim::math::Vec3;
use sim::solve_chain::stage_name::SolveStage;
use sim::{BodyDesc, JointDesc, JointKind, World, WorldParams};
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

fn joint(kind: JointKind, a: Option<usize>, b: usize, anchor: Vec3, axis: Vec3) -> JointDesc {
    JointDesc { kind, body_a: a, body_b: b, anchor, axis, limits: None }
}

/// The palm on a vertical slider, two fingers on 20 N motor sliders with
/// torsion pads closing on a 1 kg cube; the palm held still (its motor at 0).
fn gripper() -> World {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(1.0).unwrap();
    w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 1.0).unwrap();
    let palm = BodyDesc::cuboid(Vec3::new(0.15, 0.05, 0.02)).mass(1.0).position(Vec3::new(0.0, 0.0, 0.2)).mu(1.0);
    let palm = w.add_body(palm).unwrap().0;
    let lift = w.add_joint(joint(JointKind::Slider, None, palm, Vec3::new(0.0, 0.0, 0.2), Vec3::Z)).unwrap();
    w.set_motor(lift, 0.0, 200.0).unwrap();
    for x in [-0.1, 0.1] {
        let finger = w.add_box(Vec3::new(0.01, 0.04, 0.08), 0.2, Vec3::new(x, 0.0, 0.1), 1.0).unwrap();
        w.set_torsional_friction(finger, 0.02).unwrap();
        let j =
            w.add_joint(joint(JointKind::Slider, Some(palm), finger.0, Vec3::new(x, 0.0, 0.1), -Vec3::X * x.signum()));
        w.set_motor(j.unwrap(), 0.1, 20.0).unwrap();
    }
    w
}

#[test]
fn a_held_gripper_step_allocates_nothing() {
    let mut w = gripper();
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
    let mut stages = Vec::new();
    let mut count = |name: &'static str, f: &mut dyn FnMut()| {
        let before = ALLOCATIONS.load(Relaxed);
        f();
        stages.push((name, ALLOCATIONS.load(Relaxed) - before));
    };
    count("forces", &mut || w.forces_stage().unwrap());
    count("detect", &mut || w.detect());
    count("islands", &mut || w.islands());
    count("assemble", &mut || w.assemble_for_solve().unwrap());
    count("solve", &mut || w.solve(None).unwrap());
    count("integrate", &mut || w.integrate());
    assert!(held > 490, "the held gripper's steps keep their basis ({held} of 500)");
    assert_eq!(allocating, 0, "held steps that allocated, of {held} (by stage: {stages:?})");
    assert!(stages.iter().all(|&(_, n)| n == 0), "allocations by stage: {stages:?}");
}
