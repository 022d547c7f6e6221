//! The Lemke basis in block form, with O(m²) updates per pivot.
//!
//! Lemke works on `I w − M z − d z0 = q`. Variables are numbered
//! `w_i → i`, `z_j → n + j`, `z0 → 2n`; the constraint matrix is
//! `A = [I | −M | −d]`. A basis holds `n` variables: some `w_i` (identity
//! columns) and a set `S` of "z-type" columns (`z_j` or `z0`). With `R` the
//! rows whose `w_i` is *not* basic (`|R| = |S| = m`), solving `B x = b` only
//! needs the small matrix `C = A[R, S]`:
//!
//! ```text
//!   x_S   = C⁻¹ b[R]
//!   x_w,i = b_i − A[i, S] x_S          (i ∉ R)
//! ```
//!
//! We keep `C⁻¹` explicitly and update it in O(m²) for each of the four pivot
//! kinds (replace a column, border with a row and column, remove a row and
//! column, replace a row), refactoring from scratch every so often to shed
//! accumulated round-off. This is what makes a pivot O(n·m) instead of the
//! O(n³) of refactoring (Drake's Moby) or the O(n²) of a full tableau.

use crate::problem::Lcp;
use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;

/// Below this size `C⁻¹` is refactored by `gauss_jordan_inverse`, above by faer's LU.
const SMALL_INVERSE: usize = 48;

/// Inverts the row-major `m × m` matrix `a` (destroyed) into `inv` by
/// Gauss–Jordan elimination with partial pivoting. `false` when a pivot falls
/// below 1e-14 of the largest entry of `a` (numerically singular), the same
/// test the LU path applies to `U`'s diagonal.
fn gauss_jordan_inverse(a: &mut [f64], inv: &mut [f64], m: usize) -> bool {
    let amax = a.iter().fold(0.0f64, |x, v| x.max(v.abs()));
    inv.iter_mut().for_each(|v| *v = 0.0);
    (0..m).for_each(|i| inv[i * m + i] = 1.0);
    for col in 0..m {
        let piv = (col..m).max_by(|&x, &y| a[x * m + col].abs().total_cmp(&a[y * m + col].abs())).unwrap_or(col);
        let p = a[piv * m + col];
        if !(p.abs() > 1e-14 * amax) {
            return false;
        }
        if piv != col {
            for k in 0..m {
                a.swap(piv * m + k, col * m + k);
                inv.swap(piv * m + k, col * m + k);
            }
        }
        let ip = 1.0 / p;
        for k in 0..m {
            a[col * m + k] *= ip;
            inv[col * m + k] *= ip;
        }
        for r in 0..m {
            let f = a[r * m + col];
            if r != col && f != 0.0 {
                for k in 0..m {
                    a[r * m + k] -= f * a[col * m + k];
                    inv[r * m + k] -= f * inv[col * m + k];
                }
            }
        }
    }
    true
}

/// Variable numbering helpers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Var {
    W(usize),
    Z(usize),
    Z0,
}

impl Var {
    pub(crate) fn id(self, n: usize) -> usize {
        match self {
            Var::W(i) => i,
            Var::Z(j) => n + j,
            Var::Z0 => 2 * n,
        }
    }

    /// The complementary partner (`w_i ↔ z_i`); `z0` has none.
    pub(crate) fn complement(self) -> Option<Var> {
        match self {
            Var::W(i) => Some(Var::Z(i)),
            Var::Z(j) => Some(Var::W(j)),
            Var::Z0 => None,
        }
    }
}

/// The entering column expressed in the current basis: `x = B⁻¹ a_e`
/// ([`Basis::column`] sizes it).
#[derive(Default)]
pub(crate) struct Column {
    /// Entries for the z-type basics, by position in `S`.
    pub(crate) xs: Vec<f64>,
    /// Entries for basic `w_i`, indexed by row `i`; 0 where `i ∈ R` (so
    /// the ratio test and the value update can sweep all rows branch-free).
    pub(crate) xw: Vec<f64>,
}

/// Which basic variable leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Leaving {
    /// The z-type basic at position `p` of `S`.
    S(usize),
    /// The basic `w_i`.
    W(usize),
}

