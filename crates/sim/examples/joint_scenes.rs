//! `benchmarks/joints.py`'s two scenes built through the joint API (the same
//! bodies, joints, motors and torsional friction its MJCF gives), stepped in a
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

use sim::math::{Quat, Vec3};
use sim::{BodyDesc, JointDesc, JointId, JointKind, World, WorldParams};
use std::collections::BTreeMap;
use std::time::Instant;

fn joint(kind: JointKind, a: Option<usize>, b: usize, anchor: Vec3, axis: Vec3) -> JointDesc {
    JointDesc { kind, body_a: a, body_b: b, anchor, axis, limits: None }
}

/// 20 boxes 0.1 × 0.03 × 0.03 m, 0.1 kg, on ball joints end to end, tilted
/// 0.1 rad from upright with the foot 1 cm above the ground (μ = 0.5).
fn chain() -> World {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(0.5).unwrap();
    let tilt: f64 = 0.1;
    let a = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let turn = Quat::from_axis_angle(Vec3::Y, -(std::f64::consts::FRAC_PI_2 - tilt));
    let foot = Vec3::new(0.0, 0.0, 0.01);
    for i in 0..20 {
        let c = foot + a * (0.1 * i as f64 + 0.05);
        let link = BodyDesc::cuboid(Vec3::new(0.05, 0.015, 0.015)).mass(0.1).position(c).orientation(turn).mu(0.5);
        let b = w.add_body(link).unwrap().0;
        if i > 0 {
            w.add_joint(joint(JointKind::Ball, Some(b - 1), b, foot + a * (0.1 * i as f64), Vec3::Z)).unwrap();
        }
    }
    w
}

/// The palm on a vertical slider, two fingers on sliders to it with 20 N
/// motors closing at 0.1 m/s, pads with 2 cm of torsional friction, a 1 kg cube
/// (μ = 1). Returns the world and the palm's joint.
fn gripper() -> (World, JointId) {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_ground(1.0).unwrap();
    w.add_box(Vec3::splat(0.05), 1.0, Vec3::new(0.0, 0.0, 0.05), 1.0).unwrap();
    let palm = BodyDesc::cuboid(Vec3::new(0.15, 0.05, 0.02)).mass(1.0).position(Vec3::new(0.0, 0.0, 0.2)).mu(1.0);
    let palm = w.add_body(palm).unwrap().0;
    let lift = w.add_joint(joint(JointKind::Slider, None, palm, Vec3::new(0.0, 0.0, 0.2), Vec3::Z)).unwrap();
    for x in [-0.1, 0.1] {
        let finger = w.add_box(Vec3::new(0.01, 0.04, 0.08), 0.2, Vec3::new(x, 0.0, 0.1), 1.0).unwrap();
        w.set_torsional_friction(finger, 0.02).unwrap();
        let j =
            w.add_joint(joint(JointKind::Slider, Some(palm), finger.0, Vec3::new(x, 0.0, 0.1), -Vec3::X * x.signum()));
        w.set_motor(j.unwrap(), 0.1, 20.0).unwrap();
    }
    (w, lift)
}

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
            // benchmarks/joints.py's phases: closing 1,000 steps, lifting 2,200 (ramped over 200), holding.
            let k = s as f64 - 1000.0;
            let speed =
                if (0.0..2200.0).contains(&k) { 0.1 * (k / 200.0).min(1.0).min((2200.0 - k) / 200.0) } else { 0.0 };
            w.set_motor(lift, speed, 200.0).unwrap();
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
