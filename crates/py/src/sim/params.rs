//! World parameters to and from Python dicts (`World(params)`, `World.params()`,
//! `_core.WORLD_DEFAULTS`), and the body defaults (`_core.BODY_DEFAULTS`).

use super::convert::{self, cone_scale_to_py, flag, mu_combine_name, real, text, vec3, Fields};
use crate::method::method_from_py;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::{BodyDesc, Restitution, Stabilization, WorldParams};

/// The parameters `World(params)` takes: the keys of `params_dict` less the
/// derived `scale` and `method_config`.
pub(super) const WORLD_FIELDS: [&str; 17] = [
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
    d.set_item("contype", b.filter.contype)?;
    d.set_item("conaffinity", b.filter.conaffinity)?;
    Ok(d)
}

/// The `WorldParams` of `World(params, **options)`: `params` a dict of
/// [`WORLD_FIELDS`] (missing or None: `WorldParams::default()`'s value),
/// `options` the solver's.
pub(super) fn world_params(
    params: Option<&Bound<'_, PyDict>>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<WorldParams> {
    let p = Fields { of: "World", dict: params };
    p.check_names(&WORLD_FIELDS)?;
    let d = WorldParams::default();
    Ok(WorldParams {
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
        max_halvings: p.or("max_halvings", |v, f| convert::at_most(v, f, sim::limits::MAX_HALVINGS), d.max_halvings)?,
    })
}
