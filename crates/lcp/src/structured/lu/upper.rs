//! The `U` side of the basis LU, updated in place by Forrest–Tomlin.
//!
//! After `P A Q = L U`, replacing column `k` of `A Q` by `a` leaves
//! `L⁻¹ P a` (the *spike* `s`, a by-product of the entering column's solve)
//! in column `k` of `U`. Forrest & Tomlin (1972) move column and row `k` to
//! the end of the triangular order, which leaves one row out of shape: row
//! `k`, with its old entries in the columns after `k`. Those are eliminated
//! by the rows after `k`; the multipliers are kept as one row
//! transformation `R` (`t_k += Σ c_j t_j`), applied between `L` and `U` in
//! every later solve, and the spike becomes column `k`, last in the order,
//! with diagonal `(R s)_k`. `L` never changes.
//!
//! Why Forrest–Tomlin rather than the product form (an eta column per
//! pivot) it replaces, or Bartels–Golub: a solve costs the factors'
//! nonzeros plus one short row per update, where an eta column of a heap's
//! basis is as long as the basis (`B⁻¹` of a connected heap is dense; the
//! spike `L⁻¹ a` is much shorter: measured in `super::super::factor`'s
//! docs); and unlike Bartels–Golub it needs no row interchanges inside `U`,
//! so `U` stays column-wise and only the order changes. Stability is
//! watched rather than forced: the new diagonal must equal `y_r · u_kk`
//! (`y = B⁻¹ a`, the determinant's ratio) to [`DIAG_TOL`], else the caller
//! refactors.
//!
//! The elimination needs `U` by rows: the fresh factor's rows are copied
//! once per factorization, and each spike's entries are linked into their
//! rows' lists; an entry is dead once its column is replaced or its row
//! eliminated (stamps, no search). The elimination then visits only the
//! rows it uses, earliest first (a heap on the order), as in Suhl & Suhl
//! (1993). (A transposed solve by columns instead, `cᵀ U = 0` by dot
//! products, visits every column after `k`: twice the instructions of the
//! whole solve on a 52-cube heap's LCP, n = 1,440.)

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The order's mark for a column that has moved to the end.
const GONE: u32 = u32::MAX;

/// The end of a row's list of spike entries.
const NONE: u32 = u32::MAX;

/// Largest relative gap between the updated diagonal `(R s)_k` and
/// `y_r · u_kk` (equal in exact arithmetic) for an update to be kept.
pub(super) const DIAG_TOL: f64 = 1e-9;

/// Why an update was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UpdateError {
    /// The new column makes the basis singular (a zero pivot `y_r`, or a zero new diagonal).
    Singular,
    /// The new diagonal disagrees with `y_r · u_kk` beyond [`DIAG_TOL`]: round-off has grown.
    Unstable,
}

/// One row transformation: `t[row] += Σ val[e] · t[idx[e]]`, `e` in `start..end`.
struct RowEta {
    row: usize,
    start: usize,
    end: usize,
}

/// An entry `(i, col)` of a spike, in row `i`'s list: alive while column
/// `col` is the spike of update `stamp` and row `i` has not been
/// eliminated since.
struct Node {
    col: u32,
    stamp: u32,
    val: f64,
    next: u32,
}

/// `U` by columns, each column's off-diagonal entries in `start[j]..end[j]`
/// of the flat buffers (a replaced column's old entries stay there unused
/// until the next factorization), its diagonal apart; columns in the
/// triangular order `order`; and the row transformations of the updates.
#[derive(Default)]
pub(super) struct Upper {
    start: Vec<usize>,
    end: Vec<usize>,
    idx: Vec<u32>,
    val: Vec<f64>,
    diag: Vec<f64>,
    inv_diag: Vec<f64>,
    /// Columns in triangular order (each column's entries lie in rows of
    /// columns before it), [`GONE`] where a column has moved to the end.
    order: Vec<u32>,
    /// Place of each column in `order`.
    at: Vec<usize>,
    /// The fresh factor's off-diagonal entries by rows.
    rptr: Vec<usize>,
    rcol: Vec<u32>,
    rval: Vec<f64>,
    /// Per row, its spike entries ([`Node`]s, newest first).
    shead: Vec<u32>,
    nodes: Vec<Node>,
    /// Updates so far; per column the update that last replaced it, per row
    /// the one that last eliminated it (0: none).
    stamp: u32,
    col_stamp: Vec<u32>,
    row_stamp: Vec<u32>,
    etas: Vec<RowEta>,
    eidx: Vec<u32>,
    eval: Vec<f64>,
    /// Workspaces of an update: the row being eliminated (all 0 between
    /// updates), the columns to visit in order, row `k`'s entries.
    w: Vec<f64>,
    heap: BinaryHeap<Reverse<(usize, usize)>>,
    row_k: Vec<(usize, f64)>,
}

