//! Seeded generators of test LCPs. Every random generator takes a `seed` and
//! is deterministic per seed (ChaCha8), across platforms.
//!
//! - [`contact_lcp`]: the Stewart–Trinkle / Anitescu–Potra contact LCP of
//!   DESIGN §1 for one box on a plane; [`contact_lcp_from_parts`] builds the
//!   same structure from any contact Jacobians (reusable by the simulator).
//! - [`hard_contact_lcp`], [`HardScene`], [`hard_corpus`]: hard contact LCPs (issue 5):
//!   up to 16 contacts, duplicate and nearly parallel contacts, collinear (redundant)
//!   rows, mass ratios up to 1e4, `cond(M_b)` up to 1e8, μ in [0, 2], any k.
//! - [`p_matrix_lcp`], [`spd_lcp`]: random LCPs with a unique solution.
//! - [`murty`]: Murty's (1978) example, on which Lemke's method takes 2ⁿ pivots;
//!   [`murty_unit`]: the same matrix with `q = −1`.
//! - [`infeasible_lcp`], [`infeasible_examples`]: LCPs without a solution.

use std::f64::consts::PI;
use std::fmt;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::contact::ContactLayout;
use crate::problem::{Lcp, LcpError};

/// Time step of [`contact_lcp`] (s).
pub const CONTACT_H: f64 = 0.01;
/// Gravity (m/s²), DESIGN §8.
pub const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// Inverse body mass matrix (`ndof × ndof`) as given to [`contact_lcp_from_parts`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MassInverse<'a> {
    /// Its diagonal (length `ndof`), e.g. `[1/m, 1/m, 1/m, 1/I, 1/I, 1/I]` per body.
    Diagonal(&'a [f64]),
    /// Dense, row-major (`ndof²` entries), symmetric.
    Dense(&'a [f64]),
}

/// The ingredients of a contact LCP (DESIGN §1), all row-major.
/// `nc = mu.len()`, `ndof = vstar.len()`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactParts<'a> {
    /// Friction directions per contact (`k ≥ 1`).
    pub k: usize,
    /// Normal Jacobian `J_n`, `nc × ndof`.
    pub jn: &'a [f64],
    /// Friction Jacobian `J_d`, `nc·k × ndof`, row `c·k + j` = direction `j` at contact `c`.
    pub jd: &'a [f64],
    /// `M_b⁻¹`.
    pub minv: MassInverse<'a>,
    /// Free velocity `v* = v + h M_b⁻¹ f_ext`, length `ndof`.
    pub vstar: &'a [f64],
    /// Friction coefficient per contact (finite, ≥ 0).
    pub mu: &'a [f64],
    /// Optional extra term added to `b0` (stabilization such as `φ / h`), length `nc`.
    pub b0_extra: Option<&'a [f64]>,
    /// Friction-cone scale `s` (finite, ≥ 0; 1 = unscaled, 0 = the degenerate limit).
    pub scale: f64,
}

