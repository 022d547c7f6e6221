//! A `World` from arbitrary bytes — parameters, up to five boxes and spheres
//! (some static), forces — stepped a few times, and what must hold whatever
//! the input: construction and stepping return `Ok` or a `SimError`, never
//! panic; every record is consistent (its LCP size is `contacts·(k + 2)`,
//! islands cover the contacts); a solved step has finite impulses and
//! residual. Shared by `tests/properties_any_world.rs` (proptest) and the
//! fuzz target `fuzz/fuzz_targets/world.rs`.

#![allow(dead_code)]

use sim::contact::ConeScale;
use sim::lcp::{self, Status};
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, BodyId, Restitution, SimError, Stabilization, World, WorldParams};

#[path = "../../../lcp/tests/properties/bytes.rs"]
mod bytes;
use bytes::Bytes;

/// Mostly plausible values in `[-range, range]`, sometimes an extreme or raw bits.
fn value(b: &mut Bytes<'_>, range: f64) -> f64 {
    match b.u8() % 16 {
        0..=11 => (b.u8() as i8 as f64 / 127.0) * range,
        12 => b.pick(&[0.0, 1e-300, -1e-12, 1e12, 1e300]),
        13 => b.pick(&[f64::MIN_POSITIVE, 5e-324, f64::MAX, -f64::MAX]),
        _ => b.raw_f64(),
    }
}

fn vec3(b: &mut Bytes<'_>, range: f64) -> Vec3 {
    Vec3::new(value(b, range), value(b, range), value(b, range))
}

/// The world's parameters: plausible mostly, invalid sometimes (odd or huge k, dt ≤ 0, NaN).
pub fn decode_params(b: &mut Bytes<'_>) -> WorldParams {
    let d = WorldParams::default();
    let method = match b.u8() % 4 {
        0 | 1 => lcp::Method::default(),
        2 => lcp::Method::Lemke(lcp::LemkeOptions::classic()),
        _ => lcp::Method::Pgs(lcp::PgsOptions { max_iterations: 200, ..Default::default() }),
    };
    WorldParams {
        dt: b.pick(&[1e-3, 1e-2, 1e-4, 0.05]) * if b.u8() == 255 { -1.0 } else { 1.0 },
        gravity: if b.u8() % 4 == 0 { vec3(b, 20.0) } else { d.gravity },
        friction_dirs: b.pick(&[2, 4, 8, 8, 16, 3, 0, 1 << 20]),
        cone_scale: match b.u8() % 4 {
            0 => ConeScale::TimeStep,
            1 => ConeScale::Value(value(b, 1.0).abs()),
            _ => ConeScale::Unscaled,
        },
        margin: b.pick(&[1e-3, 0.0, 0.05]),
        velocity_margin: b.u8() % 2 == 0,
        stabilization: Stabilization {
            erp: b.pick(&[0.2, 0.0, 1.0]),
            slop: b.pick(&[0.0, 1e-3]),
            speculative: b.u8() % 2 == 0,
            ..d.stabilization
        },
        restitution: Restitution { coefficient: b.pick(&[0.0, 0.5, 1.0]), threshold: 1e-2 },
        method,
        threads: b.pick(&[1, 1, 2]),
        ..d
    }
}

/// A body near the origin: a box or a sphere of size ~0.01–1 m, mass ~0.01–100 kg (sometimes
/// extreme), any orientation, some velocity, now and then static.
pub fn decode_body(b: &mut Bytes<'_>) -> BodyDesc {
    let shape = if b.u8() % 2 == 0 {
        let he = vec3(b, 1.0);
        BodyDesc::cuboid(Vec3::new(he.x.abs(), he.y.abs(), he.z.abs()))
    } else {
        BodyDesc::sphere(value(b, 1.0).abs())
    };
    let mass = match b.u8() % 8 {
        0 => value(b, 1e8).abs(),
        _ => 10f64.powi(b.u8() as i32 % 5 - 2),
    };
    shape
        .mass(mass)
        .position(vec3(b, 2.0))
        .orientation(Quat::from_array([value(b, 1.0), value(b, 1.0), value(b, 1.0), value(b, 1.0)]))
        .velocity(vec3(b, 5.0))
        .angular_velocity(vec3(b, 5.0))
        .mu(value(b, 2.0).abs())
        .fixed(b.u8() % 8 == 0)
}

/// What one input exercised: steps taken, contact LCPs solved.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    pub steps: usize,
    pub contacts: usize,
    pub solved: usize,
}

/// Builds and steps the world the bytes describe, checking every record.
pub fn check(data: &[u8]) -> Result<Stats, String> {
    let mut stats = Stats::default();
    let mut b = Bytes::new(data);
    let params = decode_params(&mut b);
    let Ok(mut world) = World::new(params) else { return Ok(stats) };
    if b.u8() % 4 != 0 {
        let _ = world.add_ground(value(&mut b, 2.0).abs());
    }
    let count = 1 + b.u8() % 5;
    for _ in 0..count {
        let _ = world.add_body(decode_body(&mut b));
    }
    for _ in 0..b.u8() % 3 {
        let body = BodyId(b.u8() as usize % 6);
        let _ =
            world.apply_force(body, vec3(&mut b, 100.0), if b.u8() % 2 == 0 { Some(vec3(&mut b, 0.5)) } else { None });
    }
    let steps = 1 + b.u8() % 12;
    let k = world.params().friction_dirs;
    for _ in 0..steps {
        let rec = match world.step() {
            Ok(rec) => rec,
            Err(SimError::NonFiniteState { .. } | SimError::Lcp(_) | SimError::TooLarge(_)) => return Ok(stats),
            Err(e) => return Err(format!("step failed with an unexpected error: {e}")),
        };
        let nc = rec.contacts.len();
        if rec.lcp_size != nc * (k + 2) {
            return Err(format!("lcp_size {} for {nc} contacts, k = {k}", rec.lcp_size));
        }
        let covered: usize = rec.islands.iter().map(|i| i.contacts.len()).sum();
        if covered != nc {
            return Err(format!("islands cover {covered} of {nc} contacts"));
        }
        if rec.status == Some(Status::Solved) {
            let finite = rec.z.iter().all(|v| v.is_finite()) && rec.residuals.residual.is_finite();
            if !finite {
                return Err(format!("a solved step with non-finite z or residual: {:?}", rec.residuals));
            }
            stats.solved += 1;
        }
        stats.steps += 1;
        stats.contacts += nc;
    }
    Ok(stats)
}
