//! Peers for lcpsim's many-body benchmarks, outside the lcpsim workspace.
//!
//! - `rapier-bench scene FILE [--steps N] [--budget S] [--sample-every K] [--reps R]`
//!   steps a scene written by `benchmarks/peers/many_bodies.py` (boxes on a
//!   ground plane, see [`scene::SceneDesc`]) with Rapier and prints JSON lines
//!   on stdout: `progress`, `sample` (poses and contact count), `rep` (one
//!   repetition's steps and stepping seconds) — the protocol of many_bodies.py's
//!   Python workers.
//! - `rapier-bench broadphase [--sizes 1000,2000,5000,10000] [--steps 20] [--json]`
//!   compares parry's BVH with a plain sweep-and-prune (module [`sap`]) on the
//!   same moving random boxes and prints a table (or JSON).

mod broadphase;
mod sap;
mod scene;

use std::process::ExitCode;

/// The value after `--name`, parsed, or `default`.
fn flag<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> Result<T, String> {
    match args.iter().position(|a| a == name) {
        None => Ok(default),
        Some(i) => {
            let v = args.get(i + 1).ok_or_else(|| format!("{name} needs a value"))?;
            v.parse().map_err(|_| format!("bad value for {name}: {v:?}"))
        }
    }
}

fn run(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("scene") => {
            let file = args.get(1).ok_or("scene needs a FILE")?;
            let opts = scene::RunOptions {
                steps: flag(args, "--steps", 2000)?,
                budget_s: flag(args, "--budget", 60.0)?,
                sample_every: flag(args, "--sample-every", 200)?,
                reps: flag(args, "--reps", 1)?,
            };
            scene::run_file(file, &opts)
        }
        Some("broadphase") => {
            let sizes: String = flag(args, "--sizes", "1000,2000,5000,10000".to_string())?;
            let sizes = sizes
                .split(',')
                .map(|s| s.trim().parse::<usize>().map_err(|_| format!("bad size {s:?}")))
                .collect::<Result<Vec<_>, _>>()?;
            let steps = flag(args, "--steps", 20)?;
            let json = args.iter().any(|a| a == "--json");
            broadphase::run(&sizes, steps, json)
        }
        _ => Err("usage: rapier-bench scene FILE [--steps N --budget S --sample-every K --reps R] | \
                  broadphase [--sizes 1000,2000,5000,10000 --steps 20 --json]"
            .into()),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("rapier-bench: {e}");
            ExitCode::FAILURE
        }
    }
}
