//! Step records, converted field by field when read (`World.step`,
//! `World.last_record`), trajectories as dicts of numpy arrays (`World.run`),
//! and the small array helpers they share with `World.body` and `World.state`.

use super::capture::status_code;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString, PyTuple};
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

/// One step's record as the core wrote it (`World.step`, `World.last_record`).
/// Its fields become Python values only when read (`field`, which
/// `lcpsim.world.StepRecord` calls on first access of an attribute): a step
/// from Python then costs the step and one copy of the record, not the
/// conversion of ~25 numpy arrays it may never read. The copy is made into a
/// record dropped earlier ([`RecordPool`]): a loop of `World.step()` that lets
/// each record go allocates none of its vectors.
#[pyclass(module = "lcpsim._core", name = "StepRecord", frozen)]
pub struct PyStepRecord {
    rec: StepRecord,
    /// Where the record goes back when this object is dropped.
    pool: Option<RecordPool>,
}

impl PyStepRecord {
    pub(super) fn new(rec: StepRecord) -> Self {
        PyStepRecord { rec, pool: None }
    }

    /// A copy of `src` in a record taken from `pool` (its buffers reused),
    /// given back to `pool` when dropped.
    pub(super) fn pooled(src: &StepRecord, pool: &RecordPool) -> Self {
        let mut rec = pool.take();
        copy_record(&mut rec, src);
        PyStepRecord { rec, pool: Some(pool.clone()) }
    }
}

impl Drop for PyStepRecord {
    fn drop(&mut self) {
        if let Some(pool) = &self.pool {
            pool.give(std::mem::take(&mut self.rec));
        }
    }
}

/// Records of dropped [`PyStepRecord`]s, at most [`RecordPool::MAX`], for
/// the next steps' copies (each of the 7 vectors of a record with contacts
/// was an allocation and a free a step).
#[derive(Clone, Default)]
pub struct RecordPool(std::sync::Arc<std::sync::Mutex<Vec<StepRecord>>>);

impl RecordPool {
    const MAX: usize = 4;

    fn take(&self) -> StepRecord {
        self.0.lock().ok().and_then(|mut v| v.pop()).unwrap_or_default()
    }

    fn give(&self, rec: StepRecord) {
        if let Ok(mut v) = self.0.lock() {
            if v.len() < Self::MAX {
                v.push(rec);
            }
        }
    }
}

/// `dst` made equal to `src`, reusing `dst`'s vectors (every field is named:
/// a field added to `StepRecord` fails to compile here until it is copied).
fn copy_record(dst: &mut StepRecord, src: &StepRecord) {
    let StepRecord {
        step,
        time,
        dt,
        contacts,
        friction_dirs,
        lcp_size,
        scale,
        status,
        pivots,
        residuals,
        solver_residuals,
        zeroed,
        energy,
        z,
        w,
        basis,
        islands,
        joints,
        island_bodies,
        island_contacts,
        parts,
        retakes,
    } = src;
    (dst.step, dst.time, dst.dt, dst.friction_dirs, dst.lcp_size, dst.scale) =
        (*step, *time, *dt, *friction_dirs, *lcp_size, *scale);
    (dst.status, dst.pivots, dst.residuals, dst.solver_residuals, dst.zeroed, dst.parts) =
        (*status, *pivots, *residuals, *solver_residuals, *zeroed, *parts);
    dst.energy.clone_from(energy);
    dst.contacts.clone_from(contacts);
    dst.z.clone_from(z);
    dst.w.clone_from(w);
    dst.basis.clone_from(basis);
    dst.islands.clone_from(islands);
    dst.joints.clone_from(joints);
    dst.island_bodies.clone_from(island_bodies);
    dst.island_contacts.clone_from(island_contacts);
    dst.retakes.clone_from(retakes);
}

#[pymethods]
impl PyStepRecord {
    /// Field `name` of `lcpsim.world.StepRecord`, converted now (each array a
    /// new numpy array of its own); an `AttributeError` for any other name.
    fn field<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        field(py, &self.rec, name)
    }
}