/// Why [`contact_lcp_from_parts`] rejected its input.
#[derive(Clone, Debug, PartialEq)]
pub enum PartsError {
    /// `nc = 0`, `ndof = 0` or `k = 0`.
    Empty,
    /// A slice has the wrong length.
    Shape { what: &'static str, expected: usize, got: usize },
    /// `scale` is negative or not finite.
    Scale(f64),
    /// A friction coefficient is negative or not finite.
    Mu { index: usize, value: f64 },
    /// The assembled LCP is invalid (a non-finite entry in the inputs).
    Lcp(LcpError),
}

impl fmt::Display for PartsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartsError::Empty => write!(f, "contact LCP needs nc ≥ 1, ndof ≥ 1 and k ≥ 1"),
            PartsError::Shape { what, expected, got } => {
                write!(f, "{what} has {got} entries, expected {expected}")
            }
            PartsError::Scale(s) => write!(f, "friction-cone scale {s} must be finite and ≥ 0"),
            PartsError::Mu { index, value } => write!(f, "mu[{index}] = {value} must be finite and ≥ 0"),
            PartsError::Lcp(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for PartsError {}

/// Assembles the contact LCP of DESIGN §1 from Jacobians:
///
/// ```text
///     M = [[A00,  A01,   0 ],      q = [b0; b1; 0],   A = J M_b⁻¹ Jᵀ,  J = [J_n; J_d],
///          [A10,  A11,  sE ],      b = J v* (b0 += b0_extra),
///          [sμ,  −sEᵀ,   0 ]]      E = blockdiag(1_k),  sμ = diag(s·μ_c)
/// ```
///
/// `A` is computed on its upper triangle and mirrored, so it is exactly
/// symmetric. The result is [`Scaling::cone`](crate::Scaling::cone)`(nc, k, s)`
/// applied to the `s = 1` problem.
pub fn contact_lcp_from_parts(p: &ContactParts<'_>) -> Result<Lcp, PartsError> {
    let nc = p.mu.len();
    let ndof = p.vstar.len();
    let k = p.k;
    if nc == 0 || ndof == 0 || k == 0 {
        return Err(PartsError::Empty);
    }
    let check = |what, expected: usize, got: usize| {
        if expected == got {
            Ok(())
        } else {
            Err(PartsError::Shape { what, expected, got })
        }
    };
    check("jn", nc * ndof, p.jn.len())?;
    check("jd", nc * k * ndof, p.jd.len())?;
    match p.minv {
        MassInverse::Diagonal(d) => check("minv (diagonal)", ndof, d.len())?,
        MassInverse::Dense(d) => check("minv (dense)", ndof * ndof, d.len())?,
    }
    if let Some(extra) = p.b0_extra {
        check("b0_extra", nc, extra.len())?;
    }
    if !(p.scale >= 0.0 && p.scale.is_finite()) {
        return Err(PartsError::Scale(p.scale));
    }
    if let Some((index, &value)) = p.mu.iter().enumerate().find(|(_, m)| !(**m >= 0.0 && m.is_finite())) {
        return Err(PartsError::Mu { index, value });
    }

    let layout = ContactLayout { nc, k };
    let n = layout.n();
    let nj = nc + nc * k; // rows of J = [J_n; J_d]
    let jrow = |r: usize| -> &[f64] {
        if r < nc {
            &p.jn[r * ndof..(r + 1) * ndof]
        } else {
            let r = r - nc;
            &p.jd[r * ndof..(r + 1) * ndof]
        }
    };
    // M_b⁻¹ Jᵀ, stored by J row: minv_jt[r] = M_b⁻¹ J_rᵀ.
    let minv_jt: Vec<Vec<f64>> = (0..nj)
        .map(|r| {
            let jr = jrow(r);
            match p.minv {
                MassInverse::Diagonal(d) => jr.iter().zip(d).map(|(a, b)| a * b).collect(),
                MassInverse::Dense(d) => {
                    (0..ndof).map(|a| crate::problem::dot(&d[a * ndof..(a + 1) * ndof], jr)).collect()
                }
            }
        })
        .collect();

    let mut m = vec![0.0; n * n];
    // A = J M_b⁻¹ Jᵀ: upper triangle, mirrored.
    for r in 0..nj {
        for c in r..nj {
            let a = crate::problem::dot(jrow(r), &minv_jt[c]);
            m[r * n + c] = a;
            m[c * n + r] = a;
        }
    }
    // Cone coupling: sE, sμ, −sEᵀ.
    let s = p.scale;
    for c in 0..nc {
        let l = layout.lambda_index(c);
        m[l * n + c] = s * p.mu[c];
        for j in 0..k {
            let d = layout.fd_index(c, j);
            m[d * n + l] = s;
            m[l * n + d] = -s;
        }
    }
    // q = [J_n v* (+ extra); J_d v*; 0].
    let mut q = vec![0.0; n];
    for (r, qr) in q.iter_mut().enumerate().take(nj) {
        *qr = crate::problem::dot(jrow(r), p.vstar);
    }
    if let Some(extra) = p.b0_extra {
        for (qc, e) in q.iter_mut().zip(extra) {
            *qc += e;
        }
    }
    Lcp::new(m, q).map_err(PartsError::Lcp)
}

type V3 = [f64; 3];

fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn axpy(out: V3, s: f64, x: V3) -> V3 {
    [out[0] + s * x[0], out[1] + s * x[1], out[2] + s * x[2]]
}

/// The random scene behind [`contact_lcp`], exposed for tests and experiments.
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
    pub arms: Vec<V3>,
    /// Body velocity `[v; ω]` before the step (world frame).
    pub velocity: [f64; 6],
    /// Free velocity `v* = v + h g` (ω unchanged: the cube's inertia is isotropic).
    pub vstar: [f64; 6],
    /// Plane frame `(t1, t2, n)`.
    pub frame: [V3; 3],
}

impl BoxOnPlane {
    /// Draws the scene for `nc` contacts from `seed` (see [`contact_lcp`]).
    pub fn random(nc: usize, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let slope = rng.random_range(0.0..=60.0f64).to_radians();
        let mu = rng.random_range(0.1..=1.5f64);
        let yaw = rng.random_range(0.0..2.0 * PI);
        let (st, ct) = slope.sin_cos();
        let normal = [st, 0.0, ct];
        let t1 = [ct, 0.0, -st];
        let t2 = [0.0, 1.0, 0.0];
        // Box axes in the plane: the frame rotated by the yaw.
        let (sy, cy) = yaw.sin_cos();
        let a1 = axpy([cy * t1[0], cy * t1[1], cy * t1[2]], sy, t2);
        let a2 = axpy([-sy * t1[0], -sy * t1[1], -sy * t1[2]], cy, t2);
        // Bottom-face points (u, v) in box axes: corners first (so nc = 2 is an edge), then random.
        const CORNERS: [(f64, f64); 4] = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)];
        let arms = (0..nc)
            .map(|c| {
                let (u, v) =
                    if c < 4 { CORNERS[c] } else { (rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5)) };
                let r = [-0.5 * normal[0], -0.5 * normal[1], -0.5 * normal[2]];
                axpy(axpy(r, u, a1), v, a2)
            })
            .collect();
        // Velocity: sliding up to 2 m/s in a random in-plane direction, approaching
        // the plane at up to 0.5 m/s, spinning up to 1 rad/s about each axis.
        let speed = rng.random_range(0.0..=2.0);
        let heading = rng.random_range(0.0..2.0 * PI);
        let approach = rng.random_range(0.0..=0.5);
        let mut v = [0.0; 3];
        v = axpy(v, speed * heading.cos(), t1);
        v = axpy(v, speed * heading.sin(), t2);
        v = axpy(v, -approach, normal);
        let omega: V3 = [rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0)];
        let velocity = [v[0], v[1], v[2], omega[0], omega[1], omega[2]];
        let mut vstar = velocity;
        for a in 0..3 {
            vstar[a] += CONTACT_H * GRAVITY[a]; // mass 1: M_b⁻¹ f_ext = g
        }
        BoxOnPlane { slope, mu, yaw, arms, velocity, vstar, frame: [t1, t2, normal] }
    }

    /// Friction direction `j` of `k`: `cos(2πj/k) t1 + sin(2πj/k) t2`.
    pub fn direction(&self, j: usize, k: usize) -> V3 {
        let (s, c) = (2.0 * PI * j as f64 / k as f64).sin_cos();
        let [t1, t2, _] = self.frame;
        axpy([c * t1[0], c * t1[1], c * t1[2]], s, t2)
    }

    /// `(J_n, J_d)`, row-major with 6 columns: a row for direction `d` at arm `r` is `[dᵀ, (r × d)ᵀ]`.
    pub fn jacobians(&self, k: usize) -> (Vec<f64>, Vec<f64>) {
        let normal = self.frame[2];
        let row = |r: V3, d: V3| {
            let rxd = cross(r, d);
            [d[0], d[1], d[2], rxd[0], rxd[1], rxd[2]]
        };
        let jn = self.arms.iter().flat_map(|&r| row(r, normal)).collect();
        let jd = self.arms.iter().flat_map(|&r| (0..k).flat_map(move |j| row(r, self.direction(j, k)))).collect();
        (jn, jd)
    }
}

