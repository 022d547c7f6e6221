//! Bindings of the `sim` crate: `World` (a `sim::World` behind a mutex, so the
//! class is `Sync`), its step records and trajectories as dicts of numpy
//! arrays, scenes (`sim/scenes.rs`) and LCP capture (`sim/capture.rs`).
//!
//! `run` releases the GIL; any `SimError` is a `ValueError` naming the field
//! and value; a panic in the core is caught and becomes a `RuntimeError`.

mod capture;
mod convert;
mod scenes;

pub use scenes::{build_scene, defaults as scene_defaults, SCENES};

use crate::errors::{panic_error, value_error};
use crate::method::method_from_py;
use capture::{status_code, CaptureBuffer};
use convert::{
    cone_scale, cone_scale_to_py, flag, mat3, mu_combine_name, opt_vec3, or_default, quat, real, sim_error, text, vec3,
    Fields,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::contact::FrictionBasis;
use sim::geometry::Shape;
use sim::math::Vec3;
use sim::{BodyDesc, BodyId, Plane, Restitution, Stabilization, StepRecord, Trajectory, WorldParams};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

pub use convert::MU_COMBINE;

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
}

impl World {
    pub fn wrap(world: sim::World) -> World {
        World { world: Mutex::new(world), capture: None, capturing: false }
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

/// A body index (an int ≥ 0; its range is the world's to check).
fn body_id(body: &Bound<'_, PyAny>) -> PyResult<BodyId> {
    convert::count(body, "body").map(BodyId)
}

fn arr3<'py>(py: Python<'py>, v: Vec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v.to_array().to_vec())
}

/// A flat vector as a numpy array of shape `shape`.
fn shaped<'py, const D: usize>(py: Python<'py>, v: Vec<f64>, shape: [usize; D]) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, v).reshape(shape.to_vec())?.into_any())
}

/// A few numbers copied into a numpy-owned array of shape `shape`: for the
/// small arrays of a step record this is one Python object, where `shaped`
/// makes two (the array owning the `Vec`, then its reshaped view).
fn copied<'py, T: numpy::Element + Copy>(py: Python<'py>, v: &[T], shape: &[usize]) -> Bound<'py, PyAny> {
    // SAFETY: the array is new, C-contiguous and seen by nobody else until
    // every element is written.
    unsafe {
        let a = numpy::PyArray::<T, numpy::IxDyn>::new(py, shape, false);
        a.as_slice_mut().expect("a new array is contiguous").copy_from_slice(v);
        a.into_any()
    }
}

