//! Hard contact LCPs: seven families of scenes built to stress
//! Lemke — many, duplicate, nearly parallel and collinear contacts, mass
//! ratios up to 1e4, thin rods with `cond(M_b)` up to 1e8, μ = 0 — as the
//! simulator's bodies and contacts, assembled by its one assembly.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{principal_body, Scene};
use crate::dynamics::Body;
use crate::geometry::{Contact, Shape};
use crate::math::{Quat, Vec3};
use lcp::Lcp;

/// A family of hard contact LCPs ([`hard_contact_lcp`]). Every family draws a
/// slope in [0°, 60°], a friction coefficient per contact (0 with probability
/// 0.15, else uniform in [0, 2]), random body velocities (resting, sliding,
/// approaching, spinning) and, in a third of the scenes, a stabilization term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HardKind {
    /// One box, 5–16 contacts on its bottom face (4 corners plus random points).
    ManyContacts,
    /// One box, 1–8 contacts plus exact duplicates (identical rows of `J`), up to 16.
    Duplicate,
    /// One box, 2–8 contacts each with a twin 1e-6 m away whose normal is tilted by 1e-6 rad.
    NearlyParallel,
    /// One box, 3–8 contacts on one bottom edge and up to 4 on the opposite one:
    /// collinear points, so `J_n` has redundant rows.
    Collinear,
    /// Two dynamic boxes stacked on the slope (12 dof), mass ratio 10^U(0, 4),
    /// light on heavy or heavy on light; 4 contacts between them, 4 on the ground.
    MassRatio,
    /// A thin rod (cylinder, length 1, mass 1) lying on the slope at a random
    /// yaw, `cond(M_b) = 10^U(2, 8)`, dense world-frame `M_b⁻¹`, 2–8 contacts along its length.
    ThinRod,
    /// Everything at once: a flat, ill-conditioned board under a box with a
    /// mass ratio up to 1e4, duplicates and near-parallel twins, up to 16 contacts.
    Mixed,
}

impl HardKind {
    /// Every family, in declaration order.
    pub const ALL: [HardKind; 7] = [
        HardKind::ManyContacts,
        HardKind::Duplicate,
        HardKind::NearlyParallel,
        HardKind::Collinear,
        HardKind::MassRatio,
        HardKind::ThinRod,
        HardKind::Mixed,
    ];

    /// Stable snake_case name (labels, result files).
    pub fn as_str(self) -> &'static str {
        match self {
            HardKind::ManyContacts => "many_contacts",
            HardKind::Duplicate => "duplicate",
            HardKind::NearlyParallel => "nearly_parallel",
            HardKind::Collinear => "collinear",
            HardKind::MassRatio => "mass_ratio",
            HardKind::ThinRod => "thin_rod",
            HardKind::Mixed => "mixed",
        }
    }
}

/// Distance between twin contacts and tilt between their normals in [`HardKind::NearlyParallel`].
pub const TWIN_OFFSET: f64 = 1e-6;

/// Most contacts any hard scene has.
pub const HARD_MAX_CONTACTS: usize = 16;

/// Tangent frame `(t1, t2)` of a unit normal: `t1` downhill (gravity projected
/// on the tangent plane); for a nearly level plane (|downhill|² ≤ 1e-6) the
/// projection of x instead, so that normals 1e-6 rad apart get nearly equal frames.
fn tangent_frame(n: Vec3) -> (Vec3, Vec3) {
    let down = -Vec3::Z + n * n.z;
    let t = if down.norm_squared() > 1e-6 { down } else { Vec3::X - n * n.x };
    let t1 = t.try_normalize().expect("a unit normal has a tangent");
    (t1, n.cross(t1))
}

/// A box of a hard scene before it becomes a [`Body`]: principal axes, half extents, mass.
#[derive(Clone, Copy, Debug)]
struct Block {
    /// Centre of mass (world).
    x: Vec3,
    /// Principal axes (world, orthonormal, right-handed).
    axes: [Vec3; 3],
    /// Half extents along `axes` (for the rod `[L/2, r, r]`).
    half: Vec3,
    mass: f64,
    /// Principal moments of inertia about `axes`.
    inertia: [f64; 3],
}

