//! Where the unknowns of a contact LCP live, and the two maps every user of
//! one needs: the friction-cone scaling and the source note's sign pattern.
//!
//! ```text
//! z = [ fn (nc) ; fd (nc·k) ; λ (nc) ]      n = nc·(k + 2)
//! ```
//!
//! `fd` is contact-major: `fd[c·k + j]` is contact `c`'s impulse along `d_j`.
//! The solver never needs this (it sees an `Lcp`); the simulator's assembly,
//! the generators, the Python glue and the experiments do, and they all read
//! it from [`ContactLayout`] instead of writing `nc·(k + 1)` themselves.
//!
//! **Cone scaling**: the scaled problem is `D M D, D q` with
//! `D = diag(I, I, s·I)`; `fn`, `fd` are unchanged and `λ = s·λ_scaled`.
//!
//! **Sign pattern** of contact `c`: whether `fn_c`, `Σ_j fd_cj` and `λ_c` of a
//! physical `z` are positive. The one zero rule: a value is positive when it
//! is *strictly greater* than its threshold — the impulse threshold for `fn`
//! and `Σ fd` (N·s), the velocity threshold for `λ` (m/s); see [`ZeroLevels`].

use std::ops::Range;

use crate::problem::{Lcp, LcpError};
use crate::scaling::Scaling;

/// The layout of `z = [fn (nc); fd (nc·k); λ (nc)]` (the default: no contacts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ContactLayout {
    /// Number of contacts.
    pub nc: usize,
    /// Friction directions per contact.
    pub k: usize,
}

impl ContactLayout {
    pub fn new(nc: usize, k: usize) -> Self {
        ContactLayout { nc, k }
    }

    /// LCP size `nc·(k + 2)` (10·nc for k = 8).
    pub fn n(&self) -> usize {
        self.nc * (self.k + 2)
    }
    /// Size of the `[fn; fd]` part, the rows and columns of `A = J M_b⁻¹ Jᵀ`: `nc·(k + 1)`.
    pub fn impulses(&self) -> usize {
        self.nc * (self.k + 1)
    }
    /// Indices of `fn`.
    pub fn fn_range(&self) -> Range<usize> {
        0..self.nc
    }
    /// Indices of `fd`.
    pub fn fd_range(&self) -> Range<usize> {
        self.nc..self.impulses()
    }
    /// Indices of `λ`.
    pub fn lambda_range(&self) -> Range<usize> {
        self.impulses()..self.n()
    }
    /// Index of `fn` of contact `c`.
    #[inline]
    pub fn fn_index(&self, c: usize) -> usize {
        c
    }
    /// Indices of contact `c`'s `fd` (length `k`).
    #[inline]
    pub fn fd_of(&self, c: usize) -> Range<usize> {
        self.nc + c * self.k..self.nc + (c + 1) * self.k
    }
    /// Index of `fd` for direction `j` at contact `c`.
    #[inline]
    pub fn fd_index(&self, c: usize, j: usize) -> usize {
        self.nc + c * self.k + j
    }
    /// Index of `λ` of contact `c`.
    #[inline]
    pub fn lambda_index(&self, c: usize) -> usize {
        self.impulses() + c
    }
    /// The contact whose unknown is `z[i]` (`i < n`).
    pub fn contact_of(&self, i: usize) -> usize {
        if i < self.nc {
            i
        } else if i < self.impulses() {
            (i - self.nc) / self.k
        } else {
            i - self.impulses()
        }
    }

    /// The diagonal of `D = diag(I_nc, I_{nc·k}, s·I_nc)`.
    pub fn cone_diagonal(&self, s: f64) -> Vec<f64> {
        let mut d = vec![1.0; self.impulses()];
        d.resize(self.n(), s);
        d
    }
    /// `D` on both sides, as a [`Scaling`].
    pub fn cone_scaling(&self, s: f64) -> Scaling {
        let d = self.cone_diagonal(s);
        Scaling { row: d.clone(), col: d }
    }
    /// The scaled problem `(D M D, D q)` of an unscaled (`s = 1`) contact LCP.
    /// Fails when `lcp` is not of size `n` or an entry overflows.
    pub fn scale_lcp(&self, lcp: &Lcp, s: f64) -> Result<Lcp, LcpError> {
        self.cone_scaling(s).try_apply(lcp)
    }
    /// Physical `z` from the scaled problem's answer, in place: `λ = s·λ_scaled`.
    pub fn unscale_z(&self, z: &mut [f64], s: f64) {
        for v in &mut z[self.lambda_range()] {
            *v *= s;
        }
    }

