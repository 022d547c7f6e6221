//! The analytic test scenes as constructors (the Python `lcpsim.scenes` mirrors them).
//!
//! Each scene is a parameter struct with documented defaults and a `build`
//! taking the [`WorldParams`]; a free function builds it with the default
//! parameters: `cube_on_slope(30.0, 0.5)`. All bodies start exactly touching
//! (gap 0) and at rest unless a velocity is given. The scene's μ is given to
//! every body, ground included, so any `MuCombine` yields it.

use crate::contact::Restitution;
use crate::dynamics::{BodyDesc, BodyId};
use crate::error::{finite, non_negative, positive, SimError};
use crate::geometry::{Downhill, Plane};
use crate::limits;
use crate::math::{Quat, Vec3};
use crate::params::WorldParams;
use crate::world::World;

/// A built scene: the world and the ids that matter.
#[derive(Debug)]
pub struct Scene {
    pub world: World,
    /// The body the scene is about (the cube, the ball, the top box, …).
    pub body: BodyId,
    /// The static ground or slope.
    pub ground: BodyId,
    /// Every dynamic body, bottom to top / in creation order.
    pub bodies: Vec<BodyId>,
}

/// Rotation that turns `+z` into a slope's normal (about y).
fn slope_rotation(angle: f64, toward: Downhill) -> Quat {
    let a = match toward {
        Downhill::PlusX => angle,
        Downhill::MinusX => -angle,
    };
    Quat::from_axis_angle(Vec3::Y, a)
}

/// A cube resting on a slope (a level plane at 0°), one face on the surface,
/// edges along the downhill and horizontal directions. The slope's downhill
/// direction is the contacts' first friction direction `d_0`.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeOnSlope {
    /// Slope angle (degrees, [0, 90)).
    pub angle_deg: f64,
    /// Friction coefficient of cube and slope.
    pub mu: f64,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass (kg). Default 1.
    pub mass: f64,
    /// Which way the slope descends. Default `PlusX`.
    pub downhill: Downhill,
    /// Initial speed along the downhill direction (+x on level ground) (m/s). Default 0.
    pub speed: f64,
    /// Friction tangent rotated by this angle (rad) about the normal from the
    /// downhill direction; e.g. `π/k` puts the downhill direction on a
    /// bisector of two friction directions. Default 0.
    pub tangent_angle: f64,
}

impl CubeOnSlope {
    pub fn new(angle_deg: f64, mu: f64) -> Self {
        CubeOnSlope { angle_deg, mu, size: 1.0, mass: 1.0, downhill: Downhill::PlusX, speed: 0.0, tangent_angle: 0.0 }
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        positive("size", self.size)?;
        finite("speed", self.speed)?;
        finite("tangent_angle", self.tangent_angle)?;
        let mut plane = Plane::slope_deg(self.angle_deg, self.downhill)?;
        let n = plane.normal();
        let t = plane.friction_tangent();
        if self.tangent_angle != 0.0 {
            plane = plane.with_friction_tangent(Quat::from_axis_angle(n, self.tangent_angle).rotate(t))?;
        }
        let mut world = World::new(params)?;
        let ground = world.add_plane(plane, self.mu)?;
        let body = world.add_body(
            BodyDesc::cuboid(Vec3::splat(0.5 * self.size))
                .mass(self.mass)
                .mu(self.mu)
                .position(n * (0.5 * self.size))
                .orientation(slope_rotation(self.angle_deg.to_radians(), self.downhill))
                .velocity(t * self.speed),
        )?;
        Ok(Scene { world, body, ground, bodies: vec![body] })
    }
}

/// [`CubeOnSlope`] with its defaults: a 1 kg unit cube at rest.
pub fn cube_on_slope(angle_deg: f64, mu: f64) -> Result<Scene, SimError> {
    CubeOnSlope::new(angle_deg, mu).build(WorldParams::default())
}

/// A cube at rest on level ground pushed by a constant horizontal force along +x.
#[derive(Clone, Debug, PartialEq)]
pub struct PushedCube {
    /// Push (N), along +x (= `d_0`).
    pub force: f64,
    /// Friction coefficient of cube and ground.
    pub mu: f64,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass (kg). Default 1.
    pub mass: f64,
    /// Height of the point of application above the centre of mass (m, body
    /// frame). Default 0: the push acts at the centre of mass (no torque).
    pub height: f64,
}