/// `M_b⁻¹` of [`contact_lcp`]'s box: mass 1, unit cube inertia `I = m/6 · 1`.
pub const BOX_MINV_DIAG: [f64; 6] = [1.0, 1.0, 1.0, 6.0, 6.0, 6.0];

/// The contact LCP (DESIGN §1) of one rigid unit cube (mass 1, inertia ⅙·I,
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
    let scene = BoxOnPlane::random(nc, seed);
    let (jn, jd) = scene.jacobians(k);
    let mu = vec![scene.mu; nc];
    let parts = ContactParts {
        k,
        jn: &jn,
        jd: &jd,
        minv: MassInverse::Diagonal(&BOX_MINV_DIAG),
        vstar: &scene.vstar,
        mu: &mu,
        b0_extra: None,
        scale,
    };
    match contact_lcp_from_parts(&parts) {
        Ok(lcp) => lcp,
        Err(e) => panic!("contact_lcp(nc = {nc}, k = {k}, scale = {scale}): {e}"),
    }
}

fn uniform_matrix(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n * n).map(|_| rng.random_range(-1.0..=1.0)).collect()
}

fn uniform_vector(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-1.0..=1.0)).collect()
}

/// `A Aᵀ / n`, exactly symmetric (upper triangle mirrored).
fn gram(a: &[f64], n: usize) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in i..n {
            let v = crate::problem::dot(&a[i * n..(i + 1) * n], &a[j * n..(j + 1) * n]) / n as f64;
            m[i * n + j] = v;
            m[j * n + i] = v;
        }
    }
    m
}

