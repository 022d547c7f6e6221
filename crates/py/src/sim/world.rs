//! The `World` class: a `sim::World` behind a mutex (so the class is
//! `Sync`), its bodies, forces, stepping and LCP capture.

use super::capture::CaptureBuffer;
use super::convert::{self, cone_scale, mat3, opt_vec3, or_default, quat, real, sim_error, vec3};
use super::params::{params_dict, world_params};
use super::records::{arr3, shaped, trajectory_to_dict, PyStepRecord, RecordPool};
use crate::errors::{panic_error, value_error};
use crate::method::method_from_py;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::geometry::Shape;
use sim::{BodyDesc, BodyId, Plane, WorldParams};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

/// Runs `f`, turning a panic into a `RuntimeError` and a `SimError` into a `ValueError`.
fn guarded<T>(f: impl FnOnce() -> Result<T, sim::SimError>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(sim_error(&e)),
        Err(payload) => Err(panic_error(payload)),
    }
}

/// A rigid-body world (see `lcpsim.World` for the documented wrapper).
#[pyclass(module = "lcpsim._core", name = "World")]
pub struct World {
    world: Mutex<sim::World>,
    /// The buffer the world's sink fills, while capturing (and after, until drained).
    capture: Option<CaptureBuffer>,
    capturing: bool,
    /// Records of dropped `World.step()` results, reused by the next steps.
    records: RecordPool,
}

impl World {
    pub fn wrap(world: sim::World) -> World {
        World { world: Mutex::new(world), capture: None, capturing: false, records: RecordPool::default() }
    }

    fn inner(&mut self) -> &mut sim::World {
        self.world.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    fn shared(&self) -> std::sync::MutexGuard<'_, sim::World> {
        self.world.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn params_clone(&self) -> WorldParams {
        self.shared().params().clone()
    }

    /// `set(world, body, value)`: one of the world's per-body setters, guarded.
    fn on_body<T>(
        &mut self,
        body: &Bound<'_, PyAny>,
        value: T,
        set: fn(&mut sim::World, BodyId, T) -> Result<(), sim::SimError>,
    ) -> PyResult<()> {
        let id = body_id(body)?;
        let w = self.inner();
        guarded(|| set(w, id, value))
    }

    fn add(&mut self, desc: BodyDesc) -> PyResult<usize> {
        let w = self.inner();
        guarded(|| w.add_body(desc)).map(|id| id.0)
    }
}

/// Rows of an `(N, 3)` float array as vectors.
fn rows3(a: &PyReadonlyArray2<'_, f64>, field: &str) -> PyResult<Vec<sim::math::Vec3>> {
    let v = a.as_array();
    if v.ncols() != 3 {
        return Err(value_error(format!("{field} must have shape (N, 3), got {:?}", v.shape())));
    }
    Ok(v.rows().into_iter().map(|r| sim::math::Vec3::new(r[0], r[1], r[2])).collect())
}

/// Rows of an `(M, 3)` integer array as triangles (indices ≥ 0 that fit in u32).
fn faces3(a: &PyReadonlyArray2<'_, i64>) -> PyResult<Vec<[u32; 3]>> {
    let v = a.as_array();
    if v.ncols() != 3 {
        return Err(value_error(format!("faces must have shape (M, 3), got {:?}", v.shape())));
    }
    let mut out = Vec::with_capacity(v.nrows());
    for (f, r) in v.rows().into_iter().enumerate() {
        let mut tri = [0u32; 3];
        for k in 0..3 {
            tri[k] = u32::try_from(r[k])
                .map_err(|_| value_error(format!("faces: face {f} has vertex index {}, out of range", r[k])))?;
        }
        out.push(tri);
    }
    Ok(out)
}

/// Where a hull's or a compound's centre of mass was in the frame it was given in (zero for others).
fn com_offset(s: &Shape) -> sim::math::Vec3 {
    match s {
        Shape::Convex(c) => c.com_offset(),
        Shape::Compound(c) => c.com_offset(),
        _ => sim::math::Vec3::ZERO,
    }
}

/// A compound's parts as dicts: `kind`, `position`, `orientation` (body frame) and the
/// shape's own fields (as `body()` gives them).
fn parts_list<'py>(py: Python<'py>, c: &sim::CompoundShape) -> PyResult<Bound<'py, pyo3::types::PyList>> {
    let out = pyo3::types::PyList::empty(py);
    for p in c.parts() {
        let d = PyDict::new(py);
        d.set_item("kind", p.shape.kind())?;
        d.set_item("position", arr3(py, p.position))?;
        d.set_item("orientation", PyArray1::from_vec(py, p.orientation.to_array().to_vec()))?;
        shape_fields(py, &d, &p.shape)?;
        out.append(d)?;
    }
    Ok(out)
}

