//! The buffers of [`super::solve_on_basis`], reused across calls by their
//! owner: they keep the last factorization (and a copy held aside while
//! exchanges are tried) and count the calls in a row that found nothing.

/// Buffers of [`solve_on_basis`](super::solve_on_basis), reused across calls by their owner; they
/// also keep the last factorization for the next call.
#[derive(Clone, Debug, Default)]
pub struct BasisWorkspace {
    /// Which `z_j` are basic in the basis being tried.
    pub(super) mask: Vec<bool>,
    /// Support `S` (basic `z` indices) of the factorization.
    pub(super) support: Vec<usize>,
    /// `M_SS`, factored in place by [`principal::factor`](super::principal::factor) (row-major).
    pub(super) lu: Vec<f64>,
    /// The block `M_SS` of the last fresh factorization of this call, unfactored,
    /// and its support ([`form_block`](super::factors::form_block)); `blocked` is false at a call's start.
    pub(super) block: Vec<f64>,
    pub(super) block_support: Vec<usize>,
    pub(super) blocked: bool,
    /// Scratch of [`form_block`](super::factors::form_block): each index's position in `block_support`
    /// ([`NOT_IN_BLOCK`](super::factors::NOT_IN_BLOCK) between calls), the block before, the new indices' entries.
    pub(super) block_pos: Vec<usize>,
    pub(super) block_prev: Vec<f64>,
    pub(super) block_fresh: Vec<f64>,
    /// Pivot order (positions in `S`) and rank: `β = S[order[..rank]]`.
    pub(super) order: Vec<usize>,
    pub(super) rank: usize,
    /// `β` as a mask when `lu` holds its factors (empty when it does not).
    pub(super) factored: Vec<bool>,
    /// Right-hand side and solution, by position in `S`.
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    /// `z` and `w` of a candidate in the operator's units, and in the other units.
    pub(super) z: Vec<f64>,
    pub(super) w: Vec<f64>,
    pub(super) z2: Vec<f64>,
    pub(super) w2: Vec<f64>,
    /// The factorization of the answer held while exchanges are tried.
    pub(super) held: HeldFactors,
    /// The factors [`border`](super::factors::border) grew from, their buffers kept for the next exchange.
    pub(super) grown_from: HeldFactors,
    /// A basis whose exchanges found nothing better than its answer, and the
    /// violation below which they are not tried again from it.
    pub(super) retry: Option<(Vec<bool>, f64)>,
    /// Columns of each row kept for the acceptance rule's bounds
    /// ([`crate::accept::rejected_row_operator`]), in `op`'s units and in the other ones.
    pub(super) kept: Vec<crate::accept::KeptColumns>,
    pub(super) kept_other: Vec<crate::accept::KeptColumns>,
    /// The indices exchanged in the current call.
    pub(super) toggled: Vec<usize>,
    /// Basic indices whose `z` was negative before clipping, with that value.
    pub(super) clipped: Vec<(usize, f64)>,
    /// One row of `M` (see [`clipped_cause`](super::rounds::clipped_cause)).
    pub(super) row: Vec<f64>,
    /// Calls in a row that found no answer (the caller pivoted).
    pub(super) failures: usize,
}

/// A copy of [`BasisWorkspace`]'s factorization fields (also the factors
/// [`border`](super::factors::border) grows): packed LU of `principal::factor` (row-major,
/// `support.len()` square), support, pivot order, rank, and `β` as a mask.
#[derive(Clone, Debug, Default)]
pub(super) struct HeldFactors {
    pub(super) support: Vec<usize>,
    pub(super) lu: Vec<f64>,
    pub(super) order: Vec<usize>,
    pub(super) rank: usize,
    pub(super) factored: Vec<bool>,
}

impl BasisWorkspace {
    /// Copies the current factorization aside.
    pub(super) fn hold_factors(&mut self) {
        let h = &mut self.held;
        h.support.clone_from(&self.support);
        h.lu.clone_from(&self.lu);
        h.order.clone_from(&self.order);
        h.rank = self.rank;
        h.factored.clone_from(&self.factored);
    }

    /// Makes the factorization copied aside the current one again.
    pub(super) fn restore_factors(&mut self) {
        let mut held = std::mem::take(&mut self.held);
        self.swap_factors(&mut held);
        self.held = held;
    }

    /// Exchanges the current factorization, buffers and all, with `h`.
    pub(super) fn swap_factors(&mut self, h: &mut HeldFactors) {
        std::mem::swap(&mut h.support, &mut self.support);
        std::mem::swap(&mut h.lu, &mut self.lu);
        std::mem::swap(&mut h.order, &mut self.order);
        std::mem::swap(&mut h.rank, &mut self.rank);
        std::mem::swap(&mut h.factored, &mut self.factored);
    }

    /// Forgets the kept factorization (the next call factors afresh).
    pub fn forget(&mut self) {
        self.factored.clear();
    }

    /// Forgets the calls that found nothing: the next call tries every
    /// exchange round (for a caller whose other rungs failed, where time
    /// matters less than an answer).
    pub fn forget_failures(&mut self) {
        self.failures = 0;
    }

    /// Runs `attempt` (calls from a basis other than the previous answer's)
    /// with every exchange round; if it finds nothing, the count of failed
    /// calls is left as it was, so the back-off of the calls from the
    /// previous answer's basis goes on.
    pub fn fresh_attempt<R>(&mut self, attempt: impl FnOnce(&mut Self) -> Option<R>) -> Option<R> {
        let failures = self.failures;
        self.failures = 0;
        let found = attempt(self);
        if found.is_none() {
            self.failures = failures;
        }
        found
    }
}
