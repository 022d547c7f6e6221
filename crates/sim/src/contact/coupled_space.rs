//! The LCP of an island solved on its dense `M` — a jointed island's
//! `J P Jᵀ`, an island holding a torsion patch — reached through products
//! instead, as [`BodySpaceLcp`] reaches a contact-only island's:
//!
//! ```text
//! M z = J M_b⁻¹ Jᵀ z − E Yᵀ Y Eᵀ z      (the joints' coupling, `Y` rank × 3nc)
//!     + the cone rows (BodySpaceLcp's)
//!     + z_c on each virtual unit normal (a motor's bound, a patch's torsion)
//!     + s Σ_{i ∈ patch} fn_i on a patch's cone row
//! ```
//!
//! `E` expands a contact's frame rows `n, t1, t2` to its `fn` and `d_j = c_j
//! t1 + s_j t2` rows. `Y = L⁻¹ Πᵀ B` is the joints' (`joints::elimination`),
//! lent as a slice: the lcp crate sees an operator, not joints. A product
//! costs the body-space product plus `2 · rank · 3nc`, an entry `rank` more
//! than the body-space one; the dense `M` (`n²`, then `Yᵀ Y` and its
//! expansion) is formed only when the Lemke runs. Its blocks' entries carry
//! the dense `M`'s own bits (a basis factored here makes the dense path's
//! pivot choices); its products and rows equal the dense `M`'s to round-off
//! (the same terms summed in another order).

use super::{BodySpaceLcp, ContactLcp};
use lcp::operator::LcpOperator;
use std::cell::RefCell;

/// A dense-only island's LCP through products ([module docs](self)).
pub struct CoupledSpaceLcp<'a> {
    base: BodySpaceLcp<'a>,
    lcp: &'a ContactLcp,
    /// `Y`, row-major `rank × 3nc` (empty: no coupling).
    y: &'a [f64],
    rank: usize,
    s: f64,
    /// Its buffers (taken from this thread's spares, given back on drop).
    bufs: Buffers,
    scratch: RefCell<Scratch>,
}

/// What a [`CoupledSpaceLcp`] forms once.
#[derive(Default)]
struct Buffers {
    /// The coupled diagonal of `M`.
    diag: Vec<f64>,
    /// Per contact: its normal is a virtual unit row.
    unit: Vec<bool>,
    /// Per contact: the patch contact whose cone row reads its normal (`NONE`: none).
    patch_of: Vec<usize>,
}

/// Per-call scratch of a [`CoupledSpaceLcp`].
#[derive(Default)]
struct Scratch {
    /// Frame impulses (`3nc`), `Y f` (`rank`), `Yᵀ Y f` (`3nc`).
    f: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    /// `v` is that of the `z` of the last `w_rows` (which `w_after_rows` reuses).
    v_of_rows: bool,
    /// Rows of `Yᵀ Y` (`3nc` square) formed as the dense `M`'s are, and which are.
    gram: Vec<f64>,
    gram_ready: Vec<bool>,
}

const NONE: usize = usize::MAX;

thread_local! {
    static SPARE: RefCell<Vec<(Buffers, Scratch)>> = const { RefCell::new(Vec::new()) };
}

impl Drop for CoupledSpaceLcp<'_> {
    fn drop(&mut self) {
        let b = (std::mem::take(&mut self.bufs), std::mem::take(self.scratch.get_mut()));
        let _ = SPARE.try_with(|s| s.borrow_mut().push(b));
    }
}