impl Block {
    /// Box of half extents `half`, resting on the plane through `base` with normal `axes[2]`.
    fn cuboid(base: Vec3, axes: [Vec3; 3], half: Vec3, mass: f64) -> Block {
        let [a, b, c] = half.to_array();
        let inertia = [mass / 3.0 * (b * b + c * c), mass / 3.0 * (a * a + c * c), mass / 3.0 * (a * a + b * b)];
        Block { x: base + axes[2] * c, axes, half, mass, inertia }
    }

    /// A point of the bottom (`side = −1`) or top (`side = 1`) face, `(u, v)` in [−1, 1]².
    fn face_point(&self, u: f64, v: f64, side: f64) -> Vec3 {
        self.x
            + self.axes[0] * (u * self.half.x)
            + self.axes[1] * (v * self.half.y)
            + self.axes[2] * (side * self.half.z)
    }

    /// The dynamic body, moving with `[v; ω]`.
    fn body(&self, v: Vec3, w: Vec3) -> Body {
        let shape = Shape::cuboid(self.half).expect("hard-scene boxes have positive extents");
        principal_body(shape, self.x, self.axes, self.mass, self.inertia, v, w)
    }
}

/// One contact of a hard scene: `normal` pushes body `a` away from body `b` (or the ground).
#[derive(Clone, Copy, Debug, PartialEq)]
struct HardContact {
    point: Vec3,
    normal: Vec3,
    a: usize,
    b: Option<usize>,
    mu: f64,
    /// Gap φ ≤ 0 (penetration) for the stabilization term.
    gap: f64,
}

/// A random hard contact scene, its ingredients exposed for tests and
/// experiments. `z = [fn (nc); fd (nc·k); λ (nc)]` as everywhere (`lcp::contact`).
#[derive(Clone, Debug, PartialEq)]
pub struct HardScene {
    pub kind: HardKind,
    /// Friction directions per contact.
    pub k: usize,
    /// Number of contacts (≤ [`HARD_MAX_CONTACTS`]).
    pub nc: usize,
    /// Degrees of freedom, 6 per dynamic body.
    pub ndof: usize,
    /// Condition number of `M_b` (from the masses and principal moments).
    pub mass_cond: f64,
    /// Bodies (dynamic first, the ground last), contacts and free velocities `v + h g`
    /// (no gyroscopic term); stabilization `0.2·φ/h` in a third of the scenes.
    pub scene: Scene,
}

impl HardScene {
    /// Draws a scene of family `kind` with `k` friction directions from `seed`.
    ///
    /// # Panics
    /// If `k == 0`.
    pub fn random(kind: HardKind, k: usize, seed: u64) -> HardScene {
        assert!(k > 0, "HardScene::random: k must be ≥ 1");
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let slope = rng.random_range(0.0..=60.0f64).to_radians();
        let (st, ct) = slope.sin_cos();
        let normal = Vec3::new(st, 0.0, ct);
        let (t1, t2) = tangent_frame(normal);
        let yaw = rng.random_range(0.0..2.0 * PI);
        let (sy, cy) = yaw.sin_cos();
        let axes = [t1 * cy + t2 * sy, t1 * -sy + t2 * cy, normal];
        let stabilize = rng.random_bool(1.0 / 3.0);
        let draw = Draw { normal, axes, t1, t2, stabilize };
        let (blocks, contacts) = draw.family(kind, &mut rng);
        scene_from(kind, k, &mut rng, &blocks, &contacts)
    }

    /// The contact LCP of this scene with friction-cone scale `scale`.
    ///
    /// # Panics
    /// If `scale` is negative or not finite.
    pub fn lcp(&self, scale: f64) -> Lcp {
        assert!(scale >= 0.0 && scale.is_finite(), "hard contact LCP: scale = {scale} must be finite and ≥ 0");
        match self.scene.lcp(self.k, scale) {
            Ok(lcp) => lcp,
            Err(e) => panic!("hard contact LCP ({}, scale = {scale}): {e}", self.kind.as_str()),
        }
    }

    /// Friction coefficient per contact.
    pub fn mu(&self) -> Vec<f64> {
        self.scene.contacts.iter().map(|c| c.mu).collect()
    }

    /// Unit contact normals (world), per contact.
    pub fn normals(&self) -> Vec<Vec3> {
        self.scene.contacts.iter().map(|c| c.normal).collect()
    }

