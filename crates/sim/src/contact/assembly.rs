//! Stewart–Trinkle assembly: contacts and free velocities → the LCP `(M, q)` with `z = [fn; fd; λ]`.
//!
//! ```text
//! z = [ fn (nc) ; fd (nc·k) ; λ (nc) ]
//!
//!     | A00  A01  0  |       | b0 |      A = J M_b⁻¹ Jᵀ,  J = [J_n; J_d]
//! M = | A10  A11  sE |,  q = | b1 |      b0 = J_n v* + stabilization (+ restitution)
//!     | sμ  −sEᵀ  0  |       | 0  |      b1 = J_d v*
//! ```
//!
//! `E = blockdiag(1_k)`, `μ = diag(μ_i)`. Where each unknown lives is
//! [`ContactLayout`]'s (`fd` contact-major).
//!
//! The Jacobian is kept as rows per contact and side, each tagged with its
//! body, and `A` is accumulated body by body over the pairs of contacts that
//! touch it (`A = Σ_b J_b M_b⁻¹ J_bᵀ`). Static bodies carry no rows. So the
//! work is proportional to the non-zero blocks, and a sparse `A` could be
//! formed from the same loop.
//!
//! Only three rows are stored per contact and side — normal `n`, `t1`,
//! `t2` — because every friction row is `J_{d_j} = c_j J_{t1} + s_j J_{t2}`
//! (`c_j, s_j = cos, sin 2πj/k`). A contact pair's `(1+k)²` block of `A` is
//! expanded from its 3×3 Gram block `G = J_{n,t1,t2} M⁻¹ J_{n,t1,t2}ᵀ`,
//! about five times fewer flops than `(1+k)²` six-term dot products. Blocks
//! on the diagonal are computed on and above it and mirrored, so `A` is
//! exactly symmetric.

use super::friction::FrictionBasis;
use super::params::{Restitution, Stabilization};
use crate::dynamics::Body;
use crate::geometry::Contact;
use crate::math::{Mat3, Vec3};
use lcp::{ContactLayout, Lcp, LcpError};
use std::cell::RefCell;
use std::ops::Range;

/// One Jacobian row for one body: `[linear (3); angular (3)]`.
pub type Row6 = [f64; 6];

/// What the assembly reads about the bodies (indexed like the world's bodies).
#[derive(Clone, Copy, Debug)]
pub struct BodyDynamics<'a> {
    /// The bodies (positions, pre-step velocities for restitution, masses).
    pub bodies: &'a [Body],
    /// World-frame inverse inertia per body (zero for static bodies).
    pub inv_inertia_world: &'a [Mat3],
    /// Free linear velocity `v* = v + h f/m` per body.
    pub v_free: &'a [Vec3],
    /// Free angular velocity `ω* = ω + h I⁻¹ τ` per body.
    pub w_free: &'a [Vec3],
}

/// Scalars of one assembly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssemblyParams {
    /// Time step `h` (s).
    pub h: f64,
    /// Friction directions per contact `k`.
    pub k: usize,
    /// Friction-cone scale `s`.
    pub s: f64,
    pub stabilization: Stabilization,
    pub restitution: Restitution,
}

/// Jacobian rows of one contact: for side A and B, the body (`None` when
/// static) and the rows of `n`, `t1`, `t2` (B's are the negatives of what it
/// sees of A's directions). The row of `d_j` is `c_j·t1-row + s_j·t2-row`,
/// see [`ContactLcp::direction_row`].
#[derive(Clone, Copy, Debug)]
pub struct ContactRows {
    pub body: [Option<usize>; 2],
    pub rows: [[Row6; 3]; 2],
}

