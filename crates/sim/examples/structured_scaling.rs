//! The structured Lemke (`lcp::structured`) against the
//! dense Lemke on the contact LCP of a heap's cubes, one size per call.
//!
//! `cargo run --release -p lcpsim-sim --example structured_scaling -- BOXES K [DENSE_MAX_N]`
//!
//! `BOXES`: one box per line, `static hx hy hz px py pz qw qx qy qz mass mu`
//! (`benchmarks/lcp_scaling.py` writes it from a settled heap). The world is
//! the static boxes, a ground and the `K` dynamic boxes nearest the origin,
//! at rest; its contacts are detected and their LCP assembled (dt = 1e-3, the
//! world's defaults otherwise) as one LCP, which both solvers get (the dense
//! one only up to `DENSE_MAX_N`, default 6,000). Prints one JSON line: n,
//! contacts, and per solver seconds, pivots, status, accepted, natural
//! residual; and the peak RSS. The structured solver's `seconds` include
//! building its operator from the assembled contacts, `solve_seconds` not
//! (the dense solver's `seconds` do not include assembling its `M`).

use sim::contact::assembly::{AssemblyParams, BodyDynamics};
use sim::contact::body_factors::structured_lcp;
use sim::contact::ContactLcp;
use sim::dynamics::BodyDesc;
use sim::lcp::structured::{self, StructuredOptions};
use sim::lcp::{lemke, LemkeOptions};
use sim::math::{Quat, Vec3};
use sim::{World, WorldParams};
use std::time::Instant;

fn parse(path: &str) -> Vec<(bool, [f64; 12])> {
    let text = std::fs::read_to_string(path).expect("a boxes file");
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<f64> = l.split_whitespace().map(|x| x.parse().expect("a number")).collect();
            (f[0] != 0.0, std::array::from_fn(|i| f[i + 1]))
        })
        .collect()
}

fn world(boxes: &[(bool, [f64; 12])], k: usize) -> World {
    let mut w = World::new(WorldParams { dt: 1e-3, ..Default::default() }).unwrap();
    let mu = boxes.first().map_or(0.5, |b| b.1[11]);
    w.add_ground(mu).unwrap();
    let mut dynamic: Vec<&[f64; 12]> = boxes.iter().filter(|b| !b.0).map(|b| &b.1).collect();
    let r = |b: &[f64; 12]| b[3] * b[3] + b[4] * b[4] + b[5] * b[5];
    dynamic.sort_by(|a, b| r(a).total_cmp(&r(b)));
    let desc = |b: &[f64; 12]| {
        BodyDesc::cuboid(Vec3::new(b[0], b[1], b[2]))
            .mu(b[11])
            .position(Vec3::new(b[3], b[4], b[5]))
            .orientation(Quat::new(b[6], b[7], b[8], b[9]))
    };
    for b in boxes.iter().filter(|b| b.0) {
        w.add_body(desc(&b.1).fixed(true)).unwrap();
    }
    for b in dynamic.into_iter().take(k) {
        w.add_body(desc(b).mass(b[10])).unwrap();
    }
    w
}

fn peak_rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM"))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .unwrap_or(0.0)
        / 1024.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let boxes = parse(&args[1]);
    let k: usize = args[2].parse().expect("K");
    let dense_max: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(6000);
    let mut w = world(&boxes, k);
    w.forces_stage().unwrap();
    w.detect();
    let p = w.params().clone();
    let (v, om) = w.free_velocities();
    let dynamics = BodyDynamics { bodies: w.bodies(), inv_inertia_world: w.inv_inertias(), v_free: v, w_free: om };
    let ap = AssemblyParams {
        h: p.dt,
        k: p.friction_dirs,
        s: p.scale(),
        stabilization: p.stabilization,
        restitution: p.restitution,
    };
    let mut c = ContactLcp::new();
    c.assemble_rows(w.contacts(), &dynamics, &ap);
    let n = c.n();
    let t0 = Instant::now();
    let op = structured_lcp(&c, c.scale()).unwrap();
    let t1 = Instant::now();
    let mut so = StructuredOptions::default();
    if let Some(r) = std::env::var("REFACTOR_EVERY").ok().and_then(|v| v.parse().ok()) {
        so.refactor_every = r;
    }
    let sol = structured::solve(&op, &so, None);
    let ts = t0.elapsed().as_secs_f64();
    let ts_solve = t1.elapsed().as_secs_f64();
    let mut out = format!(
        "{{\"cubes\": {k}, \"n\": {n}, \"contacts\": {}, \"structured\": {{\"seconds\": {ts}, \"solve_seconds\": {ts_solve}, \"pivots\": {}, \"status\": \"{}\", \"accepted\": {}, \"residual\": {:e}}}",
        c.nc(),
        sol.pivots,
        sol.status.as_str(),
        sol.accepted,
        sol.residuals.residual
    );
    let rss_structured = peak_rss_mb();
    if n <= dense_max {
        c.assemble_matrix();
        let lcp = c.to_lcp().unwrap();
        let t0 = Instant::now();
        let d = lemke::solve(&lcp, &LemkeOptions::default());
        let td = t0.elapsed().as_secs_f64();
        out += &format!(
            ", \"dense\": {{\"seconds\": {td}, \"pivots\": {}, \"status\": \"{}\", \"accepted\": {}, \"residual\": {:e}}}",
            d.pivots,
            d.status.as_str(),
            d.accepted,
            d.residuals.residual
        );
    }
    println!("{out}, \"peak_rss_mb_structured\": {rss_structured:.1}, \"peak_rss_mb\": {:.1}}}", peak_rss_mb());
}
