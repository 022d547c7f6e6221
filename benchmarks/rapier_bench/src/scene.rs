//! Rapier on a scene of boxes over a ground plane `z = 0`, read from the JSON
//! that `many_bodies.py` writes (the same initial state every engine gets).
//!
//! Rapier's defaults apply (soft-constraint solver, 4 iterations) except that
//! bodies never sleep — a resting stack would otherwise fall asleep within
//! half a second and cost nothing per step, while lcpsim and MuJoCo solve
//! every contact every step. Set: gravity (−z), dt, friction (combine rule
//! "average" of equal values = μ), zero restitution; each box's mass comes
//! from a density of mass / volume.

use rapier3d_f64::na::Unit;
use rapier3d_f64::prelude::*;
use serde::Deserialize;
use serde_json::json;
use std::time::Instant;

/// One box: half extents, centre, orientation (w, x, y, z), and whether it is static.
#[derive(Deserialize)]
pub struct BoxDesc {
    pub half: [f64; 3],
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    #[serde(default)]
    pub r#static: bool,
    #[serde(default = "one")]
    pub mass: f64,
}

fn one() -> f64 {
    1.0
}

/// A scene: boxes over the ground plane `z = 0` (as many_bodies.py writes it).
#[derive(Deserialize)]
pub struct SceneDesc {
    pub dt: f64,
    pub gravity: f64,
    pub mu: f64,
    pub boxes: Vec<BoxDesc>,
}

/// How long to run: `steps` per repetition, stopped early when a repetition's
/// stepping wall clock exceeds `budget_s`; a pose sample every `sample_every`
/// steps of the first repetition.
pub struct RunOptions {
    pub steps: usize,
    pub budget_s: f64,
    pub sample_every: usize,
    pub reps: usize,
}

struct Built {
    world: PhysicsWorld,
    dynamic: Vec<RigidBodyHandle>,
}

fn build(desc: &SceneDesc) -> Built {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -desc.gravity);
    world.integration_parameters.dt = desc.dt;
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    world.insert_collider(
        ColliderBuilder::halfspace(Unit::new_unchecked(Vector::new(0.0, 0.0, 1.0)))
            .friction(desc.mu)
            .restitution(0.0),
        Some(ground),
    );
    let mut dynamic = Vec::new();
    for b in &desc.boxes {
        let [w, x, y, z] = b.quat;
        let pose = Pose::from_parts(Vector::new(b.pos[0], b.pos[1], b.pos[2]), Rotation::from_xyzw(x, y, z, w));
        let body = if b.r#static { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic().can_sleep(false) };
        let volume = 8.0 * b.half[0] * b.half[1] * b.half[2];
        let collider = ColliderBuilder::cuboid(b.half[0], b.half[1], b.half[2])
            .density(b.mass / volume)
            .friction(desc.mu)
            .restitution(0.0);
        let (handle, _) = world.insert(body.pose(pose), collider);
        if !b.r#static {
            dynamic.push(handle);
        }
    }
    Built { world, dynamic }
}

/// Contact points the solver sees (all manifolds of all touching pairs).
fn contact_count(world: &PhysicsWorld) -> usize {
    world
        .narrow_phase
        .contact_pairs()
        .flat_map(|p| p.manifolds())
        .map(|m| m.data.solver_contacts.len())
        .sum()
}

fn sample(built: &Built, step: usize) -> serde_json::Value {
    let (mut pos, mut quat) = (Vec::new(), Vec::new());
    for h in &built.dynamic {
        let b = &built.world.bodies[*h];
        let t = b.translation();
        let r = b.rotation();
        pos.push([t.x, t.y, t.z]);
        quat.push([r.w, r.x, r.y, r.z]);
    }
    json!({"event": "sample", "step": step, "pos": pos, "quat": quat, "contacts": contact_count(&built.world)})
}

fn emit(v: serde_json::Value) {
    println!("{v}");
}

/// One repetition: returns nothing, emits `progress`, `sample` (first rep) and `rep`.
fn run_rep(desc: &SceneDesc, opts: &RunOptions, rep: usize) {
    let mut built = build(desc);
    let samples = rep == 0;
    if samples {
        emit(sample(&built, 0));
    }
    let (mut done, mut seconds, mut max_contacts) = (0usize, 0.0f64, 0usize);
    let wall = Instant::now();
    let mut timed_out = false;
    while done < opts.steps {
        if wall.elapsed().as_secs_f64() > opts.budget_s {
            timed_out = true;
            break;
        }
        let t0 = Instant::now();
        built.world.step();
        seconds += t0.elapsed().as_secs_f64();
        done += 1;
        if done % opts.sample_every.max(1) == 0 || done == opts.steps {
            emit(json!({"event": "progress", "rep": rep, "steps": done, "seconds": seconds}));
            if samples {
                let s = sample(&built, done);
                max_contacts = max_contacts.max(s["contacts"].as_u64().unwrap_or(0) as usize);
                emit(s);
            }
        }
    }
    if samples && timed_out {
        emit(sample(&built, done));
    }
    emit(json!({"event": "rep", "rep": rep, "steps": done, "seconds": seconds, "timed_out": timed_out}));
}

/// Reads the scene and runs `opts.reps` fresh repetitions (at least one; more
/// only while the budget allows).
pub fn run_file(path: &str, opts: &RunOptions) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let desc: SceneDesc = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    emit(json!({"event": "ready", "engine": "rapier3d-f64", "version": rapier3d_f64::VERSION}));
    let start = Instant::now();
    let mut last = 0.0f64;
    for rep in 0..opts.reps.max(1) {
        let used = start.elapsed().as_secs_f64();
        if rep > 0 && used + last > opts.budget_s {
            break;
        }
        let t0 = Instant::now();
        run_rep(&desc, opts, rep);
        last = t0.elapsed().as_secs_f64();
    }
    Ok(())
}