/// Basis in block form over a problem `(M, q)` with covering vector `d`.
pub(crate) struct Basis<'a> {
    lcp: &'a Lcp,
    d: &'a [f64],
    n: usize,
    /// Rows whose `w` is nonbasic, in `C` column order.
    pub(crate) r: Vec<usize>,
    /// Position of row `i` in `r`, if any.
    r_pos: Vec<Option<usize>>,
    /// z-type basic columns, in `C` row order (`C⁻¹` row `p` belongs to `s[p]`).
    pub(crate) s: Vec<Var>,
    /// The columns of `G = [M | d]` for the z-type basics, contiguous, in `s`
    /// order (slot `p` is `G[:, s[p]]`): the axpys of `column` read them.
    gs: Vec<f64>,
    /// `C⁻¹`, row-major with stride `n`; only the leading `m × m` block is live.
    cinv: Vec<f64>,
    /// Values of the z-type basics, by position in `s`.
    pub(crate) val_s: Vec<f64>,
    /// Values of basic `w_i`, by row; 0 where `i ∈ R` (nonbasic `w_i`).
    pub(crate) val_w: Vec<f64>,
    /// Tableau row of each z-type basic (parallel to `s`) and of each basic
    /// `w_i`: the entering variable takes the leaving one's row. Only the
    /// classic rule's "first index on ties" reads these.
    pub(crate) row_s: Vec<usize>,
    pub(crate) row_w: Vec<usize>,
    /// Scratch of length n.
    tmp: Vec<f64>,
    /// Scratch of the Gauss–Jordan refactorization.
    gj_c: Vec<f64>,
    gj_inv: Vec<f64>,
    /// Pivots since the last refactorization.
    pub(crate) since_refactor: usize,
}

/// The buffers of a [`Basis`], kept in the caller's workspace between
/// solves: a basis takes them when it is built and gives them back with
/// [`Basis::into_buffers`], so a warm workspace pivots without allocating.
#[derive(Default)]
pub(crate) struct BasisBuffers {
    r: Vec<usize>,
    r_pos: Vec<Option<usize>>,
    s: Vec<Var>,
    gs: Vec<f64>,
    cinv: Vec<f64>,
    val_s: Vec<f64>,
    val_w: Vec<f64>,
    row_s: Vec<usize>,
    row_w: Vec<usize>,
    tmp: Vec<f64>,
    /// `C` and its inverse for the Gauss–Jordan refactorization (m ≤ [`SMALL_INVERSE`]).
    gj_c: Vec<f64>,
    gj_inv: Vec<f64>,
}

impl<'a> Basis<'a> {
    /// The all-slack basis `B = I`, values `w = q`, in the buffers `b`.
    pub(crate) fn slack(lcp: &'a Lcp, d: &'a [f64], b: BasisBuffers) -> Self {
        let n = lcp.n();
        let BasisBuffers {
            mut r,
            mut r_pos,
            mut s,
            mut gs,
            mut cinv,
            mut val_s,
            mut val_w,
            mut row_s,
            mut row_w,
            mut tmp,
            gj_c,
            gj_inv,
        } = b;
        for v in [&mut gs, &mut cinv, &mut val_s, &mut val_w, &mut tmp] {
            v.clear();
        }
        for v in [&mut r, &mut row_s, &mut row_w] {
            v.clear();
        }
        r_pos.clear();
        r_pos.resize(n, None);
        s.clear();
        // (`gs` and `cinv` grow row by row as `C` grows, see `ensure_rows`.)
        val_w.extend_from_slice(lcp.q());
        row_w.extend(0..n);
        tmp.resize(n, 0.0);
        Basis { lcp, d, n, r, r_pos, s, gs, cinv, val_s, val_w, row_s, row_w, tmp, gj_c, gj_inv, since_refactor: 0 }
    }

    /// Sets the covering vector (a complementary basis is factored without one).
    pub(crate) fn set_covering(&mut self, d: &'a [f64]) {
        self.d = d;
    }

    /// Gives the buffers back for the next basis.
    pub(crate) fn into_buffers(self) -> BasisBuffers {
        let Basis { r, r_pos, s, gs, cinv, val_s, val_w, row_s, row_w, tmp, gj_c, gj_inv, .. } = self;
        BasisBuffers { r, r_pos, s, gs, cinv, val_s, val_w, row_s, row_w, tmp, gj_c, gj_inv }
    }

