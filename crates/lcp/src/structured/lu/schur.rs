//! Column replacements of a factored matrix kept beside its LU, as a Schur
//! complement (block LU; the idea of LUMOD and of Siconos' `lcp_pivot_lumod`).
//!
//! Let `B₀` be the factored matrix and `B` the same with the columns at the
//! positions `S = (r_1 … r_s)` replaced by `a_1 … a_s`. With `Z = B₀⁻¹ A_S`
//! (column `j`: the fresh solve of `a_j`) and `C = Z[S, :]` (`s × s`),
//!
//! ```text
//!   B⁻¹ x = x₀ − (Z − E_S) C⁻¹ x₀[S],   x₀ = B₀⁻¹ x,
//! ```
//!
//! (Woodbury: `B₀⁻¹ B = I + (Z − E_S) E_Sᵀ`). A solve costs the fresh LU's
//! solve, `s` sparse updates by the columns of `Z` and `s²` for `C⁻¹`.
//!
//! Why not the product form it replaces (each pivot's `B⁻¹ a` as an eta
//! column) nor Forrest–Tomlin: on a heap's basis `B⁻¹ a` is dense (every
//! entry of it on a 52-cube heap, n = 1,440), so an eta column is as long as
//! the basis and a solve after `k` pivots streams `k` of them; a Forrest–Tomlin
//! spike is short, but its entries reach the whole of `U`, and the updated
//! `U`'s solves became dense passes over it: 538M instructions against
//! 318M for that heap's solve (measured on this branch, its first commit). The
//! columns of `Z` are solves with the fresh factors only, sparse as they are.
//!
//! `C⁻¹` is kept explicitly (`s` is at most the refactorization interval)
//! and updated in `O(s²)`: bordered by a new position, or a column replaced
//! where a position is replaced again. Its determinant's ratio is the pivot
//! `y_r` (`det B = det B₀ · det C`): an update whose computed ratio differs
//! from `y_r` by more than [`RATIO_TOL`] is refused (round-off has grown; the
//! caller refactors), and a zero ratio is a singular basis.

use std::cell::RefCell;

/// Largest relative gap between an update's determinant ratio and the pivot
/// `y_r` (equal in exact arithmetic) for the update to be kept.
const RATIO_TOL: f64 = 1e-9;

/// A slot-free position.
const FREE: usize = usize::MAX;

/// Why an update was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UpdateError {
    /// The new matrix is singular (a zero pivot `y_r`, or a zero determinant ratio).
    Singular,
    /// The determinant ratio disagrees with `y_r` beyond [`RATIO_TOL`]: round-off has grown.
    Unstable,
}

/// One column of `Z`: its entries `idx`/`val[start..end]` (rows ascending),
/// or, when `dense`, all of it in `val[start..end]`.
#[derive(Clone, Copy)]
struct ZCol {
    start: usize,
    end: usize,
    dense: bool,
}

/// The replacements since the factorization.
#[derive(Default)]
pub(super) struct Schur {
    m: usize,
    /// Position of each slot (`S`), and the slot of each position ([`FREE`] if none).
    pos: Vec<usize>,
    slot: Vec<usize>,
    zcols: Vec<ZCol>,
    /// Entries of `Z`'s columns (a replaced column's stay unused until the next reset).
    zidx: Vec<u32>,
    zval: Vec<f64>,
    /// `C⁻¹`, row-major with row stride `cap`.
    cinv: Vec<f64>,
    cap: usize,
    updates: usize,
    /// Workspaces: `x₀[S]` and `C⁻¹ x₀[S]`; a row of `C⁻¹`.
    gv: RefCell<(Vec<f64>, Vec<f64>)>,
    row: Vec<f64>,
}

impl Schur {
    /// No replacement, over `m` positions.
    pub(super) fn reset(&mut self, m: usize) {
        self.m = m;
        self.pos.clear();
        self.slot.clear();
        self.slot.resize(m, FREE);
        self.zcols.clear();
        self.zidx.clear();
        self.zval.clear();
        self.cap = 0;
        self.cinv.clear();
        self.updates = 0;
    }

