//! The joint rows eliminated from the step (Drake's `ConstraintSolver` way):
//! `S = G M⁻¹ Gᵀ` factored once per step, the free velocity projected onto
//! the joints, each contact island's LCP coupled through `S⁺`, and the joint
//! impulses the contacts add.
//!
//! For an island's contact rows `J` (per contact `n, t1, t2`, the frame
//! rows every friction direction is a combination of), `B = G M⁻¹ Jᵀ` and
//! `X = S⁺ B`. The LCP's impulse block `J M⁻¹ Jᵀ` becomes `J P Jᵀ =
//! J M⁻¹ Jᵀ − Bᵀ X`, and an answer `z` (frame impulses `f`) adds the joint
//! impulse `−X f`, so that `v⁺ = v*ₚ + M⁻¹Jᵀz − M⁻¹GᵀX f = v*ₚ + P Jᵀ z`.

use super::joint::{Joint, JointReaction};
use super::pivoted_cholesky::PivotedCholesky;
use super::rows::JointRow;
use crate::contact::assembly::{dot6, row, Row6};
use crate::contact::coupled_space::gram_row;
use crate::contact::ContactLcp;
use crate::dynamics::Body;
use crate::math::{Mat3, Vec3};

/// One step's joint rows and their factorization (buffers kept between steps).
#[derive(Clone, Debug, Default)]
pub struct JointSystem {
    pub rows: Vec<JointRow>,
    /// `M_b⁻¹ Gᵀ` per row and side.
    minv: Vec<[Row6; 2]>,
    s: Vec<f64>,
    pub(super) factor: PivotedCholesky,
    /// Impulse per row this step (N·s, N·m·s): the projection's, then the contacts' added.
    pub lambda: Vec<f64>,
    /// Pairs of dynamic bodies joined by a joint (they share an island).
    pub links: Vec<(usize, usize)>,
    /// Pairs of bodies joined by a joint, sorted (they do not collide).
    pub pairs: Vec<(usize, usize)>,
    /// Per body, whether a joint holds it.
    pub jointed: Vec<bool>,
    scratch: Vec<f64>,
    /// Scratch of [`JointSystem::couple`] (`B`) and of the contacts' joint impulses.
    pub(super) b: Vec<f64>,
    pub(super) y: Vec<f64>,
    frame: Vec<f64>,
    yf: Vec<f64>,
    dl: Vec<f64>,
    /// This step's limits in the LCP, and the step's contact index of the first
    /// (they follow the geometric contacts, in this order).
    pub limits: Vec<super::limits::LimitRow>,
    pub first_limit: usize,
    /// The position projection's rows and system, kept between steps (`stage::joints_settle`).
    pub(super) settling: Option<Box<Settling>>,
}

/// The buffers of the position projection after a step.
#[derive(Clone, Debug, Default)]
pub(super) struct Settling {
    pub rows: Vec<JointRow>,
    pub inv_inertia: Vec<Mat3>,
    pub sys: JointSystem,
    delta: Vec<f64>,
    dx: Vec<Vec3>,
    dr: Vec<Vec3>,
}

