//! Helpers shared by the scene tests.
#![allow(dead_code)]

use sim::math::{Quat, Vec3};
use sim::scenes::Scene;
use sim::{BodyId, StepRecord, World};

pub const G: f64 = 9.81;

/// Relative error `|a − b| / |b|`.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Steps once and insists the LCP (if any) was solved.
pub fn step_ok(world: &mut World) -> StepRecord {
    let r = world.step().expect("step").clone();
    assert!(r.ok(), "step {} status {:?} residual {:e}", r.step, r.status, r.residuals.residual);
    r
}

/// Runs `n` steps, all of which must solve; returns the last record.
pub fn run_ok(world: &mut World, n: usize) -> StepRecord {
    let mut last = StepRecord::default();
    for _ in 0..n {
        last = step_ok(world);
    }
    last
}

/// Position and orientation of a body.
pub fn pose(s: &Scene, id: BodyId) -> (Vec3, Quat) {
    let b = s.world.body(id).unwrap();
    (b.position(), b.orientation())
}

/// Sum of the normal impulses of the contacts between `a` and `b` (either order).
pub fn interface_fn(r: &StepRecord, a: usize, b: usize) -> f64 {
    r.contacts
        .iter()
        .enumerate()
        .filter(|(_, c)| (c.body_a == a && c.body_b == b) || (c.body_a == b && c.body_b == a))
        .map(|(i, _)| r.z[i])
        .sum()
}

/// Steps `w` a few times, then assembles the dense LCP of its state.
pub fn settled(mut w: World, steps: usize) -> World {
    for _ in 0..steps {
        w.step().unwrap();
    }
    w.forces_stage().unwrap();
    w.detect();
    w.assemble();
    w
}