    /// Replacements since the reset.
    pub(super) fn updates(&self) -> usize {
        self.updates
    }

    /// `Z`'s column of slot `j` at row `r`.
    fn z_at(&self, j: usize, r: usize) -> f64 {
        let c = self.zcols[j];
        if c.dense {
            return self.zval[c.start + r];
        }
        let idx = &self.zidx[c.start..c.end];
        idx.binary_search(&(r as u32)).map_or(0.0, |k| self.zval[c.start + k])
    }

    /// `x ← x − (Z − E_S) C⁻¹ x[S]`: from the fresh solve `x₀` to the solve with the replacements.
    pub(super) fn apply(&self, x: &mut [f64]) {
        let s = self.pos.len();
        if s == 0 {
            return;
        }
        let mut gv = self.gv.borrow_mut();
        let (g, v) = &mut *gv;
        g.clear();
        g.extend(self.pos.iter().map(|&r| x[r]));
        v.clear();
        v.extend((0..s).map(|a| {
            let row = &self.cinv[a * self.cap..a * self.cap + s];
            row.iter().zip(g.iter()).map(|(c, gi)| c * gi).sum::<f64>()
        }));
        for (j, &vj) in v.iter().enumerate() {
            if vj == 0.0 {
                continue;
            }
            let c = self.zcols[j];
            let vals = &self.zval[c.start..c.end];
            if c.dense {
                for (xi, &z) in x.iter_mut().zip(vals) {
                    *xi -= z * vj;
                }
            } else {
                for (&i, &z) in self.zidx[c.start..c.end].iter().zip(vals) {
                    x[i as usize] -= z * vj;
                }
            }
        }
        // At the replaced positions the answer is `v` (`x₀[S] − C v + v`).
        for (&r, &vj) in self.pos.iter().zip(v.iter()) {
            x[r] = vj;
        }
    }

    /// Position `r` takes the column whose fresh solve is `z` (length `m`);
    /// `yr` is entry `r` of its solve with the replacements so far. On an
    /// error nothing has changed.
    pub(super) fn replace(&mut self, r: usize, z: &[f64], yr: f64) -> Result<(), UpdateError> {
        if yr == 0.0 || !yr.is_finite() {
            return Err(UpdateError::Singular);
        }
        let s = self.pos.len();
        let cap = self.cap;
        // w = C⁻¹ z[S].
        let (mut g, mut w) = self.gv.take();
        g.clear();
        g.extend(self.pos.iter().map(|&p| z[p]));
        w.clear();
        w.extend((0..s).map(|a| self.cinv[a * cap..a * cap + s].iter().zip(&g).map(|(c, gi)| c * gi).sum::<f64>()));
        let result = match self.slot[r] {
            FREE => self.border(r, z, yr, &w),
            i => self.swap_column(i, z, yr, &w),
        };
        self.gv = RefCell::new((g, w));
        result?;
        self.updates += 1;
        Ok(())
    }

    /// `Ok` when the ratio `sigma` is usable, given the pivot `yr`.
    fn check(sigma: f64, yr: f64) -> Result<(), UpdateError> {
        if sigma == 0.0 || !sigma.is_finite() {
            Err(UpdateError::Singular)
        } else if (sigma - yr).abs() > RATIO_TOL * sigma.abs().max(yr.abs()) {
            Err(UpdateError::Unstable)
        } else {
            Ok(())
        }
    }