impl JointSystem {
    /// Rows, `S` and its factor at the bodies' current poses; with a step
    /// `h`, the damped joints' rows too (`rows`; not for a position projection).
    pub fn build(&mut self, joints: &[Joint], bodies: &[Body], inv_inertia: &[Mat3], rank_tol: f64, h: Option<f64>) {
        self.rows.clear();
        for (j, joint) in joints.iter().enumerate() {
            joint.push_rows(j, bodies, &mut self.rows);
            if let Some(h) = h {
                joint.push_damping(j, bodies, h, &mut self.rows);
            }
        }
        self.minv.clear();
        self.minv.extend(self.rows.iter().map(|r| {
            [0, 1].map(|s| match r.body[s] {
                None => [0.0; 6],
                Some(b) => {
                    let j = &r.jac[s];
                    let (lin, ang) = (Vec3::new(j[0], j[1], j[2]), Vec3::new(j[3], j[4], j[5]));
                    row(lin * bodies[b].inv_mass, inv_inertia[b] * ang)
                }
            })
        }));
        let m = self.rows.len();
        self.s.clear();
        self.s.resize(m * m, 0.0);
        for a in 0..m {
            for b in a..m {
                let v = self.g_minv(a, b);
                self.s[a * m + b] = v;
                self.s[b * m + a] = v;
            }
        }
        // The rank is judged on the rigid rows' scale (a light damper's
        // 1/(h d) would raise the stop above real pivots), then the dampers'
        // compliance added.
        let top = (0..m).map(|i| self.s[i * m + i]).fold(0.0f64, f64::max);
        for (i, r) in self.rows.iter().enumerate() {
            self.s[i * m + i] += r.compliance;
        }
        self.factor.factor(&self.s, m, rank_tol, top);
        self.lambda.clear();
        self.lambda.resize(m, 0.0);
        // Who is joined to whom.
        self.jointed.clear();
        self.jointed.resize(bodies.len(), false);
        self.links.clear();
        self.pairs.clear();
        for joint in joints {
            let dynamic = [joint.dynamic_side(bodies, 0), joint.dynamic_side(bodies, 1)];
            for b in dynamic.into_iter().flatten() {
                self.jointed[b] = true;
            }
            if let [Some(a), Some(b)] = dynamic {
                self.links.push((a, b));
            }
            if let [Some(a), Some(b)] = joint.bodies {
                self.pairs.push((a.min(b), a.max(b)));
            }
        }
        self.pairs.sort_unstable();
        self.pairs.dedup();
    }