/// The assembled contact LCP with reusable buffers (allocation-free once warm).
#[derive(Clone, Debug, Default)]
pub struct ContactLcp {
    layout: ContactLayout,
    s: f64,
    basis: Option<FrictionBasis>,
    /// `(cos, sin)` of `2πj/k`, and `[c², 2cs, s²]` of each.
    trig: Vec<(f64, f64)>,
    dir_weights: Vec<[f64; 3]>,
    /// `J` rows `[n, t1, t2]` per `(contact, side)`.
    jac: Vec<[Row6; 3]>,
    /// `M_b⁻¹ Jᵀ` rows (velocity change per unit impulse), same layout.
    minv_jt: Vec<[Row6; 3]>,
    /// Dynamic body of each `(contact, side)`, `None` for a static body.
    side_body: Vec<Option<usize>>,
    /// The same bodies numbered within the island (their rank among its
    /// dynamic bodies): per-body scratch of one island is sized by the island,
    /// not by the world (100 islands of a 1,000-body world each zeroed 1,000
    /// entries per product).
    side_slot: Vec<Option<usize>>,
    mu: Vec<f64>,
    /// The diagonal of `J M_b⁻¹ Jᵀ` per index of `z` (0 for a `λ`), for the
    /// acceptance rule's cheap bound ([`ContactLcp::set_diag`]): read by index,
    /// ~190 times a step on a resting 10-box stack, where finding the
    /// contact of an index (a division) cost more than the rule's row.
    diag: Vec<f64>,
    /// Row-major `M` (scaled by `s`) and `q`.
    m: Vec<f64>,
    q: Vec<f64>,
    /// Scratch: `(contact, side)` grouped by body (counting sort).
    adj_start: Vec<usize>,
    adj: Vec<(usize, usize)>,
    adj_cursor: Vec<usize>,
    /// Scratch for the block expansion: `G·[0; c_j; s_j]` per column direction.
    col: Vec<[f64; 3]>,
    /// Bodies in the world the rows index into.
    bodies: usize,
    /// `M` was formed for the current rows.
    matrix_ready: bool,
    /// Distinct dynamic bodies among the contacts (and scratch to count them).
    dynamic_bodies: usize,
    seen: Vec<usize>,
    /// Patch contacts (`contact::torsion`): contact `c` and the points whose
    /// normal impulses bound its cone row ([`ContactLcp::set_patch_cone`]).
    patch_cones: Vec<(usize, Range<usize>)>,
    /// Contacts whose normal is a virtual unit row pinned at a bound
    /// ([`ContactLcp::pin_normal`]: a joint motor's).
    pinned: Vec<usize>,
}

thread_local! {
    /// Per body of the world, its slot in the island being numbered
    /// ([`number_bodies`]; [`NO_SLOT`] between calls).
    static SLOT_OF: RefCell<Vec<usize>> = const { RefCell::new(Vec::new()) };
}

/// [`SLOT_OF`]'s mark of a body outside the island being numbered.
const NO_SLOT: usize = usize::MAX;

/// `seen` ← the distinct dynamic bodies of `side_body` (bodies of a world of
/// `bodies`), ascending; `side_slot` ← each side's rank among them. The
/// distinct bodies are found by marks, not by sorting every side (sorting
/// the 80 sides of a 10-box stack and a binary search per side were a sixth
/// of its assembly).
fn number_bodies(
    side_body: &[Option<usize>],
    bodies: usize,
    seen: &mut Vec<usize>,
    side_slot: &mut Vec<Option<usize>>,
) {
    SLOT_OF.with_borrow_mut(|slot_of| {
        if slot_of.len() < bodies {
            slot_of.resize(bodies, NO_SLOT);
        }
        seen.clear();
        for &b in side_body.iter().flatten() {
            if slot_of[b] == NO_SLOT {
                slot_of[b] = 0;
                seen.push(b);
            }
        }
        seen.sort_unstable();
        seen.iter().enumerate().for_each(|(r, &b)| slot_of[b] = r);
        side_slot.clear();
        side_slot.extend(side_body.iter().map(|b| b.map(|b| slot_of[b])));
        seen.iter().for_each(|&b| slot_of[b] = NO_SLOT);
    });
}

#[inline]
pub(crate) fn dot6(a: &Row6, b: &Row6) -> f64 {
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) + (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
}

#[inline]
pub(crate) fn row(lin: Vec3, ang: Vec3) -> Row6 {
    [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z]
}

/// 3×3 Gram block `G[a][b] = J_a · W_b`.
#[inline]
fn gram(j: &[Row6; 3], w: &[Row6; 3]) -> [[f64; 3]; 3] {
    let mut g = [[0.0; 3]; 3];
    for (a, ga) in g.iter_mut().enumerate() {
        for (b, gab) in ga.iter_mut().enumerate() {
            *gab = dot6(&j[a], &w[b]);
        }
    }
    g
}

/// A contact's diagonal entries of its friction directions from `d = [nn,
/// t1t1, t1t2, t2t2]`: `c²·t1t1 + 2cs·t1t2 + s²·t2t2` (`weights` `[c², 2cs, s²]`).
#[inline]
fn direction_diagonal(out: &mut [f64], weights: &[[f64; 3]], d: &[f64; 4]) {
    for (x, w) in out.iter_mut().zip(weights) {
        *x = w[0] * d[1] + w[1] * d[2] + w[2] * d[3];
    }
}

/// A contact's values of its friction directions from those of `t1` and
/// `t2`: `c·v1 + s·v2` (`trig` the directions' `(c, s)`).
#[inline]
fn direction_values(out: &mut [f64], trig: &[(f64, f64)], v1: f64, v2: f64) {
    for (x, &(c, s)) in out.iter_mut().zip(trig) {
        *x = c * v1 + s * v2;
    }
}

