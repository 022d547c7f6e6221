//! A `World` from arbitrary bytes — parameters, up to five boxes and spheres
//! (some static), forces, pairs kept apart — stepped a few times, and what must
//! hold whatever the input: construction and stepping return `Ok` or a
//! `SimError`, never panic; every record is consistent (its LCP size is
//! `contacts·(k + 2)`, islands cover the contacts, no contact joins an
//! excluded pair); a solved step has finite impulses and
//! residual; an island the robust Lemke or PGS reports solved passes the
//! acceptance rule on its LCP as solved (`M` formed densely for the check:
//! the body-space answers of the previous basis never form it). Shared by
//! `tests/properties_any_world.rs` (proptest) and the fuzz target
//! `fuzz/fuzz_targets/world.rs`.

#![allow(dead_code)]

use sim::contact::{ConeScale, ContactLcp};
use sim::lcp::contact::ContactLayout;
use sim::lcp::{self, Lcp, Status};
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, BodyId, Restitution, SimError, Stabilization, StepRecord, World, WorldParams};

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
    // Pairs kept apart (read after the step count, so older inputs decode as before).
    for _ in 0..b.u8() % 3 {
        let _ = world.exclude_pair(BodyId(b.u8() as usize % 7), BodyId(b.u8() as usize % 7));
    }
    let excluded = world.excluded_pairs().to_vec();
    let k = world.params().friction_dirs;
    for _ in 0..steps {
        let rec = match world.step() {
            Ok(rec) => rec.clone(),
            Err(SimError::NonFiniteState { .. } | SimError::Lcp(_) | SimError::TooLarge(_)) => return Ok(stats),
            Err(e) => return Err(format!("step failed with an unexpected error: {e}")),
        };
        let nc = rec.contacts.len();
        if rec.lcp_size != nc * (k + 2) {
            return Err(format!("lcp_size {} for {nc} contacts, k = {k}", rec.lcp_size));
        }
        if let Some(c) =
            rec.contacts.iter().find(|c| excluded.contains(&(c.body_a.min(c.body_b), c.body_a.max(c.body_b))))
        {
            return Err(format!("a contact between the excluded bodies {} and {}", c.body_a, c.body_b));
        }
        let covered: usize = rec.islands.iter().map(|i| i.contacts.len()).sum();
        if covered != nc {
            return Err(format!("islands cover {covered} of {nc} contacts"));
        }
        solved_islands_pass_the_rule(&world, &rec)?;
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

/// The acceptance rule's tolerance when `method` promises it for `Solved`
/// (the robust Lemke, PGS; classic pivoting keeps its own `solved`).
fn rule_tol(method: &lcp::Method) -> Option<f64> {
    match method {
        lcp::Method::Lemke(o) if o.pivoting == lcp::Pivoting::Lexicographic => Some(o.accept_tol),
        lcp::Method::Pgs(_) => Some(lcp::accept::DEFAULT_TOL),
        _ => None,
    }
}

/// Every island of `rec` reported solved passes the acceptance rule on its
/// LCP as solved (cone-scaled), `M` formed densely from the island's rows.
pub fn solved_islands_pass_the_rule(world: &World, rec: &StepRecord) -> Result<(), String> {
    let Some(tol) = rule_tol(&world.params().method) else { return Ok(()) };
    for (i, isl) in rec.islands.iter().enumerate() {
        if isl.status != Status::Solved {
            continue;
        }
        let Some(contact_lcp) = world.island_lcp(i) else { return Err(format!("island {i}: no LCP kept")) };
        // (An `M` that overflows when formed densely cannot be checked here.)
        let Some((lcp, z)) = as_solved(contact_lcp, &island_z(rec, i)) else { continue };
        let w = lcp.w_of(&z);
        if !lcp::accept::accepts(&lcp, &z, &w, tol) {
            return Err(format!(
                "step {}: island {i} solved ({} pivots) outside the acceptance rule, η = {:e}",
                rec.step,
                isl.pivots,
                lcp::accept::backward_error(&lcp, &z, &w)
            ));
        }
    }
    Ok(())
}

/// Island `i`'s physical `z` (its own contact order) out of the step's record.
pub fn island_z(rec: &StepRecord, i: usize) -> Vec<f64> {
    let ids = rec.island_contacts_of(i);
    let (isl, step) = (ContactLayout::new(ids.len(), rec.friction_dirs), rec.layout());
    let mut z = vec![0.0; isl.n()];
    for (c, &g) in ids.iter().enumerate() {
        z[isl.fn_index(c)] = rec.z[step.fn_index(g)];
        z[isl.fd_of(c)].copy_from_slice(&rec.z[step.fd_of(g)]);
        z[isl.lambda_index(c)] = rec.z[step.lambda_index(g)];
    }
    z
}

/// The island's LCP as solved, `D M D, D q` (`D = diag(I, I, s·I)`, `M`
/// formed densely), and the physical `z` mapped to it (`λ / s`); `None` when
/// that `M` is not finite.
pub fn as_solved(contact_lcp: &ContactLcp, z: &[f64]) -> Option<(Lcp, Vec<f64>)> {
    let mut lcp = contact_lcp.clone();
    lcp.assemble_matrix();
    let scaled = lcp.to_lcp().ok()?;
    let lay = lcp.layout();
    let zs =
        z.iter().enumerate().map(|(j, v)| if lay.lambda_range().contains(&j) { v / lcp.scale() } else { *v }).collect();
    Some((scaled, zs))
}

/// The physical LCP `M, q` of an island from its LCP as solved (`scaled`,
/// from [`as_solved`]), the cone scale undone.
pub fn physical(contact_lcp: &ContactLcp, scaled: &Lcp) -> Lcp {
    let (n, s, lay) = (contact_lcp.n(), contact_lcp.scale(), contact_lcp.layout());
    let d: Vec<f64> = (0..n).map(|i| if lay.lambda_range().contains(&i) { s } else { 1.0 }).collect();
    let m: Vec<f64> = (0..n * n).map(|e| scaled.m()[e] / (d[e / n] * d[e % n])).collect();
    let q: Vec<f64> = (0..n).map(|i| scaled.q()[i] / d[i]).collect();
    Lcp::new(m, q).expect("a finite LCP")
}
