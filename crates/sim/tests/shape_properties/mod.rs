//! Convex hulls, triangle meshes, compounds and height fields from arbitrary bytes — points
//! with NaN, ∞, extremes, duplicates, coplanar sets; faces with out-of-range,
//! repeated or collinear indices; compounds of no part or several, with bad
//! sizes, poses and zero quaternions; grids of any size with any heights — and what must hold whatever the input:
//! the constructor returns a shape or a `SimError::BadGeometry` naming
//! `vertices`, `faces`, `parts` or the grid's field, never panics; a refused body leaves the
//! world as it was; an accepted hull or compound has a positive volume and a
//! finite centre of mass (a hull finite vertices too); the world with the
//! shape (a hull or compound dropped on the ground, a ball dropped on the
//! mesh or field) steps with `Ok` or a `SimError`, and every island
//! reported solved passes the acceptance rule. Shared by
//! `tests/properties_any_shape.rs` (proptest) and the fuzz target
//! `fuzz/fuzz_targets/shapes.rs`; the stepping checks are the world
//! properties' (`tests/properties/`).

#![allow(dead_code)]

use crate::properties::solved_islands_pass_the_rule;
use sim::math::{Quat, Vec3};
use sim::{BodyDesc, CompoundPart, Shape, SimError, World, WorldParams};

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

/// A size: mostly in (0, 1], sometimes zero, negative or raw bits.
fn size(b: &mut Bytes<'_>) -> f64 {
    match b.u8() % 30 {
        0 => b.f64(),
        1 => -0.5,
        2 => 0.0,
        _ => 0.05 + (b.u8() as f64) / 255.0,
    }
}

/// Up to 5 parts (spheres, boxes, capsules, cylinders, hulls) at poses, now and then bad.
fn parts(b: &mut Bytes<'_>) -> Vec<CompoundPart> {
    let n = b.u8() as usize % 6;
    (0..n)
        .map(|_| {
            let shape = match b.u8() % 5 {
                0 => Shape::Sphere { radius: size(b) },
                1 => Shape::Box(sim::geometry::BoxShape { half_extents: Vec3::new(size(b), size(b), size(b)) }),
                2 => Shape::Capsule { radius: size(b), half_length: size(b) },
                3 => Shape::Cylinder { radius: size(b), half_length: size(b) },
                // A bad hull (a plane part: refused) when the points make none.
                _ => Shape::convex(&points(b)).unwrap_or(Shape::Plane(sim::Plane::ground())),
            };
            let small = |b: &mut Bytes<'_>| b.u8() as i8 as f64 / 127.0;
            let position = if b.u8() % 16 == 0 {
                Vec3::new(coord(b), coord(b), coord(b))
            } else {
                Vec3::new(small(b), small(b), small(b))
            };
            let orientation = if b.u8() % 30 == 0 {
                Quat::from_array([0.0; 4])
            } else {
                Quat::from_array([small(b), small(b), small(b), small(b)])
            };
            CompoundPart { shape, position, orientation }
        })
        .collect()
}

/// What one input did: whether the shape was accepted, steps taken.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// 0 mesh, 1 hull, 2 compound, 3 height field.
    pub kind: u8,
    pub accepted: bool,
    pub steps: usize,
}

/// A refusal must name one of `fields` (a `BadGeometry`, or a size not positive or not finite).
fn refused(e: SimError, fields: &[&str]) -> Result<Stats, String> {
    let kind = match fields[0] {
        "parts" => 2,
        "nrow" => 3,
        "vertices" if fields.len() == 1 => 1,
        _ => 0,
    };
    match e {
        SimError::BadGeometry { field, .. }
        | SimError::NotPositive { field, .. }
        | SimError::NonFinite { field, .. }
            if fields.contains(&field) =>
        {
            Ok(Stats { kind, ..Stats::default() })
        }
        e => Err(format!("refused with an unexpected error: {e}")),
    }
}

/// Builds the shape the bytes describe, adds it to a world and steps it (see the module docs).
pub fn check(data: &[u8]) -> Result<Stats, String> {
    let mut b = Bytes::new(data);
    let kind = b.u8() % 4;
    let mesh = kind == 0 || kind == 3;
    let mut w = World::new(WorldParams::default()).map_err(|e| e.to_string())?;
    let desc = if kind == 3 {
        let (nrow, ncol) = (b.u8() as usize % 7, b.u8() as usize % 7);
        let n = if b.u8() % 10 == 0 { b.u8() as usize % 40 } else { nrow * ncol };
        let heights: Vec<f64> = (0..n).map(|_| coord(&mut b) * 0.2).collect();
        match BodyDesc::heightfield(nrow, ncol, size(&mut b), size(&mut b), &heights) {
            Ok(d) => d,
            Err(e) => return refused(e, &["nrow", "ncol", "heights", "half_x", "half_y"]),
        }
    } else if kind == 2 {
        match Shape::compound(&parts(&mut b)) {
            Ok(s) => BodyDesc::new(s),
            Err(e) => return refused(e, &["parts"]),
        }
    } else if mesh {
        let pts = points(&mut b);
        let f = faces(&mut b, pts.len());
        match BodyDesc::mesh(&pts, &f) {
            Ok(d) => d,
            Err(e) => return refused(e, &["vertices", "faces"]),
        }
    } else {
        match BodyDesc::convex(&points(&mut b)) {
            Ok(d) => d,
            Err(e) => return refused(e, &["vertices"]),
        }
    };
    let mut stats = Stats { kind, accepted: true, steps: 0 };
    let r = match &desc.shape {
        Shape::Convex(h) => {
            let finite = h.vertices().iter().all(|v| v.is_finite()) && h.com_offset().is_finite();
            if !finite || !(h.volume() > 0.0) {
                return Err(format!("hull with volume {} or non-finite vertices / centre", h.volume()));
            }
            h.radius()
        }
        Shape::Mesh(m) => m.radius(),
        Shape::HeightField(h) => h.radius(),
        Shape::Compound(c) => {
            if !(c.volume() > 0.0 && c.volume().is_finite()) || !c.com_offset().is_finite() || c.parts().is_empty() {
                return Err(format!("compound with volume {} or a non-finite centre", c.volume()));
            }
            c.radius()
        }
        _ => return Err("the constructor made another shape".into()),
    };
    if !r.is_finite() {
        return Err(format!("bounding radius {r}"));
    }
    // A hull or compound falls onto the ground; a ball falls onto the mesh from just above its bound.
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