impl ContactLcp {
    pub fn new() -> Self {
        Self::default()
    }

    /// Where `fn`, `fd`, `λ` of each contact live in `z`.
    pub fn layout(&self) -> ContactLayout {
        self.layout
    }
    /// Number of contacts.
    pub fn nc(&self) -> usize {
        self.layout.nc
    }
    /// Friction directions per contact.
    pub fn k(&self) -> usize {
        self.layout.k
    }
    /// LCP size `nc·(k + 2)`.
    pub fn n(&self) -> usize {
        self.layout.n()
    }
    /// Friction-cone scale `s` used in `M`.
    pub fn scale(&self) -> f64 {
        self.s
    }
    /// Row-major `M` (empty while lent out by [`ContactLcp::take_lcp`]).
    pub fn m(&self) -> &[f64] {
        &self.m
    }
    pub fn q(&self) -> &[f64] {
        &self.q
    }
    /// Friction coefficient per contact.
    pub fn mu(&self) -> &[f64] {
        &self.mu
    }
    /// Jacobian rows (`n`, `t1`, `t2`) of contact `i`.
    pub fn rows(&self, i: usize) -> ContactRows {
        ContactRows {
            body: [self.side_body[2 * i], self.side_body[2 * i + 1]],
            rows: [self.jac[2 * i], self.jac[2 * i + 1]],
        }
    }

    /// The dynamic body on `side` (0 = A, 1 = B) of contact `c`, `None` if static.
    #[inline]
    pub fn side_body(&self, c: usize, side: usize) -> Option<usize> {
        self.side_body[2 * c + side]
    }

    /// The island's own number (`0..dynamic_body_count()`) of the body on
    /// `side` of contact `c`, `None` if static.
    #[inline]
    pub fn side_slot(&self, c: usize, side: usize) -> Option<usize> {
        self.side_slot[2 * c + side]
    }

    /// Rows `[n, t1, t2]` of `J` and of `M_b⁻¹ Jᵀ` on `side` of contact `c`.
    #[inline]
    pub fn side_rows(&self, c: usize, side: usize) -> (&[Row6; 3], &[Row6; 3]) {
        (&self.jac[2 * c + side], &self.minv_jt[2 * c + side])
    }

    /// `(J M_b⁻¹ Jᵀ)_ii` of index `i` (0 for a `λ`), from the contact's
    /// blocks formed at assembly (to round-off the entry the rows give).
    pub fn delassus_diag(&self, i: usize) -> f64 {
        self.diag[i]
    }

    /// [`ContactLcp::delassus_diag`] of every index.
    pub fn delassus_diagonal(&self) -> &[f64] {
        &self.diag
    }

    /// Contact `c`'s entries of the diagonal from its `J_t M_b⁻¹ J_tᵀ` of
    /// normal and tangents summed over its dynamic sides, `d = [nn, t1t1,
    /// t1t2, t2t2]` (a direction's is `c²·t1t1 + 2cs·t1t2 + s²·t2t2`).
    fn set_diag(&mut self, c: usize, d: [f64; 4]) {
        let lay = self.layout;
        self.diag[lay.fn_index(c)] = d[0];
        direction_diagonal(&mut self.diag[lay.fd_of(c)], &self.dir_weights, &d);
        self.diag[lay.lambda_index(c)] = 0.0;
    }

    /// `(cos, sin)` of friction direction `j`'s angle `2πj/k`.
    #[inline]
    pub fn cos_sin(&self, j: usize) -> (f64, f64) {
        self.trig[j]
    }

    /// `(cos, sin)` of every friction direction, `j = 0..k`.
    #[inline]
    pub fn trig(&self) -> &[(f64, f64)] {
        &self.trig
    }

    /// Number of bodies of the world the rows index into.
    pub fn body_count(&self) -> usize {
        self.bodies
    }

    /// Number of distinct dynamic bodies the contacts touch.
    pub fn dynamic_body_count(&self) -> usize {
        self.dynamic_bodies
    }

    /// Contact `c`'s impulse of `z` in its `(n, t1, t2)` frame:
    /// `Σ_j fd_j d_j = t1 Σ c_j fd_j + t2 Σ s_j fd_j`.
    #[inline]
    pub fn frame_impulse(&self, c: usize, z: &[f64]) -> [f64; 3] {
        let mut imp = [z[c], 0.0, 0.0];
        for (&f, &(cj, sj)) in z[self.layout.fd_of(c)].iter().zip(&self.trig) {
            imp[1] += cj * f;
            imp[2] += sj * f;
        }
        imp
    }

