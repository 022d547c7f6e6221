//! Which stage of the solve chain answered an island: the name recorded
//! per island and counted per step.

/// The stage of the solve chain whose answer an island took, as recorded
/// (`IslandRecord::stage`, `Trajectory::stage_counts`, Python's `STAGES`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolveStage {
    /// The previous step's basis (kept by island, or mapped contact by contact), solved in body space.
    PreviousBasis,
    /// A basis read from body-space projected Gauss–Seidel sweeps, solved in body space.
    GuessedBasis,
    /// The structured (sparse, body-space) Lemke.
    StructuredLemke,
    /// The world's method on the dense `M`: for the robust Lemke its warm
    /// run, then its whole repair ladder (cold runs, double-double and exact
    /// arithmetic) — the backstop. Single-body islands always come here.
    Dense,
}

impl SolveStage {
    /// Every stage, in chain order.
    pub const ALL: [SolveStage; 4] =
        [SolveStage::PreviousBasis, SolveStage::GuessedBasis, SolveStage::StructuredLemke, SolveStage::Dense];

    /// Its name in records and in Python.
    pub fn as_str(self) -> &'static str {
        match self {
            SolveStage::PreviousBasis => "previous_basis",
            SolveStage::GuessedBasis => "guessed_basis",
            SolveStage::StructuredLemke => "structured_lemke",
            SolveStage::Dense => "dense",
        }
    }

    /// Its position in [`SolveStage::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}
