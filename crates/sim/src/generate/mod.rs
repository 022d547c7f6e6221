//! Seeded contact scenes and their LCPs, for tests, benchmarks and experiments.
//!
//! Every scene is made of the simulator's own [`Body`]s and [`Contact`]s with
//! free velocities, and its LCP is assembled by the one Stewart–Trinkle
//! assembly ([`ContactLcp`]) — the solver crate never sees a body. Every
//! generator is a pure function of its seed (ChaCha8), across platforms.
//!
//! - [`box_on_plane`]: [`contact_lcp`], one unit cube on a random slope.
//! - [`hard`]: [`hard_contact_lcp`], [`HardScene`], [`hard_corpus`]: hard
//!   contact LCPs: up to 16 contacts, duplicate and nearly parallel
//!   contacts, collinear (redundant) rows, mass ratios up to 1e4, `cond(M_b)`
//!   up to 1e8, μ in [0, 2], any k.
//!
//! Matrix generators without bodies (SPD, P-matrix, Murty, infeasible) are
//! `lcp::generate`'s.

pub mod box_on_plane;
pub mod hard;

pub use box_on_plane::{contact_lcp, BoxOnPlane};
pub use hard::{
    hard_contact_lcp, hard_contact_lcp_k, hard_corpus, hard_corpus_item, HardKind, HardScene, HARD_MAX_CONTACTS,
    TWIN_OFFSET,
};

use crate::contact::assembly::{AssemblyParams, BodyDynamics};
use crate::contact::{ContactLcp, Restitution, Stabilization};
use crate::dynamics::{Body, BodyDesc};
use crate::geometry::{Contact, Plane, Shape};
use crate::math::{Mat3, Quat, Vec3};
use lcp::{Lcp, LcpError};

/// Time step `h` of every generated scene (s).
pub const CONTACT_H: f64 = 0.01;
/// Gravity (m/s²), the crate's convention.
pub const GRAVITY: Vec3 = Vec3::new(0.0, 0.0, -9.81);

/// Everything the assembly reads about a generated scene. The dynamic bodies
/// come first (6 degrees of freedom each, in order), the static ground last.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub bodies: Vec<Body>,
    pub contacts: Vec<Contact>,
    /// Free linear velocity `v + h g` per body.
    pub v_free: Vec<Vec3>,
    /// Free angular velocity per body (no torques).
    pub w_free: Vec<Vec3>,
}

impl Scene {
    /// An empty scene with its static ground (index 0 until bodies are added in front).
    fn new() -> Scene {
        Scene { bodies: Vec::new(), contacts: Vec::new(), v_free: Vec::new(), w_free: Vec::new() }
    }

    /// Adds a dynamic body with velocity `[v; ω]`; its free velocity is `v + h g`.
    fn push_body(&mut self, body: Body) {
        self.v_free.push(body.velocity + GRAVITY * CONTACT_H);
        self.w_free.push(body.angular_velocity);
        self.bodies.push(body);
    }

    /// Closes the body list with the static ground; returns its index.
    fn push_ground(&mut self) -> usize {
        let desc = BodyDesc::plane(Plane::ground()).fixed(true);
        self.bodies.push(Body::from_desc(&desc).expect("the ground plane is valid"));
        self.v_free.push(Vec3::ZERO);
        self.w_free.push(Vec3::ZERO);
        self.bodies.len() - 1
    }

    /// Number of dynamic bodies.
    pub fn dynamic(&self) -> usize {
        self.bodies.iter().filter(|b| !b.is_static()).count()
    }

    /// The contact LCP with `k` friction directions and cone scale `scale`, assembled
    /// by the simulator (stabilization `0.2·φ/h` for penetrating contacts, no restitution).
    pub fn assemble(&self, k: usize, scale: f64) -> ContactLcp {
        let inv_inertia: Vec<Mat3> = self.bodies.iter().map(Body::inv_inertia_world).collect();
        let dynamics = BodyDynamics {
            bodies: &self.bodies,
            inv_inertia_world: &inv_inertia,
            v_free: &self.v_free,
            w_free: &self.w_free,
        };
        let params = AssemblyParams {
            h: CONTACT_H,
            k,
            s: scale,
            stabilization: Stabilization::default(),
            restitution: Restitution::default(),
        };
        let mut lcp = ContactLcp::new();
        lcp.assemble(&self.contacts, &dynamics, &params);
        lcp
    }