impl Upper {
    /// A fresh `U` from its columns (`ptr`, `idx`, `val`), each column's
    /// diagonal stored last, in the natural order.
    pub(super) fn fresh(&mut self, ptr: &[usize], idx: &[usize], val: &[f64]) {
        let m = ptr.len() - 1;
        self.start.clear();
        self.end.clear();
        self.idx.clear();
        self.val.clear();
        self.diag.clear();
        self.inv_diag.clear();
        self.rptr.clear();
        self.rptr.resize(m + 1, 0);
        for j in 0..m {
            let (a, b) = (ptr[j], ptr[j + 1] - 1);
            self.start.push(self.idx.len());
            for (&i, &v) in idx[a..b].iter().zip(&val[a..b]) {
                self.idx.push(i as u32);
                self.val.push(v);
                self.rptr[i + 1] += 1;
            }
            self.end.push(self.idx.len());
            self.diag.push(val[b]);
            self.inv_diag.push(val[b].recip());
        }
        self.order.clear();
        self.order.extend(0..m as u32);
        self.at.clear();
        self.at.extend(0..m);
        self.etas.clear();
        self.eidx.clear();
        self.eval.clear();
        self.w.clear();
        self.w.resize(m, 0.0);
        // The rows: a counting sort of the columns' entries.
        for i in 0..m {
            self.rptr[i + 1] += self.rptr[i];
        }
        let mut next = self.rptr.clone();
        self.rcol.clear();
        self.rcol.resize(self.idx.len(), 0);
        self.rval.clear();
        self.rval.resize(self.idx.len(), 0.0);
        for j in 0..m {
            for e in self.start[j]..self.end[j] {
                let i = self.idx[e] as usize;
                self.rcol[next[i]] = j as u32;
                self.rval[next[i]] = self.val[e];
                next[i] += 1;
            }
        }
        self.shead.clear();
        self.shead.resize(m, NONE);
        self.nodes.clear();
        self.stamp = 0;
        self.col_stamp.clear();
        self.col_stamp.resize(m, 0);
        self.row_stamp.clear();
        self.row_stamp.resize(m, 0);
    }

    /// Column replacements since the fresh factor.
    pub(super) fn updates(&self) -> usize {
        self.order.len() - self.at.len()
    }

    /// `t ← R t`: the updates' row transformations, oldest first.
    #[inline]
    pub(super) fn apply_etas(&self, t: &mut [f64]) {
        for e in &self.etas {
            let r = e.start..e.end;
            let s: f64 = self.eidx[r.clone()].iter().zip(&self.eval[r]).map(|(&j, &c)| c * t[j as usize]).sum();
            t[e.row] += s;
        }
    }

    /// `t ← U⁻¹ t`, columns last to first in the triangular order, skipping
    /// those whose unknown is 0.
    #[inline(never)]
    pub(super) fn solve(&self, t: &mut [f64]) {
        for &j in self.order.iter().rev() {
            if j == GONE {
                continue;
            }
            let j = j as usize;
            if t[j] != 0.0 {
                let tj = t[j] * self.inv_diag[j];
                t[j] = tj;
                let r = self.start[j]..self.end[j];
                for (&i, &v) in self.idx[r.clone()].iter().zip(&self.val[r]) {
                    t[i as usize] -= v * tj;
                }
            }
        }
    }