/// A shape's own fields into `d` (half_extents, radius, vertices, parts, ...).
fn shape_fields<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, shape: &Shape) -> PyResult<()> {
    match shape {
        Shape::Box(x) => d.set_item("half_extents", arr3(py, x.half_extents))?,
        Shape::Sphere { radius } => d.set_item("radius", *radius)?,
        Shape::Capsule { radius, half_length } | Shape::Cylinder { radius, half_length } => {
            d.set_item("radius", *radius)?;
            d.set_item("half_length", *half_length)?;
        }
        Shape::Convex(c) => {
            let v: Vec<f64> = c.vertices().iter().flat_map(|p| p.to_array()).collect();
            d.set_item("vertices", shaped(py, v, [c.vertices().len(), 3])?)?;
            let f: Vec<i64> = c.faces().iter().flat_map(|t| t.map(i64::from)).collect();
            d.set_item("faces", PyArray1::from_vec(py, f).reshape(vec![c.faces().len(), 3])?)?;
            d.set_item("com_offset", arr3(py, c.com_offset()))?;
        }
        Shape::Compound(c) => {
            d.set_item("parts", parts_list(py, c)?)?;
            d.set_item("com_offset", arr3(py, c.com_offset()))?;
        }
        Shape::Mesh(m) => {
            let v: Vec<f64> = m.vertices().iter().flat_map(|p| p.to_array()).collect();
            d.set_item("vertices", shaped(py, v, [m.vertices().len(), 3])?)?;
            let f: Vec<i64> = m.faces().iter().flat_map(|t| t.map(i64::from)).collect();
            d.set_item("faces", PyArray1::from_vec(py, f).reshape(vec![m.faces().len(), 3])?)?;
        }
        Shape::HeightField(h) => {
            let (nrow, ncol) = h.dims();
            d.set_item("heights", shaped(py, h.heights().to_vec(), [nrow, ncol])?)?;
            let (hx, hy) = h.half_extents();
            d.set_item("half_extents", PyArray1::from_vec(py, vec![hx, hy]))?;
        }
        Shape::Plane(p) => {
            d.set_item("normal", arr3(py, p.normal()))?;
            d.set_item("offset", p.offset())?;
            d.set_item("tangent", arr3(py, p.friction_tangent()))?;
            d.set_item("downhill", p.downhill().map(|v| arr3(py, v)))?;
        }
    }
    Ok(())
}

/// A body index (an int ≥ 0; its range is the world's to check).
fn body_id(body: &Bound<'_, PyAny>) -> PyResult<BodyId> {
    convert::count(body, "body").map(BodyId)
}

