//! `sim::scenes` for Python: one builder taking the scene's name, a dict of
//! its parameters (the Rust struct's fields) and a template world whose
//! parameters (dt, cone scale, solver, …) the scene world gets.
//!
//! Each scene's fields are listed once, in the `scenes!` table below: it
//! makes the parameter names (`_core.SCENES`), the Rust defaults of the
//! optional ones (`_core.SCENE_DEFAULTS`, which `lcpsim.scenes` takes as its
//! signatures' defaults) and the builder that lays the given values over them.

use super::convert::{count, downhill, flag, real, repr, Fields};
use super::world::World;
use crate::errors::value_error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::scenes::{
    BallDrop, BallOnIncline, BoxPile, BoxStack, CubeDrop, CubeHeap, CubeOnSlope, CubePour, PushedCube, Scene,
};
use sim::{Downhill, WorldParams};

/// The scene's parameters: the given value of each, else the Rust default.
struct Params<'a, 'py>(Fields<'a, 'py>);

impl Params<'_, '_> {
    /// Field `name`: the given value, else `default` (the Rust struct's).
    fn field<T: Field>(&self, name: &str, default: T) -> PyResult<T> {
        self.0.or(name, T::read, default)
    }

    /// A parameter the scene's constructor needs (no Rust default).
    fn required<T: Field>(&self, name: &str) -> PyResult<T> {
        match self.0.get(name)? {
            Some(v) => T::read(&v, name),
            None => Err(value_error(format!("{} needs the parameter {name}", self.0.of))),
        }
    }
}

/// A scene parameter's type: read from Python (the error names the field and
/// value) and shown to Python as its default.
trait Field: Sized {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self>;
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>>;
    /// What the defaults table builds a scene with in place of required
    /// parameter `name` (the value is never used; the name lets the table
    /// repeat the call once per required parameter).
    fn placeholder(name: &str) -> Self;
}

impl Field for f64 {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        let v = real(value, name)?;
        if name == "angle_deg" {
            return super::convert::angle_deg(v);
        }
        Ok(v)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.into_pyobject(py)?.into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        0.0
    }
}

impl Field for usize {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        count(value, name)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.into_pyobject(py)?.into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        0
    }
}

impl Field for u64 {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        Ok(count(value, name)? as u64)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.into_pyobject(py)?.into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        0
    }
}

impl Field for bool {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        flag(value, name)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(pyo3::types::PyBool::new(py, *self).to_owned().into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        false
    }
}

impl Field for Option<f64> {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        real(value, name).map(Some)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(self.into_pyobject(py)?.into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        None
    }
}

impl Field for Downhill {
    fn read(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        let s: String = value
            .extract()
            .map_err(|_| value_error(format!("{name} must be \"+x\" or \"-x\", got {}", repr(value))))?;
        downhill(&s)
    }
    fn to_py(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let s = match self {
            Downhill::PlusX => "+x",
            Downhill::MinusX => "-x",
        };
        Ok(s.into_pyobject(py)?.into_any().unbind())
    }
    fn placeholder(_: &str) -> Self {
        Downhill::PlusX
    }
}

/// The scene table: `"name" => Struct::constructor(required, …) { optional, … }`.
/// Optional fields start at the constructor's values (the Rust defaults).
macro_rules! scenes {
    ($($name:literal => $ty:ident :: $ctor:ident ($($req:ident),*) { $($opt:ident),* $(,)? }),* $(,)?) => {
        /// Scene names and their parameters (in the order of the Rust structs).
        pub const SCENES: &[(&str, &[&str])] = &[$(($name, &[$(stringify!($req),)* $(stringify!($opt)),*])),*];

        /// Builds scene `name` with `params` and the world parameters `wp`.
        pub fn build(name: &str, dict: Option<&Bound<'_, PyDict>>, wp: WorldParams) -> PyResult<Scene> {
            let Some((_, valid)) = SCENES.iter().find(|(n, _)| *n == name) else {
                let names: Vec<&str> = SCENES.iter().map(|(n, _)| *n).collect();
                return Err(value_error(format!("unknown scene {name:?} (valid: {})", names.join(", "))));
            };
            let of = format!("scene {name}");
            let p = Params(Fields { of: &of, dict });
            p.0.check_names(valid)?;
            let built = match name {
                $($name => {
                    #[allow(unused_mut)]
                    let mut s = $ty::$ctor($(p.required(stringify!($req))?),*);
                    $(s.$opt = p.field(stringify!($opt), s.$opt)?;)*
                    s.build(wp)
                })*
                _ => unreachable!("checked against SCENES above"),
            };
            built.map_err(|e| super::convert::sim_error(&e))
        }

        /// Per scene, its optional parameters and their Rust defaults.
        pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
            let all = PyDict::new(py);
            $({
                let s = $ty::$ctor($(Field::placeholder(stringify!($req))),*);
                let d = PyDict::new(py);
                $(d.set_item(stringify!($opt), s.$opt.to_py(py)?)?;)*
                all.set_item($name, d)?;
            })*
            Ok(all)
        }
    };
}

scenes! {
    "cube_on_slope" => CubeOnSlope::new(angle_deg, mu) { size, mass, downhill, speed, tangent_angle },
    "pushed_cube" => PushedCube::new(force, mu) { size, mass, height },
    "cube_drop" => CubeDrop::default() { height, size, mass, mu, restitution },
    "ball_drop" => BallDrop::default() { height, radius, mass, mu, restitution },
    "box_stack" => BoxStack::new(n) { size, mass, mu },
    "ball_on_incline" => BallOnIncline::new(angle_deg, mu) { radius, mass, downhill },
    "box_pile" => BoxPile::default() { nx, ny, nz, size, mass, mu, spacing, yaw, seed },
    "cube_heap" => CubeHeap::new(n, seed) { walls, size, mass, mu, spacing, jitter },
    "cube_pour" => CubePour::new(n, seed) { walls, size, mass, mu, spacing, jitter },
}

/// `build_scene(name, params, template)`: the scene's world (with the
/// template's parameters) and a dict `body`, `ground`, `bodies`.
#[pyfunction]
#[pyo3(signature = (name, params, template))]
pub fn build_scene<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    template: &World,
) -> PyResult<(World, Bound<'py, PyDict>)> {
    let wp = template.params_clone();
    let scene = build(name, params, wp)?;
    let d = PyDict::new(py);
    d.set_item("body", scene.body.0)?;
    d.set_item("ground", scene.ground.0)?;
    d.set_item("bodies", scene.bodies.iter().map(|b| b.0).collect::<Vec<_>>())?;
    Ok((World::wrap(scene.world), d))
}
