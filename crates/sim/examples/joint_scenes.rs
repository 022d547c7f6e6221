//! `benchmarks/joints.py`'s two scenes (`sim::joints::scenes`), stepped in a
//! Rust loop for profiling: steps/s, Lemke pivots, the stage of each jointed
//! island and the largest joint error.
//!
//! ```text
//! cargo run --release -p lcpsim-sim --example joint_scenes -- gripper [STEPS]
//! cargo run --release -p lcpsim-sim --example joint_scenes -- chain [STEPS] [WINDOW]
//! ```
//!
//! With `WINDOW`, one line per `WINDOW` steps: the time, the jointed
//! islands' mean `n`, the pivots and the steps each stage answered.

use sim::joints::scenes::{chain, gripper, gripper_lift_speed};
use sim::JointId;
use std::collections::BTreeMap;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = args.get(1).map_or("gripper", String::as_str);
    let (mut w, lift, steps) = match scene {
        "chain" => (chain(), None, 3000),
        "gripper" => {
            let (w, lift) = gripper();
            (w, Some(lift), 5200)
        }
        other => panic!("unknown scene {other:?}: gripper or chain"),
    };
    let steps = args.get(2).map_or(steps, |s| s.parse().expect("STEPS"));
    let window: usize = args.get(3).map_or(0, |s| s.parse().expect("WINDOW"));
    let mut win = Window::default();
    let (mut pivots, mut failed, mut worst) = (0usize, 0usize, 0.0f64);
    let mut stages: BTreeMap<String, usize> = BTreeMap::new();
    let mut time = 0.0;
    for s in 0..steps {
        if let Some(lift) = lift {
            w.set_motor(lift, gripper_lift_speed(s), 200.0).unwrap();
        }
        let t0 = Instant::now();
        let rec = w.step().unwrap();
        let dt = t0.elapsed().as_secs_f64();
        time += dt;
        pivots += rec.pivots;
        if window > 0 {
            win.add(rec, dt);
            if (s + 1) % window == 0 {
                win.print(s + 1 - window..s + 1);
            }
        }
        failed += usize::from(!rec.ok());
        for isl in &rec.islands {
            *stages.entry(isl.stage.map_or("none".into(), |s| format!("{s:?}"))).or_default() += 1;
        }
        for j in 0..w.joints().len() {
            worst = worst.max(w.joint_error(JointId(j)).unwrap().0);
        }
    }
    println!(
        "{scene}: {steps} steps, {:.0} steps/s ({:.1} µs a step), pivots {pivots}, failed {failed}, joint error {worst:.1e} m",
        steps as f64 / time,
        1e6 * time / steps as f64
    );
    println!("  island stages: {stages:?}");
    let ids: Vec<_> = w.bodies().iter().map(|b| b.position().z).collect();
    println!("  heights: {:?}", &ids[..ids.len().min(4)]);
}

/// One window of steps: time, pivots, summed `n` and count of the islands, and the stages that answered.
#[derive(Default)]
struct Window {
    time: f64,
    pivots: usize,
    n: usize,
    islands: usize,
    stages: BTreeMap<String, (usize, usize)>,
}

impl Window {
    fn add(&mut self, rec: &sim::StepRecord, dt: f64) {
        self.time += dt;
        self.pivots += rec.pivots;
        for isl in &rec.islands {
            self.n += isl.lcp_size;
            self.islands += 1;
            let e = self.stages.entry(isl.stage.map_or("none".into(), |s| s.as_str().to_string())).or_default();
            (e.0, e.1) = (e.0 + 1, e.1 + isl.pivots);
        }
    }

    /// Prints the window's line (stages as `name islands/pivots`) and starts the next.
    fn print(&mut self, steps: std::ops::Range<usize>) {
        let k = steps.len() as f64;
        let stages: Vec<String> = self.stages.iter().map(|(s, (c, p))| format!("{s} {c}/{p}")).collect();
        println!(
            "  {:>5}-{:<5} {:>8.1} µs/step  n {:>4.0}  pivots/step {:>6.1}  {}",
            steps.start,
            steps.end,
            1e6 * self.time / k,
            self.n as f64 / self.islands.max(1) as f64,
            self.pivots as f64 / k,
            stages.join(", ")
        );
        *self = Window::default();
    }
}