    /// The Jacobian row of direction `d_j` of contact `i` for `side` (0 = A, 1 = B).
    pub fn direction_row(&self, i: usize, side: usize, j: usize) -> Row6 {
        let r = &self.jac[2 * i + side];
        let (c, s) = self.trig[j];
        std::array::from_fn(|m| c * r[1][m] + s * r[2][m])
    }

    /// Assembles `(M, q)` for `contacts`.
    pub fn assemble(&mut self, contacts: &[Contact], dynamics: &BodyDynamics<'_>, p: &AssemblyParams) {
        self.assemble_rows(contacts, dynamics, p);
        self.assemble_matrix();
    }

    /// `true` when `M` is formed for the current rows (after
    /// [`ContactLcp::assemble_matrix`], and not lent out).
    pub fn has_matrix(&self) -> bool {
        self.matrix_ready && self.m.len() == self.n() * self.n()
    }

    /// The Jacobian rows, `M_b⁻¹ Jᵀ` and `q` — everything but the dense `M`,
    /// which [`ContactLcp::assemble_matrix`] forms from them when it is needed
    /// (the body-space view [`super::BodySpaceLcp`] works without it).
    pub fn assemble_rows(&mut self, contacts: &[Contact], dynamics: &BodyDynamics<'_>, p: &AssemblyParams) {
        let nc = contacts.len();
        let k = p.k;
        let lay = ContactLayout::new(nc, k);
        self.layout = lay;
        self.s = p.s;
        if self.basis.as_ref().map(|b| b.k()) != Some(k) {
            let basis = FrictionBasis::new(k);
            self.trig = (0..k).map(|j| basis.cos_sin(j)).collect();
            self.dir_weights = self.trig.iter().map(|&(c, s)| [c * c, 2.0 * c * s, s * s]).collect();
            self.basis = Some(basis);
        }
        let n = lay.n();

        // Rows of n, t1, t2 and their M⁻¹Jᵀ per contact and side.
        // (Every entry is written below: sized, not zeroed first.)
        self.jac.resize(2 * nc, [[0.0; 6]; 3]);
        self.minv_jt.resize(2 * nc, [[0.0; 6]; 3]);
        self.side_body.clear();
        self.mu.clear();
        self.patch_cones.clear();
        self.pinned.clear();
        for (c, ct) in contacts.iter().enumerate() {
            self.mu.push(ct.mu);
            let dirs = [ct.normal, ct.tangent, ct.normal.cross(ct.tangent)];
            for (side, (bi, sign)) in [(ct.body_a, 1.0), (ct.body_b, -1.0)].into_iter().enumerate() {
                let body = &dynamics.bodies[bi];
                if body.is_static() {
                    self.side_body.push(None);
                    // (A static side's rows are zero.)
                    self.jac[2 * c + side] = [[0.0; 6]; 3];
                    self.minv_jt[2 * c + side] = [[0.0; 6]; 3];
                    continue;
                }
                self.side_body.push(Some(bi));
                let arm = ct.point - body.position();
                let inv_i = dynamics.inv_inertia_world[bi];
                for (r, &dir) in dirs.iter().enumerate() {
                    // Side A sees the direction, side B its opposite.
                    let d = dir * sign;
                    let ang = arm.cross(d);
                    self.jac[2 * c + side][r] = row(d, ang);
                    self.minv_jt[2 * c + side][r] = row(d * body.inv_mass(), inv_i * ang);
                }
            }
        }

        // The diagonal and q = [J_n v* + stabilization; J_d v*; 0] from the
        // rows, per contact over chunks of their buffers (every entry written:
        // sized, not zeroed first; no index checked per entry).
        self.diag.resize(n, 0.0);
        self.q.resize(n, 0.0);
        let (diag_n, rest) = self.diag.split_at_mut(nc);
        let (diag_d, diag_l) = rest.split_at_mut(nc * k);
        let (q_n, rest) = self.q.split_at_mut(nc);
        let (q_d, q_l) = rest.split_at_mut(nc * k);
        diag_l.fill(0.0);
        q_l.fill(0.0);
        let e = p.restitution.coefficient;
        let rows = self.side_body.chunks_exact(2).zip(self.jac.chunks_exact(2).zip(self.minv_jt.chunks_exact(2)));
        let outs = diag_n.iter_mut().zip(diag_d.chunks_exact_mut(k)).zip(q_n.iter_mut().zip(q_d.chunks_exact_mut(k)));
        for ((ct, (sides, (jac, minv))), ((dn, dd), (qn, qd))) in contacts.iter().zip(rows).zip(outs) {
            // Per dynamic side: the diagonal's [nn, t1t1, t1t2, t2t2], J v*
            // of n, t1, t2, and J_n v (pre-step, for restitution).
            let (mut d, mut jv, mut vn_pre) = ([0.0; 4], [0.0; 3], 0.0);
            for ((body, jac), minv) in sides.iter().zip(jac).zip(minv) {
                let Some(b) = *body else { continue };
                d[0] += dot6(&jac[0], &minv[0]);
                d[1] += dot6(&jac[1], &minv[1]);
                d[2] += dot6(&jac[1], &minv[2]);
                d[3] += dot6(&jac[2], &minv[2]);
                let vel = row(dynamics.v_free[b], dynamics.w_free[b]);
                for (v, r) in jv.iter_mut().zip(jac) {
                    *v += dot6(r, &vel);
                }
                if e > 0.0 {
                    let body = &dynamics.bodies[b];
                    vn_pre += dot6(&jac[0], &row(body.velocity(), body.angular_velocity()));
                }
            }
            *dn = d[0];
            direction_diagonal(dd, &self.dir_weights, &d);
            direction_values(qd, &self.trig, jv[1], jv[2]);
            let mut bias = p.stabilization.bias(ct.gap, p.h);
            if e > 0.0 && vn_pre < -p.restitution.threshold && ct.gap + p.h * vn_pre <= 0.0 {
                // Bounce: require v⁺_n ≥ e·|v⁻_n|, or more if stabilization asks for more.
                bias = bias.min(e * vn_pre);
            }
            *qn = jv[0] + bias;
        }

        self.bodies = dynamics.bodies.len();
        self.matrix_ready = false;
        number_bodies(&self.side_body, self.bodies, &mut self.seen, &mut self.side_slot);
        self.dynamic_bodies = self.seen.len();
    }

