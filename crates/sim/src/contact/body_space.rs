//! The contact LCP in body space: `M = J M_b⁻¹ Jᵀ` (plus the cone blocks)
//! reached through the Jacobian rows, never formed as an `n × n` matrix.
//!
//! ```text
//! (M z)_fn  = J_n Δv                       Δv = M_b⁻¹ (J_nᵀ fn + J_dᵀ fd), per body
//! (M z)_fd  = J_d Δv + s·E λ
//! (M z)_λ   = s·μ fn − s·Eᵀ fd
//! ```
//!
//! A product costs O(contacts) and an entry O(1) (two 6-vectors per shared
//! body), so checking a guessed basis ([`lcp::on_basis`]) costs the size of
//! the basis, not `n²`: this is what lets a resting stack take a step
//! without assembling or equilibrating a dense matrix. The solver still never
//! sees a body — it sees [`lcp::on_basis::LcpOperator`].

use super::assembly::{dot6, row, ContactLcp, Row6};
use crate::math::Vec3;
use lcp::operator::LcpOperator;
use std::cell::RefCell;

/// What an index of `z` is, for one contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Var {
    Normal(usize),
    Dir(usize, usize),
    Lambda(usize),
}

/// One index of `z` for [`LcpOperator::block`]: its kind and, per dynamic
/// side, `(body, row)` (none for a λ) — its `J` row as a row of the block,
/// its `M_b⁻¹ Jᵀ` row as a column (an entry is `J_i M_b⁻¹ J_jᵀ`).
#[derive(Clone, Copy)]
struct IndexRows {
    var: Var,
    sides: [Option<(usize, Row6)>; 2],
}

/// Which of an index's rows [`IndexRows`] holds.
#[derive(Clone, Copy)]
enum Role {
    /// `J` (a row of the block).
    Row,
    /// `M_b⁻¹ Jᵀ` (a column).
    Col,
}

/// A [`ContactLcp`]'s rows seen as an LCP operator at cone scale `s`
/// (`s = 1`: the unscaled, physical LCP).
pub struct BodySpaceLcp<'a> {
    lcp: &'a ContactLcp,
    s: f64,
    /// Its buffers, taken from this thread's spares and given back on drop.
    bufs: RefCell<Buffers>,
}

/// The buffers of a [`BodySpaceLcp`]: a step builds a few operators per
/// island, and a steady step should not allocate (`tests/steady_step_allocations.rs`).
#[derive(Default)]
struct Buffers {
    /// Per-body velocity change `Δv`, `Δω` of a product (island body slots).
    dv: Vec<Vec3>,
    dw: Vec<Vec3>,
    /// Rows and columns of a block, by index (reused across calls).
    rows: Vec<IndexRows>,
    cols: Vec<IndexRows>,
    /// Bodies a sparse change of `z` moves ([`LcpOperator::add_columns`]).
    touched: Vec<bool>,
}

thread_local! {
    /// Buffers of dropped operators, for the next ones on this thread.
    static SPARE: RefCell<Vec<Buffers>> = const { RefCell::new(Vec::new()) };
}

impl Drop for BodySpaceLcp<'_> {
    fn drop(&mut self) {
        let bufs = std::mem::take(self.bufs.get_mut());
        // (A thread being torn down keeps nothing.)
        let _ = SPARE.try_with(|s| s.borrow_mut().push(bufs));
    }
}

impl<'a> BodySpaceLcp<'a> {
    /// The LCP of `lcp`'s rows at its own scale.
    pub fn new(lcp: &'a ContactLcp) -> Self {
        Self::at_scale(lcp, lcp.scale())
    }

    /// The same rows at cone scale `s`.
    pub fn at_scale(lcp: &'a ContactLcp, s: f64) -> Self {
        let nb = lcp.dynamic_body_count();
        let mut bufs = SPARE.try_with(|s| s.borrow_mut().pop()).ok().flatten().unwrap_or_default();
        for v in [&mut bufs.dv, &mut bufs.dw] {
            v.clear();
            v.resize(nb, Vec3::ZERO);
        }
        BodySpaceLcp { lcp, s, bufs: RefCell::new(bufs) }
    }

    fn var(&self, i: usize) -> Var {
        let lay = self.lcp.layout();
        let c = lay.contact_of(i);
        if i == lay.fn_index(c) {
            Var::Normal(c)
        } else if i == lay.lambda_index(c) {
            Var::Lambda(c)
        } else {
            Var::Dir(c, i - lay.fd_of(c).start)
        }
    }