    /// The complementary basis `{z_j : j ∈ α} ∪ {w_i : i ∉ α}`, factored.
    /// `Err` (with the unfactored basis, for its buffers) when `M_αα` is
    /// numerically singular.
    pub(crate) fn complementary(lcp: &'a Lcp, d: &'a [f64], alpha: &[usize], b: BasisBuffers) -> Result<Self, Self> {
        let mut b = Basis::slack(lcp, d, b);
        for (p, &j) in alpha.iter().enumerate() {
            b.r.push(j);
            b.r_pos[j] = Some(p);
            b.s.push(Var::Z(j));
            b.val_s.push(0.0);
            b.row_s.push(j);
            b.val_w[j] = 0.0;
        }
        b.gather_columns(alpha);
        if b.refactor() {
            Ok(b)
        } else {
            Err(b)
        }
    }

    /// The most negative basic value and where it sits.
    pub(crate) fn most_negative(&self) -> (f64, Leaving) {
        let mut best = (f64::INFINITY, Leaving::S(0));
        for (p, &v) in self.val_s.iter().enumerate() {
            if v < best.0 {
                best = (v, Leaving::S(p));
            }
        }
        for (i, &v) in self.val_w.iter().enumerate() {
            if self.r_pos[i].is_none() && v < best.0 {
                best = (v, Leaving::W(i));
            }
        }
        best
    }

    /// XOR of the basic variables' keys (see [`key`]).
    pub(crate) fn hash(&self, n: usize) -> u64 {
        let w = (0..n).filter(|&i| self.r_pos[i].is_none()).fold(0u64, |h, i| h ^ key(i));
        self.s.iter().fold(w, |h, v| h ^ key(v.id(n)))
    }

    #[inline]
    pub(crate) fn m(&self) -> usize {
        self.s.len()
    }

    /// Is `w_i` basic?
    #[inline]
    pub(crate) fn w_basic(&self, i: usize) -> bool {
        self.r_pos[i].is_none()
    }

    /// `G[i, v]` with `G = [M | d]`, i.e. `−A[i, v]` for a z-type `v`.
    #[inline]
    fn g(&self, i: usize, v: Var) -> f64 {
        match v {
            Var::Z(j) => self.lcp.at(i, j),
            Var::Z0 => self.d[i],
            Var::W(_) => unreachable!("w columns are never in S"),
        }
    }

    /// `A[i, e]` for any variable.
    #[inline]
    fn a(&self, i: usize, e: Var) -> f64 {
        match e {
            Var::W(k) => (i == k) as u8 as f64,
            v => -self.g(i, v),
        }
    }

    #[inline]
    fn ci(&self, p: usize, q: usize) -> f64 {
        self.cinv[p * self.n + q]
    }

    /// `x = B⁻¹ a_e` for the entering variable `e`.
    pub(crate) fn column(&mut self, e: Var, out: &mut Column) {
        let (n, m) = (self.n, self.m());
        // a_e restricted to R.
        let (lcp, d, t) = (self.lcp, self.d, &mut self.tmp[..m]);
        match e {
            Var::Z(j) => t.iter_mut().zip(&self.r).for_each(|(t, &i)| *t = -lcp.at(i, j)),
            Var::Z0 => t.iter_mut().zip(&self.r).for_each(|(t, &i)| *t = -d[i]),
            Var::W(k) => {
                t.iter_mut().for_each(|t| *t = 0.0);
                if let Some(qk) = self.r_pos[k] {
                    t[qk] = 1.0;
                }
            }
        }
        // x_S = C⁻¹ a_e[R].
        out.xs.clear();
        let t = &self.tmp[..m];
        let mut rows = self.cinv.chunks(n).take(m);
        // Four rows at a time: four independent sums, each in the order of a
        // plain dot, where one long sum would wait on every add (m ~ n/2 on
        // SPD problems).
        while rows.len() >= 4 {
            let r: [&[f64]; 4] = std::array::from_fn(|_| &rows.next().expect("four rows left")[..m]);
            let mut acc = [-0.0f64; 4];
            for (q, &tq) in t.iter().enumerate() {
                for k in 0..4 {
                    acc[k] += r[k][q] * tq;
                }
            }
            out.xs.extend_from_slice(&acc);
        }
        for row in rows {
            out.xs.push(row[..m].iter().zip(t).map(|(c, t)| c * t).sum());
        }
        // x_w = a_e + G[:, S] x_S over all rows (rows in R are ignored), as
        // contiguous axpys over the columns of M (rows of Mᵀ).
        out.xw.clear();
        match e {
            Var::Z(j) => out.xw.extend(self.lcp.m().chunks_exact(n).map(|row| -row[j])),
            Var::Z0 => out.xw.extend(self.d.iter().map(|v| -v)),
            Var::W(k) => {
                out.xw.resize(n, 0.0);
                out.xw[k] = 1.0;
            }
        }
        for (col, &u) in self.gs.chunks_exact(n).zip(&out.xs) {
            if u != 0.0 {
                for (x, g) in out.xw.iter_mut().zip(col) {
                    *x += u * g;
                }
            }
        }
        for &i in &self.r {
            out.xw[i] = 0.0;
        }
    }