    /// Forms the dense `M` from the rows of [`ContactLcp::assemble_rows`].
    pub fn assemble_matrix(&mut self) {
        let lay = self.layout;
        let (nc, k, n, s) = (lay.nc, lay.k, lay.n(), self.s);
        let nb = self.dynamic_bodies;
        // Group (contact, side) by body: a counting sort over the island's body slots.
        self.adj_start.clear();
        self.adj_start.resize(nb + 1, 0);
        for b in self.side_slot.iter().flatten() {
            self.adj_start[b + 1] += 1;
        }
        for b in 0..nb {
            self.adj_start[b + 1] += self.adj_start[b];
        }
        self.adj.clear();
        self.adj.resize(self.adj_start[nb], (0, 0));
        self.adj_cursor.clear();
        self.adj_cursor.extend_from_slice(&self.adj_start[..nb]);
        for (idx, sb) in self.side_slot.iter().enumerate() {
            if let Some(b) = *sb {
                self.adj[self.adj_cursor[b]] = (idx / 2, idx % 2);
                self.adj_cursor[b] += 1;
            }
        }

        // M = 0, then A = Σ_b J_b M_b⁻¹ J_bᵀ over pairs of contacts sharing body b.
        self.m.clear();
        self.m.resize(n * n, 0.0);
        self.col.clear();
        self.col.resize(k, [0.0; 3]);
        for b in 0..nb {
            for x in self.adj_start[b]..self.adj_start[b + 1] {
                for y in x..self.adj_start[b + 1] {
                    let (c1, s1) = self.adj[x];
                    let (c2, s2) = self.adj[y];
                    let g = gram(&self.jac[2 * c1 + s1], &self.minv_jt[2 * c2 + s2]);
                    self.add_block(c1, c2, &g);
                }
            }
        }
        // The lower triangle of the impulse block from the upper (each entry
        // the same sums in the same order as its mirror), by tiles of T × T
        // so that the rows written stay in cache across a tile's columns.
        const T: usize = 8;
        let na = lay.impulses();
        for ib in (0..na).step_by(T) {
            for jb in (ib..na).step_by(T) {
                for i in ib..(ib + T).min(na) {
                    for j in jb.max(i + 1)..(jb + T).min(na) {
                        self.m[j * n + i] = self.m[i * n + j];
                    }
                }
            }
        }

        // Friction-cone coupling: sE in the friction rows, sμ and −sEᵀ in the cone rows.
        for c in 0..nc {
            let l = lay.lambda_index(c);
            for f in lay.fd_of(c) {
                self.m[f * n + l] = s;
                self.m[l * n + f] = -s;
            }
            self.m[l * n + c] = s * self.mu[c];
        }
        for (c, points) in &self.patch_cones {
            let l = lay.lambda_index(*c);
            self.m[c * n + c] = 1.0;
            for i in points.clone() {
                self.m[l * n + lay.fn_index(i)] = s;
            }
        }
        for &c in &self.pinned {
            self.m[c * n + c] = 1.0;
        }

        self.matrix_ready = true;
    }