fn build(m: Vec<f64>, q: Vec<f64>, what: &str) -> Lcp {
    match Lcp::new(m, q) {
        Ok(lcp) => lcp,
        Err(e) => panic!("{what}: {e}"),
    }
}

/// A random LCP with a nonsymmetric positive definite — hence P — matrix:
/// `M = A Aᵀ/n + ½ I + (B − Bᵀ)/√n` (`A`, `B` uniform in [−1, 1]), whose
/// symmetric part `A Aᵀ/n + ½ I` is positive definite; `q` uniform in [−1, 1].
/// Unique solution for every `q`.
///
/// # Panics
/// If `n == 0`.
pub fn p_matrix_lcp(n: usize, seed: u64) -> Lcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let a = uniform_matrix(&mut rng, n);
    let b = uniform_matrix(&mut rng, n);
    let q = uniform_vector(&mut rng, n);
    let mut m = gram(&a, n);
    let skew = 1.0 / (n as f64).sqrt();
    for i in 0..n {
        m[i * n + i] += 0.5;
        for j in 0..n {
            m[i * n + j] += skew * (b[i * n + j] - b[j * n + i]);
        }
    }
    build(m, q, "p_matrix_lcp")
}

/// A random LCP with an exactly symmetric positive definite matrix:
/// `M = A Aᵀ/n + 0.1 I` (`A` uniform in [−1, 1], so cond(M) ≲ 40); `q` uniform in [−1, 1].
///
/// # Panics
/// If `n == 0`.
pub fn spd_lcp(n: usize, seed: u64) -> Lcp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let a = uniform_matrix(&mut rng, n);
    let q = uniform_vector(&mut rng, n);
    let mut m = gram(&a, n);
    for i in 0..n {
        m[i * n + i] += 0.1;
    }
    build(m, q, "spd_lcp")
}

/// Murty's `M̃(n)`: lower triangular, 1 on the diagonal and 2 below it. A
/// P-matrix (every principal submatrix is again of this form, determinant 1).
fn murty_matrix(n: usize) -> Vec<f64> {
    (0..n * n)
        .map(|e| match (e / n).cmp(&(e % n)) {
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Greater => 2.0,
            std::cmp::Ordering::Less => 0.0,
        })
        .collect()
}

/// Murty's example on which Lemke's method takes 2ⁿ pivots (K. G. Murty,
/// "Computational complexity of complementary pivot methods", Math.
/// Programming Study 7, 1978): `M̃(n)` lower triangular with 1 on the diagonal
/// and 2 below it, `q̃_j = −(2ⁿ + 2ⁿ⁻¹ + … + 2ⁿ⁻ʲ⁺¹)` (1-based `j`), i.e.
/// `q̃ = (−2ⁿ, −2ⁿ − 2ⁿ⁻¹, …, −(2ⁿ⁺¹ − 2))`.
///
/// `M̃` is a P-matrix, so the solution is unique: `z = (2ⁿ, 0, …, 0)` with
/// `w = (0, 2ⁿ⁻¹, 2ⁿ⁻², …, 2)`. Lemke's method with covering vector 1 on the
/// problem as given visits 2ⁿ bases (measured with this crate's Lemke without
/// equilibration, both pivoting rules, n ≤ 8); equilibration changes the
/// effective covering vector and the path becomes short. All data are exact
/// for `n ≤ 52`. See [`murty_unit`] for the `q = −1` form.
///
/// # Panics
/// If `n == 0`.
pub fn murty(n: usize) -> Lcp {
    let q = (1..=n).map(|j| -((n + 1 - j)..=n).map(|i| 2f64.powi(i as i32)).sum::<f64>()).collect();
    build(murty_matrix(n), q, "murty")
}

/// Murty's matrix `M̃(n)` (see [`murty`]) with `q = −1`, the form found in
/// LCP test collections: unique solution `z = e₁ = (1, 0, …, 0)`,
/// `w = (0, 1, …, 1)`. Not hard for Lemke (2 pivots, measured). The
/// transposed-order variant (2 above the diagonal) is the same problem with the
/// indices reversed, solution `(0, …, 0, 1)`.
///
/// # Panics
/// If `n == 0`.
pub fn murty_unit(n: usize) -> Lcp {
    build(murty_matrix(n), vec![-1.0; n], "murty_unit")
}

/// The smallest LCP without a solution: `M = [−1]`, `q = [−1]` (`w = −z − 1 < 0`).
pub fn infeasible_lcp() -> Lcp {
    build(vec![-1.0], vec![-1.0], "infeasible_lcp")
}

