//! The structured LCP `M = G H + K`, `q`: `G` (`n × p`), `H` (`p × n`) and
//! `K` (`n × n`) sparse, `p` small against `n²/nnz`. A contact LCP is one with
//! `G = J` (contact Jacobian rows over the bodies' `p` degrees of freedom),
//! `H = M_b⁻¹ Jᵀ` and `K` the friction-cone blocks; the solver sees only the
//! three sparse matrices.

use super::sparse::Compressed;
use crate::operator::LcpOperator;
use crate::problem::{Lcp, LcpError};
use std::cell::RefCell;

/// An LCP `(G H + K, q)` with sparse `G`, `H`, `K`.
#[derive(Clone, Debug)]
pub struct StructuredLcp {
    n: usize,
    p: usize,
    q: Vec<f64>,
    /// `G` by rows and by columns.
    pub(crate) g_rows: Compressed,
    pub(crate) g_cols: Compressed,
    /// `H` by columns (column `j`: the `p`-vector of `z_j`) and by rows.
    pub(crate) h_cols: Compressed,
    h_rows: Compressed,
    /// `K` by columns and by rows.
    pub(crate) k_cols: Compressed,
    k_rows: Compressed,
    /// Scratch of [`StructuredLcp::row_into`] and of the `p`-space product.
    scratch: RefCell<Scratch>,
    /// Where each entry of `G`, `H`, `K` went, when built to be refilled
    /// ([`StructuredLcp::refillable`]).
    slots: Option<Box<Slots>>,
}

/// The places of the entries in the six compressed matrices, in the order of
/// the fields of [`StructuredLcp`] (`g_rows`, `g_cols`, `h_cols`, `h_rows`, `k_cols`, `k_rows`).
#[derive(Clone, Debug)]
struct Slots([Vec<usize>; 6]);

/// Buffers of the products: a sparse accumulator over `n` and a `p`-vector.
#[derive(Clone, Debug, Default)]
struct Scratch {
    acc: Vec<f64>,
    mark: Vec<bool>,
    touched: Vec<usize>,
    u: Vec<f64>,
}

/// A sparse entry `(row, column, value)`.
pub type Entry = (usize, usize, f64);

impl Scratch {
    fn new(n: usize, p: usize) -> Self {
        Scratch { acc: vec![0.0; n], mark: vec![false; n], touched: Vec::new(), u: vec![0.0; p] }
    }
}

/// The entries of the transpose.
fn transposed(e: &[Entry]) -> impl ExactSizeIterator<Item = Entry> + Clone + '_ {
    e.iter().map(|&(r, c, v)| (c, r, v))
}

/// Errors of `G` (`n × p`), `H` (`p × n`), `K` (`n × n`) and `q`: an empty
/// problem, an index out of range, a non-finite value.
fn check(n: usize, p: usize, g: &[Entry], h: &[Entry], k: &[Entry], q: &[f64]) -> Result<(), LcpError> {
    if n == 0 {
        return Err(LcpError::Empty);
    }
    for (field, entries, rows, cols) in [("G", g, n, p), ("H", h, p, n), ("K", k, n, n)] {
        for (index, &(r, c, v)) in entries.iter().enumerate() {
            if r >= rows || c >= cols {
                return Err(LcpError::NotSquare { entries: r.max(c) + 1, n: rows.max(cols) });
            }
            if !v.is_finite() {
                return Err(LcpError::NonFinite { field, index, value: v });
            }
        }
    }
    if let Some((index, &value)) = q.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LcpError::NonFinite { field: "q", index, value });
    }
    Ok(())
}

impl StructuredLcp {
    /// `M = G H + K` from the entries of `G` (`n × p`), `H` (`p × n`) and
    /// `K` (`n × n`) (repeated entries are summed) and `q` (length `n`).
    /// Errors on an empty problem, an index out of range or a non-finite value.
    pub fn new(p: usize, g: &[Entry], h: &[Entry], k: &[Entry], q: Vec<f64>) -> Result<Self, LcpError> {
        let n = q.len();
        check(n, p, g, h, k, &q)?;
        let transpose = |e: &[Entry]| e.iter().map(|&(r, c, v)| (c, r, v)).collect::<Vec<_>>();
        Ok(StructuredLcp {
            n,
            p,
            g_rows: Compressed::new(n, g),
            g_cols: Compressed::new(p, &transpose(g)),
            h_cols: Compressed::new(n, &transpose(h)),
            h_rows: Compressed::new(p, h),
            k_cols: Compressed::new(n, &transpose(k)),
            k_rows: Compressed::new(n, k),
            scratch: RefCell::new(Scratch::new(n, p)),
            q,
            slots: None,
        })
    }