impl PushedCube {
    pub fn new(force: f64, mu: f64) -> Self {
        PushedCube { force, mu, size: 1.0, mass: 1.0, height: 0.0 }
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        finite("force", self.force)?;
        finite("height", self.height)?;
        let mut world = World::new(params)?;
        let ground = world.add_ground(self.mu)?;
        let body =
            world.add_box(Vec3::splat(0.5 * self.size), self.mass, Vec3::new(0.0, 0.0, 0.5 * self.size), self.mu)?;
        let point = if self.height != 0.0 { Some(Vec3::new(0.0, 0.0, self.height)) } else { None };
        world.apply_force(body, Vec3::new(self.force, 0.0, 0.0), point)?;
        Ok(Scene { world, body, ground, bodies: vec![body] })
    }
}

/// [`PushedCube`] with its defaults (1 kg unit cube, push at the centre of mass).
pub fn pushed_cube(force: f64, mu: f64) -> Result<Scene, SimError> {
    PushedCube::new(force, mu).build(WorldParams::default())
}

/// A cube dropped flat onto level ground from rest.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeDrop {
    /// Initial gap between the bottom face and the ground (m). Default 1.
    pub height: f64,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient. Default 0.5.
    pub mu: f64,
    /// Restitution coefficient; overrides `params.restitution.coefficient` when set. Default `None`.
    pub restitution: Option<f64>,
}

impl Default for CubeDrop {
    fn default() -> Self {
        CubeDrop { height: 1.0, size: 1.0, mass: 1.0, mu: 0.5, restitution: None }
    }
}

impl CubeDrop {
    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        let (mut world, ground) = drop_world(params, self.height, self.mu, self.restitution)?;
        let body = world.add_box(
            Vec3::splat(0.5 * self.size),
            self.mass,
            Vec3::new(0.0, 0.0, self.height + 0.5 * self.size),
            self.mu,
        )?;
        Ok(Scene { world, body, ground, bodies: vec![body] })
    }
}

/// A world with level ground for a drop from `height`, with the drop's
/// restitution (if set) overriding the world's.
fn drop_world(
    mut params: WorldParams,
    height: f64,
    mu: f64,
    restitution: Option<f64>,
) -> Result<(World, BodyId), SimError> {
    non_negative("height", height)?;
    if let Some(e) = restitution {
        params.restitution = Restitution { coefficient: e, ..params.restitution };
    }
    let mut world = World::new(params)?;
    let ground = world.add_ground(mu)?;
    Ok((world, ground))
}

/// [`CubeDrop`] from `height` with the other defaults.
pub fn cube_drop(height: f64) -> Result<Scene, SimError> {
    CubeDrop { height, ..Default::default() }.build(WorldParams::default())
}

/// A ball dropped onto level ground from rest.
#[derive(Clone, Debug, PartialEq)]
pub struct BallDrop {
    /// Initial gap between the ball's lowest point and the ground (m). Default 1.
    pub height: f64,
    /// Radius (m). Default 0.1.
    pub radius: f64,
    /// Mass (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient. Default 0.5.
    pub mu: f64,
    /// Restitution coefficient; overrides `params.restitution.coefficient` when set. Default `None`.
    pub restitution: Option<f64>,
}

impl Default for BallDrop {
    fn default() -> Self {
        BallDrop { height: 1.0, radius: 0.1, mass: 1.0, mu: 0.5, restitution: None }
    }
}

impl BallDrop {
    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        let (mut world, ground) = drop_world(params, self.height, self.mu, self.restitution)?;
        let body = world.add_sphere(self.radius, self.mass, Vec3::new(0.0, 0.0, self.height + self.radius), self.mu)?;
        Ok(Scene { world, body, ground, bodies: vec![body] })
    }
}

/// [`BallDrop`] from `height` with restitution `e`.
pub fn ball_drop(height: f64, e: f64) -> Result<Scene, SimError> {
    BallDrop { height, restitution: Some(e), ..Default::default() }.build(WorldParams::default())
}