    /// A new slot for position `r`: `C` bordered by the new column `z[S ∪ r]`
    /// and the row `Z[r, :]`, `w = C⁻¹ z[S]`.
    fn border(&mut self, r: usize, z: &[f64], yr: f64, w: &[f64]) -> Result<(), UpdateError> {
        let s = self.pos.len();
        // d = Z[r, :], vt = dᵀ C⁻¹, sigma = z_r − d·w (the Schur complement).
        let d: Vec<f64> = (0..s).map(|j| self.z_at(j, r)).collect();
        let sigma = z[r] - d.iter().zip(w).map(|(a, b)| a * b).sum::<f64>();
        Self::check(sigma, yr)?;
        let mut vt = std::mem::take(&mut self.row);
        vt.clear();
        vt.resize(s, 0.0);
        for (a, &da) in d.iter().enumerate() {
            if da != 0.0 {
                let row = &self.cinv[a * self.cap..a * self.cap + s];
                vt.iter_mut().zip(row).for_each(|(t, c)| *t += da * c);
            }
        }
        if s + 1 > self.cap {
            self.grow(2 * (s + 1));
        }
        let cap = self.cap;
        // [C b; dᵀ e]⁻¹ = [C⁻¹ + w vtᵀ/σ, −w/σ; −vtᵀ/σ, 1/σ].
        let inv = sigma.recip();
        for a in 0..s {
            let wa = w[a] * inv;
            let row = &mut self.cinv[a * cap..a * cap + s];
            row.iter_mut().zip(&vt).for_each(|(c, t)| *c += wa * t);
            self.cinv[a * cap + s] = -wa;
        }
        for b in 0..s {
            self.cinv[s * cap + b] = -vt[b] * inv;
        }
        self.cinv[s * cap + s] = inv;
        self.row = vt;
        self.pos.push(r);
        self.slot[r] = s;
        let col = self.store(z);
        self.zcols.push(col);
        Ok(())
    }

    /// Slot `i` (its position replaced again) takes the column `z`:
    /// `C`'s column `i` becomes `z[S]`, `w = C⁻¹ z[S]`.
    fn swap_column(&mut self, i: usize, z: &[f64], yr: f64, w: &[f64]) -> Result<(), UpdateError> {
        let s = self.pos.len();
        let cap = self.cap;
        let sigma = w[i];
        Self::check(sigma, yr)?;
        // C'⁻¹ = C⁻¹ − (w − e_i) (row i of C⁻¹) / σ.
        let mut row = std::mem::take(&mut self.row);
        row.clear();
        row.extend_from_slice(&self.cinv[i * cap..i * cap + s]);
        let inv = sigma.recip();
        for a in 0..s {
            let f = (w[a] - if a == i { 1.0 } else { 0.0 }) * inv;
            if f != 0.0 {
                let dst = &mut self.cinv[a * cap..a * cap + s];
                dst.iter_mut().zip(&row).for_each(|(c, t)| *c -= f * t);
            }
        }
        self.row = row;
        self.zcols[i] = self.store(z);
        Ok(())
    }

    /// `C⁻¹`'s row stride raised to `cap`, its entries kept.
    fn grow(&mut self, cap: usize) {
        let s = self.pos.len();
        let mut bigger = vec![0.0; cap * cap];
        for a in 0..s {
            bigger[a * cap..a * cap + s].copy_from_slice(&self.cinv[a * self.cap..a * self.cap + s]);
        }
        self.cinv = bigger;
        self.cap = cap;
    }

    /// `z` appended to `Z`'s entries: sparse, or dense when at least half of it is nonzero.
    fn store(&mut self, z: &[f64]) -> ZCol {
        let nnz = z.iter().filter(|&&v| v != 0.0).count();
        let dense = 2 * nnz >= z.len();
        let start = self.zval.len();
        if dense {
            self.zval.extend_from_slice(z);
            // Dense columns keep no indices: pad so that sparse ones' stay aligned with their values.
            self.zidx.resize(self.zval.len(), 0);
        } else {
            for (i, &v) in z.iter().enumerate() {
                if v != 0.0 {
                    self.zidx.push(i as u32);
                    self.zval.push(v);
                }
            }
        }
        ZCol { start, end: self.zval.len(), dense }
    }
}
