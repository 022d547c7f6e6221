//! A height field: static terrain given as heights on a regular grid (MJCF's
//! `hfield`), collided as parry's `HeightField` (its triangles, internal edges
//! fixed).
//!
//! In its body frame the grid spans x ∈ [−half_x, half_x] over `ncol`
//! columns and y ∈ [−half_y, half_y] over `nrow` rows; `heights[r·ncol + c]`
//! is the surface's z at column c, row r (row 0 at y = −half_y, as MuJoCo's
//! `hfield_data`). Solids rest on the top side. parry's field is y-up with its
//! rows along z: it is turned a quarter about x (its y onto our z, its z onto
//! our −y), so its rows run in the opposite order.

use super::convex::pvec;
use crate::error::{finite, positive, SimError};
use crate::math::Vec3;
use parry3d_f64::shape::{HeightField, HeightFieldFlags};
use parry3d_f64::utils::Array2;
use std::sync::Arc;

/// The most grid points of one height field.
pub const MAX_HFIELD_POINTS: usize = 16_000_000;

/// Heights on a regular grid (see the module docs); static bodies only.
#[derive(Clone, Debug)]
pub struct HeightFieldShape {
    inner: Arc<HfData>,
}

#[derive(Debug)]
struct HfData {
    nrow: usize,
    ncol: usize,
    half_x: f64,
    half_y: f64,
    heights: Vec<f64>,
    radius: f64,
    parry: HeightField,
}

impl PartialEq for HeightFieldShape {
    fn eq(&self, o: &Self) -> bool {
        let (a, b) = (&self.inner, &o.inner);
        Arc::ptr_eq(a, b)
            || (a.nrow == b.nrow
                && a.ncol == b.ncol
                && a.half_x == b.half_x
                && a.half_y == b.half_y
                && a.heights == b.heights)
    }
}

fn bad(field: &'static str, reason: String) -> SimError {
    SimError::BadGeometry { field, reason }
}

impl HeightFieldShape {
    /// A field of `nrow × ncol` heights (each ≥ 2, at most [`MAX_HFIELD_POINTS`]
    /// in all, row-major, finite) over x ∈ [−half_x, half_x], y ∈ [−half_y, half_y].
    pub fn new(nrow: usize, ncol: usize, half_x: f64, half_y: f64, heights: &[f64]) -> Result<Self, SimError> {
        positive("half_x", half_x)?;
        positive("half_y", half_y)?;
        for (field, n) in [("nrow", nrow), ("ncol", ncol)] {
            if n < 2 {
                return Err(bad(field, format!("must be at least 2, got {n}")));
            }
        }
        let points = nrow.checked_mul(ncol).filter(|&p| p <= MAX_HFIELD_POINTS).ok_or_else(|| {
            bad("heights", format!("of {nrow} × {ncol} points are more than the limit of {MAX_HFIELD_POINTS}"))
        })?;
        if heights.len() != points {
            return Err(bad("heights", format!("has {} values, expected nrow × ncol = {points}", heights.len())));
        }
        for &h in heights {
            finite("heights", h)?;
        }
        let hmax = heights.iter().fold(0.0f64, |m, h| m.max(h.abs()));
        let radius = Vec3::new(half_x, half_y, hmax).norm();
        if !radius.is_finite() {
            return Err(bad("heights", format!("and the half sizes {half_x}, {half_y} span more than a finite bound")));
        }
        let grid = Array2::from_fn(nrow, ncol, |i, j| heights[(nrow - 1 - i) * ncol + j]);
        let scale = pvec(Vec3::new(2.0 * half_x, 1.0, 2.0 * half_y));
        let parry = HeightField::with_flags(grid, scale, HeightFieldFlags::FIX_INTERNAL_EDGES);
        Ok(HeightFieldShape {
            inner: Arc::new(HfData { nrow, ncol, half_x, half_y, heights: heights.to_vec(), radius, parry }),
        })
    }

    /// Rows (along y) and columns (along x) of the grid.
    pub fn dims(&self) -> (usize, usize) {
        (self.inner.nrow, self.inner.ncol)
    }
    /// Half the grid's extent along x and along y.
    pub fn half_extents(&self) -> (f64, f64) {
        (self.inner.half_x, self.inner.half_y)
    }
    /// The heights, row-major, row 0 at y = −half_y.
    pub fn heights(&self) -> &[f64] {
        &self.inner.heights
    }
    /// Largest distance of a grid point from the body's origin (a bound).
    pub fn radius(&self) -> f64 {
        self.inner.radius
    }
    pub(crate) fn parry(&self) -> &HeightField {
        &self.inner.parry
    }
}
