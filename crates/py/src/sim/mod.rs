//! Bindings of the `sim` crate: `World` (a `sim::World` behind a mutex, so the
//! class is `Sync`), its step records (fields converted when read) and
//! trajectories as dicts of numpy
//! arrays, scenes and LCP capture.
//!
//! `run` releases the GIL; any `SimError` is a `ValueError` naming the field
//! and value; a panic in the core is caught and becomes a `RuntimeError`.
//!
//! - [`world`]: the `World` class (bodies, forces, stepping, capture);
//! - [`params`]: world parameters to and from dicts, and the body defaults;
//! - [`records`]: step records read field by field, trajectories as dicts of arrays;
//! - [`scenes`]: the scene builders; [`capture`]: the LCP capture buffer;
//! - [`convert`]: Python values to the core's, with the validation messages.

mod capture;
mod convert;
mod params;
mod records;
mod scenes;
mod world;

pub use convert::MU_COMBINE;
pub use params::{body_defaults, params_dict};
pub use records::PyStepRecord;
pub use scenes::{build_scene, defaults as scene_defaults, SCENES};
pub use world::World;
