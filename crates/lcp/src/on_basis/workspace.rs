//! The buffers of [`super::solve_on_basis`], reused across calls by their
//! owner: they keep the last factorization (and a copy held aside while
//! exchanges are tried) and count the calls in a row that found nothing.

/// Buffers of [`solve_on_basis`](super::solve_on_basis), reused across calls by their owner; they
/// also keep the last factorization for the next call.
#[derive(Clone, Debug, Default)]
pub struct BasisWorkspace {
    /// Which `z_j` are basic in the basis being tried.
    pub(super) mask: Vec<bool>,
    /// The factorization of `M_SS` (the last one, kept for the next call).
    pub(super) f: Factors,
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
    /// Scratch of [`form_block`](super::factors::form_block): the new indices' positions in the support, and the indices.
    pub(super) fresh_at: Vec<usize>,
    /// Scratch of [`form_block`](super::factors::form_block): the runs of the new support whose columns
    /// are consecutive in the block before (start in the new support, in the old, length).
    pub(super) block_runs: Vec<(usize, usize, usize)>,
    pub(super) fresh: Vec<usize>,
    /// The indices of `β`, the rows a refinement step reads.
    pub(super) rows: Vec<usize>,
    /// Right-hand side and solution, by position in `S`.
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    /// `z` and `w` of a candidate in the operator's units, and in the other units.
    pub(super) z: Vec<f64>,
    pub(super) w: Vec<f64>,
    pub(super) z2: Vec<f64>,
    pub(super) w2: Vec<f64>,
    /// `‖q‖∞` of the operator of the current call, and the residuals of
    /// `z`, `w` as [`within_both`](super::check::within_both) last formed them.
    pub(super) q_norm: f64,
    pub(super) residuals: crate::solution::Residuals,
    /// The factorization of the answer held while exchanges are tried.
    pub(super) held: Factors,
    /// The factors [`border`](super::factors::border) grew from, their buffers kept for the next exchange.
    pub(super) grown_from: Factors,
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
    /// The same indices with the change clipping made (`−z_j`).
    pub(super) moved: Vec<(usize, f64)>,
    /// One row of `M` (see [`clipped_cause`](super::rounds::clipped_cause); the acceptance rule's full reads).
    pub(super) row: Vec<f64>,
    /// Calls in a row that found no answer (the caller pivoted).
    pub(super) failures: usize,
    /// Vectors of earlier answers handed back ([`BasisWorkspace::recycle`]):
    /// an answer's vectors come from them, so a steady caller allocates none.
    pub(super) spare: Spare,
}

/// Buffers handed back by the caller, at most [`SPARE_MAX`] of each kind.
#[derive(Clone, Debug, Default)]
pub(super) struct Spare {
    pub(super) values: Vec<Vec<f64>>,
    pub(super) masks: Vec<Vec<bool>>,
}

/// Spare vectors kept of each kind: an answer takes at most four
/// (`z`, `w` and the same in the other units) and one basis.
const SPARE_MAX: usize = 4;

impl Spare {
    /// `v` moved out, a spare vector left in its place (its values stale).
    pub(super) fn take(&mut self, v: &mut Vec<f64>) -> Vec<f64> {
        std::mem::replace(v, self.values.pop().unwrap_or_default())
    }

    /// A copy of `v` in a spare vector.
    pub(super) fn copy(&mut self, v: &[f64]) -> Vec<f64> {
        let mut c = self.values.pop().unwrap_or_default();
        c.clear();
        c.extend_from_slice(v);
        c
    }

    /// A copy of `mask` in a spare vector.
    pub(super) fn copy_mask(&mut self, mask: &[bool]) -> Vec<bool> {
        let mut c = self.masks.pop().unwrap_or_default();
        c.clear();
        c.extend_from_slice(mask);
        c
    }
}

/// A factorization of a block `M_SS`: the workspace's current one, the one
/// held aside while exchanges are tried, or the one [`border`](super::factors::border) grows.
#[derive(Clone, Debug, Default)]
pub(super) struct Factors {
    /// Support `S` (basic `z` indices) of the factorization.
    pub(super) support: Vec<usize>,
    /// `M_SS`, factored in place by [`principal::factor`](super::principal::factor)
    /// (packed LU, row-major, `support.len()` square).
    pub(super) lu: Vec<f64>,
    /// Pivot order (positions in `S`) and rank: `β = S[order[..rank]]`.
    pub(super) order: Vec<usize>,
    pub(super) rank: usize,
    /// `β` as a mask when `lu` holds its factors (empty when it does not).
    pub(super) factored: Vec<bool>,
    /// `M_ββ⁻¹` formed from `lu` ([`principal::inverse`](super::principal::inverse)) and its error
    /// bound, once a kept factorization's refinement reads it; `None`
    /// until then (and whenever `lu` changes).
    pub(super) inverse: Option<f64>,
    pub(super) inv: Vec<f64>,
}

impl Factors {
    /// Copies `other` into `self`, reusing `self`'s buffers.
    fn copy_from(&mut self, other: &Factors) {
        self.support.clone_from(&other.support);
        self.lu.clone_from(&other.lu);
        self.order.clone_from(&other.order);
        self.rank = other.rank;
        self.factored.clone_from(&other.factored);
        self.inverse = other.inverse;
        if other.inverse.is_some() {
            self.inv.clone_from(&other.inv);
        }
    }
}

impl BasisWorkspace {
    /// `rows` ← the indices of `β`, the factored regular block, in pivot
    /// order (the rows a refinement step reads).
    pub(super) fn basic_rows(&mut self) {
        let BasisWorkspace { rows, f, .. } = self;
        rows.clear();
        rows.extend(f.order[..f.rank].iter().map(|&p| f.support[p]));
    }

    /// Copies the current factorization aside.
    pub(super) fn hold_factors(&mut self) {
        self.held.copy_from(&self.f);
    }

    /// Makes the factorization copied aside the current one again.
    pub(super) fn restore_factors(&mut self) {
        let mut held = std::mem::take(&mut self.held);
        self.swap_factors(&mut held);
        self.held = held;
    }

    /// Exchanges the current factorization, buffers and all, with `h`.
    pub(super) fn swap_factors(&mut self, h: &mut Factors) {
        std::mem::swap(h, &mut self.f);
    }

    /// Takes back vectors of an earlier answer (its `z`, `w`, basis, or
    /// any other the caller is done with) for the next answers' (beyond a
    /// few of each kind they are dropped).
    pub fn recycle(&mut self, values: impl IntoIterator<Item = Vec<f64>>, masks: impl IntoIterator<Item = Vec<bool>>) {
        // (A vector that never held anything would only be replaced.)
        for v in values {
            if v.capacity() > 0 && self.spare.values.len() < SPARE_MAX {
                self.spare.values.push(v);
            }
        }
        for m in masks {
            if m.capacity() > 0 && self.spare.masks.len() < SPARE_MAX {
                self.spare.masks.push(m);
            }
        }
    }

    /// Takes back the vectors of an answer not returned.
    pub(super) fn recycle_answer(&mut self, a: super::BasisAnswer) {
        let (z2, w2) = a.other.unwrap_or_default();
        let s = a.solution;
        self.recycle([s.z, s.w, z2, w2], s.basis);
    }

    /// Forgets the kept factorization (the next call factors afresh).
    pub fn forget(&mut self) {
        self.f.factored.clear();
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