    /// Adds the `(1+k)²` block of contacts `(c1, c2)` (`c1 ≤ c2`) expanded
    /// from the Gram block `g` of their `[n, t1, t2]` rows, on and above the
    /// diagonal of `M` only (its transpose's entries there, for the entries of
    /// the block below it): [`ContactLcp::assemble_matrix`] mirrors the upper
    /// triangle once all blocks are in. For `c1 == c2` only the block's own
    /// upper triangle is computed, so the diagonal blocks are exactly symmetric.
    fn add_block(&mut self, c1: usize, c2: usize, g: &[[f64; 3]; 3]) {
        let lay = self.layout;
        let (n, k) = (lay.n(), lay.k);
        let diag = c1 == c2;
        debug_assert!(c1 <= c2);
        // col[j'] = G·[0; c_j'; s_j'] : the block's column of direction j' in the n, t1, t2 rows.
        for (jp, col) in self.col.iter_mut().enumerate() {
            let (c, s) = self.trig[jp];
            *col = [g[0][1] * c + g[0][2] * s, g[1][1] * c + g[1][2] * s, g[2][1] * c + g[2][2] * s];
        }
        let (fd1, fd2) = (lay.fd_index(c1, 0), lay.fd_index(c2, 0));
        let m = &mut self.m;
        // normal–normal, and normal–friction: row n of c1 against d_j' of c2
        m[c1 * n + c2] += g[0][0];
        for (v, col) in m[c1 * n + fd2..c1 * n + fd2 + k].iter_mut().zip(&self.col) {
            *v += col[0];
        }
        // friction–normal, at its mirror in row c2 (on the diagonal it is the normal–friction row)
        if !diag {
            for (v, &(c, s)) in m[c2 * n + fd1..c2 * n + fd1 + k].iter_mut().zip(&self.trig) {
                *v += c * g[1][0] + s * g[2][0];
            }
        }
        // friction–friction
        for j in 0..k {
            let (c, s) = self.trig[j];
            let first = if diag { j } else { 0 };
            let row = &mut m[(fd1 + j) * n + fd2 + first..(fd1 + j) * n + fd2 + k];
            for (v, col) in row.iter_mut().zip(&self.col[first..]) {
                *v += c * col[1] + s * col[2];
            }
        }
    }

    /// Replaces contact `c`'s rows by rows that are not a point's (a joint
    /// limit or motor, `joints::limits`): rows `[n, t1, t2]` and `M_b⁻¹` of
    /// them per side (`None`: no body on that side), and `q` of its `n`, `t1`,
    /// `t2` (each friction direction's a combination). Call before the dense
    /// `M` is formed (or form it again).
    pub fn set_generalized_rows(
        &mut self,
        c: usize,
        body: [Option<usize>; 2],
        jac: [[Row6; 3]; 2],
        minv: [[Row6; 3]; 2],
        q_frame: [f64; 3],
    ) {
        for side in 0..2 {
            let k = 2 * c + side;
            self.side_body[k] = body[side];
            self.side_slot[k] = body[side].map(|b| self.seen.partition_point(|&x| x < b));
            self.jac[k] = jac[side];
            self.minv_jt[k] = minv[side];
        }
        let mut d = [0.0; 4];
        for s in (0..2).filter(|&s| body[s].is_some()) {
            d[0] += dot6(&jac[s][0], &minv[s][0]);
            d[1] += dot6(&jac[s][1], &minv[s][1]);
            d[2] += dot6(&jac[s][1], &minv[s][2]);
            d[3] += dot6(&jac[s][2], &minv[s][2]);
        }
        self.set_diag(c, d);
        let lay = self.layout;
        self.q[c] = q_frame[0];
        direction_values(&mut self.q[lay.fd_of(c)], &self.trig, q_frame[1], q_frame[2]);
        self.matrix_ready = false;
    }

    /// Makes contact `c`'s normal a virtual unit row pinned at `value`
    /// (`M_cc = 1`, `q_c = −value`: `fn = value` is the only complementary
    /// answer), for a contact whose normal row has no velocity part (a joint
    /// motor's bound, `joints::limits`). Applied whenever the dense `M` is
    /// formed (and to a formed one).
    pub fn pin_normal(&mut self, c: usize, value: f64) {
        let n = self.layout.n();
        if self.has_matrix() {
            self.m[c * n + c] = 1.0;
        }
        self.q[c] = -value;
        self.diag[c] = 1.0;
        self.pinned.push(c);
    }

    /// The contacts whose normal [`ContactLcp::pin_normal`] pinned.
    pub fn pinned(&self) -> &[usize] {
        &self.pinned
    }