    /// [`Scene::assemble`] as an [`Lcp`]; fails only on non-finite data.
    pub fn lcp(&self, k: usize, scale: f64) -> Result<Lcp, LcpError> {
        self.assemble(k, scale).take_lcp()
    }

    /// `b0`'s stabilization term per contact (`0.2·φ/h`, 0 when touching).
    pub fn b0_extra(&self) -> Vec<f64> {
        self.contacts.iter().map(|c| Stabilization::default().bias(c.gap, CONTACT_H)).collect()
    }

    /// Dense `(J_n, J_d)` (row-major, `6·dynamic()` columns) of the assembly's
    /// rows, `J_d` row `c·k + j` = direction `j` at contact `c`.
    pub fn jacobians(&self, k: usize) -> (Vec<f64>, Vec<f64>) {
        let (nc, ndof) = (self.contacts.len(), 6 * self.dynamic());
        let a = self.assemble(k, 1.0);
        let (mut jn, mut jd) = (vec![0.0; nc * ndof], vec![0.0; nc * k * ndof]);
        for c in 0..nc {
            let rows = a.rows(c);
            for (side, body) in rows.body.iter().enumerate() {
                let Some(b) = *body else { continue };
                jn[c * ndof + 6 * b..c * ndof + 6 * b + 6].copy_from_slice(&rows.rows[side][0]);
                for j in 0..k {
                    let r = (c * k + j) * ndof + 6 * b;
                    jd[r..r + 6].copy_from_slice(&a.direction_row(c, side, j));
                }
            }
        }
        (jn, jd)
    }

    /// Dense, exactly symmetric `M_b⁻¹` of the dynamic bodies (`ndof²`, row-major).
    pub fn minv(&self) -> Vec<f64> {
        let ndof = 6 * self.dynamic();
        let mut m = vec![0.0; ndof * ndof];
        for (b, body) in self.bodies.iter().enumerate().filter(|(_, b)| !b.is_static()) {
            let inv_i = body.inv_inertia_world();
            for i in 0..3 {
                m[(6 * b + i) * ndof + 6 * b + i] = body.inv_mass();
                for j in 0..3 {
                    m[(6 * b + 3 + i) * ndof + 6 * b + 3 + j] = inv_i.m[i][j];
                }
            }
        }
        m
    }

    /// `v* = [v + h g; ω]` of the dynamic bodies, length `6·dynamic()`.
    pub fn vstar(&self) -> Vec<f64> {
        (0..self.dynamic())
            .flat_map(|b| self.v_free[b].to_array().into_iter().chain(self.w_free[b].to_array()))
            .collect()
    }
}

/// A dynamic rigid body at `position` with principal `axes` (world, orthonormal)
/// and principal `moments`. Its body frame is the world frame at this instant,
/// so the inertia tensor is given in world axes, `Σ_k I_k a_k a_kᵀ`, and
/// `M_b⁻¹`'s rotational block is `Σ_k a_k a_kᵀ / I_k` entry for entry
/// (computed on and above the diagonal and mirrored: exactly symmetric).
fn principal_body(
    shape: Shape,
    position: Vec3,
    axes: [Vec3; 3],
    mass: f64,
    moments: [f64; 3],
    velocity: Vec3,
    angular: Vec3,
) -> Body {
    let outer = |op: fn(f64, f64) -> f64| {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                let v: f64 = (0..3).map(|k| op(axes[k][i] * axes[k][j], moments[k])).sum();
                m[i][j] = v;
                m[j][i] = v;
            }
        }
        Mat3::from_rows(m)
    };
    Body {
        shape,
        mass,
        inv_mass: 1.0 / mass,
        inertia: outer(|x, i| x * i),
        inv_inertia: outer(|x, i| x / i),
        position,
        orientation: Quat::IDENTITY,
        velocity,
        angular_velocity: angular,
        mu: 0.0,
        mu_torsion: 0.0,
        is_static: false,
        filter: Default::default(),
    }
}
