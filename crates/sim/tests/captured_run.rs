//! A captured run is the uncaptured one: the sink gets every island's LCP
//! with its dense `M` (formed for it when a body-space stage answered), and
//! the answer it records solves that `M`.

use sim::scenes::{BoxStack, CubeOnSlope, Scene};
use sim::{LcpBuffer, SolveStage, WorldParams};

/// `steps` steps of `make()` with a sink and without: the same bits, and
/// what the sink got.
fn both_ways(make: impl Fn() -> Scene, steps: usize) -> (Scene, Vec<sim::OwnedLcp>) {
    let (mut plain, mut captured) = (make(), make());
    let buf = LcpBuffer::new();
    captured.world.set_sink(Box::new(buf.clone()));
    let mut body_space = 0;
    for _ in 0..steps {
        let a = plain.world.step().unwrap().clone();
        let b = captured.world.step().unwrap();
        assert_eq!(&a, b, "step {}: the records differ", a.step);
        body_space += b.islands.iter().filter(|i| i.stage == Some(SolveStage::PreviousBasis)).count();
    }
    assert_eq!(plain.world.bodies(), captured.world.bodies());
    assert!(body_space > steps / 2, "most steps answered in body space ({body_space} of {steps})");
    (captured, buf.drain())
}

/// Every captured answer solves its captured LCP: `w = M z + q` to round-off.
fn answers_solve_their_lcps(lcps: &[sim::OwnedLcp]) {
    for l in lcps {
        let n = l.n();
        assert_eq!(l.m.len(), n * n, "step {}: M captured", l.step);
        let scale = 1.0 + l.q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            let mz: f64 = (0..n).map(|j| l.m[i * n + j] * l.z[j]).sum();
            let w = mz + l.q[i];
            assert!((w - l.w[i]).abs() <= 1e-9 * scale, "step {}, row {i}: Mz + q = {w:e}, w = {:e}", l.step, l.w[i]);
        }
    }
}

#[test]
fn a_sliding_cube_steps_the_same_with_and_without_a_sink() {
    let (_, lcps) = both_ways(|| CubeOnSlope::new(30.0, 0.5).build(WorldParams::default()).unwrap(), 500);
    assert_eq!(lcps.len(), 500, "one LCP a step");
    answers_solve_their_lcps(&lcps);
}

#[test]
fn a_resting_stack_steps_the_same_with_and_without_a_sink() {
    let (_, lcps) = both_ways(|| BoxStack::new(5).build(WorldParams::default()).unwrap(), 300);
    answers_solve_their_lcps(&lcps);
}