    /// The sign pattern of contact `c` in the physical `z` (length `n`), by the one zero rule.
    pub fn pattern(&self, z: &[f64], c: usize, zero: ZeroLevels) -> Pattern {
        let fd: f64 = z[self.fd_of(c)].iter().sum();
        Pattern {
            normal: z[c] > zero.impulse,
            friction: fd > zero.impulse,
            sliding: z[self.lambda_index(c)] > zero.velocity,
        }
    }
}

/// Thresholds of the zero rule ([`ContactLayout::pattern`]): a value is
/// positive when it is strictly greater than its threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZeroLevels {
    /// For `fn` and `Σ fd` (N·s).
    pub impulse: f64,
    /// For `λ` (m/s).
    pub velocity: f64,
}

impl ZeroLevels {
    /// The same threshold for impulses and velocities (units as given; `0` = exact signs).
    pub fn absolute(zero: f64) -> Self {
        ZeroLevels { impulse: zero, velocity: zero }
    }

    /// `rel` times the scales of one LCP, so that round-off around an exact
    /// zero counts as zero at every size of the data:
    /// - impulses: the largest `|fn|, |fd|` of `z` or, when larger, the
    ///   impulse that `q` asks for, `‖q‖∞ / max|A|` (N·s);
    /// - velocities: `‖q‖∞` (m/s).
    ///
    /// Each scale is at least `1e-300`. `m` is the row-major `M` of the
    /// *unscaled* problem (only its `A` block is read, which scaling leaves
    /// unchanged), `q` its `q`, `z` the physical answer.
    pub fn relative(layout: &ContactLayout, m: &[f64], q: &[f64], z: &[f64], rel: f64) -> Self {
        let (n, na) = (layout.n(), layout.impulses());
        let abs_max = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let qn = abs_max(q);
        let an = (0..na).fold(0.0f64, |a, i| a.max(abs_max(&m[i * n..i * n + na])));
        let asked = qn / if an > 0.0 { an } else { 1.0 };
        let impulse = abs_max(&z[..na]).max(asked).max(1e-300);
        ZeroLevels { impulse: rel * impulse, velocity: rel * qn.max(1e-300) }
    }
}

/// The source note's sign pattern `(fn, Σfd, λ)` of one contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Pattern {
    /// `fn > 0`: the contact pushes.
    pub normal: bool,
    /// `Σ fd > 0`: friction acts.
    pub friction: bool,
    /// `λ > 0`: the contact slides.
    pub sliding: bool,
}

impl Pattern {
    /// Every pattern in the source note's table order `000, 00+, 0+0, 0++, +00, +0+, ++0, +++`.
    pub const ALL: [&'static str; 8] = ["000", "00+", "0+0", "0++", "+00", "+0+", "++0", "+++"];

    /// Position in [`Pattern::ALL`]: `4·fn + 2·fd + λ`.
    pub fn code(self) -> u8 {
        (self.normal as u8) << 2 | (self.friction as u8) << 1 | self.sliding as u8
    }
    /// `"+0+"` style: `+` positive, `0` not.
    pub fn as_str(self) -> &'static str {
        Self::ALL[self.code() as usize]
    }
    /// Impossible for an exact solution with μ > 0: friction without a
    /// normal impulse (the cone row forces `fd = 0`), or `+0+` (cone slack
    /// `μ fn > 0` with `λ > 0` violates complementarity).
    pub fn impossible(self) -> bool {
        (!self.normal && self.friction) || (self.normal && !self.friction && self.sliding)
    }
}