impl<'a> CoupledSpaceLcp<'a> {
    /// The LCP of `lcp` at its own scale, coupled by `y` (`rank × 3nc`,
    /// row-major; empty for none).
    pub fn new(lcp: &'a ContactLcp, y: &'a [f64], rank: usize) -> Self {
        let (lay, nf) = (lcp.layout(), 3 * lcp.nc());
        let rank = if y.len() == rank * nf && rank > 0 { rank } else { 0 };
        let (mut bufs, mut scratch) = SPARE.try_with(|s| s.borrow_mut().pop()).ok().flatten().unwrap_or_default();
        scratch.gram.resize(nf * nf, 0.0);
        scratch.gram_ready.clear();
        scratch.gram_ready.resize(nf, false);
        scratch.v_of_rows = false;
        bufs.unit.clear();
        bufs.unit.resize(lay.nc, false);
        bufs.patch_of.clear();
        bufs.patch_of.resize(lay.nc, NONE);
        for &c in lcp.pinned() {
            bufs.unit[c] = true;
        }
        for (c, points) in lcp.patch_cones() {
            bufs.unit[*c] = true;
            bufs.patch_of[points.clone()].fill(*c);
        }
        let mut op = CoupledSpaceLcp {
            base: BodySpaceLcp::new(lcp),
            lcp,
            y,
            rank,
            s: lcp.scale(),
            bufs,
            scratch: RefCell::new(scratch),
        };
        let mut diag = std::mem::take(&mut op.bufs.diag);
        diag.clear();
        diag.extend_from_slice(lcp.delassus_diagonal());
        if rank > 0 {
            // |Y E_i|² from each contact's Gram of its three frame columns of Y:
            // a direction's is c²·t1t1 + 2cs·t1t2 + s²·t2t2.
            for c in 0..lay.nc {
                let mut g = [0.0; 4];
                for yr in y.chunks_exact(nf) {
                    let (n, t1, t2) = (yr[3 * c], yr[3 * c + 1], yr[3 * c + 2]);
                    g[0] += n * n;
                    g[1] += t1 * t1;
                    g[2] += t1 * t2;
                    g[3] += t2 * t2;
                }
                diag[lay.fn_index(c)] -= g[0];
                for (d, &(cj, sj)) in diag[lay.fd_of(c)].iter_mut().zip(lcp.trig()) {
                    *d -= cj * cj * g[1] + 2.0 * cj * sj * g[2] + sj * sj * g[3];
                }
            }
        }
        op.bufs.diag = diag;
        op
    }

    /// `Y E_i` for impulse index `i` (its column of the coupling factor).
    fn coupling_column(&self, i: usize, g: &mut [f64]) {
        let lay = self.lcp.layout();
        let (nf, c) = (3 * self.lcp.nc(), lay.contact_of(i));
        let rows = self.y.chunks_exact(nf).zip(g.iter_mut());
        if i == lay.fn_index(c) {
            rows.for_each(|(yr, x)| *x = yr[3 * c]);
        } else {
            let (cj, sj) = self.lcp.cos_sin(i - lay.fd_of(c).start);
            rows.for_each(|(yr, x)| *x = cj * yr[3 * c + 1] + sj * yr[3 * c + 2]);
        }
    }

    /// `v = Yᵀ Y f` of the frame impulses `f` (in the scratch), `u = Y f` between.
    fn coupled_frames(&self, sc: &mut Scratch) {
        let (nf, r) = (3 * self.lcp.nc(), self.rank);
        let Scratch { f, u, v, .. } = sc;
        u.clear();
        u.extend(self.y.chunks_exact(nf).take(r).map(|yr| yr.iter().zip(f.iter()).map(|(a, b)| a * b).sum::<f64>()));
        Self::combine_rows(self.y, nf, u, v);
    }

    /// `v = Yᵀ u`: `Y`'s rows (`nf` long) weighted by `u`.
    fn combine_rows(y: &[f64], nf: usize, u: &[f64], v: &mut Vec<f64>) {
        v.clear();
        v.resize(nf, 0.0);
        for (yr, &ur) in y.chunks_exact(nf).zip(u) {
            if ur != 0.0 {
                v.iter_mut().zip(yr).for_each(|(x, &a)| *x += ur * a);
            }
        }
    }

    /// The points whose normals bound patch contact `c`'s cone row (`None`: `c` is no patch).
    fn patch_points(&self, c: usize) -> Option<std::ops::Range<usize>> {
        self.lcp.patch_cones().iter().find(|(p, _)| *p == c).map(|(_, points)| points.clone())
    }

    /// `(E v)_i` for impulse row `i`, `v` in frame rows (`3nc`): its
    /// contact's normal entry, or `c_j t1 + s_j t2` for friction direction `j`.
    fn expanded(&self, i: usize, v: &[f64]) -> f64 {
        let lay = self.lcp.layout();
        let c = lay.contact_of(i);
        if i == lay.fn_index(c) {
            v[3 * c]
        } else {
            let (cj, sj) = self.lcp.cos_sin(i - lay.fd_of(c).start);
            cj * v[3 * c + 1] + sj * v[3 * c + 2]
        }
    }