/// A tower of `n` identical cubes on level ground, exactly touching.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxStack {
    /// Number of boxes (≥ 1).
    pub n: usize,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass of each box (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient. Default 0.5.
    pub mu: f64,
}

impl BoxStack {
    pub fn new(n: usize) -> Self {
        BoxStack { n, size: 1.0, mass: 1.0, mu: 0.5 }
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        if self.n == 0 {
            return Err(SimError::NotPositive { field: "n", value: 0.0 });
        }
        let mut world = World::new(params)?;
        // One stack is one contact island.
        limits::check_scene("box_stack", "n", (Some(self.n), self.n as f64), self.n, world.params().friction_dirs)?;
        let ground = world.add_ground(self.mu)?;
        let h = 0.5 * self.size;
        let bodies = (0..self.n)
            .map(|i| world.add_box(Vec3::splat(h), self.mass, Vec3::new(0.0, 0.0, h + i as f64 * self.size), self.mu))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Scene { world, body: *bodies.last().expect("n ≥ 1"), ground, bodies })
    }
}

/// [`BoxStack`] of `n` unit cubes.
pub fn box_stack(n: usize) -> Result<Scene, SimError> {
    BoxStack::new(n).build(WorldParams::default())
}

/// A solid ball at rest on a slope; the downhill direction is `d_0`.
#[derive(Clone, Debug, PartialEq)]
pub struct BallOnIncline {
    /// Slope angle (degrees, [0, 90)).
    pub angle_deg: f64,
    /// Friction coefficient of ball and slope.
    pub mu: f64,
    /// Radius (m). Default 0.5.
    pub radius: f64,
    /// Mass (kg). Default 1.
    pub mass: f64,
    /// Which way the slope descends. Default `PlusX`.
    pub downhill: Downhill,
}

impl BallOnIncline {
    pub fn new(angle_deg: f64, mu: f64) -> Self {
        BallOnIncline { angle_deg, mu, radius: 0.5, mass: 1.0, downhill: Downhill::PlusX }
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        positive("radius", self.radius)?;
        let plane = Plane::slope_deg(self.angle_deg, self.downhill)?;
        let mut world = World::new(params)?;
        let ground = world.add_plane(plane, self.mu)?;
        let body = world.add_sphere(self.radius, self.mass, plane.normal() * self.radius, self.mu)?;
        Ok(Scene { world, body, ground, bodies: vec![body] })
    }
}

/// [`BallOnIncline`] with its defaults (1 kg ball of radius 0.5 m).
pub fn ball_on_incline(angle_deg: f64, mu: f64) -> Result<Scene, SimError> {
    BallOnIncline::new(angle_deg, mu).build(WorldParams::default())
}

