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

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("METHODS", method::METHODS.to_vec())?;
    m.add("PIVOTINGS", method::PIVOTINGS.to_vec())?;
    m.add("STATUSES", ::lcp::Status::ALL.iter().map(|s| s.as_str()).collect::<Vec<_>>())?;
    let opts = PyDict::new(py);
    for (name, list) in method::method_options() {
        opts.set_item(name, list.to_vec())?;
    }
    m.add("METHOD_OPTIONS", opts)?;
    m.add("LEMKE_DEFAULTS", method::lemke_defaults(py)?)?;
    m.add_function(wrap_pyfunction!(lcp::solve_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(lcp::solve_lcp_batch, m)?)?;
    m.add_function(wrap_pyfunction!(lcp::lcp_residual, m)?)?;
    m.add_function(wrap_pyfunction!(lcp::lcp_residuals, m)?)?;
    // The simulator.
    m.add_class::<sim::World>()?;
    m.add_function(wrap_pyfunction!(sim::build_scene, m)?)?;
    let scenes = PyDict::new(py);
    for (name, params) in sim::SCENES {
        scenes.set_item(name, params.to_vec())?;
    }
    m.add("SCENES", scenes)?;
    m.add("MU_COMBINE", sim::MU_COMBINE.to_vec())?;
    // Rotations (sim::math) for placing bodies from Python.
    m.add_function(wrap_pyfunction!(math::quat_from_axis_angle, m)?)?;
    m.add_function(wrap_pyfunction!(math::quat_mul, m)?)?;
    m.add_function(wrap_pyfunction!(math::quat_to_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(math::quat_from_matrix, m)?)?;
    // Where fn, fd, λ live in a contact LCP's z.
    m.add_class::<contact::PyContactLayout>()?;
    // Seeded test-LCP generators.
    m.add_function(wrap_pyfunction!(generate::contact_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(generate::spd_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(generate::p_matrix_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(generate::hard_contact_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(generate::hard_corpus, m)?)?;
    m.add("HARD_KINDS", generate::hard_kinds())?;
    // Exact certification and the pivot trace of failure dumps (issue 5).
    m.add_function(wrap_pyfunction!(certify::certify_lcp, m)?)?;
    m.add_function(wrap_pyfunction!(certify::certify_lcp_batch, m)?)?;
    m.add_function(wrap_pyfunction!(certify::solve_lcp_traced, m)?)?;
    Ok(())
}