    /// A label that reproduces this scene with [`HardScene::random`].
    pub fn label(&self, seed: u64) -> String {
        format!("{}/k{}/nc{}/seed{seed}", self.kind.as_str(), self.k, self.nc)
    }
}

/// The draws every family shares: the slope frame, μ per contact, the gap
/// (stabilization in a third of the scenes), random boxes.
struct Draw {
    normal: Vec3,
    axes: [Vec3; 3],
    t1: Vec3,
    t2: Vec3,
    stabilize: bool,
}

impl Draw {
    /// 0 with probability 0.15, else uniform in [0, 2].
    fn mu(&self, rng: &mut ChaCha8Rng) -> f64 {
        if rng.random_bool(0.15) {
            0.0
        } else {
            rng.random_range(0.0..=2.0)
        }
    }

    fn gap(&self, rng: &mut ChaCha8Rng) -> f64 {
        if self.stabilize {
            rng.random_range(-1e-3..=0.0)
        } else {
            0.0
        }
    }

    /// A contact of body `a` with the ground at `point`.
    fn ground(&self, rng: &mut ChaCha8Rng, point: Vec3, a: usize) -> HardContact {
        let mu = self.mu(rng);
        HardContact { point, normal: self.normal, a, b: None, mu, gap: self.gap(rng) }
    }

    /// `count` ground contacts on the bottom face of block 0, `b`: its corners
    /// first, then random points (see [`face_uv`]).
    fn bottom_contacts(&self, rng: &mut ChaCha8Rng, b: &Block, count: usize, contacts: &mut Vec<HardContact>) {
        for c in 0..count {
            let (u, v) = face_uv(rng, c);
            contacts.push(self.ground(rng, b.face_point(u, v, -1.0), 0));
        }
    }

    fn random_box(&self, rng: &mut ChaCha8Rng) -> Block {
        let half = Vec3::new(rng.random_range(0.1..=1.0), rng.random_range(0.1..=1.0), rng.random_range(0.1..=1.0));
        let mass = 10f64.powf(rng.random_range(-1.0..=1.0));
        Block::cuboid(Vec3::ZERO, self.axes, half, mass)
    }