/// LCPs without a solution, each with a name, all `{z ≥ 0 : M z + q ≥ 0}` empty
/// (a Farkas certificate `y ≥ 0`, `Mᵀ y ≤ 0`, `qᵀ y < 0` is in the name).
/// The last two have copositive-plus `M`, for which Lemke's method must end in
/// ray termination — which then proves infeasibility.
pub fn infeasible_examples() -> Vec<(&'static str, Lcp)> {
    vec![
        ("negative scalar M=[-1] q=[-1]; y=(1)", infeasible_lcp()),
        (
            "PSD M=[[1,-1],[-1,1]] q=[-1,-1]; y=(1,1)",
            build(vec![1.0, -1.0, -1.0, 1.0], vec![-1.0, -1.0], "infeasible_examples"),
        ),
        (
            "skew M=[[0,1],[-1,0]] q=[1,-1]; y=(0,1)",
            build(vec![0.0, 1.0, -1.0, 0.0], vec![1.0, -1.0], "infeasible_examples"),
        ),
    ]
}

// ---------------------------------------------------------------------------
// Hard contact LCPs (issue 5)
// ---------------------------------------------------------------------------

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

fn dot3(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale3(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

fn sub3(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn normalize3(a: V3) -> V3 {
    scale3(1.0 / dot3(a, a).sqrt(), a)
}

/// Rotation of `v` by `angle` about the unit `axis` (Rodrigues).
fn rotate3(v: V3, axis: V3, angle: f64) -> V3 {
    let (s, c) = angle.sin_cos();
    let along = scale3(dot3(axis, v) * (1.0 - c), axis);
    axpy(axpy(scale3(c, v), s, cross(axis, v)), 1.0, along)
}

/// Tangent frame `(t1, t2)` of a unit normal: `t1` downhill (gravity projected
/// on the tangent plane) as in [`BoxOnPlane`]; for a nearly horizontal plane the
/// projection of x instead, so that normals 1e-6 rad apart get nearly equal frames.
fn tangent_frame(n: V3) -> (V3, V3) {
    let down = axpy([0.0, 0.0, -1.0], n[2], n); // −z − (−z·n) n
    let t1 = if dot3(down, down) > 1e-6 { normalize3(down) } else { normalize3(axpy([1.0, 0.0, 0.0], -n[0], n)) };
    (t1, cross(n, t1))
}

/// A rigid body of a hard scene: pose, mass and principal inertia.
#[derive(Clone, Debug, PartialEq)]
struct Body {
    /// Centre of mass (world).
    x: V3,
    /// Principal axes (world, orthonormal, right-handed).
    axes: [V3; 3],
    mass: f64,
    /// Principal moments of inertia about `axes`.
    inertia: V3,
    /// Half extents along `axes` (boxes; for the rod `[L/2, r, r]`).
    half: V3,
}

impl Body {
    /// Box of half extents `half`, resting on the plane through `base` with normal `axes[2]`.
    fn cuboid(base: V3, axes: [V3; 3], half: V3, mass: f64) -> Body {
        let [a, b, c] = half;
        let inertia = [mass / 3.0 * (b * b + c * c), mass / 3.0 * (a * a + c * c), mass / 3.0 * (a * a + b * b)];
        Body { x: axpy(base, c, axes[2]), axes, mass, inertia, half }
    }

    /// A point of the bottom (`side = −1`) or top (`side = 1`) face, `(u, v)` in [−1, 1]².
    fn face_point(&self, u: f64, v: f64, side: f64) -> V3 {
        let p = axpy(self.x, u * self.half[0], self.axes[0]);
        let p = axpy(p, v * self.half[1], self.axes[1]);
        axpy(p, side * self.half[2], self.axes[2])
    }

    /// World-frame `M_b⁻¹` block (6×6, row-major): `[1/m I, 0; 0, R I⁻¹ Rᵀ]`.
    fn minv_block(&self) -> [[f64; 6]; 6] {
        let mut b = [[0.0; 6]; 6];
        for (i, row) in b.iter_mut().enumerate().take(3) {
            row[i] = 1.0 / self.mass;
        }
        for i in 0..3 {
            for j in i..3 {
                let v: f64 = (0..3).map(|k| self.axes[k][i] * self.axes[k][j] / self.inertia[k]).sum();
                b[3 + i][3 + j] = v;
                b[3 + j][3 + i] = v;
            }
        }
        b
    }
}

/// One contact of a hard scene: `normal` pushes body `a` away from body `b` (or the ground).
#[derive(Clone, Copy, Debug, PartialEq)]
struct HardContact {
    point: V3,
    normal: V3,
    a: usize,
    b: Option<usize>,
    mu: f64,
    /// Gap φ ≤ 0 (penetration) for the stabilization term.
    gap: f64,
}

/// A random hard contact scene, its ingredients exposed for tests and
/// experiments. `z = [fn (nc); fd (nc·k); λ (nc)]` as everywhere (DESIGN §1).
#[derive(Clone, Debug, PartialEq)]
pub struct HardScene {
    pub kind: HardKind,
    /// Friction directions per contact.
    pub k: usize,
    /// Number of contacts (≤ [`HARD_MAX_CONTACTS`]).
    pub nc: usize,
    /// Degrees of freedom, 6 per dynamic body.
    pub ndof: usize,
    /// `J_n`, `nc × ndof`, row-major.
    pub jn: Vec<f64>,
    /// `J_d`, `nc·k × ndof`, row-major, row `c·k + j` = direction `j` at contact `c`.
    pub jd: Vec<f64>,
    /// Dense, exactly symmetric `M_b⁻¹` (`ndof²`, row-major).
    pub minv: Vec<f64>,
    /// Condition number of `M_b` (from the masses and principal moments).
    pub mass_cond: f64,
    /// `v* = v + h g` (no gyroscopic term), length `ndof`.
    pub vstar: Vec<f64>,
    /// Friction coefficient per contact.
    pub mu: Vec<f64>,
    /// Stabilization `0.2·φ/h` per contact (φ ≤ 0), all zero in two scenes of three.
    pub b0_extra: Vec<f64>,
    /// Unit contact normals (world), per contact.
    pub normals: Vec<V3>,
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
        let normal = [st, 0.0, ct];
        let (t1, t2) = tangent_frame(normal);
        let yaw = rng.random_range(0.0..2.0 * PI);
        let (sy, cy) = yaw.sin_cos();
        let a1 = axpy(scale3(cy, t1), sy, t2);
        let a2 = axpy(scale3(-sy, t1), cy, t2);
        let axes = [a1, a2, normal];
        let origin = [0.0; 3];
        let mu = |rng: &mut ChaCha8Rng| if rng.random_bool(0.15) { 0.0 } else { rng.random_range(0.0..=2.0) };
        let stabilize = rng.random_bool(1.0 / 3.0);
        let gap = |rng: &mut ChaCha8Rng| if stabilize { rng.random_range(-1e-3..=0.0) } else { 0.0 };
        let ground = |rng: &mut ChaCha8Rng, point: V3, a: usize| HardContact {
            point,
            normal,
            a,
            b: None,
            mu: mu(rng),
            gap: gap(rng),
        };
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let random_box = |rng: &mut ChaCha8Rng| {
            let half = [rng.random_range(0.1..=1.0), rng.random_range(0.1..=1.0), rng.random_range(0.1..=1.0)];
            let mass = 10f64.powf(rng.random_range(-1.0..=1.0));
            Body::cuboid(origin, axes, half, mass)
        };

        let mut bodies = Vec::new();
        let mut contacts: Vec<HardContact> = Vec::new();
        match kind {
            HardKind::ManyContacts => {
                let b = random_box(&mut rng);
                let nc = rng.random_range(5..=HARD_MAX_CONTACTS);
                for c in 0..nc {
                    let (u, v) = face_uv(&mut rng, c);
                    contacts.push(ground(&mut rng, b.face_point(u, v, -1.0), 0));
                }
                bodies.push(b);
            }
            HardKind::Duplicate => {
                let b = random_box(&mut rng);
                let base = rng.random_range(1..=8usize);
                for c in 0..base {
                    let (u, v) = face_uv(&mut rng, c);
                    contacts.push(ground(&mut rng, b.face_point(u, v, -1.0), 0));
                }
                let copies = rng.random_range(1..=HARD_MAX_CONTACTS - base);
                for _ in 0..copies {
                    let c = contacts[rng.random_range(0..contacts.len())];
                    contacts.push(c);
                }
                bodies.push(b);
            }
            HardKind::NearlyParallel => {
                let b = random_box(&mut rng);
                let base = rng.random_range(2..=8usize);
                for c in 0..base {
                    let (u, v) = face_uv(&mut rng, c);
                    contacts.push(ground(&mut rng, b.face_point(u, v, -1.0), 0));
                }
                for c in 0..base {
                    let m = mu(&mut rng);
                    let twin = twin_of(&mut rng, contacts[c], t1, t2, m);
                    contacts.push(twin);
                }
                bodies.push(b);
            }
            HardKind::Collinear => {
                let b = random_box(&mut rng);
                let on_edge = rng.random_range(3..=8usize);
                let opposite = rng.random_range(0..=4usize);
                for c in 0..on_edge + opposite {
                    let v = if c < on_edge { -1.0 } else { 1.0 };
                    let p = b.face_point(rng.random_range(-1.0..=1.0), v, -1.0);
                    contacts.push(ground(&mut rng, p, 0));
                }
                bodies.push(b);
            }
            HardKind::MassRatio => {
                let ratio = 10f64.powf(rng.random_range(0.0..=4.0));
                let (lower_mass, upper_mass) = if rng.random_bool(0.5) { (ratio, 1.0) } else { (1.0, ratio) };
                let half_l = [rng.random_range(0.3..=1.0), rng.random_range(0.3..=1.0), rng.random_range(0.1..=0.5)];
                let half_u = [rng.random_range(0.1..=0.5), rng.random_range(0.1..=0.5), rng.random_range(0.1..=0.5)];
                let lower = Body::cuboid(origin, axes, half_l, lower_mass);
                let top = lower.face_point(rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5), 1.0);
                let upper = Body::cuboid(top, axes, half_u, upper_mass);
                for (u, v) in corners {
                    contacts.push(HardContact { b: Some(0), ..ground(&mut rng, upper.face_point(u, v, -1.0), 1) });
                }
                for (u, v) in corners {
                    contacts.push(ground(&mut rng, lower.face_point(u, v, -1.0), 0));
                }
                bodies.push(lower);
                bodies.push(upper);
            }
            HardKind::ThinRod => {
                let cond = 10f64.powf(rng.random_range(2.0..=8.0));
                let r = (2.0 / cond).sqrt(); // mass 1: cond(M_b) = 1 / (m r²/2)
                let length = 1.0;
                let mut rod = Body::cuboid(origin, axes, [length / 2.0, r, r], 1.0);
                rod.inertia =
                    [0.5 * r * r, (3.0 * r * r + length * length) / 12.0, (3.0 * r * r + length * length) / 12.0];
                // Axis-symmetric: any roll about the axis leaves M_b⁻¹ unchanged, the yaw makes it dense.
                let nc = rng.random_range(2..=8usize);
                for _ in 0..nc {
                    let p = rod.face_point(rng.random_range(-1.0..=1.0), 0.0, -1.0);
                    contacts.push(ground(&mut rng, p, 0));
                }
                bodies.push(rod);
            }
            HardKind::Mixed => {
                // A flat board (thin along the normal) and a box on it, either one heavy.
                let thin = 10f64.powf(rng.random_range(-3.0..=-1.0));
                let ratio = 10f64.powf(rng.random_range(0.0..=4.0));
                let (lower_mass, upper_mass) = if rng.random_bool(0.5) { (ratio, 1.0) } else { (1.0, ratio) };
                let board = Body::cuboid(origin, axes, [1.0, rng.random_range(0.05..=1.0), thin], lower_mass);
                let top = board.face_point(rng.random_range(-0.5..=0.5), rng.random_range(-0.5..=0.5), 1.0);
                let half_u = [rng.random_range(0.05..=0.5), rng.random_range(0.05..=0.5), rng.random_range(0.05..=0.5)];
                let upper = Body::cuboid(top, axes, half_u, upper_mass);
                for (u, v) in corners {
                    contacts.push(HardContact { b: Some(0), ..ground(&mut rng, upper.face_point(u, v, -1.0), 1) });
                }
                for (u, v) in corners {
                    contacts.push(ground(&mut rng, board.face_point(u, v, -1.0), 0));
                }
                // Fill up to 16 with duplicates and near-parallel twins of random contacts.
                let extra = rng.random_range(0..=HARD_MAX_CONTACTS - contacts.len());
                for _ in 0..extra {
                    let c = contacts[rng.random_range(0..contacts.len())];
                    let c = if rng.random_bool(0.5) { c } else { twin_of(&mut rng, c, t1, t2, c.mu) };
                    contacts.push(c);
                }
                bodies.push(board);
                bodies.push(upper);
            }
        }
        scene_from(kind, k, &mut rng, &bodies, &contacts)
    }

    /// The contact LCP of this scene with friction-cone scale `scale`.
    ///
    /// # Panics
    /// If `scale` is negative or not finite.
    pub fn lcp(&self, scale: f64) -> Lcp {
        let parts = ContactParts {
            k: self.k,
            jn: &self.jn,
            jd: &self.jd,
            minv: MassInverse::Dense(&self.minv),
            vstar: &self.vstar,
            mu: &self.mu,
            b0_extra: Some(&self.b0_extra),
            scale,
        };
        match contact_lcp_from_parts(&parts) {
            Ok(lcp) => lcp,
            Err(e) => panic!("hard contact LCP ({}, scale = {scale}): {e}", self.kind.as_str()),
        }
    }

    /// A label that reproduces this scene with [`HardScene::random`].
    pub fn label(&self, seed: u64) -> String {
        format!("{}/k{}/nc{}/seed{seed}", self.kind.as_str(), self.k, self.nc)
    }
}

/// Bottom-face coordinates of the `c`-th contact: the 4 corners first, then random points.
fn face_uv(rng: &mut ChaCha8Rng, c: usize) -> (f64, f64) {
    const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    match CORNERS.get(c) {
        Some(&uv) => uv,
        None => (rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0)),
    }
}