    /// Entry `B⁻¹[b, c]` for the basic variable `b` and constraint `c`:
    /// O(1) for a z-type basic, O(m) for a basic `w_i`.
    pub(crate) fn binv_entry(&self, b: Leaving, c: usize) -> f64 {
        let Some(qc) = self.r_pos[c] else {
            // Column c of B⁻¹ outside R: the identity column of basic w_c.
            return matches!(b, Leaving::W(i) if i == c) as u8 as f64;
        };
        match b {
            Leaving::S(p) => self.ci(p, qc),
            // e_iᵀ − A[i, S] C⁻¹ restricted to R (i ∉ R, so the e_i part is 0 here).
            Leaving::W(i) => (0..self.m()).map(|p| self.gs[p * self.n + i] * self.ci(p, qc)).sum(),
        }
    }

    /// Writes `G[:, v]` into slot `p` of `gs` (appending when `p` is the end).
    fn set_gs(&mut self, p: usize, v: Var) {
        let n = self.n;
        if self.gs.len() < (p + 1) * n {
            self.gs.resize((p + 1) * n, 0.0);
        }
        let slot = &mut self.gs[p * n..(p + 1) * n];
        match v {
            Var::Z(j) => slot.iter_mut().zip(self.lcp.m().chunks_exact(n)).for_each(|(g, row)| *g = row[j]),
            _ => slot.copy_from_slice(self.d),
        }
    }

    /// Writes `M[:, alpha[p]]` into slot `p` of `gs` for every `p` (`gs` was
    /// empty), reading `M` row by row: a column read alone touches one cache
    /// line per row, and a warm start's `|α|` columns of a dense `M` of
    /// n = 640 (3.3 MB) read it `|α|` times over (`set_gs` was 6 % of a
    /// jointed chain's steps answered by their warm basis).
    fn gather_columns(&mut self, alpha: &[usize]) {
        let n = self.n;
        self.gs.resize(alpha.len() * n, 0.0);
        for (i, row) in self.lcp.m().chunks_exact(n).enumerate() {
            for (p, &j) in alpha.iter().enumerate() {
                self.gs[p * n + i] = row[j];
            }
        }
    }

    /// Makes room in `C⁻¹` for `rows` rows of stride n.
    fn ensure_rows(&mut self, rows: usize) {
        if self.cinv.len() < rows * self.n {
            self.cinv.resize(rows * self.n, 0.0);
        }
    }

    /// `t = A[i, S] C⁻¹` (row-wise, so `C⁻¹` is read contiguously).
    fn row_times_cinv(&self, i: usize, t: &mut [f64]) {
        let (n, m) = (self.n, self.m());
        let t = &mut t[..m];
        t.iter_mut().for_each(|x| *x = 0.0);
        for p in 0..m {
            let a = -self.gs[p * n + i];
            if a != 0.0 {
                for (tc, c) in t.iter_mut().zip(&self.cinv[p * n..p * n + m]) {
                    *tc += a * c;
                }
            }
        }
    }

    /// Pivots `e` in for `l` with step `theta`, given `x = B⁻¹ a_e`.
    pub(crate) fn pivot(&mut self, e: Var, l: Leaving, x: &Column, theta: f64) {
        // Values: every basic moves by −θ·x, the entering one takes θ.
        for (v, xs) in self.val_s.iter_mut().zip(&x.xs) {
            *v -= theta * xs;
        }
        // (x.xw and val_w are 0 on the rows of R, which stay 0.)
        for (v, xw) in self.val_w.iter_mut().zip(&x.xw) {
            *v -= theta * xw;
        }
        match (e, l) {
            (Var::W(i), Leaving::S(p)) => self.shrink(i, p, theta),
            (Var::W(i), Leaving::W(k)) => self.replace_row(i, k, theta),
            (_, Leaving::S(p)) => self.replace_column(e, p, &x.xs, theta),
            (_, Leaving::W(i)) => self.border(e, i, &x.xs, x.xw[i], theta),
        }
        self.since_refactor += 1;
    }

