//! The step starts Lemke from the previous step's basis. Median
//! pivots per step must at least halve on resting and sliding scenes, and
//! every step must still be solved.

use lcp::{LemkeOptions, Method, Status};
use sim::scenes::{BoxStack, CubeOnSlope, Scene};
use sim::WorldParams;

fn median(mut v: Vec<usize>) -> usize {
    v.sort_unstable();
    v[v.len() / 2]
}

/// Pivots per step over `steps` steps (skipping the first, which has no history).
fn pivots(build: &dyn Fn(WorldParams) -> Scene, warm: bool, steps: usize) -> Vec<usize> {
    let method = Method::Lemke(LemkeOptions { warm_start: warm, ..Default::default() });
    let mut s = build(WorldParams { method, ..Default::default() });
    (0..steps)
        .filter_map(|i| {
            let r = s.world.step().unwrap();
            assert_eq!(r.status, Some(Status::Solved), "step {i}");
            (i > 0).then_some(r.pivots)
        })
        .collect()
}

/// Median pivots per step, cold and warm.
fn compare(name: &str, build: &dyn Fn(WorldParams) -> Scene, steps: usize) -> (usize, usize) {
    let cold = median(pivots(build, false, steps));
    let warm = median(pivots(build, true, steps));
    println!("{name}: median pivots per step cold {cold}, warm {warm}");
    (cold, warm)
}

fn check(name: &str, build: &dyn Fn(WorldParams) -> Scene, steps: usize) {
    let (cold, warm) = compare(name, build, steps);
    assert!(2 * warm <= cold, "{name}: warm {warm} vs cold {cold}");
}

#[test]
fn warm_start_halves_pivots_resting_and_sliding() {
    check("resting cube", &|p| CubeOnSlope::new(0.0, 0.5).build(p).unwrap(), 300);
    check("sticking on 20°", &|p| CubeOnSlope::new(20.0, 0.5).build(p).unwrap(), 300);
    check("sliding on 30°", &|p| CubeOnSlope::new(30.0, 0.3).build(p).unwrap(), 300);
    check("sliding at 45.2°", &|p| CubeOnSlope::new(45.2, 1.0).build(p).unwrap(), 300);
}

/// Stacks gain less: once the loads settle, the previous basis often no
/// longer fits and the cold ladder runs after the warm attempt (measured:
/// median 101 pivots cold, 59 warm for 5 boxes). Warm must still not cost more.
#[test]
fn warm_start_does_not_cost_more_on_stacks() {
    let (cold, warm) = compare("stack of 5", &|p| BoxStack::new(5).build(p).unwrap(), 100);
    assert!(warm <= cold, "stack: warm {warm} vs cold {cold}");
}