/// The record's failed attempts (`sim::Retake`), each a dict: `time`, `h`,
/// `pivots`, and its islands' `lcp_size` and `status` (tuples, island order).
fn retakes_to_py<'py>(py: Python<'py>, r: &StepRecord) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
    r.retakes
        .iter()
        .map(|t| {
            let d = PyDict::new(py);
            d.set_item("time", t.time)?;
            d.set_item("h", t.h)?;
            d.set_item("pivots", t.pivots)?;
            let sizes: Vec<usize> = t.islands.iter().map(|i| i.lcp_size).collect();
            let status: Vec<&str> = t.islands.iter().map(|i| i.status.as_str()).collect();
            d.set_item("lcp_size", pyo3::types::PyTuple::new(py, sizes)?)?;
            d.set_item("status", pyo3::types::PyTuple::new(py, status)?)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()
        .and_then(|v| pyo3::types::PyTuple::new(py, v))
}

/// Status of a step without contacts (`lcpsim.world.NO_CONTACT`).
const NO_CONTACT: &str = "no_contact";

/// One step record as a dict whose keys are exactly the fields of
/// `lcpsim.world.StepRecord`, which takes it as its `__dict__` (a step from
/// Python costs microseconds, so the keys are interned and each array is one
/// object).
fn record_to_dict<'py>(py: Python<'py>, r: &StepRecord) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let nc = r.nc();
    let k = r.friction_dirs;
    d.set_item(intern!(py, "step"), r.step)?;
    d.set_item(intern!(py, "time"), r.time)?;
    d.set_item(intern!(py, "dt"), r.dt)?;
    d.set_item(intern!(py, "contacts"), nc)?;
    d.set_item(intern!(py, "friction_dirs"), k)?;
    d.set_item(intern!(py, "lcp_size"), r.lcp_size)?;
    d.set_item(intern!(py, "scale"), r.scale)?;
    d.set_item(intern!(py, "status"), r.status.map_or(NO_CONTACT, |s| s.as_str()))?;
    d.set_item(intern!(py, "pivots"), r.pivots)?;
    d.set_item(intern!(py, "residual"), r.residuals.residual)?;
    d.set_item(intern!(py, "min_z"), r.residuals.min_z)?;
    d.set_item(intern!(py, "min_w"), r.residuals.min_w)?;
    d.set_item(intern!(py, "max_complementarity"), r.residuals.max_complementarity)?;
    d.set_item(intern!(py, "solver_residual"), r.solver_residuals.residual)?;
    d.set_item(intern!(py, "zeroed"), r.zeroed)?;
    d.set_item(intern!(py, "parts"), r.parts)?;
    d.set_item(intern!(py, "retakes"), retakes_to_py(py, r)?)?;
    d.set_item(intern!(py, "energy_before"), r.energy.before)?;
    d.set_item(intern!(py, "energy_after"), r.energy.after)?;
    d.set_item(intern!(py, "external_work"), r.energy.external_work)?;
    d.set_item(intern!(py, "stabilization_work"), r.energy.stabilization)?;
    // The solver's z, or zeros where it was unusable (then also no friction).
    let lay = r.layout();
    let has_z = r.z.len() == lay.n();
    let zeros;
    let z: &[f64] = if has_z {
        &r.z
    } else {
        zeros = vec![0.0; lay.n()];
        &zeros
    };
    d.set_item(intern!(py, "fn"), copied(py, &z[lay.fn_range()], &[nc]))?;
    d.set_item(intern!(py, "fd"), copied(py, &z[lay.fd_range()], &[nc, k]))?;
    d.set_item(intern!(py, "lam"), copied(py, &z[lay.lambda_range()], &[nc]))?;
    d.set_item(intern!(py, "z"), copied(py, z, &[z.len()]))?;
    d.set_item(intern!(py, "w"), copied(py, &r.w, &[r.w.len()]))?;
    let mut points = Vec::with_capacity(3 * nc);
    let mut normals = Vec::with_capacity(3 * nc);
    let mut tangents = Vec::with_capacity(3 * nc);
    let mut friction = Vec::with_capacity(3 * nc);
    let mut directions = Vec::with_capacity(3 * nc * k);
    let basis = FrictionBasis::new(k.max(2));
    for (i, c) in r.contacts.iter().enumerate() {
        points.extend_from_slice(&c.point.to_array());
        normals.extend_from_slice(&c.normal.to_array());
        tangents.extend_from_slice(&c.tangent.to_array());
        friction.extend_from_slice(&if has_z { r.friction_impulse(i) } else { Vec3::ZERO }.to_array());
        for j in 0..k {
            directions.extend_from_slice(&basis.direction(c.normal, c.tangent, j).to_array());
        }
    }
    d.set_item(intern!(py, "points"), copied(py, &points, &[nc, 3]))?;
    d.set_item(intern!(py, "normals"), copied(py, &normals, &[nc, 3]))?;
    d.set_item(intern!(py, "tangents"), copied(py, &tangents, &[nc, 3]))?;
    d.set_item(intern!(py, "friction"), copied(py, &friction, &[nc, 3]))?;
    d.set_item(intern!(py, "directions"), copied(py, &directions, &[nc, k, 3]))?;
    let per_contact = |f: fn(&sim::Contact) -> f64| r.contacts.iter().map(f).collect::<Vec<_>>();
    d.set_item(intern!(py, "gaps"), copied(py, &per_contact(|c| c.gap), &[nc]))?;
    d.set_item(intern!(py, "mu"), copied(py, &per_contact(|c| c.mu), &[nc]))?;
    let body = |f: fn(&sim::Contact) -> usize| r.contacts.iter().map(|c| f(c) as i64).collect::<Vec<_>>();
    d.set_item(intern!(py, "body_a"), copied(py, &body(|c| c.body_a), &[nc]))?;
    d.set_item(intern!(py, "body_b"), copied(py, &body(|c| c.body_b), &[nc]))?;
    match &r.basis {
        Some(b) => d.set_item(intern!(py, "basis"), copied(py, b, &[b.len()]))?,
        None => d.set_item(intern!(py, "basis"), py.None())?,
    }
    islands_to_dict(py, r, &d)?;
    Ok(d)
}

