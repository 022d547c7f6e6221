//! The narrow phase of boxes, spheres and planes: the hand-written routines
//! against parry's contact manifolds, on the built-in scenes. Run it twice,
//! once with `LCPSIM_NARROW=parry`, and compare the lines (steps/s, failures,
//! deepest penetration, final positions).
//!
//! `cargo run --release -p lcpsim-sim --example narrow_phase -- [STEPS] [SCENE] [HEAP_SEED]`
//! prints per scene (all, or the one named): name, steps/s, contacts per step,
//! failures, deepest penetration (m), steps whose deepest exceeds 0.1 mm, then
//! the final centre of every dynamic body.

use sim::scenes::{BallOnIncline, BoxPile, BoxStack, CubeHeap, CubeOnSlope, Scene};
use sim::WorldParams;
use std::time::Instant;

fn main() {
    let steps: usize = std::env::args().nth(1).map_or(2000, |s| s.parse().expect("STEPS"));
    let which = if std::env::var("LCPSIM_NARROW").is_ok_and(|v| v == "parry") { "parry" } else { "own" };
    let p = WorldParams::default;
    let scenes: Vec<(&str, Scene)> = vec![
        ("cube_on_slope", CubeOnSlope::new(30.0, 0.3).build(p()).unwrap()),
        ("ball_on_incline", BallOnIncline::new(20.0, 0.5).build(p()).unwrap()),
        ("stack10", BoxStack::new(10).build(p()).unwrap()),
        ("pile3_yaw", BoxPile { yaw: 0.4, seed: 3, ..Default::default() }.build(p()).unwrap()),
        (
            "heap50",
            CubeHeap::new(50, std::env::args().nth(3).map_or(1, |s| s.parse().expect("HEAP_SEED"))).build(p()).unwrap(),
        ),
    ];
    let only = std::env::args().nth(2);
    for (name, mut s) in scenes.into_iter().filter(|(n, _)| only.as_deref().is_none_or(|o| o == *n)) {
        let (mut failures, mut contacts, mut deepest, mut deep_steps) = (0usize, 0usize, 0.0f64, 0usize);
        let (mut deep_on_static, mut deep_between) = (0usize, 0usize);
        let t0 = Instant::now();
        for _ in 0..steps {
            let r = s.world.step().unwrap().clone();
            failures += r.islands.iter().filter(|i| i.status != lcp::Status::Solved).count();
            contacts += r.contacts.len();
            let step_deepest = r.contacts.iter().fold(0.0f64, |d, c| d.max(-c.gap));
            deepest = deepest.max(step_deepest);
            deep_steps += usize::from(step_deepest > 1e-4);
            for c in r.contacts.iter().filter(|c| c.gap < -1e-4) {
                if s.world.body(sim::BodyId(c.body_b)).unwrap().is_static() {
                    deep_on_static += 1;
                } else {
                    deep_between += 1;
                }
            }
        }
        let secs = t0.elapsed().as_secs_f64();
        println!(
            "{which} {name}: {:.0} steps/s, {:.1} contacts/step, {failures} failures, deepest {deepest:.3e} m, \
             {deep_steps} steps deeper than 0.1 mm ({deep_on_static} such contacts with a static body, \
             {deep_between} between dynamic ones)",
            steps as f64 / secs,
            contacts as f64 / steps as f64
        );
        let mut line = format!("{which} {name} final");
        for &b in &s.bodies {
            let x = s.world.body(b).unwrap().position();
            line += &format!(" {:.12e} {:.12e} {:.12e}", x.x, x.y, x.z);
        }
        println!("{line}");
    }
}