    /// `(body, J row)` or `(body, M_b⁻¹ Jᵀ row)` (`role`) of variable `v` on
    /// `side`, if that side is dynamic.
    fn side_row(&self, c: usize, v: Var, side: usize, role: Role) -> Option<(usize, Row6)> {
        let body = self.lcp.side_body(c, side)?;
        let (jac, minv) = self.lcp.side_rows(c, side);
        let rows = match role {
            Role::Row => jac,
            Role::Col => minv,
        };
        let picked = match v {
            Var::Normal(_) => rows[0],
            Var::Dir(_, j) => {
                let (cj, sj) = self.lcp.cos_sin(j);
                std::array::from_fn(|m| cj * rows[1][m] + sj * rows[2][m])
            }
            Var::Lambda(_) => [0.0; 6],
        };
        Some((body, picked))
    }
}

impl BodySpaceLcp<'_> {
    /// [`IndexRows`] of every index in `idx` in `role`, into `out`.
    fn index_rows(&self, idx: &[usize], role: Role, out: &mut Vec<IndexRows>) {
        out.clear();
        out.extend(idx.iter().map(|&i| {
            let var = self.var(i);
            let sides = match var {
                Var::Lambda(_) => [None, None],
                _ => std::array::from_fn(|side| self.side_row(contact(var), var, side, role)),
            };
            IndexRows { var, sides }
        }));
    }
}

fn contact(v: Var) -> usize {
    match v {
        Var::Normal(c) | Var::Dir(c, _) | Var::Lambda(c) => c,
    }
}