    /// Calls `f(column, value)` for each entry of row `i` beyond the diagonal.
    fn row(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        if self.row_stamp[i] == 0 {
            let r = self.rptr[i]..self.rptr[i + 1];
            for (&j, &v) in self.rcol[r.clone()].iter().zip(&self.rval[r]) {
                if self.col_stamp[j as usize] == 0 {
                    f(j as usize, v);
                }
            }
        }
        let mut e = self.shead[i];
        while e != NONE {
            let node = &self.nodes[e as usize];
            if self.col_stamp[node.col as usize] == node.stamp && self.row_stamp[i] < node.stamp {
                f(node.col as usize, node.val);
            }
            e = node.next;
        }
    }

    /// Replaces column `k` by the spike `s` (dense, `R L⁻¹ P a` of the
    /// entering column `a`), given `y_k` of the same column's full solve.
    /// On an error nothing has changed.
    pub(super) fn replace(&mut self, k: usize, s: &[f64], yk: f64) -> Result<(), UpdateError> {
        if yk == 0.0 || !yk.is_finite() {
            return Err(UpdateError::Singular);
        }
        let eta_start = self.eidx.len();
        let mut d = s[k];
        // Row k beyond the diagonal, eliminated by the rows after k in
        // order (earliest first): w += c_j · row j, c_j = −w_j / u_jj.
        let mut w = std::mem::take(&mut self.w);
        let mut heap = std::mem::take(&mut self.heap);
        let mut row_k = std::mem::take(&mut self.row_k);
        row_k.clear();
        self.row(k, |j, v| row_k.push((j, v)));
        for &(j, v) in &row_k {
            if w[j] == 0.0 {
                heap.push(Reverse((self.at[j], j)));
            }
            w[j] += v;
        }
        while let Some(Reverse((_, j))) = heap.pop() {
            let wj = std::mem::replace(&mut w[j], 0.0);
            if wj == 0.0 {
                continue;
            }
            let cj = -wj * self.inv_diag[j];
            self.eidx.push(j as u32);
            self.eval.push(cj);
            d += cj * s[j];
            self.row(j, |l, v| {
                if w[l] == 0.0 {
                    heap.push(Reverse((self.at[l], l)));
                }
                w[l] += cj * v;
                // A cancellation to exactly 0 leaves l in the heap: popped as 0 and skipped.
            });
        }
        (self.w, self.heap) = (w, heap);
        let expected = yk * self.diag[k];
        let refused = if d == 0.0 || !d.is_finite() {
            Some(UpdateError::Singular)
        } else if (d - expected).abs() > DIAG_TOL * d.abs().max(expected.abs()) {
            Some(UpdateError::Unstable)
        } else {
            None
        };
        if let Some(err) = refused {
            self.eidx.truncate(eta_start);
            self.eval.truncate(eta_start);
            self.row_k = row_k;
            return Err(err);
        }
        self.stamp += 1;
        let t = self.stamp;
        if self.eidx.len() > eta_start {
            self.etas.push(RowEta { row: k, start: eta_start, end: self.eidx.len() });
        }
        // Row k leaves the columns after it (one entry per column; a
        // swap-remove keeps each column contiguous).
        for &(j, _) in &row_k {
            if let Some(e) = (self.start[j]..self.end[j]).find(|&e| self.idx[e] as usize == k) {
                let last = self.end[j] - 1;
                self.idx[e] = self.idx[last];
                self.val[e] = self.val[last];
                self.end[j] = last;
            }
        }
        self.row_k = row_k;
        self.row_stamp[k] = t;
        // Column k leaves; the spike comes last.
        self.col_stamp[k] = t;
        self.order[self.at[k]] = GONE;
        self.start[k] = self.idx.len();
        for (i, &v) in s.iter().enumerate() {
            if v != 0.0 && i != k {
                self.idx.push(i as u32);
                self.val.push(v);
                self.nodes.push(Node { col: k as u32, stamp: t, val: v, next: self.shead[i] });
                self.shead[i] = (self.nodes.len() - 1) as u32;
            }
        }
        self.end[k] = self.idx.len();
        self.diag[k] = d;
        self.inv_diag[k] = d.recip();
        self.at[k] = self.order.len();
        self.order.push(k as u32);
        Ok(())
    }
}