/// The step's contact islands into the record's dict (`StepRecord.islands` … in Python).
fn islands_to_dict(py: Python<'_>, r: &StepRecord, d: &Bound<'_, PyDict>) -> PyResult<()> {
    let count = r.islands.len();
    let mut of_contact = vec![0i64; r.nc()];
    for (i, isl) in r.islands.iter().enumerate() {
        for &c in &r.island_contacts[isl.contacts.clone()] {
            of_contact[c] = i as i64;
        }
    }
    let each = |f: fn(&sim::IslandRecord) -> i64| r.islands.iter().map(f).collect::<Vec<_>>();
    let bodies = (0..count).map(|i| {
        let b: Vec<i64> = r.island_bodies_of(i).iter().map(|&b| b as i64).collect();
        copied(py, &b, &[b.len()])
    });
    d.set_item(intern!(py, "islands"), count)?;
    d.set_item(intern!(py, "island_of_contact"), copied(py, &of_contact, &[r.nc()]))?;
    d.set_item(intern!(py, "island_bodies"), pyo3::types::PyTuple::new(py, bodies)?)?;
    d.set_item(intern!(py, "island_lcp_size"), copied(py, &each(|i| i.lcp_size as i64), &[count]))?;
    d.set_item(intern!(py, "island_pivots"), copied(py, &each(|i| i.pivots as i64), &[count]))?;
    let entered = each(|i| i.entered.map_or(-1, |e| e as i64));
    d.set_item(intern!(py, "island_entered"), copied(py, &entered, &[count]))?;
    let res: Vec<f64> = r.islands.iter().map(|i| i.residual).collect();
    d.set_item(intern!(py, "island_residual"), copied(py, &res, &[count]))?;
    let eta: Vec<f64> = r.islands.iter().map(|i| i.body_eta).collect();
    d.set_item(intern!(py, "island_body_eta"), copied(py, &eta, &[count]))?;
    let status = r.islands.iter().map(|i| i.status.as_str());
    d.set_item(intern!(py, "island_status"), pyo3::types::PyTuple::new(py, status)?)?;
    Ok(())
}

