//! The LCP data: find `z ≥ 0` with `w = M z + q ≥ 0` and `zᵀw = 0`.
//!
//! `M` is dense and row-major. Construction validates shape and finiteness, so
//! every solver can assume well-formed input and never has to panic on it.

use std::fmt;

use crate::kernels::{all_finite, dot4, dot4_sparse, max_abs_finite, LANES};

/// [`Lcp::w_of`] reads only `z`'s nonzeros when at most `1 /` this fraction
/// of them is nonzero (the dense sweep vectorizes; the sparse one gathers).
const SPARSE_FRACTION: usize = 6;

/// A dense linear complementarity problem `(M, q)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lcp {
    n: usize,
    m: Vec<f64>,
    q: Vec<f64>,
}

/// Why an `(M, q)` pair is not a valid LCP. Invalid input is an error, never a status.
#[derive(Clone, Debug, PartialEq)]
pub enum LcpError {
    /// `n == 0`.
    Empty,
    /// `M` does not hold `n·n` entries.
    NotSquare { entries: usize, n: usize },
    /// `q` does not have length `n`.
    LengthMismatch { q_len: usize, n: usize },
    /// An entry of `M` (`field = "M"`, index `row*n + col`) or `q` is NaN or infinite.
    NonFinite { field: &'static str, index: usize, value: f64 },
}

impl fmt::Display for LcpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LcpError::Empty => write!(f, "the LCP is empty (n = 0)"),
            LcpError::NotSquare { entries, n } => {
                write!(f, "M must be square n×n with n = {n}, got {entries} entries")
            }
            LcpError::LengthMismatch { q_len, n } => {
                write!(f, "q has length {q_len} but M is {n}×{n}")
            }
            LcpError::NonFinite { field, index, value } => write!(f, "{field}[{index}] = {value} is not finite"),
        }
    }
}

impl std::error::Error for LcpError {}

impl Lcp {
    /// Builds an LCP from row-major `m` (n·n entries) and `q` (n entries).
    pub fn new(m: Vec<f64>, q: Vec<f64>) -> Result<Self, LcpError> {
        let n = q.len();
        if n == 0 {
            return Err(LcpError::Empty);
        }
        if m.len() != n * n {
            // Distinguish "q is the wrong length" from "M is not square".
            let side = (m.len() as f64).sqrt().round() as usize;
            if side * side == m.len() && side != 0 {
                return Err(LcpError::LengthMismatch { q_len: n, n: side });
            }
            return Err(LcpError::NotSquare { entries: m.len(), n });
        }
        // A branch-free sweep first; the offending index is looked up only on failure.
        for (field, a) in [("M", &m), ("q", &q)] {
            if !all_finite(a) {
                let (index, &value) = a.iter().enumerate().find(|(_, v)| !v.is_finite()).expect("a non-finite entry");
                return Err(LcpError::NonFinite { field, index, value });
            }
        }
        Ok(Lcp { n, m, q })
    }

    /// The principal sub-LCP on the indices `keep` (each below `n`, in the
    /// order given): `M[keep, keep]`, `q[keep]`, gathered row by row. Its
    /// entries are this LCP's, already checked finite; `Err(Empty)` when
    /// `keep` is empty.
    pub fn principal(&self, keep: &[usize]) -> Result<Self, LcpError> {
        if keep.is_empty() {
            return Err(LcpError::Empty);
        }
        let mut m = Vec::with_capacity(keep.len() * keep.len());
        for &i in keep {
            let row = self.row(i);
            m.extend(keep.iter().map(|&j| row[j]));
        }
        Ok(Lcp::from_parts_unchecked(m, keep.iter().map(|&i| self.q[i]).collect()))
    }

    /// Builds an LCP whose validity the caller guarantees (internal use: a
    /// power-of-two rescaling of a validated problem).
    pub(crate) fn from_parts_unchecked(m: Vec<f64>, q: Vec<f64>) -> Self {
        debug_assert_eq!(m.len(), q.len() * q.len());
        Lcp { n: q.len(), m, q }
    }

    /// Builds an LCP from a closure `m(i, j)`; convenient in tests and generators.
    pub fn from_fn(n: usize, m: impl Fn(usize, usize) -> f64, q: Vec<f64>) -> Result<Self, LcpError> {
        let mut data = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                data.push(m(i, j));
            }
        }
        Lcp::new(data, q)
    }

    /// Problem size.
    #[inline]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Row-major `M`.
    #[inline]
    pub fn m(&self) -> &[f64] {
        &self.m
    }

    /// `q`.
    #[inline]
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// `‖q‖∞`: the scale tolerances on `w` refer to.
    pub fn q_norm_inf(&self) -> f64 {
        max_abs_finite(&self.q, 0.0).0
    }

    /// Entry `M[i, j]`.
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.m[i * self.n + j]
    }

    /// Row `i` of `M`.
    #[inline]
    pub fn row(&self, i: usize) -> &[f64] {
        &self.m[i * self.n..(i + 1) * self.n]
    }

    /// `w = M z + q` (each row's products summed in four lanes).
    /// A `z` with few nonzero entries (a pivoting answer: the nonbasic ones
    /// are 0) is read through its nonzeros only, with the same sums bit for
    /// bit (`kernels::dot4_sparse`).
    pub fn w_of(&self, z: &[f64]) -> Vec<f64> {
        let n = self.n;
        let chunked = n - n % LANES;
        if z.len() == n {
            // (NaN != 0: a NaN in z reaches w as before.)
            let nz: Vec<usize> = (0..chunked).filter(|&j| z[j] != 0.0).collect();
            if nz.len() * SPARSE_FRACTION <= chunked {
                return (0..n).map(|i| dot4_sparse(self.row(i), z, &nz) + self.q[i]).collect();
            }
        }
        (0..n).map(|i| dot4(self.row(i), z) + self.q[i]).collect()
    }

    /// Splits into `(M, q)` without copying.
    pub fn into_parts(self) -> (Vec<f64>, Vec<f64>) {
        (self.m, self.q)
    }
}

/// Dot product; the shared inner kernel of residuals and solvers.
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
