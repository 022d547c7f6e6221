//! `lcpsim._core`: the private compiled module behind the `lcpsim` package.
//!
//! Glue only — conversion, validation messages, GIL release — mirroring the
//! core crates one module each: `problem` (numpy → `Lcp`), `method` (name +
//! options → `Method`), `solution` (`Solution` → dict), `lcp` (the solver
//! functions), `contact` (`ContactLayout`), `math` (quaternions), `errors`. `sim` (the simulator: `World`, scenes, LCP capture).

mod args;
mod certify;
mod contact;
mod errors;
mod generate;
mod lcp;
mod math;
mod method;
mod problem;
mod sim;
mod solution;

use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `{name: [names]}`: the option names of each method, the parameters of each scene.
fn names_table<'py>(
    py: Python<'py>,
    rows: impl IntoIterator<Item = (&'static str, &'static [&'static str])>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, names) in rows {
        d.set_item(name, names.to_vec())?;
    }
    Ok(d)
}

/// Adds each `#[pyfunction]` to the module.
macro_rules! add_functions {
    ($m:expr; $($f:path),+ $(,)?) => {
        $($m.add_function(wrap_pyfunction!($f, $m)?)?;)+
    };
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("METHODS", method::METHODS.to_vec())?;
    m.add("PIVOTINGS", method::PIVOTINGS.to_vec())?;
    m.add("STATUSES", ::lcp::Status::ALL.iter().map(|s| s.as_str()).collect::<Vec<_>>())?;
    m.add("METHOD_OPTIONS", names_table(py, method::method_options())?)?;
    m.add("LEMKE_DEFAULTS", method::lemke_defaults(py)?)?;
    add_functions!(m; lcp::solve_lcp, lcp::solve_lcp_batch, lcp::lcp_residual, lcp::lcp_residuals);
    // The simulator; its defaults (the Python wrappers' defaults) and scenes.
    m.add_class::<sim::World>()?;
    m.add_class::<sim::PyStepRecord>()?;
    add_functions!(m; sim::build_scene);
    m.add("SCENES", names_table(py, sim::SCENES.iter().copied())?)?;
    m.add("SCENE_DEFAULTS", sim::scene_defaults(py)?)?;
    m.add("WORLD_DEFAULTS", sim::params_dict(py, &::sim::WorldParams::default())?)?;
    m.add("BODY_DEFAULTS", sim::body_defaults(py)?)?;
    m.add("MU_COMBINE", sim::MU_COMBINE.to_vec())?;
    // Rotations (sim::math) for placing bodies from Python.
    add_functions!(m; math::quat_from_axis_angle, math::quat_mul, math::quat_to_matrix, math::quat_from_matrix);
    // Where fn, fd, λ live in a contact LCP's z.
    m.add_class::<contact::PyContactLayout>()?;
    // Seeded test-LCP generators.
    add_functions!(m; generate::contact_lcp, generate::spd_lcp, generate::p_matrix_lcp, generate::hard_contact_lcp,
                   generate::hard_corpus);
    m.add("HARD_KINDS", generate::hard_kinds())?;
    // Exact certification and the pivot trace of failure dumps.
    add_functions!(m; certify::certify_lcp, certify::certify_lcp_batch, certify::solve_lcp_traced);
    Ok(())
}