/// A pile of `nx × ny × nz` cubes: `nx × ny` towers of `nz` cubes on a grid,
/// each cube optionally turned about the vertical by a seeded random angle in
/// `[−yaw, yaw]` (turned cubes touch in up to 8 points).
#[derive(Clone, Debug, PartialEq)]
pub struct BoxPile {
    pub nx: usize,
    pub ny: usize,
    pub nz: usize,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass of each cube (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient. Default 0.5.
    pub mu: f64,
    /// Distance between tower axes as a multiple of `size`. Default 1.5 (towers do not touch).
    pub spacing: f64,
    /// Largest random turn about z (rad). Default 0 (all aligned).
    pub yaw: f64,
    /// Seed of the turns. Default 0.
    pub seed: u64,
}

impl Default for BoxPile {
    fn default() -> Self {
        BoxPile { nx: 3, ny: 3, nz: 3, size: 1.0, mass: 1.0, mu: 0.5, spacing: 1.5, yaw: 0.0, seed: 0 }
    }
}

impl BoxPile {
    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        positive("size", self.size)?;
        positive("spacing", self.spacing)?;
        non_negative("yaw", self.yaw)?;
        let count = self.nx.checked_mul(self.ny).and_then(|c| c.checked_mul(self.nz));
        if count == Some(0) {
            return Err(SimError::NotPositive { field: "nx*ny*nz", value: 0.0 });
        }
        let mut world = World::new(params)?;
        // Each tower of nz boxes is one contact island.
        let requested = self.nx as f64 * self.ny as f64 * self.nz as f64;
        let k = world.params().friction_dirs;
        let count = limits::check_scene("box_pile", "nx*ny*nz", (count, requested), self.nz, k)?;
        let ground = world.add_ground(self.mu)?;
        let mut rng = SplitMix64(self.seed);
        let h = 0.5 * self.size;
        let step = self.spacing * self.size;
        let (ox, oy) = (0.5 * (self.nx - 1) as f64 * step, 0.5 * (self.ny - 1) as f64 * step);
        let mut bodies = Vec::with_capacity(count);
        for iz in 0..self.nz {
            for iy in 0..self.ny {
                for ix in 0..self.nx {
                    let yaw = self.yaw * (2.0 * rng.next_f64() - 1.0);
                    let id = world.add_body(
                        BodyDesc::cuboid(Vec3::splat(h))
                            .mass(self.mass)
                            .mu(self.mu)
                            .position(Vec3::new(
                                ix as f64 * step - ox,
                                iy as f64 * step - oy,
                                h + iz as f64 * self.size,
                            ))
                            .orientation(Quat::from_axis_angle(Vec3::Z, yaw)),
                    )?;
                    bodies.push(id);
                }
            }
        }
        Ok(Scene { world, body: *bodies.last().expect("count > 0"), ground, bodies })
    }
}

/// The default 3×3×3 [`BoxPile`].
pub fn box_pile() -> Result<Scene, SimError> {
    BoxPile::default().build(WorldParams::default())
}

/// `n` cubes dropped into one connected heap: a stepped pyramid whose layer
/// `L` holds `(g − L)²` cubes above the gaps of the layer below (each resting
/// on four corners, so the whole heap is one contact island), filled bottom
/// up with the smallest `g` that holds `n`. Every cube is turned and shifted
/// by seeded random amounts and starts a little above where it will land;
/// optionally four static boxes wall the heap in.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeHeap {
    /// Number of cubes (≥ 1).
    pub n: usize,
    /// Seed of the turns and shifts. Default 0.
    pub seed: u64,
    /// Four static boxes around the base, `0.1·size` clear of it. Default false.
    pub walls: bool,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass of each cube (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient (cubes, ground, walls). Default 0.5.
    pub mu: f64,
    /// Distance between neighbouring centres of a layer, in `size` (≥ 1 + 4·jitter). Default 1.1.
    pub spacing: f64,
    /// Largest random turn about each axis (rad) and shift (in `size`), in [0, 0.05]. Default 0.02.
    pub jitter: f64,
}

impl CubeHeap {
    pub fn new(n: usize, seed: u64) -> Self {
        CubeHeap { n, seed, walls: false, size: 1.0, mass: 1.0, mu: 0.5, spacing: 1.1, jitter: 0.02 }
    }