/// The shape `kind` of `size`: half extents (box), radius (sphere),
/// (radius, half_length) (capsule, cylinder), an (N, 3) float64 array of
/// points (convex), or `(parts, com)` (compound): a list of parts `(kind,
/// size, position, orientation)` in the compound's frame and its centre of
/// mass there (None: the parts' at uniform density).
fn shape_of(kind: &str, size: &Bound<'_, PyAny>) -> PyResult<Shape> {
    Ok(match kind {
        "box" => Shape::Box(sim::geometry::BoxShape { half_extents: vec3(size, "half_extents")? }),
        "sphere" => Shape::Sphere { radius: real(size, "radius")? },
        "capsule" | "cylinder" => {
            let (radius, half_length): (f64, f64) = size
                .extract()
                .map_err(|_| value_error(format!("size of a {kind} must be (radius, half_length), got {size}")))?;
            if kind == "capsule" {
                Shape::Capsule { radius, half_length }
            } else {
                Shape::Cylinder { radius, half_length }
            }
        }
        "convex" => {
            let vertices: PyReadonlyArray2<'_, f64> = size
                .extract()
                .map_err(|_| value_error(format!("vertices must be an (N, 3) float64 array, got {size}")))?;
            let pts = rows3(&vertices, "vertices")?;
            guarded(|| Shape::convex(&pts))?
        }
        "compound" => {
            let (items, com): (Vec<Bound<'_, PyAny>>, Option<Bound<'_, PyAny>>) = size
                .extract()
                .map_err(|_| value_error(format!("size of a compound must be (parts, com), got {size}")))?;
            let com = com.map(|c| vec3(&c, "com")).transpose()?;
            let mut parts = Vec::with_capacity(items.len());
            for (k, item) in items.iter().enumerate() {
                let (pk, psize, pos, q): (String, Bound<'_, PyAny>, Bound<'_, PyAny>, Bound<'_, PyAny>) =
                    item.extract().map_err(|_| {
                        value_error(format!("parts[{k}] must be (kind, size, position, orientation), got {item}"))
                    })?;
                if pk == "compound" {
                    return Err(value_error(format!("parts[{k}] is a compound; parts cannot be compounds")));
                }
                let at = |e: PyErr| value_error(format!("parts[{k}]: {e}"));
                parts.push(sim::CompoundPart {
                    shape: shape_of(&pk, &psize).map_err(at)?,
                    position: vec3(&pos, "position").map_err(at)?,
                    orientation: quat(&q, "orientation").map_err(at)?,
                });
            }
            guarded(|| sim::CompoundShape::about(&parts, com).map(Shape::Compound))?
        }
        _ => {
            return Err(value_error(format!(
                "shape must be \"box\", \"sphere\", \"capsule\", \"cylinder\", \"convex\" or \"compound\", got {kind:?}"
            )))
        }
    })
}

#[pymethods]
impl World {
    /// `World(params, **options)`: `params` a dict of `WORLD_FIELDS` (missing or
    /// None: `WorldParams::default()`'s value), `options` the solver's.
    #[new]
    #[pyo3(signature = (params = None, **options))]
    fn new(params: Option<&Bound<'_, PyDict>>, options: Option<&Bound<'_, PyDict>>) -> PyResult<World> {
        let params = world_params(params, options)?;
        guarded(|| sim::World::new(params)).map(World::wrap)
    }

    /// The parameters as a dict (cone_scale: "none", "dt" or the number).
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        params_dict(py, &self.params_clone())
    }

    /// Replaces the solver (name + options as in `solve_lcp`).
    #[pyo3(signature = (method, **options))]
    fn set_method(&mut self, method: &str, options: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let m = method_from_py(method, options)?;
        self.inner().set_method(m);
        Ok(())
    }

    /// Replaces the friction-cone scale (None, "dt" or a number > 0).
    #[pyo3(signature = (scale = None))]
    fn set_cone_scale(&mut self, scale: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let s = cone_scale(scale)?;
        let w = self.inner();
        let p = WorldParams { cone_scale: s, ..w.params().clone() };
        guarded(|| w.set_params(p))
    }

    /// A copy of the state and parameters (without any LCP capture).
    fn copy(&self) -> World {
        World::wrap(self.shared().clone())
    }

    #[getter]
    fn time(&self) -> f64 {
        self.shared().time()
    }

    #[getter]
    fn steps(&self) -> u64 {
        self.shared().steps()
    }

    #[getter]
    fn body_count(&self) -> usize {
        self.shared().body_count()
    }

    /// Kinetic + gravitational potential energy (J).
    fn energy(&self) -> f64 {
        self.shared().energy()
    }

    // ----- bodies -----

    /// A box (`shape` "box", `size` its half extents), a solid sphere
    /// ("sphere", `size` its radius), capsule or cylinder ("capsule",
    /// "cylinder", `size` (radius, half_length)) or the dynamic convex hull of
    /// points ("convex", `size` an (N, 3) float64 array; the body frame is at
    /// its centre of mass, see `sim::ConvexHull`, `position` places that
    /// centre). Values not given (or None) keep
    /// `sim::BodyDesc`'s defaults: mass 1, at the origin, upright, at rest,
    /// μ 0.5, dynamic, the solid's inertia.
    #[pyo3(signature = (shape, size, mass = None, position = None, orientation = None, velocity = None,
                        angular_velocity = None, mu = None, is_static = false, inertia = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        shape: &str,
        size: &Bound<'_, PyAny>,
        mass: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        mu: Option<&Bound<'_, PyAny>>,
        is_static: bool,
        inertia: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let d = BodyDesc::new(shape_of(shape, size)?);
        // The optional fields (None keeps `BodyDesc`'s default).
        let mut d = d;
        d.mass = or_default(mass, "mass", real, d.mass)?;
        d.position = or_default(position, "position", vec3, d.position)?;
        d.orientation = or_default(orientation, "orientation", quat, d.orientation)?;
        d.velocity = or_default(velocity, "velocity", vec3, d.velocity)?;
        d.angular_velocity = or_default(angular_velocity, "angular_velocity", vec3, d.angular_velocity)?;
        d.mu = or_default(mu, "mu", real, d.mu)?;
        d.inertia = or_default(inertia, "inertia", |v, f| mat3(v, f).map(Some), d.inertia)?;
        self.add(d.fixed(is_static))
    }

    /// A static triangle mesh: `vertices` (N, 3) in its frame, `faces` (M, 3) indices.
    #[pyo3(signature = (vertices, faces, mu = None, position = None, orientation = None))]
    fn add_mesh(
        &mut self,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        mu: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let pts = rows3(&vertices, "vertices")?;
        let tris = faces3(&faces)?;
        let mut d = guarded(|| BodyDesc::mesh(&pts, &tris))?;
        d.position = or_default(position, "position", vec3, d.position)?;
        d.orientation = or_default(orientation, "orientation", quat, d.orientation)?;
        d.mu = or_default(mu, "mu", real, d.mu)?;
        self.add(d.fixed(true))
    }

    /// A static height field: `heights` (nrow, ncol), row r at y = −half_y + 2·half_y·r/(nrow − 1),
    /// column c at x = −half_x + 2·half_x·c/(ncol − 1), in its frame (placed by `position`, `orientation`).
    #[pyo3(signature = (heights, half_x, half_y, mu = None, position = None, orientation = None))]
    fn add_heightfield(
        &mut self,
        heights: PyReadonlyArray2<'_, f64>,
        half_x: &Bound<'_, PyAny>,
        half_y: &Bound<'_, PyAny>,
        mu: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let h = heights.as_array();
        let (nrow, ncol) = (h.nrows(), h.ncols());
        let values: Vec<f64> = h.iter().copied().collect();
        let (hx, hy) = (real(half_x, "half_x")?, real(half_y, "half_y")?);
        let mut d = guarded(|| BodyDesc::heightfield(nrow, ncol, hx, hy, &values))?;
        d.position = or_default(position, "position", vec3, d.position)?;
        d.orientation = or_default(orientation, "orientation", quat, d.orientation)?;
        d.mu = or_default(mu, "mu", real, d.mu)?;
        self.add(d.fixed(true))
    }

    /// The hull's centre of mass in the frame of the points it was built from
    /// (zeros for other shapes).
    fn com_offset<'py>(&self, py: Python<'py>, index: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let id = body_id(index)?;
        let w = self.shared();
        let b = w.body(id).map_err(|e| sim_error(&e))?;
        Ok(arr3(py, com_offset(b.shape())))
    }
    /// A static plane `normal·x = offset` (normal normalized; the solid is below it).
    /// `tangent` sets the first friction direction (projected into the plane);
    /// `mu` not given (or None) is `sim::BodyDesc`'s default.
    #[pyo3(signature = (normal, offset, mu = None, tangent = None))]
    fn add_plane(
        &mut self,
        normal: &Bound<'_, PyAny>,
        offset: &Bound<'_, PyAny>,
        mu: Option<&Bound<'_, PyAny>>,
        tangent: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let n = vec3(normal, "normal")?;
        let off = real(offset, "offset")?;
        let mu = or_default(mu, "mu", real, BodyDesc::sphere(1.0).mu)?;
        let t = opt_vec3(tangent, "tangent")?;
        let w = self.inner();
        guarded(|| {
            let mut p = Plane::new(n, off)?;
            if let Some(t) = t {
                p = p.with_friction_tangent(t)?;
            }
            w.add_plane(p, mu)
        })
        .map(|id| id.0)
    }

    /// A static slope through `(0, 0, offset)`-shifted origin at `angle_deg`
    /// descending towards `downhill` ("+x" or "-x"); its first friction
    /// direction is the downhill direction, turned by `tangent_angle` (rad) about the normal.
    #[pyo3(signature = (angle_deg, mu, downhill, offset, tangent_angle))]
    fn add_slope(
        &mut self,
        angle_deg: &Bound<'_, PyAny>,
        mu: Option<&Bound<'_, PyAny>>,
        downhill: &str,
        offset: &Bound<'_, PyAny>,
        tangent_angle: &Bound<'_, PyAny>,
    ) -> PyResult<usize> {
        let a = convert::angle_deg(real(angle_deg, "angle_deg")?)?;
        let mu = or_default(mu, "mu", real, BodyDesc::sphere(1.0).mu)?;
        let side = convert::downhill(downhill)?;
        let off = real(offset, "offset")?;
        let ta = real(tangent_angle, "tangent_angle")?;
        if !ta.is_finite() {
            return Err(value_error(format!("tangent_angle must be finite, got {}", crate::errors::py_float(ta))));
        }
        let w = self.inner();
        guarded(|| {
            let mut p = Plane::slope_deg(a, side)?.with_offset(off)?;
            if ta != 0.0 {
                let t = sim::math::Quat::from_axis_angle(p.normal(), ta).rotate(p.friction_tangent());
                p = p.with_friction_tangent(t)?;
            }
            w.add_plane(p, mu)
        })
        .map(|id| id.0)
    }

    /// A body's description and state as a dict.
    fn body<'py>(&self, py: Python<'py>, index: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let id = body_id(index)?;
        let w = self.shared();
        let b = w.body(id).map_err(|e| sim_error(&e))?;
        let d = PyDict::new(py);
        d.set_item("index", id.0)?;
        d.set_item("kind", b.shape().kind())?;
        d.set_item("is_static", b.is_static())?;
        d.set_item("mass", b.mass())?;
        d.set_item("mu", b.mu())?;
        d.set_item("contype", b.collision_filter().contype)?;
        d.set_item("conaffinity", b.collision_filter().conaffinity)?;
        d.set_item("position", arr3(py, b.position()))?;
        d.set_item("orientation", PyArray1::from_vec(py, b.orientation().to_array().to_vec()))?;
        d.set_item("velocity", arr3(py, b.velocity()))?;
        d.set_item("angular_velocity", arr3(py, b.angular_velocity()))?;
        let i = b.inertia();
        d.set_item("inertia", shaped(py, i.m.iter().flatten().copied().collect(), [3, 3])?)?;
        shape_fields(py, &d, b.shape())?;
        Ok(d)
    }

    /// Positions (B, 3), orientations (B, 4), velocities (B, 3), angular velocities (B, 3).
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = self.shared();
        let nb = w.body_count();
        let (mut p, mut q, mut v, mut o) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for b in w.bodies() {
            p.extend_from_slice(&b.position().to_array());
            q.extend_from_slice(&b.orientation().to_array());
            v.extend_from_slice(&b.velocity().to_array());
            o.extend_from_slice(&b.angular_velocity().to_array());
        }
        let d = PyDict::new(py);
        d.set_item("position", shaped(py, p, [nb, 3])?)?;
        d.set_item("orientation", shaped(py, q, [nb, 4])?)?;
        d.set_item("velocity", shaped(py, v, [nb, 3])?)?;
        d.set_item("angular_velocity", shaped(py, o, [nb, 3])?)?;
        d.set_item("is_static", w.bodies().iter().map(|b| b.is_static()).collect::<Vec<_>>())?;
        Ok(d)
    }

    fn set_position(&mut self, body: &Bound<'_, PyAny>, position: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, vec3(position, "position")?, sim::World::set_position)
    }

    fn set_orientation(&mut self, body: &Bound<'_, PyAny>, orientation: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, quat(orientation, "orientation")?, sim::World::set_orientation)
    }

    fn set_velocity(&mut self, body: &Bound<'_, PyAny>, velocity: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, vec3(velocity, "velocity")?, sim::World::set_velocity)
    }

    fn set_angular_velocity(&mut self, body: &Bound<'_, PyAny>, angular_velocity: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, vec3(angular_velocity, "angular_velocity")?, sim::World::set_angular_velocity)
    }

    fn set_mu(&mut self, body: &Bound<'_, PyAny>, mu: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, real(mu, "mu")?, sim::World::set_mu)
    }

    fn set_torsional_friction(&mut self, body: &Bound<'_, PyAny>, mu_torsion: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, real(mu_torsion, "torsional_friction")?, sim::World::set_torsional_friction)
    }

    /// MuJoCo's collision bits of a body (any body; both integers in [0, 2³²)).
    fn set_collision_filter(&mut self, body: &Bound<'_, PyAny>, contype: u64, conaffinity: u64) -> PyResult<()> {
        let bits = |v: u64, field: &str| {
            u32::try_from(v).map_err(|_| value_error(format!("{field} must be an integer in [0, 2**32), got {v}")))
        };
        let (t, a) = (bits(contype, "contype")?, bits(conaffinity, "conaffinity")?);
        self.on_body(body, (t, a), |w, id, (t, a)| w.set_collision_filter(id, t, a))
    }

    /// Keeps two bodies from touching whatever their collision bits.
    fn exclude_pair(&mut self, body_a: &Bound<'_, PyAny>, body_b: &Bound<'_, PyAny>) -> PyResult<()> {
        let b = body_id(body_b)?;
        self.on_body(body_a, b, sim::World::exclude_pair)
    }

    /// The excluded pairs, lower index first, sorted.
    fn excluded_pairs(&self) -> Vec<(usize, usize)> {
        self.shared().excluded_pairs().to_vec()
    }

    /// Makes two bodies touch whatever their collision bits and exclusions, with their own μ.
    fn add_contact_pair(
        &mut self,
        body_a: &Bound<'_, PyAny>,
        body_b: &Bound<'_, PyAny>,
        mu: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let pair = (body_id(body_b)?, real(mu, "mu")?);
        self.on_body(body_a, pair, |w, a, (b, mu)| w.add_contact_pair(a, b, mu))
    }

    /// The contact pairs (lower index first, sorted), each with its μ.
    fn contact_pairs(&self) -> Vec<(usize, usize, f64)> {
        let w = self.shared();
        let (pairs, mus) = w.contact_pairs();
        pairs.iter().zip(mus).map(|(&(a, b), &mu)| (a, b, mu)).collect()
    }

    // ----- joints -----

    /// A joint of `kind` ("ball", "hinge", "slider", "fixed") between
    /// `body_a` (None: the world) and `body_b`, anchor and axis given in the
    /// world; returns its index.
    #[pyo3(signature = (kind, body_a, body_b, anchor, axis = None, limits = None))]
    fn add_joint(
        &mut self,
        kind: &str,
        body_a: Option<&Bound<'_, PyAny>>,
        body_b: &Bound<'_, PyAny>,
        anchor: &Bound<'_, PyAny>,
        axis: Option<&Bound<'_, PyAny>>,
        limits: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let kind = match kind {
            "ball" => sim::JointKind::Ball,
            "hinge" => sim::JointKind::Hinge,
            "slider" => sim::JointKind::Slider,
            "fixed" => sim::JointKind::Fixed,
            _ => return Err(value_error(format!("kind must be ball, hinge, slider or fixed, got {kind:?}"))),
        };
        let body_a = match body_a {
            Some(b) if !b.is_none() => Some(convert::count(b, "body_a")?),
            _ => None,
        };
        let body_b = convert::count(body_b, "body_b")?;
        let anchor = vec3(anchor, "anchor")?;
        let axis = opt_vec3(axis, "axis")?.unwrap_or(sim::math::Vec3::Z);
        let w = self.inner();
        let limits = match limits {
            Some(l) if !l.is_none() => {
                let bad = || value_error(format!("limits must be (lower, upper), got {}", l));
                let v: Vec<f64> = l.extract().map_err(|_| bad())?;
                let [lo, hi]: [f64; 2] = v.try_into().map_err(|_| bad())?;
                Some((lo, hi))
            }
            _ => None,
        };
        guarded(|| w.add_joint(sim::JointDesc { kind, body_a, body_b, anchor, axis, limits })).map(|j| j.0)
    }

    /// A velocity motor on a hinge or slider: its rate driven to `speed`
    /// (rad/s, m/s) with at most `max_force` (N·m, N); 0 turns it off.
    fn set_motor(&mut self, joint: &Bound<'_, PyAny>, speed: f64, max_force: f64) -> PyResult<()> {
        let j = sim::JointId(convert::count(joint, "joint")?);
        let w = self.inner();
        guarded(|| w.set_motor(j, speed, max_force))
    }

    /// Viscous damping of a hinge's or slider's rate (N·m·s/rad, N·s/m),
    /// integrated implicitly; 0 turns it off.
    fn set_joint_damping(&mut self, joint: &Bound<'_, PyAny>, damping: f64) -> PyResult<()> {
        let j = sim::JointId(convert::count(joint, "joint")?);
        let w = self.inner();
        guarded(|| w.set_joint_damping(j, damping))
    }

    #[getter]
    fn joint_count(&self) -> usize {
        self.shared().joints().len()
    }

    /// A joint's kind, bodies (None: the world) and geometry: `anchor` and
    /// `axis` per side in that side's frame (the anchor from its centre of
    /// mass; the world's: in the world), `limits` and `motor` (speed,
    /// max_force) or None. For `World.config` and the viewer.
    fn joint_config<'py>(&self, py: Python<'py>, joint: &Bound<'_, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let j = convert::count(joint, "joint")?;
        let w = self.shared();
        let n = w.joints().len();
        let joint = w.joints().get(j).ok_or_else(|| sim_error(&sim::SimError::UnknownJoint { index: j, joints: n }))?;
        let d = PyDict::new(py);
        d.set_item("kind", joint.kind.name())?;
        d.set_item("body_a", joint.bodies[0])?;
        d.set_item("body_b", joint.bodies[1])?;
        d.set_item("anchor", joint.anchor.map(|a| a.to_array()))?;
        d.set_item("axis", joint.axis.map(|a| a.to_array()))?;
        d.set_item("limits", joint.limits)?;
        d.set_item("motor", joint.motor.map(|m| (m.speed, m.max_force)))?;
        Ok(d)
    }

    /// A joint's position error now: (largest linear row error in m, largest angular in rad).
    fn joint_error(&self, joint: &Bound<'_, PyAny>) -> PyResult<(f64, f64)> {
        let j = sim::JointId(convert::count(joint, "joint")?);
        let w = self.shared();
        guarded(|| w.joint_error(j))
    }

    /// A hinge's angle (rad) or a slider's displacement (m) now, 0 at creation.
    fn joint_position(&self, joint: &Bound<'_, PyAny>) -> PyResult<f64> {
        let j = convert::count(joint, "joint")?;
        let w = self.shared();
        let n = w.joints().len();
        let joint = w.joints().get(j).ok_or_else(|| sim_error(&sim::SimError::UnknownJoint { index: j, joints: n }))?;
        Ok(joint.coordinate(w.bodies()))
    }

    /// The last step's joint reactions (what side A exerts on side B at the
    /// anchor): forces (J, 3) in N and torques (J, 3) in N·m.
    fn joint_reactions<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let w = self.shared();
        let r = &w.last_record().joints;
        let f: Vec<f64> = r.iter().flat_map(|x| x.force.to_array()).collect();
        let t: Vec<f64> = r.iter().flat_map(|x| x.torque.to_array()).collect();
        Ok((shaped(py, f, [r.len(), 3])?, shaped(py, t, [r.len(), 3])?))
    }

    /// The joints' drift factor β, settle passes and rank tolerance (`sim::JointParams`).
    fn joint_params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.shared().joint_params();
        let d = PyDict::new(py);
        d.set_item("drift", p.drift)?;
        d.set_item("rank_tol", p.rank_tol)?;
        d.set_item("settle_passes", p.settle_passes)?;
        d.set_item("settle_tol", p.settle_tol)?;
        Ok(d)
    }

    #[pyo3(signature = (drift = None, rank_tol = None, settle_passes = None, settle_tol = None))]
    fn set_joint_params(
        &mut self,
        drift: Option<f64>,
        rank_tol: Option<f64>,
        settle_passes: Option<u32>,
        settle_tol: Option<f64>,
    ) -> PyResult<()> {
        let w = self.inner();
        let mut p = w.joint_params();
        p.drift = drift.unwrap_or(p.drift);
        p.rank_tol = rank_tol.unwrap_or(p.rank_tol);
        p.settle_passes = settle_passes.unwrap_or(p.settle_passes);
        p.settle_tol = settle_tol.unwrap_or(p.settle_tol);
        guarded(|| w.set_joint_params(p))
    }

    // ----- forces -----

    /// A constant force (world frame, N); `point` relative to the centre of
    /// mass in the body frame (None: at the centre of mass).
    #[pyo3(signature = (body, force, point = None))]
    fn apply_force(
        &mut self,
        body: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let (id, f, p) = (body_id(body)?, vec3(force, "force")?, opt_vec3(point, "point")?);
        let w = self.inner();
        guarded(|| w.apply_force(id, f, p))
    }

    /// A constant torque (world frame, N·m).
    fn apply_torque(&mut self, body: &Bound<'_, PyAny>, torque: &Bound<'_, PyAny>) -> PyResult<()> {
        self.on_body(body, vec3(torque, "torque")?, sim::World::apply_torque)
    }

    fn clear_forces(&mut self) {
        self.inner().clear_forces();
    }

    // ----- stepping -----

    /// One step; returns its record (fields converted when read).
    fn step(&mut self) -> PyResult<PyStepRecord> {
        let pool = self.records.clone();
        let w = self.inner();
        guarded(|| w.step().map(|r| PyStepRecord::pooled(r, &pool)))
    }

    /// The record of the last step.
    fn last_record(&self) -> PyStepRecord {
        PyStepRecord::new(self.shared().last_record().clone())
    }

    /// Runs up to `steps` steps with the GIL released and returns the
    /// trajectory as a dict of arrays. Stops early (after at least one step)
    /// once the LCP capture holds `max_capture_bytes`, so the caller can drain it.
    #[pyo3(signature = (steps, max_capture_bytes = None))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        steps: usize,
        max_capture_bytes: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let capture = self.capture.clone();
        let limit = max_capture_bytes.filter(|_| self.capturing);
        let w = self.inner();
        // Stop early once the capture holds `limit` bytes, so the caller can drain it.
        let full =
            move |_: &sim::World| matches!((limit, capture.as_ref()), (Some(lim), Some(c)) if c.lock().bytes() >= lim);
        let out = py.detach(|| catch_unwind(AssertUnwindSafe(|| w.run_until(steps, full))));
        match out {
            Err(payload) => Err(panic_error(payload)),
            Ok(Err(e)) => Err(value_error(format!("step {}: {e}", self.shared().steps()))),
            Ok(Ok(traj)) => trajectory_to_dict(py, traj),
        }
    }

    // ----- LCP capture -----

    /// Starts capturing every solved LCP into a buffer (see `drain_capture`).
    fn start_capture(&mut self) {
        let buf = CaptureBuffer::default();
        self.capture = Some(buf.clone());
        self.capturing = true;
        self.inner().set_sink(Box::new(buf));
    }

    /// Stops capturing (whatever is still buffered stays drainable).
    fn stop_capture(&mut self) {
        self.capturing = false;
        self.inner().take_sink();
    }

    #[getter]
    fn capturing(&self) -> bool {
        self.capturing
    }

    /// LCPs waiting in the capture buffer.
    fn captured_count(&self) -> usize {
        self.capture.as_ref().map_or(0, |c| c.lock().len())
    }

    /// Takes the captured LCPs: a dict with flat `M`, `q`, `z`, `w` (problems
    /// concatenated) and per-problem `n`, `step`, `island`, `time`, `contacts`,
    /// `friction_dirs`, `scale`, `status` (index into STATUSES),
    /// `pivots`, `method`.
    fn drain_capture<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let buf = self.capture.clone().unwrap_or_default();
        buf.drain(py)
    }

    fn __repr__(&self) -> String {
        let w = self.shared();
        format!("World(bodies={}, steps={}, time={})", w.body_count(), w.steps(), w.time())
    }
}