    /// z-type `e` replaces the z-type basic at position `p`: product-form update.
    fn replace_column(&mut self, e: Var, p: usize, u: &[f64], theta: f64) {
        let (n, m) = (self.n, self.m());
        let up = u[p];
        for c in 0..m {
            self.cinv[p * n + c] /= up;
        }
        for r in 0..m {
            if r == p || u[r] == 0.0 {
                continue;
            }
            let f = u[r];
            for c in 0..m {
                self.cinv[r * n + c] -= f * self.cinv[p * n + c];
            }
        }
        self.s[p] = e;
        self.set_gs(p, e);
        self.val_s[p] = theta;
    }

    /// z-type `e` enters, `w_i` leaves: `C` gains row `i` and column `e`.
    fn border(&mut self, e: Var, i: usize, u: &[f64], sigma: f64, theta: f64) {
        let (n, m) = (self.n, self.m());
        // v = rᵀ C⁻¹ with r = A[i, S] = −G[i, S].
        let mut v = std::mem::take(&mut self.tmp);
        self.row_times_cinv(i, &mut v);
        self.ensure_rows(m + 1);
        for r in 0..m {
            let f = u[r] / sigma;
            for c in 0..m {
                self.cinv[r * n + c] += f * v[c];
            }
            self.cinv[r * n + m] = -f;
        }
        for c in 0..m {
            self.cinv[m * n + c] = -v[c] / sigma;
        }
        self.cinv[m * n + m] = 1.0 / sigma;
        self.tmp = v;
        self.r_pos[i] = Some(m);
        self.r.push(i);
        self.val_w[i] = 0.0;
        self.s.push(e);
        self.set_gs(m, e);
        self.val_s.push(theta);
        self.row_s.push(self.row_w[i]);
    }

    /// `w_i` enters, the z-type basic at `p` leaves: `C` loses a row and a column.
    fn shrink(&mut self, i: usize, p: usize, theta: f64) {
        let (n, m) = (self.n, self.m());
        let qi = self.r_pos[i].expect("entering w must be nonbasic");
        let g = self.ci(p, qi);
        for r in 0..m {
            if r == p {
                continue;
            }
            let f = self.ci(r, qi) / g;
            if f == 0.0 {
                continue;
            }
            for c in 0..m {
                if c != qi {
                    self.cinv[r * n + c] -= f * self.cinv[p * n + c];
                }
            }
        }
        self.row_w[i] = self.row_s[p];
        // Move the last row into p and the last column into qi.
        let last = m - 1;
        if p != last {
            self.row_s[p] = self.row_s[last];
            for c in 0..m {
                self.cinv[p * n + c] = self.cinv[last * n + c];
            }
            self.s[p] = self.s[last];
            self.gs.copy_within(last * n..(last + 1) * n, p * n);
            self.val_s[p] = self.val_s[last];
        }
        if qi != last {
            for r in 0..m {
                self.cinv[r * n + qi] = self.cinv[r * n + last];
            }
            let moved = self.r[last];
            self.r[qi] = moved;
            self.r_pos[moved] = Some(qi);
        }
        self.s.pop();
        self.gs.truncate(last * n);
        self.val_s.pop();
        self.row_s.pop();
        self.r.pop();
        self.r_pos[i] = None;
        self.val_w[i] = theta;
    }

    /// `w_i` enters, `w_k` leaves: row `i` of `C` is replaced by row `k`.
    fn replace_row(&mut self, i: usize, k: usize, theta: f64) {
        let (n, m) = (self.n, self.m());
        let qi = self.r_pos[i].expect("entering w must be nonbasic");
        // t = r_newᵀ C⁻¹ with r_new = A[k, S] = −G[k, S].
        let mut t = std::mem::take(&mut self.tmp);
        self.row_times_cinv(k, &mut t);
        let tq = t[qi];
        for r in 0..m {
            let f = self.ci(r, qi) / tq;
            for c in 0..m {
                let delta = if c == qi { t[c] - 1.0 } else { t[c] };
                self.cinv[r * n + c] -= f * delta;
            }
        }
        self.tmp = t;
        self.r[qi] = k;
        self.r_pos[k] = Some(qi);
        self.val_w[k] = 0.0;
        self.row_w[i] = self.row_w[k];
        self.r_pos[i] = None;
        self.val_w[i] = theta;
    }