    /// `G_a M⁻¹ G_bᵀ`: the two rows' products over the bodies they share.
    fn g_minv(&self, a: usize, b: usize) -> f64 {
        let (ra, rb) = (&self.rows[a], &self.rows[b]);
        let mut v = 0.0;
        for sa in 0..2 {
            let Some(body) = ra.body[sa] else { continue };
            for sb in 0..2 {
                if rb.body[sb] == Some(body) {
                    v += dot6(&ra.jac[sa], &self.minv[b][sb]);
                }
            }
        }
        v
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Whether a joint joins bodies `i` and `j` (they get no contact).
    pub fn joins(&self, i: usize, j: usize) -> bool {
        !self.pairs.is_empty() && self.pairs.binary_search(&(i.min(j), i.max(j))).is_ok()
    }

    /// Whether any of `bodies` (world indices) is a jointed dynamic body.
    pub fn holds_jointed(&self, bodies: &[usize]) -> bool {
        !self.jointed.is_empty() && bodies.iter().any(|&b| self.jointed[b])
    }

    /// Rank of `S` (rows minus the dependent ones dropped).
    pub fn rank(&self) -> usize {
        self.factor.rank()
    }

    /// Projects the free velocities onto the joints: `λ₀ = −S⁺(G v* + β C/h)`,
    /// `v* += M⁻¹ Gᵀ λ₀`.
    pub fn project(&mut self, v: &mut [Vec3], w: &mut [Vec3], h: f64, drift: f64) {
        let m = self.rows.len();
        self.scratch.clear();
        self.scratch.extend(self.rows.iter().map(|r| {
            let gv: f64 = (0..2).filter_map(|s| r.body[s].map(|b| dot6(&r.jac[s], &row(v[b], w[b])))).sum();
            -(gv + drift * r.error / h)
        }));
        let mut lambda = std::mem::take(&mut self.lambda);
        lambda.resize(m, 0.0);
        self.factor.solve(&self.scratch, &mut lambda);
        self.add_velocity(&lambda, v, w);
        self.lambda = lambda;
    }

    /// One position projection: `δ = S⁺(−C)`, each body moved by `M⁻¹Gᵀδ`
    /// (rotations as a rotation vector), `st`'s buffers reused. The largest row error before it.
    pub(super) fn settle(&mut self, bodies: &mut [Body], st: &mut Settling) -> f64 {
        let worst = self.rows.iter().fold(0.0f64, |m, r| m.max(r.error.abs()));
        self.scratch.clear();
        self.scratch.extend(self.rows.iter().map(|r| -r.error));
        let Settling { delta, dx, dr, .. } = st;
        delta.clear();
        delta.resize(self.rows.len(), 0.0);
        self.factor.solve(&self.scratch, delta);
        for v in [&mut *dx, &mut *dr] {
            v.clear();
            v.resize(bodies.len(), Vec3::ZERO);
        }
        self.add_velocity(delta, dx, dr);
        for ((b, x), r) in bodies.iter_mut().zip(dx.iter()).zip(dr.iter()) {
            if b.is_static {
                continue;
            }
            b.position += *x;
            b.orientation = b.orientation.integrate(*r, 1.0);
        }
        worst
    }

    /// `v += M⁻¹ Gᵀ λ` for row impulses `λ`.
    pub(crate) fn add_velocity(&self, lambda: &[f64], v: &mut [Vec3], w: &mut [Vec3]) {
        for ((r, minv), &l) in self.rows.iter().zip(&self.minv).zip(lambda) {
            if l == 0.0 {
                continue;
            }
            for (body, x) in r.body.iter().zip(minv) {
                let Some(b) = *body else { continue };
                v[b] += Vec3::new(x[0], x[1], x[2]) * l;
                w[b] += Vec3::new(x[3], x[4], x[5]) * l;
            }
        }
    }

    /// Couples an island's contacts through the joints: `Y = L⁻¹ Πᵀ B`
    /// (`X = S⁺ B = Π L⁻ᵀ Y`) into `out`. The dense `M`, when it is formed,
    /// gets `−Bᵀ X = −Yᵀ Y` on its impulse block ([`JointCoupling::subtract_from`]);
    /// the operator of `contact::coupled_space` reads `Y` without forming it.
    pub fn couple(&mut self, lcp: &ContactLcp, out: &mut JointCoupling) {
        let (m, nf) = (self.rows.len(), 3 * lcp.nc());
        // B = G M⁻¹ J_frameᵀ over the bodies a joint row and a contact side share.
        let b = &mut self.b;
        b.clear();
        b.resize(m * nf, 0.0);
        for (r, jr) in self.rows.iter().enumerate() {
            for c in 0..lcp.nc() {
                for side in 0..2 {
                    let Some(body) = lcp.side_body(c, side) else { continue };
                    let minv_c = lcp.side_rows(c, side).1;
                    for js in (0..2).filter(|&js| jr.body[js] == Some(body)) {
                        for k in 0..3 {
                            b[r * nf + 3 * c + k] += dot6(&jr.jac[js], &minv_c[k]);
                        }
                    }
                }
            }
        }
        self.factor.forward(b, nf, &mut out.y);
        out.rank = self.factor.rank();
        out.frames = nf;
    }

    /// The joint impulses of an island's applied contact impulses `z`
    /// (physical) through its `coupling`: `λ += −X f`, and their velocity
    /// change added to `dv`, `dw`.
    pub fn add_contact_response(
        &mut self,
        coupling: &JointCoupling,
        lcp: &ContactLcp,
        z: &[f64],
        dv: &mut [Vec3],
        dw: &mut [Vec3],
    ) {
        let mut dl = std::mem::take(&mut self.dl);
        if self.row_impulses_into(coupling, lcp, z, &mut dl) {
            self.add_velocity(&dl, dv, dw);
            for (l, d) in self.lambda.iter_mut().zip(&dl) {
                *l += d;
            }
        }
        self.dl = dl;
    }

    /// The joint row impulses `−X f` that an island's contact impulses `z`
    /// (physical) cause through its `coupling`; `None` when no joint couples it.
    pub fn contact_row_impulses(&mut self, coupling: &JointCoupling, lcp: &ContactLcp, z: &[f64]) -> Option<Vec<f64>> {
        let mut dl = Vec::new();
        self.row_impulses_into(coupling, lcp, z, &mut dl).then_some(dl)
    }

    /// [`JointSystem::contact_row_impulses`] into `dl` (its buffers reused);
    /// `false` when no joint couples the island.
    fn row_impulses_into(&mut self, coupling: &JointCoupling, lcp: &ContactLcp, z: &[f64], dl: &mut Vec<f64>) -> bool {
        let (m, nf) = (self.rows.len(), 3 * lcp.nc());
        let y = &coupling.y;
        if y.is_empty() || y.len() != self.factor.rank() * nf || z.len() != lcp.n() {
            return false;
        }
        // −X f = −S⁺ B f = −Π L⁻ᵀ (Y f).
        self.frame.clear();
        self.frame.extend((0..lcp.nc()).flat_map(|c| lcp.frame_impulse(c, z)));
        let f = &self.frame;
        self.yf.clear();
        self.yf.extend(y.chunks_exact(nf).map(|yr| -yr.iter().zip(f).map(|(a, b)| a * b).sum::<f64>()));
        dl.clear();
        dl.resize(m, 0.0);
        self.factor.backward(&self.yf, dl);
        true
    }

    /// Each joint's reaction from the row impulses: what side A exerts on
    /// side B, at B's anchor, over a step of `h`.
    pub fn reactions(&self, joints: &[Joint], bodies: &[Body], h: f64, out: &mut Vec<JointReaction>) {
        out.clear();
        out.resize(joints.len(), JointReaction::default());
        for (r, &l) in self.rows.iter().zip(&self.lambda) {
            // B's row is −(the row A sees); the impulse on B is jac_B·λ.
            let j = &r.jac[1];
            let (p, a) = (Vec3::new(j[0], j[1], j[2]) * l, Vec3::new(j[3], j[4], j[5]) * l);
            let rec = &mut out[r.joint];
            rec.force += p;
            rec.torque += a;
        }
        for (rec, joint) in out.iter_mut().zip(joints) {
            // Angular impulse about B's centre of mass → about the anchor.
            let xb = joint.anchors_world(bodies)[1];
            let pb = super::joint::pose(bodies, joint.bodies[1]).0;
            rec.torque -= (xb - pb).cross(rec.force);
            rec.force = rec.force / h;
            rec.torque = rec.torque / h;
        }
    }
}

/// An island's coupling through the joints: `Y = L⁻¹ Πᵀ B` (`rank × 3nc`,
/// row-major, `B = G M⁻¹ J_frameᵀ` on each contact's `n, t1, t2` rows), so
/// that the joints take `Bᵀ S⁺ B = Yᵀ Y` from the impulse block of its `M`.
/// Kept in the island's slot from step to step (its buffers reused); empty
/// when no joint holds the island.
#[derive(Clone, Debug, Default)]
pub struct JointCoupling {
    /// `Y`, row-major (`rank` rows of `frames` entries).
    pub y: Vec<f64>,
    pub rank: usize,
    /// `3 nc`: the contacts' frame rows.
    pub frames: usize,
    /// Scratch: `Yᵀ Y` when the dense `M` is formed.
    gram: Vec<f64>,
}

impl JointCoupling {
    /// No coupling (not a jointed island, or `S` of rank 0).
    pub fn is_empty(&self) -> bool {
        self.y.is_empty()
    }

    /// Forgets the coupling (an island no joint holds).
    pub fn clear(&mut self) {
        self.y.clear();
        self.rank = 0;
        self.frames = 0;
    }

    /// `Y` and its row count, for an operator that reads it.
    pub fn factor(&self) -> (&[f64], usize) {
        (&self.y, self.rank)
    }

    /// Subtracts `Yᵀ Y`, expanded to the impulse rows, from the formed dense
    /// `M` of `lcp` (`J P Jᵀ = J M⁻¹ Jᵀ − Bᵀ S⁺ B`).
    pub fn subtract_from(&mut self, lcp: &mut ContactLcp) {
        let nf = self.frames;
        if self.is_empty() || nf != 3 * lcp.nc() {
            return;
        }
        // Yᵀ Y row by row, each summed over Y's rows in order (exactly
        // symmetric as accumulated, and the coupled operator's entries' bits).
        let cm = &mut self.gram;
        cm.resize(nf * nf, 0.0);
        for (k, row) in cm.chunks_exact_mut(nf).enumerate() {
            gram_row(&self.y, nf, k, row);
        }
        lcp.subtract_frame_block(cm);
    }
}