    /// The patch contacts and their points ([`ContactLcp::set_patch_cone`]).
    pub fn patch_cones(&self) -> &[(usize, Range<usize>)] {
        &self.patch_cones
    }

    /// Makes contact `c` (its rows set by [`ContactLcp::set_generalized_rows`]
    /// with no normal row) a patch's torsional friction (`contact::torsion`):
    /// its normal a virtual unit row pinned at 0 (`M_cc = 1`, `q_c = 0`) and
    /// its cone row `Σ_{i ∈ points} fn_i − Σ_j fd_cj` (`M_{λc, fn_i} = s`),
    /// so its friction is bounded by the points' normal impulses. Applied
    /// whenever the dense `M` is formed; [`ContactLcp::unscaled_w`] reads it.
    pub fn set_patch_cone(&mut self, c: usize, points: Range<usize>) {
        debug_assert!(self.mu[c] == 0.0 && self.q[c] == 0.0 && points.end <= self.layout.nc);
        self.diag[c] = 1.0;
        self.patch_cones.push((c, points));
        self.matrix_ready = false;
    }

    /// As [`ContactLcp::set_generalized_rows`] with only a normal row.
    pub fn set_generalized_row(
        &mut self,
        c: usize,
        body: [Option<usize>; 2],
        jac: [Row6; 2],
        minv: [Row6; 2],
        q_n: f64,
    ) {
        let z = [0.0; 6];
        let rows = |r: [Row6; 2]| r.map(|x| [x, z, z]);
        self.set_generalized_rows(c, body, rows(jac), rows(minv), [q_n, 0.0, 0.0]);
    }

    /// Subtracts from the impulse block of the formed `M` a symmetric block
    /// `c` given on the contacts' frame rows (`3·nc` square, row-major, rows
    /// `n, t1, t2` per contact), expanded as the rows of `fn` and each `d_j`
    /// are (`joints::elimination`: the joints' coupling `Bᵀ S⁺ B`).
    pub fn subtract_frame_block(&mut self, c: &[f64]) {
        let lay = self.layout;
        let (n, na, nc) = (lay.n(), lay.impulses(), lay.nc);
        let nf = 3 * nc;
        debug_assert!(self.has_matrix() && c.len() == nf * nf);
        // T = C W (nf × na), W's column per impulse unknown: `fn` weighs its
        // contact's n row, `fd_j` its t1, t2 rows by (cos, sin); then
        // M_aa −= Wᵀ T row by row (contiguous rows: no strided writes).
        let mut t = vec![0.0; nf * na];
        for (crow, trow) in c.chunks_exact(nf).zip(t.chunks_exact_mut(na)) {
            let (tn, td) = trow.split_at_mut(nc);
            for (k, (v, fd)) in tn.iter_mut().zip(td.chunks_exact_mut(self.trig.len())).enumerate() {
                *v = crow[3 * k];
                let (c1, c2) = (crow[3 * k + 1], crow[3 * k + 2]);
                for (d, &(cj, sj)) in fd.iter_mut().zip(&self.trig) {
                    *d = cj * c1 + sj * c2;
                }
            }
        }
        for i in 0..na {
            let ci = lay.contact_of(i);
            let row = &mut self.m[i * n..i * n + na];
            if i == lay.fn_index(ci) {
                for (m, &v) in row.iter_mut().zip(&t[3 * ci * na..(3 * ci + 1) * na]) {
                    *m -= v;
                }
            } else {
                let (cj, sj) = self.trig[i - lay.fd_of(ci).start];
                let (t1, t2) = (&t[(3 * ci + 1) * na..(3 * ci + 2) * na], &t[(3 * ci + 2) * na..(3 * ci + 3) * na]);
                for ((m, &a), &b) in row.iter_mut().zip(t1).zip(t2) {
                    *m -= cj * a + sj * b;
                }
            }
        }
    }

    /// Room for the dense `M` of `n` unknowns (`try_reserve`: an allocation the
    /// system refuses is an error, not an abort).
    pub fn reserve_matrix(&mut self, n: usize) -> Result<(), lcp::limits::SizeError> {
        lcp::limits::try_reserve(&mut self.m, n.saturating_mul(n), || format!("a dense matrix of {n} × {n}"))
    }

    /// Gives the dense matrix's memory back when it holds more than twice
    /// `n × n` entries: an island slot of the step's pool keeps its buffers from
    /// step to step, so without this every slot would keep the largest matrix it
    /// ever formed (a 1,000-cube pour's slots reached several GiB together).
    pub fn trim_matrix(&mut self, n: usize) {
        if self.m.capacity() / 2 > n.saturating_mul(n) {
            self.m = Vec::new();
            self.matrix_ready = false;
        }
    }