    /// Base width `g` of the pyramid: the smallest with `Σ_{L<g} (g − L)² ≥ n`.
    pub fn base(&self) -> usize {
        (1..).find(|&g: &usize| g * (g + 1) * (2 * g + 1) / 6 >= self.n).expect("n is finite")
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        if self.n == 0 {
            return Err(SimError::NotPositive { field: "n", value: 0.0 });
        }
        positive("size", self.size)?;
        crate::error::in_range("jitter", self.jitter, 0.0, 0.05, "[0, 0.05]")?;
        // Also rejects a NaN spacing.
        if self.spacing.is_nan() || self.spacing < 1.0 + 4.0 * self.jitter {
            return Err(SimError::OutOfRange { field: "spacing", value: self.spacing, range: "[1 + 4·jitter, ∞)" });
        }
        let mut world = World::new(params)?;
        // A heap can join into one contact island.
        limits::check_scene("cube_heap", "n", (Some(self.n), self.n as f64), self.n, world.params().friction_dirs)?;
        let ground = world.add_ground(self.mu)?;
        let (g, s, h) = (self.base(), self.size, 0.5 * self.size);
        let step = self.spacing * s;
        // Each layer starts this far above its resting place (more than a turned cube sinks).
        let drop = 2.0 * self.jitter * s + 0.01 * s;
        let mut rng = SplitMix64(self.seed);
        let mut bodies = Vec::with_capacity(self.n);
        'layers: for layer in 0..g {
            let m = g - layer;
            // Centred: layer L's cubes sit above the gaps of layer L − 1.
            let o = -0.5 * (m - 1) as f64 * step;
            for iy in 0..m {
                for ix in 0..m {
                    if bodies.len() == self.n {
                        break 'layers;
                    }
                    let mut turn = || self.jitter * (2.0 * rng.next_f64() - 1.0);
                    let (ax, ay, az, dx, dy) = (turn(), turn(), turn(), turn() * s, turn() * s);
                    let q = Quat::from_axis_angle(Vec3::Z, az)
                        * Quat::from_axis_angle(Vec3::Y, ay)
                        * Quat::from_axis_angle(Vec3::X, ax);
                    let p = Vec3::new(
                        o + ix as f64 * step + dx,
                        o + iy as f64 * step + dy,
                        h + layer as f64 * (s + drop) + drop,
                    );
                    let desc = BodyDesc::cuboid(Vec3::splat(h)).mass(self.mass).mu(self.mu).position(p).orientation(q);
                    bodies.push(world.add_body(desc)?);
                }
            }
        }
        if self.walls {
            // Inner faces 0.1·size clear of the base's outer faces; as tall as the heap.
            let inner = 0.5 * (g - 1) as f64 * step + h + 0.1 * s;
            let (t, tall) = (0.5 * s, 0.5 * g as f64 * (s + drop));
            let long = inner + 2.0 * t;
            for (c, he) in [
                (Vec3::new(inner + t, 0.0, tall), Vec3::new(t, long, tall)),
                (Vec3::new(-inner - t, 0.0, tall), Vec3::new(t, long, tall)),
                (Vec3::new(0.0, inner + t, tall), Vec3::new(inner, t, tall)),
                (Vec3::new(0.0, -inner - t, tall), Vec3::new(inner, t, tall)),
            ] {
                world.add_body(BodyDesc::cuboid(he).mu(self.mu).position(c).fixed(true))?;
            }
        }
        Ok(Scene { world, body: *bodies.last().expect("n ≥ 1"), ground, bodies })
    }
}

/// [`CubeHeap`] of `n` unit cubes with its defaults.
pub fn cube_heap(n: usize, seed: u64, walls: bool) -> Result<Scene, SimError> {
    CubeHeap { walls, ..CubeHeap::new(n, seed) }.build(WorldParams::default())
}

/// `n` cubes poured into a heap: each with a uniformly random orientation,
/// released at rest from a random place in a loose column above a square
/// floor region, so that they tumble into one heap and their contacts change
/// every step while it forms; optionally inside a bin of four static walls.
/// The column has `g × g` cells per layer (`g = max(2, ⌈√(n/10)⌉)`, about ten
/// layers), cells `spacing·size` apart, each cube at its cell's centre moved
/// by up to `jitter·size` along each axis; the lowest cubes start 0.1·size
/// above the largest reach of a turned cube (`√3/2·size`).
#[derive(Clone, Debug, PartialEq)]
pub struct CubePour {
    /// Number of cubes (≥ 1).
    pub n: usize,
    /// Seed of the orientations and places. Default 0.
    pub seed: u64,
    /// A bin of four static walls around the floor region. Default true.
    pub walls: bool,
    /// Edge length (m). Default 1.
    pub size: f64,
    /// Mass of each cube (kg). Default 1.
    pub mass: f64,
    /// Friction coefficient (cubes, ground, walls). Default 0.5.
    pub mu: f64,
    /// Distance between neighbouring cells, in `size` (≥ √3 + 2·jitter, so no two cubes touch at the start). Default 1.8.
    pub spacing: f64,
    /// Largest shift from a cell's centre along each axis, in `size`, in [0, 0.1]. Default 0.03.
    pub jitter: f64,
}