    /// `w_i −= (E v)_i` for the impulse rows `rows` (all with `None`).
    fn subtract_expanded(&self, v: &[f64], rows: Option<&[usize]>, w: &mut [f64]) {
        let lay = self.lcp.layout();
        let Some(rows) = rows else {
            // Every impulse row, contact by contact.
            let (wn, rest) = w.split_at_mut(lay.nc);
            let parts = wn.iter_mut().zip(rest.chunks_exact_mut(lay.k)).zip(v.chunks_exact(3));
            for ((wc, wd), vc) in parts {
                *wc -= vc[0];
                for (x, &(cj, sj)) in wd.iter_mut().zip(self.lcp.trig()) {
                    *x -= cj * vc[1] + sj * vc[2];
                }
            }
            return;
        };
        rows.iter().filter(|&&i| i < lay.impulses()).for_each(|&i| w[i] -= self.expanded(i, v));
    }

    /// The coupling's part of `w = M z + q` on `rows` (all with `None`);
    /// `reuse`: `z` is that of the last `w_rows`, whose `v` serves.
    fn subtract_coupling(&self, z: &[f64], rows: Option<&[usize]>, w: &mut [f64], reuse: bool) {
        if self.rank == 0 {
            return;
        }
        let mut sc = self.scratch.borrow_mut();
        let kept = std::mem::replace(&mut sc.v_of_rows, rows.is_some());
        if reuse && kept {
            return self.subtract_expanded(&sc.v, rows, w);
        }
        sc.f.clear();
        sc.f.extend((0..self.lcp.nc()).flat_map(|c| self.lcp.frame_impulse(c, z)));
        self.coupled_frames(&mut sc);
        self.subtract_expanded(&sc.v, rows, w);
    }

    /// The virtual rows' part of `w = M z + q` on `rows` (all with `None`):
    /// `z_c` on a unit normal, `s Σ fn_i` on a patch's cone row.
    fn add_virtual(&self, z: &[f64], rows: Option<&[usize]>, w: &mut [f64]) {
        let lay = self.lcp.layout();
        let one = |i: usize, w: &mut [f64]| {
            if i < lay.nc && self.bufs.unit[i] {
                w[i] += z[i];
            } else if i >= lay.impulses() {
                let c = lay.contact_of(i);
                if let Some(points) = self.patch_points(c) {
                    w[i] += self.s * points.map(|p| z[lay.fn_index(p)]).sum::<f64>();
                }
            }
        };
        match rows {
            Some(rows) => rows.iter().for_each(|&i| one(i, w)),
            None => {
                (0..lay.nc).filter(|&c| self.bufs.unit[c]).for_each(|c| one(c, w));
                self.lcp.patch_cones().iter().for_each(|(c, _)| one(lay.lambda_index(*c), w));
            }
        }
    }
}