    /// The blocks and contacts of family `kind`.
    fn family(&self, kind: HardKind, rng: &mut ChaCha8Rng) -> (Vec<Block>, Vec<HardContact>) {
        let mut blocks = Vec::new();
        let mut contacts: Vec<HardContact> = Vec::new();
        match kind {
            HardKind::ManyContacts => {
                let b = self.random_box(rng);
                let nc = rng.random_range(5..=HARD_MAX_CONTACTS);
                self.bottom_contacts(rng, &b, nc, &mut contacts);
                blocks.push(b);
            }
            HardKind::Duplicate => {
                let b = self.random_box(rng);
                let base = rng.random_range(1..=8usize);
                self.bottom_contacts(rng, &b, base, &mut contacts);
                let copies = rng.random_range(1..=HARD_MAX_CONTACTS - base);
                for _ in 0..copies {
                    let c = contacts[rng.random_range(0..contacts.len())];
                    contacts.push(c);
                }
                blocks.push(b);
            }
            HardKind::NearlyParallel => {
                let b = self.random_box(rng);
                let base = rng.random_range(2..=8usize);
                self.bottom_contacts(rng, &b, base, &mut contacts);
                for c in 0..base {
                    let m = self.mu(rng);
                    let twin = twin_of(rng, contacts[c], self.t1, self.t2, m);
                    contacts.push(twin);
                }
                blocks.push(b);
            }
            HardKind::Collinear => {
                let b = self.random_box(rng);
                let on_edge = rng.random_range(3..=8usize);
                let opposite = rng.random_range(0..=4usize);
                for c in 0..on_edge + opposite {
                    let v = if c < on_edge { -1.0 } else { 1.0 };
                    let p = b.face_point(rng.random_range(-1.0..=1.0), v, -1.0);
                    contacts.push(self.ground(rng, p, 0));
                }
                blocks.push(b);
            }
            HardKind::MassRatio => {
                let ratio = 10f64.powf(rng.random_range(0.0..=4.0));
                let (lower_mass, upper_mass) = if rng.random_bool(0.5) { (ratio, 1.0) } else { (1.0, ratio) };
                let half_l =
                    Vec3::new(rng.random_range(0.3..=1.0), rng.random_range(0.3..=1.0), rng.random_range(0.1..=0.5));
                let half_u =
                    Vec3::new(rng.random_range(0.1..=0.5), rng.random_range(0.1..=0.5), rng.random_range(0.1..=0.5));
                let lower = Block::cuboid(Vec3::ZERO, self.axes, half_l, lower_mass);
                let top = lower.face_point(rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5), 1.0);
                let upper = Block::cuboid(top, self.axes, half_u, upper_mass);
                for (u, v) in CORNERS {
                    contacts.push(HardContact { b: Some(0), ..self.ground(rng, upper.face_point(u, v, -1.0), 1) });
                }
                for (u, v) in CORNERS {
                    contacts.push(self.ground(rng, lower.face_point(u, v, -1.0), 0));
                }
                blocks.push(lower);
                blocks.push(upper);
            }
            HardKind::ThinRod => {
                let cond = 10f64.powf(rng.random_range(2.0..=8.0));
                let r = (2.0 / cond).sqrt(); // mass 1: cond(M_b) = 1 / (m r²/2)
                let length = 1.0;
                let mut rod = Block::cuboid(Vec3::ZERO, self.axes, Vec3::new(length / 2.0, r, r), 1.0);
                rod.inertia =
                    [0.5 * r * r, (3.0 * r * r + length * length) / 12.0, (3.0 * r * r + length * length) / 12.0];
                // Axis-symmetric: any roll about the axis leaves M_b⁻¹ unchanged, the yaw makes it dense.
                let nc = rng.random_range(2..=8usize);
                for _ in 0..nc {
                    let p = rod.face_point(rng.random_range(-1.0..=1.0), 0.0, -1.0);
                    contacts.push(self.ground(rng, p, 0));
                }
                blocks.push(rod);
            }
            HardKind::Mixed => {
                // A flat board (thin along the normal) and a box on it, either one heavy.
                let thin = 10f64.powf(rng.random_range(-3.0..=-1.0));
                let ratio = 10f64.powf(rng.random_range(0.0..=4.0));
                let (lower_mass, upper_mass) = if rng.random_bool(0.5) { (ratio, 1.0) } else { (1.0, ratio) };
                let board = Block::cuboid(
                    Vec3::ZERO,
                    self.axes,
                    Vec3::new(1.0, rng.random_range(0.05..=1.0), thin),
                    lower_mass,
                );
                let top = board.face_point(rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5), 1.0);
                let half_u =
                    Vec3::new(rng.random_range(0.05..=0.5), rng.random_range(0.05..=0.5), rng.random_range(0.05..=0.5));
                let upper = Block::cuboid(top, self.axes, half_u, upper_mass);
                for (u, v) in CORNERS {
                    contacts.push(HardContact { b: Some(0), ..self.ground(rng, upper.face_point(u, v, -1.0), 1) });
                }
                for (u, v) in CORNERS {
                    contacts.push(self.ground(rng, board.face_point(u, v, -1.0), 0));
                }
                // Fill up to 16 with duplicates and near-parallel twins of random contacts.
                let extra = rng.random_range(0..=HARD_MAX_CONTACTS - contacts.len());
                for _ in 0..extra {
                    let c = contacts[rng.random_range(0..contacts.len())];
                    let c = if rng.random_bool(0.5) { c } else { twin_of(rng, c, self.t1, self.t2, c.mu) };
                    contacts.push(c);
                }
                blocks.push(board);
                blocks.push(upper);
            }
        }
        (blocks, contacts)
    }
}

/// A face's corners in its `(u, v)` coordinates, in contact order.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// Bottom-face coordinates of the `c`-th contact: the 4 corners first, then random points.
fn face_uv(rng: &mut ChaCha8Rng, c: usize) -> (f64, f64) {
    match CORNERS.get(c) {
        Some(&uv) => uv,
        None => (rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0)),
    }
}

/// A twin of contact `c`: the point moved [`TWIN_OFFSET`] within the tangent
/// plane, the normal tilted by [`TWIN_OFFSET`] rad about a random tangent axis.
fn twin_of(rng: &mut ChaCha8Rng, c: HardContact, t1: Vec3, t2: Vec3, mu: f64) -> HardContact {
    let phi = rng.random_range(0.0..2.0 * PI);
    let dir = t1 * phi.cos() + t2 * phi.sin();
    let psi = rng.random_range(0.0..2.0 * PI);
    let axis = t1 * psi.cos() + t2 * psi.sin();
    let tilted = Quat::from_axis_angle(axis, TWIN_OFFSET).rotate(c.normal);
    HardContact {
        point: c.point + dir * TWIN_OFFSET,
        normal: tilted.try_normalize().expect("a rotated unit normal"),
        mu,
        ..c
    }
}