fn trajectory_to_dict(py: Python<'_>, t: Trajectory) -> PyResult<Bound<'_, PyDict>> {
    let (n, b) = (t.len(), t.bodies);
    let ints = |v: &[usize]| PyArray1::from_vec(py, v.iter().map(|&c| c as i64).collect::<Vec<_>>());
    let status: Vec<i8> = t.status.iter().map(|s| s.map_or(-1, status_code)).collect();
    let d = PyDict::new(py);
    d.set_item("contacts", ints(&t.contacts))?;
    d.set_item("lcp_size", ints(&t.lcp_size))?;
    d.set_item("pivots", ints(&t.pivots))?;
    d.set_item("islands", ints(&t.islands))?;
    d.set_item("max_island_size", ints(&t.max_island_size))?;
    d.set_item("parts", ints(&t.parts))?;
    d.set_item("status", PyArray1::from_vec(py, status))?;
    d.set_item("time", PyArray1::from_vec(py, t.time))?;
    d.set_item("position", shaped(py, t.position, [n, b, 3])?)?;
    d.set_item("orientation", shaped(py, t.orientation, [n, b, 4])?)?;
    d.set_item("velocity", shaped(py, t.velocity, [n, b, 3])?)?;
    d.set_item("angular_velocity", shaped(py, t.angular_velocity, [n, b, 3])?)?;
    d.set_item("residual", PyArray1::from_vec(py, t.residual))?;
    d.set_item("solver_residual", PyArray1::from_vec(py, t.solver_residual))?;
    d.set_item("normal_impulse", PyArray1::from_vec(py, t.normal_impulse))?;
    d.set_item("friction_impulse", shaped(py, t.friction_impulse, [n, 3])?)?;
    d.set_item("max_lambda", PyArray1::from_vec(py, t.max_lambda))?;
    Ok(d)
}

/// The parameters `World(params)` takes: the keys of `params_dict` less the
/// derived `scale` and `method_config`.
const WORLD_FIELDS: [&str; 17] = [
    "dt",
    "gravity",
    "friction_dirs",
    "cone_scale",
    "method",
    "margin",
    "velocity_margin",
    "erp",
    "slop",
    "speculative",
    "gap_floor",
    "restitution",
    "restitution_threshold",
    "mu_combine",
    "mu_override",
    "threads",
    "max_halvings",
];

/// World parameters as a dict (cone_scale: "none", "dt" or the number): a
/// world's `params()`, and `WorldParams::default()` as `_core.WORLD_DEFAULTS`,
/// which `lcpsim.World` and `lcpsim.Stabilization` take as their defaults.
pub fn params_dict<'py>(py: Python<'py>, p: &WorldParams) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("dt", p.dt)?;
    d.set_item("gravity", p.gravity.to_array().to_vec())?;
    d.set_item("friction_dirs", p.friction_dirs)?;
    d.set_item("cone_scale", cone_scale_to_py(py, p.cone_scale)?)?;
    d.set_item("scale", p.scale())?;
    d.set_item("margin", p.margin)?;
    d.set_item("velocity_margin", p.velocity_margin)?;
    d.set_item("erp", p.stabilization.erp)?;
    d.set_item("slop", p.stabilization.slop)?;
    d.set_item("speculative", p.stabilization.speculative)?;
    d.set_item("gap_floor", p.stabilization.gap_floor)?;
    d.set_item("restitution", p.restitution.coefficient)?;
    d.set_item("restitution_threshold", p.restitution.threshold)?;
    d.set_item("mu_combine", mu_combine_name(p.mu_combine))?;
    d.set_item("mu_override", p.mu_override)?;
    d.set_item("threads", p.threads)?;
    d.set_item("max_halvings", p.max_halvings)?;
    d.set_item("method", p.method.name())?;
    d.set_item("method_config", format!("{:?}", p.method))?;
    Ok(d)
}

/// `sim::BodyDesc`'s defaults (shape aside), as `_core.BODY_DEFAULTS`: the
/// defaults of `lcpsim.World.add_box`/`add_sphere` and of the planes' μ.
pub fn body_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let b = BodyDesc::sphere(1.0);
    let d = PyDict::new(py);
    d.set_item("mass", b.mass)?;
    d.set_item("position", b.position.to_array().to_vec())?;
    d.set_item("orientation", b.orientation.to_array().to_vec())?;
    d.set_item("velocity", b.velocity.to_array().to_vec())?;
    d.set_item("angular_velocity", b.angular_velocity.to_array().to_vec())?;
    d.set_item("mu", b.mu)?;
    d.set_item("static", b.is_static)?;
    Ok(d)
}