    /// [`StructuredLcp::new`], keeping where each entry went so that
    /// [`StructuredLcp::refill`] can give it new values in place: a
    /// simulator's LCP keeps its sparsity from step to step while its
    /// contacts do (only `J` and `M_b⁻¹` move), and the sorting of the six
    /// compressed matrices was a fifth of a settled heap's step.
    pub fn refillable(p: usize, g: &[Entry], h: &[Entry], k: &[Entry], q: Vec<f64>) -> Result<Self, LcpError> {
        let n = q.len();
        check(n, p, g, h, k, &q)?;
        let t = transposed;
        let (g_rows, s0) = Compressed::with_slots(n, g.iter().copied());
        let (g_cols, s1) = Compressed::with_slots(p, t(g));
        let (h_cols, s2) = Compressed::with_slots(n, t(h));
        let (h_rows, s3) = Compressed::with_slots(p, h.iter().copied());
        let (k_cols, s4) = Compressed::with_slots(n, t(k));
        let (k_rows, s5) = Compressed::with_slots(n, k.iter().copied());
        Ok(StructuredLcp {
            n,
            p,
            g_rows,
            g_cols,
            h_cols,
            h_rows,
            k_cols,
            k_rows,
            scratch: RefCell::new(Scratch::new(n, p)),
            q,
            slots: Some(Box::new(Slots([s0, s1, s2, s3, s4, s5]))),
        })
    }

    /// New values for an operator built by [`StructuredLcp::refillable`]
    /// from entries at the same `(row, column)` places, in the same order:
    /// the result is the operator [`StructuredLcp::new`] would build from
    /// them, to the bit. `Ok(false)`, the operator then unusable until
    /// refilled or rebuilt, when it was not built so or the places differ;
    /// an error on a non-finite value or a `q` of another length.
    pub fn refill(&mut self, g: &[Entry], h: &[Entry], k: &[Entry], q: &[f64]) -> Result<bool, LcpError> {
        if q.len() != self.n {
            return Err(LcpError::LengthMismatch { q_len: q.len(), n: self.n });
        }
        check(self.n, self.p, g, h, k, q)?;
        let Some(s) = self.slots.as_deref() else { return Ok(false) };
        let t = transposed;
        let ok = self.g_rows.refill(&s.0[0], g.iter().copied())
            && self.g_cols.refill(&s.0[1], t(g))
            && self.h_cols.refill(&s.0[2], t(h))
            && self.h_rows.refill(&s.0[3], h.iter().copied())
            && self.k_cols.refill(&s.0[4], t(k))
            && self.k_rows.refill(&s.0[5], k.iter().copied());
        if ok {
            self.q.copy_from_slice(q);
        }
        Ok(ok)
    }

