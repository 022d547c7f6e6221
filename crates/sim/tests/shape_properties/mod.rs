//! Convex hulls and triangle meshes from arbitrary bytes — points with NaN,
//! ∞, extremes, duplicates, coplanar sets; faces with out-of-range, repeated
//! or collinear indices — and what must hold whatever the input: the
//! constructor returns a shape or a `SimError::BadGeometry` naming
//! `vertices` or `faces`, never panics; a refused body leaves the world as it
//! was; an accepted hull has finite vertices, a positive volume and a finite
//! centre of mass; the world with the shape (a hull dropped on the ground, a
//! ball dropped on the mesh) steps with `Ok` or a `SimError`, and every island
//! reported solved passes the acceptance rule. Shared by
//! `tests/properties_any_shape.rs` (proptest) and the fuzz target
//! `fuzz/fuzz_targets/shapes.rs`; the stepping checks are the world
//! properties' (`tests/properties/`).

#![allow(dead_code)]

use crate::properties::solved_islands_pass_the_rule;
use sim::math::Vec3;
use sim::{BodyDesc, Shape, SimError, World, WorldParams};

#[path = "../../../lcp/tests/properties/bytes.rs"]
mod bytes;
use bytes::Bytes;

/// A coordinate: mostly in [-1, 1], sometimes an extreme or raw bits (`Bytes::f64`).
fn coord(b: &mut Bytes<'_>) -> f64 {
    if b.u8() % 8 == 0 {
        b.f64()
    } else {
        b.u8() as i8 as f64 / 127.0
    }
}

/// Points: up to 40, now and then all in one plane or with repeats.
fn points(b: &mut Bytes<'_>) -> Vec<Vec3> {
    let n = b.u8() as usize % 41;
    let flat = b.u8() % 6 == 0;
    let mut out: Vec<Vec3> = Vec::with_capacity(n);
    for _ in 0..n {
        let p = if !out.is_empty() && b.u8() % 8 == 0 {
            out[b.u8() as usize % out.len()]
        } else {
            Vec3::new(coord(b), coord(b), if flat { 0.0 } else { coord(b) })
        };
        out.push(p);
    }
    out
}

/// Triangles: indices mostly in range, sometimes one past it or huge.
fn faces(b: &mut Bytes<'_>, n: usize) -> Vec<[u32; 3]> {
    let m = b.u8() as usize % 12;
    (0..m)
        .map(|_| {
            std::array::from_fn(|_| match b.u8() % 16 {
                0 => n as u32,
                1 => u32::MAX,
                _ => (b.u8() as usize % n.max(1)) as u32,
            })
        })
        .collect()
}

/// What one input did: whether the shape was accepted, steps taken.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    pub accepted: bool,
    pub steps: usize,
}

/// A refusal must be a `BadGeometry` naming one of `fields`.
fn refused(e: SimError, fields: &[&str]) -> Result<Stats, String> {
    match e {
        SimError::BadGeometry { field, .. } if fields.contains(&field) => Ok(Stats::default()),
        e => Err(format!("refused with an unexpected error: {e}")),
    }
}

/// Builds the shape the bytes describe, adds it to a world and steps it (see the module docs).
pub fn check(data: &[u8]) -> Result<Stats, String> {
    let mut b = Bytes::new(data);
    let mesh = b.bool();
    let pts = points(&mut b);
    let mut w = World::new(WorldParams::default()).map_err(|e| e.to_string())?;
    let desc = if mesh {
        let f = faces(&mut b, pts.len());
        match BodyDesc::mesh(&pts, &f) {
            Ok(d) => d,
            Err(e) => return refused(e, &["vertices", "faces"]),
        }
    } else {
        match BodyDesc::convex(&pts) {
            Ok(d) => d,
            Err(e) => return refused(e, &["vertices"]),
        }
    };
    let mut stats = Stats { accepted: true, steps: 0 };
    let r = match &desc.shape {
        Shape::Convex(h) => {
            let finite = h.vertices().iter().all(|v| v.is_finite()) && h.com_offset().is_finite();
            if !finite || !(h.volume() > 0.0) {
                return Err(format!("hull with volume {} or non-finite vertices / centre", h.volume()));
            }
            h.radius()
        }
        Shape::Mesh(m) => m.radius(),
        _ => return Err("the constructor made another shape".into()),
    };
    if !r.is_finite() {
        return Err(format!("bounding radius {r}"));
    }
    // A hull falls onto the ground; a ball falls onto the mesh from just above its bound.
    if !mesh {
        w.add_ground(0.5).map_err(|e| e.to_string())?;
    }
    let before = w.body_count();
    let added = if mesh {
        w.add_body(desc).map(|_| ())
    } else {
        w.add_body(desc.position(Vec3::new(0.0, 0.0, r + 0.01)).angular_velocity(Vec3::new(0.3, 0.0, 0.1))).map(|_| ())
    };
    if let Err(e) = added {
        // (A hull so small or flat that its inertia under- or overflows is refused here.)
        if w.body_count() != before {
            return Err(format!("a refused body ({e}) was added"));
        }
        return Ok(stats);
    }
    if mesh {
        let _ = w.add_sphere(0.2, 1.0, Vec3::new(0.0, 0.0, r.min(10.0) + 0.25), 0.5);
    }
    for _ in 0..1 + b.u8() % 8 {
        let rec = match w.step() {
            Ok(rec) => rec.clone(),
            Err(SimError::NonFiniteState { .. } | SimError::Lcp(_) | SimError::TooLarge(_)) => return Ok(stats),
            Err(e) => return Err(format!("step failed with an unexpected error: {e}")),
        };
        solved_islands_pass_the_rule(&w, &rec)?;
        stats.steps += 1;
    }
    Ok(stats)
}