impl CoupledSpaceLcp<'_> {
    /// `M_ij` with the bits of the dense `M` (`ContactLcp::assemble_matrix`,
    /// then `JointCoupling::subtract_from`): the same terms, in the same order.
    fn dense_entry(&self, i: usize, j: usize, sc: &mut Scratch) -> f64 {
        let (lay, s) = (self.lcp.layout(), self.s);
        let (na, nc) = (lay.impulses(), lay.nc);
        if i < na && j < na {
            let mut m = if i == j && i < nc && self.bufs.unit[i] { 1.0 } else { self.upper_entry(i.min(j), i.max(j)) };
            if self.rank > 0 {
                let ci = lay.contact_of(i);
                if i == lay.fn_index(ci) {
                    m -= self.frame_entry(3 * ci, j, sc);
                } else {
                    let (cj, sj) = self.lcp.cos_sin(i - lay.fd_of(ci).start);
                    let (a, b) = (self.frame_entry(3 * ci + 1, j, sc), self.frame_entry(3 * ci + 2, j, sc));
                    m -= cj * a + sj * b;
                }
            }
            return m;
        }
        let (ci, cj) = (lay.contact_of(i), lay.contact_of(j));
        match (i < na, j < na) {
            // A friction row's λ, of its own contact.
            (true, false) if i >= nc && ci == cj => s,
            // A cone row's friction, of its own contact.
            (false, true) if j >= nc && ci == cj => -s,
            (false, true) if j >= nc => 0.0,
            // A cone row's normal: a patch's point, or its own (μ).
            (false, true) if self.bufs.patch_of[j] == ci => s,
            (false, true) if ci == cj => s * self.lcp.mu()[ci],
            _ => 0.0,
        }
    }

    /// `(J M_b⁻¹ Jᵀ)_ab`, `a ≤ b`, as `assemble_matrix` accumulates it: over
    /// the bodies the two contacts share (slot order), each body's term
    /// expanded from the Gram block of the lower contact's `J` rows and the
    /// other's `M_b⁻¹ Jᵀ` rows, as `add_block` expands it.
    fn upper_entry(&self, a: usize, b: usize) -> f64 {
        let (lay, lcp) = (self.lcp.layout(), self.lcp);
        let (ca, cb) = (lay.contact_of(a), lay.contact_of(b));
        let dir = |i: usize, c: usize| (i != lay.fn_index(c)).then(|| i - lay.fd_of(c).start);
        let (da, db) = (dir(a, ca), dir(b, cb));
        let (c1, c2) = (ca.min(cb), ca.max(cb));
        let mut shared = [(usize::MAX, 0, 0); 2];
        let mut count = 0;
        for s1 in 0..2 {
            for s2 in 0..2 {
                if let (Some(x), Some(y)) = (lcp.side_slot(c1, s1), lcp.side_slot(c2, s2)) {
                    if x == y && count < 2 {
                        shared[count] = (x, s1, s2);
                        count += 1;
                    }
                }
            }
        }
        if count == 2 && shared[1].0 < shared[0].0 {
            shared.swap(0, 1);
        }
        let mut m = 0.0;
        for &(_, s1, s2) in &shared[..count] {
            let (jr, wr) = (lcp.side_rows(c1, s1).0, lcp.side_rows(c2, s2).1);
            let g = |x: usize, y: usize| super::assembly::dot6(&jr[x], &wr[y]);
            m += match (da, db) {
                (None, None) => g(0, 0),
                // Normal–friction in the lower contact's normal row.
                (None, Some(jp)) if ca <= cb => {
                    let (c, s) = lcp.cos_sin(jp);
                    g(0, 1) * c + g(0, 2) * s
                }
                // Friction–normal, at its mirror in the higher contact's normal row.
                (None, Some(jj)) => {
                    let (c, s) = lcp.cos_sin(jj);
                    c * g(1, 0) + s * g(2, 0)
                }
                (Some(j1), Some(j2)) => {
                    let ((c, s), (cp, sp)) = (lcp.cos_sin(j1), lcp.cos_sin(j2));
                    let col1 = g(1, 1) * cp + g(1, 2) * sp;
                    let col2 = g(2, 1) * cp + g(2, 2) * sp;
                    c * col1 + s * col2
                }
                (Some(_), None) => unreachable!("a normal's index is below every friction index"),
            };
        }
        m
    }

    /// Entry `j` of frame row `k` of `Yᵀ Y W` (`W` expanding the frame
    /// columns to the impulse ones), as `subtract_frame_block` forms it.
    fn frame_entry(&self, k: usize, j: usize, sc: &mut Scratch) -> f64 {
        let nf = 3 * self.lcp.nc();
        if !sc.gram_ready[k] {
            gram_row(&self.y[..self.rank * nf], nf, k, &mut sc.gram[k * nf..(k + 1) * nf]);
            sc.gram_ready[k] = true;
        }
        self.expanded(j, &sc.gram[k * nf..(k + 1) * nf])
    }
}

