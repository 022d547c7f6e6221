//! What a stage of the solve chain sees ([`Attempt`]) and what it answers
//! ([`Found`]); every stage before the dense Lemke is a [`Stage`].

use crate::pipeline::island::IslandLcp;
use lcp::Solution;

/// Physical `z` and `w` of an island's answer.
pub(crate) type PhysicalZw = (Vec<f64>, Vec<f64>);

/// What a stage knows of the island's solve besides the island itself.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Attempt<'a> {
    /// The basis the island starts from (the previous step's answer), if any.
    pub warm: Option<&'a [bool]>,
    /// The previous step's physical impulses of this island (empty when there were none).
    pub z_prev: &'a [f64],
    /// Lemke's acceptance bound.
    pub accept_tol: f64,
    /// Whether the answer check will judge the answer (bodies of very
    /// different mobilities, `contact::BodyCheck::applies`): a body-space
    /// answer then gets its last digits.
    pub mixed: bool,
    /// Whether the dense Lemke's `M` would fit (else a failed answer is kept as it is).
    pub dense_fits: bool,
    /// Whether the previous-basis stage tried the warm basis before.
    pub previous_tried: bool,
}

/// A stage's answer: the solution of the LCP as scaled, and, when the stage
/// checked it in physical units, the physical `z` and `w` it checked.
#[derive(Clone, Debug)]
pub(crate) struct Found {
    pub sol: Solution,
    pub physical: Option<PhysicalZw>,
}

/// A stage before the dense Lemke: an answer, or `None` to pass the island on.
pub(crate) type Stage = fn(&mut IslandLcp, &Attempt<'_>) -> Option<Found>;