    /// Recomputes `C⁻¹` by LU and the basic values from `q`. Returns `false`
    /// when `C` is numerically singular.
    pub(crate) fn refactor(&mut self) -> bool {
        let (n, m) = (self.n, self.m());
        self.since_refactor = 0;
        if m > 0 && m <= SMALL_INVERSE {
            // Small C (the warm-started simulator step): Gauss–Jordan in place,
            // without faer's setup cost, which dominates below a few dozen rows.
            let (mut c, mut inv) = (std::mem::take(&mut self.gj_c), std::mem::take(&mut self.gj_inv));
            c.clear();
            c.extend((0..m * m).map(|k| self.a(self.r[k / m], self.s[k % m])));
            inv.clear();
            inv.resize(m * m, 0.0);
            let regular = gauss_jordan_inverse(&mut c, &mut inv, m);
            if regular {
                self.ensure_rows(m);
                for a in 0..m {
                    self.cinv[a * n..a * n + m].copy_from_slice(&inv[a * m..(a + 1) * m]);
                }
            }
            (self.gj_c, self.gj_inv) = (c, inv);
            if !regular {
                return false;
            }
        } else if m > 0 {
            let c = Mat::<f64>::from_fn(m, m, |a, b| self.a(self.r[a], self.s[b]));
            let lu = c.partial_piv_lu();
            let u = lu.U();
            let cmax =
                (0..m).flat_map(|a| (0..m).map(move |b| (a, b))).fold(0.0f64, |acc, (a, b)| acc.max(c[(a, b)].abs()));
            let umin = (0..m).fold(f64::INFINITY, |acc, a| acc.min(u[(a, a)].abs()));
            if !(umin > 1e-14 * cmax) {
                return false;
            }
            let inv = lu.inverse();
            self.ensure_rows(m);
            for a in 0..m {
                for b in 0..m {
                    self.cinv[a * n + b] = inv[(a, b)];
                }
            }
        }
        // β = B⁻¹ q.
        let q = self.lcp.q();
        for p in 0..m {
            self.val_s[p] = (0..m).map(|c| self.ci(p, c) * q[self.r[c]]).sum();
        }
        // w = q + G[:, S] z_S as axpys over the contiguous columns of `gs`
        // (each w_i summed in the order p = 0, 1, …, as a dot per row would),
        // then 0 on the rows of R.
        self.val_w.copy_from_slice(q);
        for (col, &v) in self.gs.chunks_exact(n).zip(&self.val_s) {
            for (w, g) in self.val_w.iter_mut().zip(col) {
                *w += g * v;
            }
        }
        for &i in &self.r {
            self.val_w[i] = 0.0;
        }
        true
    }

    /// Polishes the values of a complementary basis (z0 nonbasic) by one
    /// step of iterative refinement with the kept `C⁻¹`:
    /// `z_S += C⁻¹ (M z + q)[R]`, O(m²).
    pub(crate) fn polish(&mut self) {
        let (n, m) = (self.n, self.m());
        let mut res = std::mem::take(&mut self.tmp);
        // res = (M z + q) on the rows of R, which must vanish.
        for (qi, &i) in self.r.iter().enumerate() {
            let mut acc = self.lcp.q()[i];
            for p in 0..m {
                acc += self.gs[p * n + i] * self.val_s[p];
            }
            res[qi] = acc;
        }
        if res[..m].iter().any(|v| v.abs() > 0.0) {
            for p in 0..m {
                let row = &self.cinv[p * n..p * n + m];
                self.val_s[p] += row.iter().zip(&res[..m]).map(|(c, r)| c * r).sum::<f64>();
            }
        }
        self.tmp = res;
    }

    /// Current `z` (length n) from the basic values, written into `z`; `z0` is returned.
    pub(crate) fn z_into(&self, z: &mut Vec<f64>) -> f64 {
        z.clear();
        z.resize(self.n, 0.0);
        let mut z0 = 0.0;
        for (p, &v) in self.s.iter().enumerate() {
            match v {
                Var::Z(j) => z[j] = self.val_s[p],
                Var::Z0 => z0 = self.val_s[p],
                Var::W(_) => {}
            }
        }
        z0
    }
}

/// Key of a variable for the basis hash (splitmix64 of its id).
pub(crate) fn key(id: usize) -> u64 {
    let mut x = (id as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}
