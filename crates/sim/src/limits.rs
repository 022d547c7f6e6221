//! The simulator's size limits, checked before anything is allocated (the
//! sizes and the memory behind them are `lcp::limits`'s):
//!
//! - friction directions per contact: at most
//!   [`crate::contact::friction::MAX_FRICTION_DIRS`];
//! - bodies in a scene: at most [`MAX_SCENE_BODIES`], and a scene whose bodies
//!   would settle into one contact island (a stack, a heap) is refused when
//!   that island's dense LCP could not fit in memory;
//! - every step: each island's dense LCP is checked, then reserved with
//!   `try_reserve`, so an island too large for memory is a [`SimError::TooLarge`]
//!   naming its size and the memory it needs, never an abort.

use crate::error::SimError;
use lcp::limits::{check_dense, SizeError};

/// The deepest a failed step is halved (`WorldParams::max_halvings`): parts of `h/1024`.
pub const MAX_HALVINGS: u32 = 10;

/// [`MAX_HALVINGS`]'s range as an error message spells it (a test holds the two together).
pub const HALVINGS_RANGE: &str = "[0, 10]";

/// The most bodies a scene builds.
pub const MAX_SCENE_BODIES: usize = 1_000_000;

/// Contacts of one box resting on a face: its four corners.
pub const CONTACTS_PER_RESTING_BOX: usize = 4;

/// Unknowns of a contact LCP of `contacts` contacts with `k` directions
/// (`None` if that overflows).
pub fn lcp_size(contacts: usize, k: usize) -> Option<usize> {
    contacts.checked_mul(k.checked_add(2)?)
}

/// Refuses a contact LCP of `contacts` contacts whose dense matrix cannot fit in memory.
pub fn check_contact_lcp(what: impl FnOnce() -> String, contacts: usize, k: usize) -> Result<(), SimError> {
    let n = lcp_size(contacts, k).unwrap_or(usize::MAX);
    check_dense(
        || {
            format!(
                "{}: a contact LCP of {contacts} contacts × (k + 2 = {}) = {n} unknowns",
                what(),
                k.saturating_add(2)
            )
        },
        n,
        1,
    )
    .map_err(SimError::TooLarge)
}

/// A scene's body count `count` (`None`: it overflowed) checked against
/// [`MAX_SCENE_BODIES`], and the island that `one_island` of its boxes form
/// when they rest on one another checked against memory.
/// `requested` is the count as a float, for the message when `count` overflowed.
pub fn check_scene(
    scene: &str,
    field: &'static str,
    (count, requested): (Option<usize>, f64),
    one_island: usize,
    k: usize,
) -> Result<usize, SimError> {
    let count = match count {
        Some(c) if c <= MAX_SCENE_BODIES => c,
        _ => return Err(SimError::OutOfRange { field, value: requested, range: "[1, 1000000] bodies" }),
    };
    let contacts = one_island.saturating_mul(CONTACTS_PER_RESTING_BOX);
    check_contact_lcp(|| format!("{scene} ({one_island} boxes resting on one another)"), contacts, k)?;
    Ok(count)
}

impl From<SizeError> for SimError {
    fn from(e: SizeError) -> Self {
        SimError::TooLarge(e)
    }
}

/// Bytes a trajectory keeps per step and body (position 3, orientation 4,
/// velocity 3, angular velocity 3 floats) and per step (the step's scalars).
const TRAJECTORY_BODY_BYTES: u128 = 13 * 8;
const TRAJECTORY_STEP_BYTES: u128 = 16 * 8;
/// Per step and joint: force 3, torque 3, coordinate 1, errors 2 floats.
const TRAJECTORY_JOINT_BYTES: u128 = 9 * 8;

/// Refuses a run of `steps` steps of `bodies` bodies and `joints` joints
/// whose trajectory cannot fit in memory.
pub fn check_trajectory(steps: usize, bodies: usize, joints: usize) -> Result<(), SimError> {
    let per_step = (bodies as u128)
        .saturating_mul(TRAJECTORY_BODY_BYTES)
        .saturating_add((joints as u128).saturating_mul(TRAJECTORY_JOINT_BYTES))
        .saturating_add(TRAJECTORY_STEP_BYTES);
    lcp::limits::check_bytes(
        || format!("a trajectory of {steps} steps of {bodies} bodies"),
        per_step.saturating_mul(steps as u128),
    )
    .map_err(SimError::TooLarge)
}
