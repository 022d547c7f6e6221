//! `sim::scenes` for Python: one builder taking the scene's name, a dict of
//! its parameters (the Rust struct's fields) and a template world whose
//! parameters (dt, cone scale, solver, …) the scene world gets.

use super::convert::{count, downhill, real, repr};
use super::World;
use crate::errors::value_error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::scenes::{BallDrop, BallOnIncline, BoxPile, BoxStack, CubeDrop, CubeHeap, CubeOnSlope, PushedCube, Scene};
use sim::WorldParams;

/// Scene names and their parameters (in the order of the Rust structs).
pub const SCENES: [(&str, &[&str]); 8] = [
    ("cube_on_slope", &["angle_deg", "mu", "size", "mass", "downhill", "speed", "tangent_angle"]),
    ("pushed_cube", &["force", "mu", "size", "mass", "height"]),
    ("cube_drop", &["height", "size", "mass", "mu", "restitution"]),
    ("ball_drop", &["height", "radius", "mass", "mu", "restitution"]),
    ("box_stack", &["n", "size", "mass", "mu"]),
    ("ball_on_incline", &["angle_deg", "mu", "radius", "mass", "downhill"]),
    ("box_pile", &["nx", "ny", "nz", "size", "mass", "mu", "spacing", "yaw", "seed"]),
    ("cube_heap", &["n", "seed", "walls", "size", "mass", "mu", "spacing", "jitter"]),
];

/// Reads the scene parameters out of `params`, rejecting unknown names.
struct Params<'a, 'py> {
    scene: &'a str,
    dict: Option<&'a Bound<'py, PyDict>>,
    valid: &'static [&'static str],
}

impl<'py> Params<'_, 'py> {
    fn get(&self, name: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.dict {
            Some(d) => Ok(d.get_item(name)?.filter(|v| !v.is_none())),
            None => Ok(None),
        }
    }

    fn real(&self, name: &str, default: f64) -> PyResult<f64> {
        self.get(name)?.map_or(Ok(default), |v| real(&v, name))
    }

    fn opt_real(&self, name: &str) -> PyResult<Option<f64>> {
        self.get(name)?.map(|v| real(&v, name)).transpose()
    }

    fn required(&self, name: &str) -> PyResult<f64> {
        match self.get(name)? {
            Some(v) if name == "angle_deg" => super::convert::angle_deg(real(&v, name)?),
            Some(v) => real(&v, name),
            None => Err(value_error(format!("scene {} needs the parameter {name}", self.scene))),
        }
    }

    fn count(&self, name: &str, default: usize) -> PyResult<usize> {
        self.get(name)?.map_or(Ok(default), |v| count(&v, name))
    }

    fn flag(&self, name: &str, default: bool) -> PyResult<bool> {
        match self.get(name)? {
            None => Ok(default),
            Some(v) if v.is_instance_of::<pyo3::types::PyBool>() => v.extract(),
            Some(v) => Err(value_error(format!("{name} must be True or False, got {}", repr(&v)))),
        }
    }

    fn downhill(&self, default: sim::Downhill) -> PyResult<sim::Downhill> {
        match self.get("downhill")? {
            None => Ok(default),
            Some(v) => {
                let s: String = v
                    .extract()
                    .map_err(|_| value_error(format!("downhill must be \"+x\" or \"-x\", got {}", repr(&v))))?;
                downhill(&s)
            }
        }
    }

    fn check_names(&self) -> PyResult<()> {
        for key in self.dict.into_iter().flat_map(|d| d.keys()) {
            let name: String = key.extract()?;
            if !self.valid.contains(&name.as_str()) {
                return Err(value_error(format!(
                    "unknown parameter {name:?} for scene {} (valid: {})",
                    self.scene,
                    self.valid.join(", ")
                )));
            }
        }
        Ok(())
    }
}

/// Builds scene `name` with `params` and the world parameters `wp`.
pub fn build(name: &str, dict: Option<&Bound<'_, PyDict>>, wp: WorldParams) -> PyResult<Scene> {
    let Some((_, valid)) = SCENES.iter().find(|(n, _)| *n == name) else {
        let names: Vec<&str> = SCENES.iter().map(|(n, _)| *n).collect();
        return Err(value_error(format!("unknown scene {name:?} (valid: {})", names.join(", "))));
    };
    let p = Params { scene: name, dict, valid };
    p.check_names()?;
    let built = match name {
        "cube_on_slope" => {
            let d = CubeOnSlope::new(p.required("angle_deg")?, p.required("mu")?);
            CubeOnSlope {
                size: p.real("size", d.size)?,
                mass: p.real("mass", d.mass)?,
                downhill: p.downhill(d.downhill)?,
                speed: p.real("speed", d.speed)?,
                tangent_angle: p.real("tangent_angle", d.tangent_angle)?,
                ..d
            }
            .build(wp)
        }
        "pushed_cube" => {
            let d = PushedCube::new(p.required("force")?, p.required("mu")?);
            PushedCube {
                size: p.real("size", d.size)?,
                mass: p.real("mass", d.mass)?,
                height: p.real("height", d.height)?,
                ..d
            }
            .build(wp)
        }
        "cube_drop" => {
            let d = CubeDrop::default();
            CubeDrop {
                height: p.real("height", d.height)?,
                size: p.real("size", d.size)?,
                mass: p.real("mass", d.mass)?,
                mu: p.real("mu", d.mu)?,
                restitution: p.opt_real("restitution")?.or(d.restitution),
            }
            .build(wp)
        }
        "ball_drop" => {
            let d = BallDrop::default();
            BallDrop {
                height: p.real("height", d.height)?,
                radius: p.real("radius", d.radius)?,
                mass: p.real("mass", d.mass)?,
                mu: p.real("mu", d.mu)?,
                restitution: p.opt_real("restitution")?.or(d.restitution),
            }
            .build(wp)
        }
        "box_stack" => {
            let d = BoxStack::new(p.count("n", 3)?);
            BoxStack { size: p.real("size", d.size)?, mass: p.real("mass", d.mass)?, mu: p.real("mu", d.mu)?, ..d }
                .build(wp)
        }
        "ball_on_incline" => {
            let d = BallOnIncline::new(p.required("angle_deg")?, p.required("mu")?);
            BallOnIncline {
                radius: p.real("radius", d.radius)?,
                mass: p.real("mass", d.mass)?,
                downhill: p.downhill(d.downhill)?,
                ..d
            }
            .build(wp)
        }
        "box_pile" => {
            let d = BoxPile::default();
            BoxPile {
                nx: p.count("nx", d.nx)?,
                ny: p.count("ny", d.ny)?,
                nz: p.count("nz", d.nz)?,
                size: p.real("size", d.size)?,
                mass: p.real("mass", d.mass)?,
                mu: p.real("mu", d.mu)?,
                spacing: p.real("spacing", d.spacing)?,
                yaw: p.real("yaw", d.yaw)?,
                seed: p.count("seed", d.seed as usize)? as u64,
            }
            .build(wp)
        }
        "cube_heap" => {
            let d = CubeHeap::new(p.count("n", 50)?, p.count("seed", 0)? as u64);
            CubeHeap {
                walls: p.flag("walls", d.walls)?,
                size: p.real("size", d.size)?,
                mass: p.real("mass", d.mass)?,
                mu: p.real("mu", d.mu)?,
                spacing: p.real("spacing", d.spacing)?,
                jitter: p.real("jitter", d.jitter)?,
                ..d
            }
            .build(wp)
        }
        _ => unreachable!("checked against SCENES above"),
    };
    built.map_err(|e| super::convert::sim_error(&e))
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