impl LcpOperator for BodySpaceLcp<'_> {
    fn n(&self) -> usize {
        self.lcp.n()
    }

    fn q(&self) -> &[f64] {
        self.lcp.q()
    }

    fn block(&self, rows: &[usize], cols: &[usize], out: &mut [f64]) {
        if let [i] = rows {
            return self.row_entries(*i, cols, out);
        }
        // Each index's kind and rows per side, computed once: an entry is then
        // one or two 6-term dots (bodies shared by the two contacts).
        let mut guard = self.bufs.borrow_mut();
        let Buffers { rows: rs, cols: cs, .. } = &mut *guard;
        self.index_rows(rows, Role::Row, rs);
        self.index_rows(cols, Role::Col, cs);
        let width = cols.len();
        for (r, ri) in rs.iter().enumerate() {
            let line = &mut out[r * width..(r + 1) * width];
            for (o, ci) in line.iter_mut().zip(cs.iter()) {
                *o = match (ri.var, ci.var) {
                    (Var::Lambda(a), Var::Normal(b)) if a == b => self.s * self.lcp.mu()[a],
                    (Var::Lambda(a), Var::Dir(b, _)) if a == b => -self.s,
                    (Var::Dir(a, _), Var::Lambda(b)) if a == b => self.s,
                    (Var::Lambda(_), _) | (_, Var::Lambda(_)) => 0.0,
                    _ => {
                        let mut sum = 0.0;
                        for (bi, jrow) in ri.sides.iter().flatten() {
                            for (bj, mrow) in ci.sides.iter().flatten() {
                                if bi == bj {
                                    sum += dot6(jrow, mrow);
                                }
                            }
                        }
                        sum
                    }
                };
            }
        }
    }

    fn row(&self, i: usize, out: &mut [f64]) {
        // Row i of J M_b⁻¹ Jᵀ is J (M_b⁻¹ J_iᵀ): the unit impulse of index i
        // seen by every contact on its bodies; plus the cone entries.
        let (lay, s) = (self.lcp.layout(), self.s);
        out.fill(0.0);
        let var = self.var(i);
        if let Var::Lambda(c) = var {
            out[lay.fn_index(c)] = s * self.lcp.mu()[c];
            out[lay.fd_of(c)].fill(-s);
            return;
        }
        let c = contact(var);
        for side in 0..2 {
            let (Some(slot), Some((_, m6))) = (self.lcp.side_slot(c, side), self.side_row(c, var, side, Role::Col))
            else {
                continue;
            };
            for c2 in 0..lay.nc {
                for side2 in 0..2 {
                    if self.lcp.side_slot(c2, side2) != Some(slot) {
                        continue;
                    }
                    let (jac, _) = self.lcp.side_rows(c2, side2);
                    let jv = [dot6(&jac[0], &m6), dot6(&jac[1], &m6), dot6(&jac[2], &m6)];
                    out[lay.fn_index(c2)] += jv[0];
                    for (j, f) in lay.fd_of(c2).enumerate() {
                        let (cj, sj) = self.lcp.cos_sin(j);
                        out[f] += cj * jv[1] + sj * jv[2];
                    }
                }
            }
        }
        if let Var::Dir(..) = var {
            out[lay.lambda_index(c)] = s;
        }
    }

    fn diag(&self, i: usize) -> f64 {
        // J_i M_b⁻¹ J_iᵀ over the contact's dynamic sides (a λ's is 0), from its blocks.
        self.lcp.delassus_diag(i)
    }

    fn diagonal(&self) -> Option<&[f64]> {
        Some(self.lcp.delassus_diagonal())
    }

    fn w_of(&self, z: &[f64], w: &mut [f64]) {
        self.velocities_of(z);
        self.w_after_rows(z, w);
    }

    fn w_after_rows(&self, z: &[f64], w: &mut [f64]) {
        // `w_rows` (or `w_of`) left Δv = M_b⁻¹ Jᵀ z in the buffers.
        let guard = self.bufs.borrow();
        w.copy_from_slice(self.lcp.q());
        self.add_velocities(&guard.dv, &guard.dw, None, w);
        self.add_cone(z, w);
    }

    fn w_rows(&self, z: &[f64], rows: &[usize], w: &mut [f64]) {
        let (lay, s) = (self.lcp.layout(), self.s);
        self.velocities_of(z);
        let guard = self.bufs.borrow();
        let Buffers { dv, dw, .. } = &*guard;
        let q = self.lcp.q();
        // Each row as `w_of` forms it (the same sums in the same order).
        for &i in rows {
            let var = self.var(i);
            if let Var::Lambda(c) = var {
                let sum_fd = z[lay.fd_of(c)].iter().fold(0.0, |a, &v| a + v);
                w[i] = s * (self.lcp.mu()[c] * z[lay.fn_index(c)] - sum_fd);
                continue;
            }
            let c = contact(var);
            // J Δv along n, or along t1 and t2.
            let along = if let Var::Normal(_) = var { 0..1 } else { 1..3 };
            let mut jv = [0.0; 3];
            for side in 0..2 {
                let Some(b) = self.lcp.side_slot(c, side) else { continue };
                let (jac, _) = self.lcp.side_rows(c, side);
                let vel = row(dv[b], dw[b]);
                for r in along.clone() {
                    jv[r] += dot6(&jac[r], &vel);
                }
            }
            w[i] = match var {
                Var::Dir(_, j) => {
                    let (cj, sj) = self.lcp.cos_sin(j);
                    q[i] + (cj * jv[1] + sj * jv[2]) + s * z[lay.lambda_index(c)]
                }
                _ => q[i] + jv[0],
            };
        }
    }

    fn add_columns(&self, moved: &[(usize, f64)], w: &mut [f64]) {
        let (lay, s) = (self.lcp.layout(), self.s);
        let mut guard = self.bufs.borrow_mut();
        let Buffers { dv, dw, touched, .. } = &mut *guard;
        dv.fill(Vec3::ZERO);
        dw.fill(Vec3::ZERO);
        touched.clear();
        touched.resize(dv.len(), false);
        for &(i, d) in moved {
            // The impulse of d at index i in its contact's (n, t1, t2) frame; its cone entries.
            let imp = match self.var(i) {
                Var::Normal(c) => {
                    w[lay.lambda_index(c)] += s * self.lcp.mu()[c] * d;
                    [d, 0.0, 0.0]
                }
                Var::Dir(c, j) => {
                    w[lay.lambda_index(c)] -= s * d;
                    let (cj, sj) = self.lcp.cos_sin(j);
                    [0.0, cj * d, sj * d]
                }
                Var::Lambda(c) => {
                    w[lay.fd_of(c)].iter_mut().for_each(|v| *v += s * d);
                    continue;
                }
            };
            let c = contact(self.var(i));
            for side in 0..2 {
                let Some(b) = self.lcp.side_slot(c, side) else { continue };
                let (_, minv) = self.lcp.side_rows(c, side);
                for (r, &x) in minv.iter().zip(&imp) {
                    dv[b] += Vec3::new(r[0], r[1], r[2]) * x;
                    dw[b] += Vec3::new(r[3], r[4], r[5]) * x;
                }
                touched[b] = true;
            }
        }
        self.add_velocities(dv, dw, Some(touched), w);
    }
}

