//! Runs the stacking scenes and writes every LCP the default solver did not
//! solve to `DIR/<scene>_step<k>.json` (`{"scene", "step", "status", "n",
//! "M" (row-major), "q", "prev_z_residual"}`) — reproducers for the solver.
//! `prev_z_residual` is the natural residual of the previous step's answer
//! on the failing LCP (when the contacts did not change): a small value shows
//! the LCP is solvable and nearly solved by a neighbour.
//!
//! `cargo run --release -p lcpsim-sim --example lcp_failures -- DIR [STEPS]`

use sim::scenes::{BoxPile, BoxStack, Scene};
use sim::{LcpBuffer, WorldParams};
use std::fmt::Write as _;

fn json_array(v: &[f64]) -> String {
    let mut s = String::from("[");
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        write!(s, "{x:?}").unwrap();
    }
    s.push(']');
    s
}

fn run(name: &str, mut scene: Scene, steps: usize, dir: &str) {
    let buf = LcpBuffer::new();
    scene.world.set_sink(Box::new(buf.clone()));
    let mut failed = 0;
    let mut prev: Option<sim::OwnedLcp> = None;
    for _ in 0..steps {
        scene.world.step().unwrap();
        for c in buf.drain() {
            if c.status != sim::lcp::Status::Solved {
                failed += 1;
                let prev_res = match &prev {
                    Some(p) if p.q.len() == c.q.len() => {
                        let l = sim::lcp::Lcp::new(c.m.clone(), c.q.clone()).unwrap();
                        sim::lcp::Residuals::compute(&l, &p.z).1.residual
                    }
                    _ => f64::NAN,
                };
                println!(
                    "  {name} step {}: {} (n = {}), previous z residual {prev_res:.1e}, |q|∞ {:.1e}",
                    c.step,
                    c.status.as_str(),
                    c.q.len(),
                    c.q.iter().fold(0.0f64, |a, v| a.max(v.abs()))
                );
                let path = format!("{dir}/{name}_step{}.json", c.step);
                let body = format!(
                    "{{\"scene\":\"{name}\",\"step\":{},\"status\":\"{}\",\"n\":{},\"M\":{},\"q\":{},\"prev_z_residual\":{}}}\n",
                    c.step,
                    c.status.as_str(),
                    c.q.len(),
                    json_array(&c.m),
                    json_array(&c.q),
                    if prev_res.is_finite() { format!("{prev_res:e}") } else { "null".into() }
                );
                std::fs::write(&path, body).unwrap();
            } else {
                prev = Some(c);
            }
        }
    }
    println!("{name}: {failed} of {steps} LCPs not solved");
}

fn main() {
    let mut args = std::env::args().skip(1);
    let dir = args.next().unwrap_or_else(|| "lcp_failures".into());
    let steps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(500);
    std::fs::create_dir_all(&dir).unwrap();
    let p = WorldParams::default;
    run("stack3", BoxStack::new(3).build(p()).unwrap(), steps, &dir);
    run("stack10", BoxStack::new(10).build(p()).unwrap(), steps.min(100), &dir);
    let turned = BoxPile { nx: 2, ny: 1, nz: 3, yaw: 0.4, seed: 7, spacing: 1.6, ..Default::default() };
    run("turned_pile", turned.build(p()).unwrap(), steps.min(200), &dir);
}
