//! [`contact_lcp`]: the contact LCP of one unit cube on a random slope.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{principal_body, Scene, CONTACT_H, GRAVITY};
use crate::contact::FrictionBasis;
use crate::geometry::{Contact, Shape};
use crate::math::Vec3;
use lcp::Lcp;

/// The random scene behind [`contact_lcp`], exposed for tests and experiments.
/// The cube's centre is at the origin, its bottom face on the plane.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxOnPlane {
    /// Slope angle θ (rad), uniform in [0°, 60°]. The plane's normal is
    /// `(sin θ, 0, cos θ)`, its downhill direction `t1 = (cos θ, 0, −sin θ)`, `t2 = (0, 1, 0)`.
    pub slope: f64,
    /// Friction coefficient, uniform in [0.1, 1.5], the same at every contact.
    pub mu: f64,
    /// Box rotation about the plane normal (rad), uniform in [0, 2π).
    pub yaw: f64,
    /// Contact points relative to the box centre (world frame), all on the bottom face.
    pub arms: Vec<Vec3>,
    /// Body velocity `[v; ω]` before the step (world frame).
    pub velocity: [f64; 6],
    /// Free velocity `v* = v + h g` (ω unchanged: the cube's inertia is isotropic).
    pub vstar: [f64; 6],
    /// Plane frame `(t1, t2, n)`.
    pub frame: [Vec3; 3],
}

/// Mass of [`contact_lcp`]'s cube (kg) and its principal moments (unit cube, `m/6`).
const BOX_MASS: f64 = 1.0;
const BOX_MOMENT: f64 = 1.0 / 6.0;

impl BoxOnPlane {
    /// Draws the scene for `nc` contacts from `seed` (see [`contact_lcp`]).
    pub fn random(nc: usize, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let slope = rng.random_range(0.0..=60.0f64).to_radians();
        let mu = rng.random_range(0.1..=1.5f64);
        let yaw = rng.random_range(0.0..2.0 * PI);
        let (st, ct) = slope.sin_cos();
        let normal = Vec3::new(st, 0.0, ct);
        let t1 = Vec3::new(ct, 0.0, -st);
        let t2 = Vec3::Y;
        // Box axes in the plane: the frame rotated by the yaw.
        let (sy, cy) = yaw.sin_cos();
        let a1 = t1 * cy + t2 * sy;
        let a2 = t1 * -sy + t2 * cy;
        // Bottom-face points (u, v) in box axes: corners first (so nc = 2 is an edge), then random.
        const CORNERS: [(f64, f64); 4] = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)];
        let arms = (0..nc)
            .map(|c| {
                let (u, v) =
                    if c < 4 { CORNERS[c] } else { (rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5)) };
                normal * -0.5 + a1 * u + a2 * v
            })
            .collect();
        // Velocity: sliding up to 2 m/s in a random in-plane direction, approaching
        // the plane at up to 0.5 m/s, spinning up to 1 rad/s about each axis.
        let speed = rng.random_range(0.0..=2.0);
        let heading = rng.random_range(0.0..2.0 * PI);
        let approach = rng.random_range(0.0..=0.5);
        let v = t1 * (speed * heading.cos()) + t2 * (speed * heading.sin()) + normal * -approach;
        let omega = Vec3::new(rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0));
        let vs = v + GRAVITY * CONTACT_H;
        BoxOnPlane {
            slope,
            mu,
            yaw,
            arms,
            velocity: [v.x, v.y, v.z, omega.x, omega.y, omega.z],
            vstar: [vs.x, vs.y, vs.z, omega.x, omega.y, omega.z],
            frame: [t1, t2, normal],
        }
    }

    /// Friction direction `j` of `k` (the simulator's basis, `d_0 = t1`).
    pub fn direction(&self, j: usize, k: usize) -> Vec3 {
        FrictionBasis::new(k).direction(self.frame[2], self.frame[0], j)
    }

    /// The cube (mass 1, inertia ⅙·I) with its contacts on the plane.
    pub fn scene(&self) -> Scene {
        let mut scene = Scene::new();
        let [v0, v1, v2, w0, w1, w2] = self.velocity;
        let axes = [Vec3::X, Vec3::Y, Vec3::Z];
        let shape = Shape::cuboid(Vec3::splat(0.5)).expect("a unit cube is valid");
        let cube = principal_body(
            shape,
            Vec3::ZERO,
            axes,
            BOX_MASS,
            [BOX_MOMENT; 3],
            Vec3::new(v0, v1, v2),
            Vec3::new(w0, w1, w2),
        );
        scene.push_body(cube);
        let ground = scene.push_ground();
        let [t1, _, normal] = self.frame;
        scene.contacts = self
            .arms
            .iter()
            .map(|&arm| Contact { body_a: 0, body_b: ground, point: arm, normal, gap: 0.0, mu: self.mu, tangent: t1 })
            .collect();
        scene
    }
}

/// The contact LCP of one rigid unit cube (mass 1, inertia ⅙·I,
/// h = [`CONTACT_H`]) on a plane through `nc` contact points with `k` friction
/// directions each and friction-cone scale `scale` (`s`).
///
/// The scene ([`BoxOnPlane::random`]): slope uniform in 0–60° (tilted about
/// the y axis), `μ` uniform in [0.1, 1.5], a random yaw of the box about the
/// plane normal, contacts at bottom-face corners for `nc ≤ 4` (`nc = 2`: one
/// edge) plus uniformly random bottom-face points beyond 4, random initial
/// velocity (sliding, approaching, spinning), no stabilization (zero gap).
/// `z = [fn (nc); fd (nc·k); λ (nc)]`, size `nc·(k + 2)`.
///
/// # Panics
/// If `nc == 0`, `k == 0`, or `scale` is negative or not finite.
pub fn contact_lcp(nc: usize, k: usize, scale: f64, seed: u64) -> Lcp {
    assert!(nc > 0 && k > 0, "contact_lcp: nc = {nc} and k = {k} must be ≥ 1");
    assert!(scale >= 0.0 && scale.is_finite(), "contact_lcp: scale = {scale} must be finite and ≥ 0");
    match BoxOnPlane::random(nc, seed).scene().lcp(k, scale) {
        Ok(lcp) => lcp,
        Err(e) => panic!("contact_lcp(nc = {nc}, k = {k}, scale = {scale}): {e}"),
    }
}
