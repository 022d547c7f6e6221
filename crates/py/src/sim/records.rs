//! Step records and trajectories as dicts of numpy arrays (`World.step`,
//! `World.last_record`, `World.run`), and the small array helpers they share
//! with `World.body` and `World.state`.

use super::capture::status_code;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::contact::FrictionBasis;
use sim::math::Vec3;
use sim::{StepRecord, Trajectory};

pub(super) fn arr3<'py>(py: Python<'py>, v: Vec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v.to_array().to_vec())
}

/// A flat vector as a numpy array of shape `shape`.
pub(super) fn shaped<'py, const D: usize>(
    py: Python<'py>,
    v: Vec<f64>,
    shape: [usize; D],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, v).reshape(shape.to_vec())?.into_any())
}

/// A few numbers copied into a numpy-owned array of shape `shape`: for the
/// small arrays of a step record this is one Python object, where `shaped`
/// makes two (the array owning the `Vec`, then its reshaped view).
pub(super) fn copied<'py, T: numpy::Element + Copy>(py: Python<'py>, v: &[T], shape: &[usize]) -> Bound<'py, PyAny> {
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
pub(super) fn retakes_to_py<'py>(py: Python<'py>, r: &StepRecord) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
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
pub(super) fn record_to_dict<'py>(py: Python<'py>, r: &StepRecord) -> PyResult<Bound<'py, PyDict>> {
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
pub(super) fn islands_to_dict(py: Python<'_>, r: &StepRecord, d: &Bound<'_, PyDict>) -> PyResult<()> {
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
    let stage = r.islands.iter().map(|i| i.stage.map_or("none", sim::SolveStage::as_str));
    d.set_item(intern!(py, "island_stage"), pyo3::types::PyTuple::new(py, stage)?)?;
    Ok(())
}

pub(super) fn trajectory_to_dict(py: Python<'_>, t: Trajectory) -> PyResult<Bound<'_, PyDict>> {
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
    let counts: Vec<i64> = t.stage_counts.iter().map(|&c| c as i64).collect();
    d.set_item("stage_counts", copied(py, &counts, &[n, sim::SolveStage::ALL.len()]))?;
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