/// A twin of contact `c`: the point moved [`TWIN_OFFSET`] within the tangent
/// plane, the normal tilted by [`TWIN_OFFSET`] rad about a random tangent axis.
fn twin_of(rng: &mut ChaCha8Rng, c: HardContact, t1: V3, t2: V3, mu: f64) -> HardContact {
    let phi = rng.random_range(0.0..2.0 * PI);
    let dir = axpy(scale3(phi.cos(), t1), phi.sin(), t2);
    let psi = rng.random_range(0.0..2.0 * PI);
    let axis = axpy(scale3(psi.cos(), t1), psi.sin(), t2);
    HardContact {
        point: axpy(c.point, TWIN_OFFSET, dir),
        normal: normalize3(rotate3(c.normal, axis, TWIN_OFFSET)),
        mu,
        ..c
    }
}

/// Jacobians, `M_b⁻¹`, velocities and friction data of bodies and contacts.
fn scene_from(kind: HardKind, k: usize, rng: &mut ChaCha8Rng, bodies: &[Body], contacts: &[HardContact]) -> HardScene {
    let nc = contacts.len();
    let ndof = 6 * bodies.len();
    // Row of J for direction d at contact c: +[d, (p − x_a) × d] on a, −[d, (p − x_b) × d] on b.
    let row = |c: &HardContact, d: V3| -> Vec<f64> {
        let mut r = vec![0.0; ndof];
        let mut put = |body: usize, sign: f64| {
            let arm = cross(sub3(c.point, bodies[body].x), d);
            for i in 0..3 {
                r[6 * body + i] += sign * d[i];
                r[6 * body + 3 + i] += sign * arm[i];
            }
        };
        put(c.a, 1.0);
        if let Some(b) = c.b {
            put(b, -1.0);
        }
        r
    };
    let mut jn = Vec::with_capacity(nc * ndof);
    let mut jd = Vec::with_capacity(nc * k * ndof);
    for c in contacts {
        jn.extend(row(c, c.normal));
        let (t1, t2) = tangent_frame(c.normal);
        for j in 0..k {
            let (s, co) = (2.0 * PI * j as f64 / k as f64).sin_cos();
            jd.extend(row(c, axpy(scale3(co, t1), s, t2)));
        }
    }
    let mut minv = vec![0.0; ndof * ndof];
    for (bi, body) in bodies.iter().enumerate() {
        let block = body.minv_block();
        for i in 0..6 {
            for j in 0..6 {
                minv[(6 * bi + i) * ndof + 6 * bi + j] = block[i][j];
            }
        }
    }
    let diag: Vec<f64> =
        bodies.iter().flat_map(|b| [b.mass, b.mass, b.mass, b.inertia[0], b.inertia[1], b.inertia[2]]).collect();
    let mass_cond = diag.iter().fold(0.0f64, |a, &v| a.max(v)) / diag.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    // Velocities: resting, sliding in the plane, approaching it, spinning — independently per body.
    let normal = contacts.first().map_or([0.0, 0.0, 1.0], |c| c.normal);
    let (t1, t2) = tangent_frame(normal);
    let mut vstar = Vec::with_capacity(ndof);
    for _ in bodies {
        let speed = if rng.random_bool(0.3) { 0.0 } else { rng.random_range(0.0..=2.0) };
        let heading = rng.random_range(0.0..2.0 * PI);
        let approach = if rng.random_bool(0.5) { 0.0 } else { rng.random_range(0.0..=0.5) };
        let mut v = axpy(axpy(scale3(-approach, normal), speed * heading.cos(), t1), speed * heading.sin(), t2);
        v = axpy(v, CONTACT_H, GRAVITY);
        let omega: V3 = if rng.random_bool(0.5) {
            [0.0; 3]
        } else {
            [rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0), rng.random_range(-1.0..=1.0)]
        };
        vstar.extend(v);
        vstar.extend(omega);
    }
    HardScene {
        kind,
        k,
        nc,
        ndof,
        jn,
        jd,
        minv,
        mass_cond,
        vstar,
        mu: contacts.iter().map(|c| c.mu).collect(),
        b0_extra: contacts.iter().map(|c| 0.2 * c.gap / CONTACT_H).collect(),
        normals: contacts.iter().map(|c| c.normal).collect(),
    }
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