impl BodySpaceLcp<'_> {
    /// `Δv = M_b⁻¹ Jᵀ z` per body into the buffers (the integrator's own map
    /// of impulses), which `w_of`, `w_rows` and `w_after_rows` read.
    fn velocities_of(&self, z: &[f64]) {
        let mut guard = self.bufs.borrow_mut();
        let Buffers { dv, dw, .. } = &mut *guard;
        dv.fill(Vec3::ZERO);
        dw.fill(Vec3::ZERO);
        self.lcp.apply_impulses_local(z, dv, dw);
    }

    /// Row `i`'s entries in `cols` (a `1 × cols.len()` block, the acceptance
    /// rule's read of a few kept entries): the same sums as
    /// [`LcpOperator::block`]'s, with a column's `M_b⁻¹ Jᵀ` row formed only
    /// on a side whose body row `i` shares, and no per-index buffers (on a
    /// sliding cube, reading the four entries of its cone rows cost a sixth
    /// of the step).
    fn row_entries(&self, i: usize, cols: &[usize], out: &mut [f64]) {
        let (vi, s) = (self.var(i), self.s);
        if let Var::Lambda(a) = vi {
            for (o, &j) in out.iter_mut().zip(cols) {
                *o = match self.var(j) {
                    Var::Normal(b) if a == b => s * self.lcp.mu()[a],
                    Var::Dir(b, _) if a == b => -s,
                    _ => 0.0,
                };
            }
            return;
        }
        let sides: [Option<(usize, Row6)>; 2] =
            std::array::from_fn(|side| self.side_row(contact(vi), vi, side, Role::Row));
        for (o, &j) in out.iter_mut().zip(cols) {
            let vj = self.var(j);
            *o = match vj {
                Var::Lambda(b) => match vi {
                    Var::Dir(a, _) if a == b => s,
                    _ => 0.0,
                },
                _ => {
                    let cj = contact(vj);
                    let mut sum = 0.0;
                    for (bi, jrow) in sides.iter().flatten() {
                        for side in 0..2 {
                            if self.lcp.side_body(cj, side) == Some(*bi) {
                                let (_, mrow) = self.side_row(cj, vj, side, Role::Col).expect("a dynamic side");
                                sum += dot6(jrow, &mrow);
                            }
                        }
                    }
                    sum
                }
            };
        }
    }

    /// `w[fn, fd] += J Δv` for the per-body `Δv`, `Δω` (island slots); with
    /// `only`, for the contacts with a side on a body it marks (the others' is 0).
    fn add_velocities(&self, dv: &[Vec3], dw: &[Vec3], only: Option<&[bool]>, w: &mut [f64]) {
        let lay = self.lcp.layout();
        let (nc, k) = (lay.nc, lay.k);
        let (wn, rest) = w.split_at_mut(nc);
        let trig = self.lcp.trig();
        for (c, (wnc, wd)) in wn.iter_mut().zip(rest.chunks_exact_mut(k)).enumerate() {
            // J Δv along n, t1, t2.
            let mut jv = [0.0; 3];
            let mut moved = only.is_none();
            for side in 0..2 {
                let Some(b) = self.lcp.side_slot(c, side) else { continue };
                if only.is_some_and(|t| !t[b]) {
                    continue;
                }
                moved = true;
                let (jac, _) = self.lcp.side_rows(c, side);
                let vel = row(dv[b], dw[b]);
                for (v, r) in jv.iter_mut().zip(jac) {
                    *v += dot6(r, &vel);
                }
            }
            if !moved {
                continue;
            }
            *wnc += jv[0];
            for (wf, &(cj, sj)) in wd.iter_mut().zip(trig) {
                *wf += cj * jv[1] + sj * jv[2];
            }
        }
    }

    /// The cone terms of `w = M z + q`: `s·λ` on every `fd`, and the `λ` rows
    /// `s·(μ fn − Σ fd)` (written, not added).
    fn add_cone(&self, z: &[f64], w: &mut [f64]) {
        let (lay, s) = (self.lcp.layout(), self.s);
        let (nc, k) = (lay.nc, lay.k);
        let (zn, zrest) = z.split_at(nc);
        let (zd, zl) = zrest.split_at(nc * k);
        let (wd, wl) = w[nc..].split_at_mut(nc * k);
        let mu = self.lcp.mu();
        let parts = wd.chunks_exact_mut(k).zip(zd.chunks_exact(k)).zip(wl.iter_mut().zip(zl)).zip(zn.iter().zip(mu));
        for (((wdc, zdc), (wlc, &lambda)), (&zf, &m)) in parts {
            let mut sum_fd = 0.0;
            for (wf, &zj) in wdc.iter_mut().zip(zdc) {
                *wf += s * lambda;
                sum_fd += zj;
            }
            *wlc = s * (m * zf - sum_fd);
        }
    }
}