#[pymethods]
impl World {
    /// `World(params, **options)`: `params` a dict of `WORLD_FIELDS` (missing or
    /// None: `WorldParams::default()`'s value), `options` the solver's.
    #[new]
    #[pyo3(signature = (params = None, **options))]
    fn new(params: Option<&Bound<'_, PyDict>>, options: Option<&Bound<'_, PyDict>>) -> PyResult<World> {
        let p = Fields { of: "World", dict: params };
        p.check_names(&WORLD_FIELDS)?;
        let d = WorldParams::default();
        let params = WorldParams {
            dt: p.or("dt", real, d.dt)?,
            gravity: p.or("gravity", vec3, d.gravity)?,
            friction_dirs: p.or("friction_dirs", convert::count, d.friction_dirs)?,
            cone_scale: convert::cone_scale(p.get("cone_scale")?.as_ref())?,
            margin: p.or("margin", real, d.margin)?,
            velocity_margin: p.or("velocity_margin", flag, d.velocity_margin)?,
            stabilization: Stabilization {
                erp: p.or("erp", real, d.stabilization.erp)?,
                slop: p.or("slop", real, d.stabilization.slop)?,
                speculative: p.or("speculative", flag, d.stabilization.speculative)?,
                gap_floor: p.or("gap_floor", real, d.stabilization.gap_floor)?,
            },
            restitution: Restitution {
                coefficient: p.or("restitution", real, d.restitution.coefficient)?,
                threshold: p.or("restitution_threshold", real, d.restitution.threshold)?,
            },
            mu_combine: p.or("mu_combine", |v, f| convert::mu_combine(&text(v, f)?), d.mu_combine)?,
            mu_override: p.or("mu_override", |v, f| real(v, f).map(Some), d.mu_override)?,
            method: method_from_py(&p.or("method", text, d.method.name().to_string())?, options)?,
            threads: p.or("threads", convert::count, d.threads)?,
            max_halvings: p.or(
                "max_halvings",
                |v, f| convert::at_most(v, f, sim::limits::MAX_HALVINGS),
                d.max_halvings,
            )?,
        };
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

    /// A box (`shape` "box", `size` its half extents) or a solid sphere
    /// ("sphere", `size` its radius). Values not given (or None) keep
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
        let mut d = match shape {
            "box" => BodyDesc::cuboid(vec3(size, "half_extents")?),
            "sphere" => BodyDesc::sphere(real(size, "radius")?),
            _ => return Err(value_error(format!("shape must be \"box\" or \"sphere\", got {shape:?}"))),
        };
        d.mass = or_default(mass, "mass", real, d.mass)?;
        d.position = or_default(position, "position", vec3, d.position)?;
        d.orientation = or_default(orientation, "orientation", quat, d.orientation)?;
        d.velocity = or_default(velocity, "velocity", vec3, d.velocity)?;
        d.angular_velocity = or_default(angular_velocity, "angular_velocity", vec3, d.angular_velocity)?;
        d.mu = or_default(mu, "mu", real, d.mu)?;
        d.inertia = or_default(inertia, "inertia", |v, f| mat3(v, f).map(Some), d.inertia)?;
        self.add(d.fixed(is_static))
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
        d.set_item("position", arr3(py, b.position()))?;
        d.set_item("orientation", PyArray1::from_vec(py, b.orientation().to_array().to_vec()))?;
        d.set_item("velocity", arr3(py, b.velocity()))?;
        d.set_item("angular_velocity", arr3(py, b.angular_velocity()))?;
        let i = b.inertia();
        d.set_item("inertia", shaped(py, i.m.iter().flatten().copied().collect(), [3, 3])?)?;
        match b.shape() {
            Shape::Box(x) => d.set_item("half_extents", arr3(py, x.half_extents))?,
            Shape::Sphere { radius } => d.set_item("radius", *radius)?,
            Shape::Plane(p) => {
                d.set_item("normal", arr3(py, p.normal()))?;
                d.set_item("offset", p.offset())?;
                d.set_item("tangent", arr3(py, p.friction_tangent()))?;
                d.set_item("downhill", p.downhill().map(|v| arr3(py, v)))?;
            }
        }
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

    /// One step; returns its record as a dict.
    fn step<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = self.inner();
        let rec = guarded(|| w.step().cloned())?;
        record_to_dict(py, &rec)
    }

    /// The record of the last step.
    fn last_record<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        record_to_dict(py, self.shared().last_record())
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