    /// Moves `(M, q)` into an [`Lcp`] without copying (give it back with
    /// [`ContactLcp::restore`] to keep the buffers). Fails only on non-finite data.
    pub fn take_lcp(&mut self) -> Result<Lcp, LcpError> {
        let m = std::mem::take(&mut self.m);
        let q = std::mem::take(&mut self.q);
        Lcp::new(m, q)
    }

    /// Takes the buffers back from an LCP made by [`ContactLcp::take_lcp`].
    pub fn restore(&mut self, lcp: Lcp) {
        let (m, q) = lcp.into_parts();
        self.m = m;
        self.q = q;
    }

    /// A copy of the LCP (for inspection and tests).
    pub fn to_lcp(&self) -> Result<Lcp, LcpError> {
        Lcp::new(self.m.clone(), self.q.clone())
    }

    /// Maps a solution of the scaled LCP to physical units: `fn`, `fd`
    /// unchanged, `λ = s·λ_scaled` (`z = D z_scaled`).
    pub fn unscale_z(&self, z_scaled: &[f64], z: &mut Vec<f64>) {
        z.clear();
        z.extend_from_slice(z_scaled);
        self.layout.unscale_z(z, self.s);
    }

    /// `w = M₁ z + q` of the *unscaled* LCP (`s = 1`) for a physical `z`:
    /// normal velocities, tangential velocities + λ, and the cone slack
    /// `μ fn − Σ_j fd_j`. Requires `(M, q)` to be present (not lent out).
    pub fn unscaled_w(&self, z: &[f64], w: &mut Vec<f64>) {
        let lay = self.layout;
        let (n, na) = (lay.n(), lay.impulses());
        w.clear();
        w.resize(n, 0.0);
        // The A block does not depend on s.
        for (i, wi) in w.iter_mut().enumerate().take(na) {
            let mrow = &self.m[i * n..i * n + na];
            *wi = lcp::problem::dot(mrow, &z[..na]) + self.q[i];
        }
        for c in 0..lay.nc {
            let lambda = z[lay.lambda_index(c)];
            let mut sum_fd = 0.0;
            for f in lay.fd_of(c) {
                w[f] += lambda;
                sum_fd += z[f];
            }
            w[lay.lambda_index(c)] = self.mu[c] * z[c] - sum_fd;
        }
        for (c, points) in &self.patch_cones {
            w[lay.lambda_index(*c)] += points.clone().map(|i| z[lay.fn_index(i)]).sum::<f64>();
        }
    }

    /// Adds `M_b⁻¹ Jᵀ z` (the velocity change of the impulses `fn`, `fd` in
    /// the physical `z`) to the per-body `dv`, `dw`.
    pub fn apply_impulses(&self, z: &[f64], dv: &mut [Vec3], dw: &mut [Vec3]) {
        self.add_impulses(&self.side_body, z, dv, dw);
    }

    /// As [`ContactLcp::apply_impulses`], into per-body arrays of the island
    /// (`dynamic_body_count()` long, indexed by [`ContactLcp::side_slot`]).
    pub fn apply_impulses_local(&self, z: &[f64], dv: &mut [Vec3], dw: &mut [Vec3]) {
        self.add_impulses(&self.side_slot, z, dv, dw);
    }

    fn add_impulses(&self, index: &[Option<usize>], z: &[f64], dv: &mut [Vec3], dw: &mut [Vec3]) {
        for c in 0..self.layout.nc {
            let imp = self.frame_impulse(c, z);
            // (An unloaded contact adds nothing: on a resting stack half the corners.)
            if imp == [0.0; 3] {
                continue;
            }
            for side in 0..2 {
                let Some(b) = index[2 * c + side] else { continue };
                // (A contact without friction impulse, a resting stack's, adds its normal only.)
                for (w, &zi) in self.minv_jt[2 * c + side].iter().zip(&imp).filter(|(_, &zi)| zi != 0.0) {
                    dv[b] += Vec3::new(w[0], w[1], w[2]) * zi;
                    dw[b] += Vec3::new(w[3], w[4], w[5]) * zi;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ContactLcp;

    #[test]
    fn a_slot_gives_back_a_dense_matrix_over_twice_its_islands_size() {
        let mut lcp = ContactLcp::default();
        lcp.reserve_matrix(100).unwrap();
        assert!(lcp.m.capacity() >= 100 * 100);
        lcp.trim_matrix(80); // 2 · 80² ≥ 100²: kept for reuse
        assert!(lcp.m.capacity() >= 100 * 100);
        lcp.trim_matrix(10);
        assert_eq!(lcp.m.capacity(), 0);
        assert!(!lcp.has_matrix());
    }
}