impl CubePour {
    pub fn new(n: usize, seed: u64) -> Self {
        CubePour { n, seed, walls: true, size: 1.0, mass: 1.0, mu: 0.5, spacing: 1.8, jitter: 0.03 }
    }

    /// Cells per side of a layer.
    pub fn grid(&self) -> usize {
        ((self.n as f64 / 10.0).sqrt().ceil() as usize).max(2)
    }

    pub fn build(&self, params: WorldParams) -> Result<Scene, SimError> {
        if self.n == 0 {
            return Err(SimError::NotPositive { field: "n", value: 0.0 });
        }
        positive("size", self.size)?;
        positive("mass", self.mass)?;
        non_negative("mu", self.mu)?;
        crate::error::in_range("jitter", self.jitter, 0.0, 0.1, "[0, 0.1]")?;
        let least = 3f64.sqrt() + 2.0 * self.jitter;
        // Also rejects a NaN spacing.
        if self.spacing.is_nan() || self.spacing < least {
            return Err(SimError::OutOfRange {
                field: "spacing", value: self.spacing, range: "[√3 + 2·jitter, ∞)"
            });
        }
        let mut world = World::new(params)?;
        // A pour joins into one contact island.
        limits::check_scene("cube_pour", "n", (Some(self.n), self.n as f64), self.n, world.params().friction_dirs)?;
        let ground = world.add_ground(self.mu)?;
        let (g, s) = (self.grid(), self.size);
        let step = self.spacing * s;
        let z0 = 0.5 * 3f64.sqrt() * s + 0.1 * s;
        let mut rng = SplitMix64(self.seed);
        let mut bodies = Vec::with_capacity(self.n);
        for i in 0..self.n {
            let (layer, cell) = (i / (g * g), i % (g * g));
            let (iy, ix) = (cell / g, cell % g);
            let mut shift = || self.jitter * s * (2.0 * rng.next_f64() - 1.0);
            let c = Vec3::new(
                (ix as f64 - 0.5 * (g - 1) as f64) * step + shift(),
                (iy as f64 - 0.5 * (g - 1) as f64) * step + shift(),
                z0 + layer as f64 * step + shift(),
            );
            let q = rng.rotation();
            let desc = BodyDesc::cuboid(Vec3::splat(0.5 * s)).mass(self.mass).mu(self.mu).position(c).orientation(q);
            bodies.push(world.add_body(desc)?);
        }
        if self.walls {
            // The bin: inner half-width g·spacing/2, 1 m thick walls, 4 size tall,
            // 1 cm above the ground and 1 cm apart at the corners (static bodies never touch).
            let (a, t, tall) = (0.5 * g as f64 * step, 0.5 * s, 2.0 * s);
            let zc = tall + 0.01 * s;
            for sign in [-1.0, 1.0] {
                let along_y = BodyDesc::cuboid(Vec3::new(t, a + 2.0 * t, tall));
                world.add_body(along_y.mu(self.mu).position(Vec3::new(sign * (a + t), 0.0, zc)).fixed(true))?;
                let along_x = BodyDesc::cuboid(Vec3::new(a - 0.01 * s, t, tall));
                world.add_body(along_x.mu(self.mu).position(Vec3::new(0.0, sign * (a + t), zc)).fixed(true))?;
            }
        }
        Ok(Scene { world, body: *bodies.last().expect("n ≥ 1"), ground, bodies })
    }
}

/// [`CubePour`] of `n` unit cubes with its defaults (inside the bin when `walls`).
pub fn cube_pour(n: usize, seed: u64, walls: bool) -> Result<Scene, SimError> {
    CubePour { walls, ..CubePour::new(n, seed) }.build(WorldParams::default())
}

/// SplitMix64: a tiny seeded generator, enough for scene jitter (and random test scenes).
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

impl SplitMix64 {
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// A uniformly random rotation (Shoemake's method).
    pub fn rotation(&mut self) -> Quat {
        let (u1, u2, u3) = (self.next_f64(), self.next_f64(), self.next_f64());
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let tau = 2.0 * std::f64::consts::PI;
        Quat::new(b * (tau * u3).cos(), a * (tau * u2).sin(), a * (tau * u2).cos(), b * (tau * u3).sin())
    }
}