/// Bodies with their velocities, the ground, and the contacts between them.
fn scene_from(kind: HardKind, k: usize, rng: &mut ChaCha8Rng, blocks: &[Block], contacts: &[HardContact]) -> HardScene {
    let diag: Vec<f64> =
        blocks.iter().flat_map(|b| [b.mass, b.mass, b.mass, b.inertia[0], b.inertia[1], b.inertia[2]]).collect();
    let mass_cond = diag.iter().fold(0.0f64, |a, &v| a.max(v)) / diag.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    // Velocities: resting, sliding in the plane, approaching it, spinning — independently per body.
    let normal = contacts.first().map_or(Vec3::Z, |c| c.normal);
    let (t1, t2) = tangent_frame(normal);
    let mut scene = Scene::new();
    for b in blocks {
        let speed = if rng.random_bool(0.3) { 0.0 } else { rng.random_range(0.0..=2.0) };
        let heading = rng.random_range(0.0..2.0 * PI);
        let approach = if rng.random_bool(0.5) { 0.0 } else { rng.random_range(0.0..=0.5) };
        let v = normal * -approach + t1 * (speed * heading.cos()) + t2 * (speed * heading.sin());
        let omega = if rng.random_bool(0.5) {
            Vec3::ZERO
        } else {
            Vec3::new(rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0))
        };
        scene.push_body(b.body(v, omega));
    }
    let ground = scene.push_ground();
    scene.contacts = contacts
        .iter()
        .map(|c| Contact {
            body_a: c.a,
            body_b: c.b.unwrap_or(ground),
            point: c.point,
            normal: c.normal,
            gap: c.gap,
            mu: c.mu,
            tangent: tangent_frame(c.normal).0,
        })
        .collect();
    HardScene { kind, k, nc: contacts.len(), ndof: 6 * blocks.len(), mass_cond, scene }
}

/// A hard contact LCP of family `kind` with k = 8 friction directions and
/// friction-cone scale `scale` (see [`HardKind`], [`HardScene`]). Deterministic per seed.
///
/// # Panics
/// If `scale` is negative or not finite.
pub fn hard_contact_lcp(kind: HardKind, scale: f64, seed: u64) -> Lcp {
    HardScene::random(kind, 8, seed).lcp(scale)
}

/// [`hard_contact_lcp`] with `k` friction directions.
///
/// # Panics
/// If `k == 0` or `scale` is negative or not finite.
pub fn hard_contact_lcp_k(kind: HardKind, k: usize, scale: f64, seed: u64) -> Lcp {
    HardScene::random(kind, k, seed).lcp(scale)
}

/// SplitMix64: independent per-item seeds from one corpus seed.
fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The `i`-th item of [`hard_corpus`]: `(kind, k, seed)` for [`HardScene::random`].
/// Families cycle through [`HardKind::ALL`]; one round in ten uses k = 4, one k = 16, the rest k = 8.
pub fn hard_corpus_item(seed: u64, i: usize) -> (HardKind, usize, u64) {
    let kinds = HardKind::ALL.len();
    let kind = HardKind::ALL[i % kinds];
    let k = match (i / kinds) % 10 {
        3 => 4,
        7 => 16,
        _ => 8,
    };
    (kind, k, splitmix64(seed ^ splitmix64(i as u64)))
}

/// `count` hard contact LCPs at friction-cone scale `scale`, each with a label
/// `kind/kK/ncN/seedS` that reproduces it (`HardScene::random(kind, K, S).lcp(scale)`).
/// The same `seed` gives the same scenes at every scale.
///
/// # Panics
/// If `scale` is negative or not finite.
pub fn hard_corpus(seed: u64, count: usize, scale: f64) -> Vec<(String, Lcp)> {
    (0..count)
        .map(|i| {
            let (kind, k, s) = hard_corpus_item(seed, i);
            let scene = HardScene::random(kind, k, s);
            (scene.label(s), scene.lcp(scale))
        })
        .collect()
}