/// One field of a step record as `lcpsim.world.StepRecord` holds it.
fn field<'py>(py: Python<'py>, r: &StepRecord, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let nc = r.nc();
    let k = r.friction_dirs;
    let lay = r.layout();
    // The solver's z, or zeros where it was unusable (then also no friction).
    let has_z = r.z.len() == lay.n();
    let zeros;
    let z: &[f64] = if has_z {
        &r.z
    } else {
        zeros = vec![0.0; lay.n()];
        &zeros
    };
    // Per contact, a vector of 3 (or k·3) numbers.
    let per_contact3 = |f: &dyn Fn(usize, &sim::Contact, &mut Vec<f64>), width: usize, shape: &[usize]| {
        let mut out = Vec::with_capacity(width * nc);
        for (i, c) in r.contacts.iter().enumerate() {
            f(i, c, &mut out);
        }
        copied(py, &out, shape)
    };
    let per_contact = |f: fn(&sim::Contact) -> f64| copied(py, &r.contacts.iter().map(f).collect::<Vec<_>>(), &[nc]);
    let body =
        |f: fn(&sim::Contact) -> usize| copied(py, &r.contacts.iter().map(|c| f(c) as i64).collect::<Vec<_>>(), &[nc]);
    let count = r.islands.len();
    let each = |f: fn(&sim::IslandRecord) -> i64| copied(py, &r.islands.iter().map(f).collect::<Vec<_>>(), &[count]);
    let each_f = |f: fn(&sim::IslandRecord) -> f64| copied(py, &r.islands.iter().map(f).collect::<Vec<_>>(), &[count]);
    Ok(match name {
        "step" => r.step.into_pyobject(py)?.into_any(),
        "time" => r.time.into_pyobject(py)?.into_any(),
        "dt" => r.dt.into_pyobject(py)?.into_any(),
        "contacts" => nc.into_pyobject(py)?.into_any(),
        "friction_dirs" => k.into_pyobject(py)?.into_any(),
        "lcp_size" => r.lcp_size.into_pyobject(py)?.into_any(),
        "scale" => r.scale.into_pyobject(py)?.into_any(),
        "status" => PyString::new(py, r.status.map_or(NO_CONTACT, |s| s.as_str())).into_any(),
        "pivots" => r.pivots.into_pyobject(py)?.into_any(),
        "residual" => r.residuals.residual.into_pyobject(py)?.into_any(),
        "min_z" => r.residuals.min_z.into_pyobject(py)?.into_any(),
        "min_w" => r.residuals.min_w.into_pyobject(py)?.into_any(),
        "max_complementarity" => r.residuals.max_complementarity.into_pyobject(py)?.into_any(),
        "solver_residual" => r.solver_residuals.residual.into_pyobject(py)?.into_any(),
        "zeroed" => PyBool::new(py, r.zeroed).to_owned().into_any(),
        "parts" => r.parts.into_pyobject(py)?.into_any(),
        "joint_force" | "joint_torque" => {
            let of = |x: &sim::JointReaction| if name == "joint_force" { x.force } else { x.torque };
            let flat: Vec<f64> = r.joints.iter().flat_map(|x| of(x).to_array()).collect();
            copied(py, &flat, &[r.joints.len(), 3])
        }
        "retakes" => retakes_to_py(py, r)?.into_any(),
        "energy_before" => r.energy.before.into_pyobject(py)?.into_any(),
        "energy_after" => r.energy.after.into_pyobject(py)?.into_any(),
        "external_work" => r.energy.external_work.into_pyobject(py)?.into_any(),
        "stabilization_work" => r.energy.stabilization.into_pyobject(py)?.into_any(),
        "motor_work" => r.energy.motor_work.into_pyobject(py)?.into_any(),
        "joint_drift_work" => r.energy.joint_drift.into_pyobject(py)?.into_any(),
        "joint_projection_energy" => r.energy.joint_projection.into_pyobject(py)?.into_any(),
        "fn" => copied(py, &z[lay.fn_range()], &[nc]),
        "fd" => copied(py, &z[lay.fd_range()], &[nc, k]),
        "lam" => copied(py, &z[lay.lambda_range()], &[nc]),
        "z" => copied(py, z, &[lay.n()]),
        "w" => copied(py, &r.w, &[r.w.len()]),
        "points" => per_contact3(&|_, c, o| o.extend_from_slice(&c.point.to_array()), 3, &[nc, 3]),
        "normals" => per_contact3(&|_, c, o| o.extend_from_slice(&c.normal.to_array()), 3, &[nc, 3]),
        "tangents" => per_contact3(&|_, c, o| o.extend_from_slice(&c.tangent.to_array()), 3, &[nc, 3]),
        "friction" => per_contact3(
            &|i, _, o| o.extend_from_slice(&if has_z { r.friction_impulse(i) } else { Vec3::ZERO }.to_array()),
            3,
            &[nc, 3],
        ),
        "directions" => {
            let basis = FrictionBasis::new(k.max(2));
            let dirs = |_: usize, c: &sim::Contact, o: &mut Vec<f64>| {
                for j in 0..k {
                    o.extend_from_slice(&basis.direction(c.normal, c.tangent, j).to_array());
                }
            };
            per_contact3(&dirs, 3 * k, &[nc, k, 3])
        }
        "gaps" => per_contact(|c| c.gap),
        "mu" => per_contact(|c| c.mu),
        "body_a" => body(|c| c.body_a),
        "body_b" => body(|c| c.body_b),
        "basis" => match &r.basis {
            Some(b) => copied(py, b, &[b.len()]),
            None => py.None().into_bound(py),
        },
        "islands" => count.into_pyobject(py)?.into_any(),
        "island_of_contact" => {
            let mut of_contact = vec![0i64; nc];
            for (i, isl) in r.islands.iter().enumerate() {
                for &c in &r.island_contacts[isl.contacts.clone()] {
                    of_contact[c] = i as i64;
                }
            }
            copied(py, &of_contact, &[nc])
        }
        "island_bodies" => {
            let bodies = (0..count).map(|i| {
                let b: Vec<i64> = r.island_bodies_of(i).iter().map(|&b| b as i64).collect();
                copied(py, &b, &[b.len()])
            });
            PyTuple::new(py, bodies)?.into_any()
        }
        "island_lcp_size" => each(|i| i.lcp_size as i64),
        "island_pivots" => each(|i| i.pivots as i64),
        "island_entered" => each(|i| i.entered.map_or(-1, |e| e as i64)),
        "island_residual" => each_f(|i| i.residual),
        "island_body_eta" => each_f(|i| i.body_eta),
        "island_status" => PyTuple::new(py, r.islands.iter().map(|i| i.status.as_str()))?.into_any(),
        "island_stage" => {
            PyTuple::new(py, r.islands.iter().map(|i| i.stage.map_or("none", sim::SolveStage::as_str)))?.into_any()
        }
        _ => return Err(PyAttributeError::new_err(format!("StepRecord has no field {name:?}"))),
    })
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
    let j = t.joints;
    d.set_item("joint_force", shaped(py, t.joint_force, [n, j, 3])?)?;
    d.set_item("joint_torque", shaped(py, t.joint_torque, [n, j, 3])?)?;
    d.set_item("joint_position", shaped(py, t.joint_position, [n, j])?)?;
    d.set_item("joint_error", shaped(py, t.joint_error, [n, j, 2])?)?;
    Ok(d)
}
