//! A compound shape: several solid parts (boxes, spheres, capsules, cylinders,
//! convex hulls) rigidly joined at poses in one body frame — a table of a top
//! and legs, a dumbbell of two spheres and a bar. Its contacts are parry's
//! (`Compound`, one manifold per touching part, through the same dispatcher
//! as every other pair).
//!
//! The parts are given in a frame of the caller's; the compound is recentred
//! at the centre of mass of the solid union at uniform density (overlaps count
//! twice, as MuJoCo's sum over geoms does): its parts' poses are in the body
//! frame (axes those of the frame given), `com_offset` is where that centre was
//! in the frame given, and its inertia per unit mass is the full tensor about
//! that centre. A hull part's pose places the frame of its points (its own
//! centre of mass is at `com_offset` in that frame), so hull points given in
//! the compound's frame take the identity pose.

use super::parry_pair::parry_shape;
use super::{Placement, Shape};
use crate::error::SimError;
use crate::math::{Mat3, Quat, Vec3};
use parry3d_f64::shape::{Compound, SharedShape};
use std::sync::Arc;

/// The most parts of one compound.
pub const MAX_COMPOUND_PARTS: usize = 10_000;

/// One part of a compound: a solid shape at a pose in the compound's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct CompoundPart {
    pub shape: Shape,
    pub position: Vec3,
    pub orientation: Quat,
}

/// Several solid parts in one body frame (see the module docs).
#[derive(Clone, Debug)]
pub struct CompoundShape {
    inner: Arc<CompoundData>,
}

#[derive(Debug)]
struct CompoundData {
    /// The parts, their poses in the body frame (centre of mass at the origin).
    parts: Vec<CompoundPart>,
    volume: f64,
    /// Inertia about the centre of mass per unit mass (body frame).
    unit_inertia: Mat3,
    com_offset: Vec3,
    radius: f64,
    parry: Compound,
}

impl PartialEq for CompoundShape {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.inner, &o.inner) || self.inner.parts == o.inner.parts
    }
}

fn bad(reason: String) -> SimError {
    SimError::BadGeometry { field: "parts", reason }
}

/// `d d` outer product subtracted from `|d|² I`: the parallel-axis term per unit mass.
fn shift(d: Vec3) -> Mat3 {
    let a = d.to_array();
    let n2 = d.norm_squared();
    Mat3::from_rows(std::array::from_fn(|r| std::array::from_fn(|c| if r == c { n2 } else { 0.0 } - a[r] * a[c])))
}

impl CompoundShape {
    /// A compound of `parts` (1 to [`MAX_COMPOUND_PARTS`]; each a valid box,
    /// sphere, capsule, cylinder or hull at a finite pose with a non-zero
    /// quaternion), recentred at their centre of mass at uniform density.
    pub fn new(parts: &[CompoundPart]) -> Result<CompoundShape, SimError> {
        CompoundShape::about(parts, None)
    }

    /// [`CompoundShape::new`] recentred at `com` (in the parts' frame) when
    /// given: the centre of mass of a body whose density is not uniform (an
    /// MJCF body's compiled `ipos`). The inertia per unit mass is then the
    /// uniform solid's about `com` (give the body its own inertia).
    pub fn about(parts: &[CompoundPart], com: Option<Vec3>) -> Result<CompoundShape, SimError> {
        if parts.is_empty() {
            return Err(bad("must hold at least one part, got none".into()));
        }
        if parts.len() > MAX_COMPOUND_PARTS {
            return Err(bad(format!("has {} parts, more than the limit of {MAX_COMPOUND_PARTS}", parts.len())));
        }
        // Each part's centre (its own centre of mass) and rotation in the frame given.
        let mut placed = Vec::with_capacity(parts.len());
        for (k, p) in parts.iter().enumerate() {
            let why = |e: SimError| bad(format!("[{k}] ({}): {e}", p.shape.kind()));
            p.shape.validate().map_err(why)?;
            let Some(volume) = p.shape.volume() else {
                return Err(bad(format!(
                    "[{k}] is a {}; parts must be boxes, spheres, capsules, cylinders or convex hulls",
                    p.shape.kind()
                )));
            };
            crate::error::finite_vec("position", p.position).map_err(why)?;
            let q = crate::dynamics::body::normalize_quat(p.orientation).map_err(why)?;
            let centre = match &p.shape {
                Shape::Convex(h) => p.position + q.rotate(h.com_offset()),
                _ => p.position,
            };
            placed.push((centre, q, volume));
        }
        let volume: f64 = placed.iter().map(|p| p.2).sum();
        if !(volume > 0.0 && volume.is_finite()) {
            return Err(bad(format!("have a total volume of {volume}, not a positive finite number")));
        }
        let com = match com {
            Some(c) => crate::error::finite_vec("com", c).map_err(|e| bad(format!("centre: {e}")))?,
            None => placed.iter().fold(Vec3::ZERO, |c, p| c + p.0 * (p.2 / volume)),
        };
        let mut unit_inertia = Mat3::ZERO;
        let mut radius = 0.0f64;
        let mut out = Vec::with_capacity(parts.len());
        for (p, &(centre, q, v)) in parts.iter().zip(&placed) {
            let d = centre - com;
            let share = v / volume;
            let r = q.to_mat3();
            let own = p.shape.inertia(share).expect("a solid part has an inertia");
            unit_inertia = unit_inertia + r * own * r.transpose() + shift(d) * share;
            radius = radius.max(d.norm() + p.shape.bounding_radius());
            out.push(CompoundPart { shape: p.shape.clone(), position: d, orientation: q });
        }
        if !(radius.is_finite() && unit_inertia.is_finite()) {
            return Err(bad(format!("reach {radius} from their centre, beyond a finite bound")));
        }
        // Exactly symmetric (the sums round).
        let mut m = unit_inertia.m;
        for r in 0..3 {
            for c in (r + 1)..3 {
                let s = 0.5 * (m[r][c] + m[c][r]);
                m[r][c] = s;
                m[c][r] = s;
            }
        }
        let shapes = out
            .iter()
            .map(|p| {
                let (s, pose) =
                    parry_shape(&p.shape, &Placement { center: p.position, rotation: p.orientation.to_mat3() });
                (pose, SharedShape(Arc::from(s.get().clone_dyn())))
            })
            .collect();
        Ok(CompoundShape {
            inner: Arc::new(CompoundData {
                parts: out,
                volume,
                unit_inertia: Mat3::from_rows(m),
                com_offset: com,
                radius,
                parry: Compound::new(shapes),
            }),
        })
    }

    /// The parts, their poses in the body frame (centre of mass at the origin).
    pub fn parts(&self) -> &[CompoundPart] {
        &self.inner.parts
    }
    /// The summed volume of the parts (m³).
    pub fn volume(&self) -> f64 {
        self.inner.volume
    }
    /// Inertia about the centre of mass of a compound of `mass` (uniform density).
    pub fn inertia(&self, mass: f64) -> Mat3 {
        self.inner.unit_inertia * mass
    }
    /// The centre of mass in the frame the parts were given in.
    pub fn com_offset(&self) -> Vec3 {
        self.inner.com_offset
    }
    /// Largest distance of a point of a part from the centre of mass (a bound).
    pub fn radius(&self) -> f64 {
        self.inner.radius
    }
    pub(crate) fn parry(&self) -> &Compound {
        &self.inner.parry
    }
}