    /// The same `M` with another `q` (same length, finite).
    pub fn with_q(&self, q: Vec<f64>) -> Result<Self, LcpError> {
        if q.len() != self.n {
            return Err(LcpError::LengthMismatch { q_len: q.len(), n: self.n });
        }
        if let Some((index, &value)) = q.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(LcpError::NonFinite { field: "q", index, value });
        }
        Ok(StructuredLcp { q, ..self.clone() })
    }

    /// The principal sub-LCP on the unknowns `keep` (ascending, no repeats):
    /// `M[keep, keep] = G[keep, :]·H[:, keep] + K[keep, keep]`, `q[keep]`;
    /// unknown `i` of the result is `keep[i]`. Same `p`. O(nnz): the six
    /// compressed matrices are cut from this one's, the operator
    /// [`StructuredLcp::new`] builds from the kept entries, to the bit.
    pub fn restrict(&self, keep: &[usize]) -> Result<Self, LcpError> {
        if keep.is_empty() {
            return Err(LcpError::Empty);
        }
        let mut new_of = vec![usize::MAX; self.n];
        for (i, &j) in keep.iter().enumerate() {
            if j >= self.n || (i > 0 && j <= keep[i - 1]) {
                return Err(LcpError::NotSquare { entries: j + 1, n: self.n });
            }
            new_of[j] = i;
        }
        let (n, p) = (keep.len(), self.p);
        let all: Vec<usize> = (0..p).collect();
        let kept = || keep.iter().copied();
        Ok(StructuredLcp {
            n,
            p,
            g_rows: self.g_rows.restricted(kept(), &all),
            g_cols: self.g_cols.restricted(0..p, &new_of),
            h_cols: self.h_cols.restricted(kept(), &all),
            h_rows: self.h_rows.restricted(0..p, &new_of),
            k_cols: self.k_cols.restricted(kept(), &new_of),
            k_rows: self.k_rows.restricted(kept(), &new_of),
            scratch: RefCell::new(Scratch::new(n, p)),
            q: kept().map(|j| self.q[j]).collect(),
            slots: None,
        })
    }

    /// Size `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Inner dimension `p` (the bodies' degrees of freedom for a contact LCP).
    pub fn p(&self) -> usize {
        self.p
    }

    /// The vector `q`.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// `‖q‖∞`.
    pub fn q_norm_inf(&self) -> f64 {
        self.q.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    }

    /// `u = H z` over the leading entries of `z` given (the rest taken as 0), `u` of length `p`. O(nnz(H)).
    pub(crate) fn h_times(&self, z: &[f64], u: &mut [f64]) {
        u.iter_mut().for_each(|v| *v = 0.0);
        for (j, &zj) in z.iter().enumerate() {
            if zj != 0.0 {
                self.h_cols.axpy(j, zj, u);
            }
        }
    }

    /// `w = M z + q`: `u = H z`, `w = G u + K z + q`. O(nnz).
    pub fn w_of(&self, z: &[f64], w: &mut [f64]) {
        let mut guard = self.scratch.borrow_mut();
        let u = &mut guard.u;
        self.h_times(z, u);
        for (i, wi) in w.iter_mut().enumerate() {
            *wi = self.q[i] + self.g_rows.dot(i, u) + self.k_rows.dot(i, z);
        }
    }

    /// Row `i` of `M` as `(column, value)` pairs (structural nonzeros, in no
    /// particular order) appended to `out` after clearing it.
    pub fn row_into(&self, i: usize, out: &mut Vec<(usize, f64)>) {
        out.clear();
        let mut guard = self.scratch.borrow_mut();
        let Scratch { acc, mark, touched, .. } = &mut *guard;
        let mut add = |j: usize, v: f64| {
            if !mark[j] {
                mark[j] = true;
                touched.push(j);
            }
            acc[j] += v;
        };
        for (k, gik) in self.g_rows.iter(i) {
            for (j, hkj) in self.h_rows.iter(k) {
                add(j, gik * hkj);
            }
        }
        for (j, v) in self.k_rows.iter(i) {
            add(j, v);
        }
        for &j in touched.iter() {
            out.push((j, acc[j]));
            (acc[j], mark[j]) = (0.0, false);
        }
        touched.clear();
    }

    /// Entry `M_ij`.
    pub fn at(&self, i: usize, j: usize) -> f64 {
        let gh: f64 = self.g_rows.iter(i).map(|(k, g)| g * self.h_cols.get(j, k)).sum();
        gh + self.k_cols.get(j, i)
    }

    /// The dense LCP (for tests and small problems): O(n²) memory.
    pub fn to_dense(&self) -> Lcp {
        let n = self.n;
        let mut m = vec![0.0; n * n];
        let mut row = Vec::new();
        for i in 0..n {
            self.row_into(i, &mut row);
            for &(j, v) in &row {
                m[i * n + j] = v;
            }
        }
        Lcp::new(m, self.q.clone()).expect("finite entries make a finite dense M")
    }
}

impl LcpOperator for StructuredLcp {
    fn n(&self) -> usize {
        self.n
    }
    fn q(&self) -> &[f64] {
        &self.q
    }
    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]) {
        for (r, &i) in rows.iter().enumerate() {
            for (c, &j) in cols.iter().enumerate() {
                out[r * cols.len() + c] = self.at(i, j);
            }
        }
    }
    fn w_of(&self, z: &[f64], w: &mut [f64]) {
        StructuredLcp::w_of(self, z, w)
    }
}