/// Row `k` of `Yᵀ Y` into `row` (`Y` row-major, rows `nf` long): `Y`'s rows
/// accumulated in order, those with a zero in column `k` skipped — the one
/// order in which both the dense `M` (`joints::JointCoupling::subtract_from`)
/// and [`CoupledSpaceLcp`]'s entries sum it, so that they agree to the bit.
pub fn gram_row(y: &[f64], nf: usize, k: usize, row: &mut [f64]) {
    row.fill(0.0);
    for yr in y.chunks_exact(nf) {
        let yk = yr[k];
        if yk != 0.0 {
            for (c, &yj) in row.iter_mut().zip(yr) {
                *c += yk * yj;
            }
        }
    }
}

impl LcpOperator for CoupledSpaceLcp<'_> {
    fn n(&self) -> usize {
        self.base.n()
    }

    fn q(&self) -> &[f64] {
        self.base.q()
    }

    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]) {
        // The dense M's own bits: a basic block factored here is the one the
        // dense path factors (its rank decisions on degenerate blocks, ties of
        // equal pivots, are the same).
        if cols.is_empty() {
            return;
        }
        let mut sc = self.scratch.borrow_mut();
        for (&i, line) in rows.iter().zip(out.chunks_exact_mut(cols.len())) {
            for (o, &j) in line.iter_mut().zip(cols) {
                *o = self.dense_entry(i, j, &mut sc);
            }
        }
    }

    fn row(&self, i: usize, out: &mut [f64]) {
        self.base.row(i, out);
        let lay = self.lcp.layout();
        if self.rank > 0 && i < lay.impulses() {
            let mut sc = self.scratch.borrow_mut();
            let sc = &mut *sc;
            sc.v_of_rows = false;
            sc.u.clear();
            sc.u.resize(self.rank, 0.0);
            self.coupling_column(i, &mut sc.u);
            Self::combine_rows(self.y, 3 * lay.nc, &sc.u, &mut sc.v);
            self.subtract_expanded(&sc.v, None, out);
        }
        if i < lay.nc && self.bufs.unit[i] {
            out[i] += 1.0;
        } else if i >= lay.impulses() {
            if let Some(points) = self.patch_points(lay.contact_of(i)) {
                points.for_each(|p| out[lay.fn_index(p)] += self.s);
            }
        }
    }

    fn diag(&self, i: usize) -> f64 {
        self.bufs.diag[i]
    }

    fn diagonal(&self) -> Option<&[f64]> {
        Some(&self.bufs.diag)
    }

    fn w_of(&self, z: &[f64], w: &mut [f64]) {
        self.base.w_of(z, w);
        self.subtract_coupling(z, None, w, false);
        self.add_virtual(z, None, w);
    }

    fn w_rows(&self, z: &[f64], rows: &[usize], w: &mut [f64]) {
        self.base.w_rows(z, rows, w);
        self.subtract_coupling(z, Some(rows), w, false);
        self.add_virtual(z, Some(rows), w);
    }

    fn w_after_rows(&self, z: &[f64], w: &mut [f64]) {
        // (`w_rows` with this z left its `Yᵀ Y f` in the scratch.)
        self.base.w_after_rows(z, w);
        self.subtract_coupling(z, None, w, true);
        self.add_virtual(z, None, w);
    }

    fn add_columns(&self, moved: &[(usize, f64)], w: &mut [f64]) {
        self.base.add_columns(moved, w);
        let lay = self.lcp.layout();
        if self.rank > 0 {
            let mut sc = self.scratch.borrow_mut();
            sc.v_of_rows = false;
            sc.f.clear();
            sc.f.resize(3 * lay.nc, 0.0);
            for &(i, d) in moved.iter().filter(|&&(i, _)| i < lay.impulses()) {
                let c = lay.contact_of(i);
                if i == lay.fn_index(c) {
                    sc.f[3 * c] += d;
                } else {
                    let (cj, sj) = self.lcp.cos_sin(i - lay.fd_of(c).start);
                    sc.f[3 * c + 1] += cj * d;
                    sc.f[3 * c + 2] += sj * d;
                }
            }
            self.coupled_frames(&mut sc);
            self.subtract_expanded(&sc.v, None, w);
        }
        for &(j, d) in moved.iter().filter(|&&(j, _)| j < lay.nc) {
            if self.bufs.unit[j] {
                w[j] += d;
            }
            if self.bufs.patch_of[j] != NONE {
                w[lay.lambda_index(self.bufs.patch_of[j])] += self.s * d;
            }
        }
    }
}
