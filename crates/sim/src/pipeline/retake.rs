//! Retaking a failed step in parts: when an island's LCP fails and
//! `WorldParams::max_halvings` allows, the step (or the part of it being
//! taken) is taken again from its start as two parts of `h/2`, each of which
//! may be halved again. Every part solves its own exact LCP: nothing about the
//! problem is relaxed. A smaller `h` changes `q` (the free velocities and the
//! stabilization term) and with it Lemke's path, which is what rescues the
//! LCPs of a forming heap that fail from every start at the full step (README,
//! "Many bodies": the 200-cube heap).
//!
//! A failed attempt leaves nothing behind: bodies move only in `integrate`,
//! which it never reaches, and the warm starts and the record its solve
//! consumed are put back as they were at its start, so that its first half
//! starts from what it started from.

use super::energy::EnergyAudit;
use super::record::{Retake, StepRecord};
use crate::solve_chain::warm_starts::WarmStarts;
use lcp::Status;

/// What the parts of the step being taken add up to, and the state a part
/// that may still be retaken started from.
#[derive(Default)]
pub(crate) struct Parts {
    /// Warm starts and record at the start of the part being solved (kept
    /// only when it may be retaken).
    warm: WarmStarts,
    record: StepRecord,
    /// Parts integrated, pivots of every attempt, failed attempts.
    count: usize,
    pivots: usize,
    retakes: Vec<Retake>,
    /// Energy over the parts integrated so far.
    energy: Option<EnergyAudit>,
    /// The first integrated part left failed (no halvings left), and whether any applied a fallback.
    failed: Option<Status>,
    zeroed: bool,
}

impl Parts {
    /// Forgets the previous step's parts.
    pub fn begin(&mut self) {
        self.count = 0;
        self.pivots = 0;
        self.retakes.clear();
        self.energy = None;
        self.failed = None;
        self.zeroed = false;
    }

    /// Keeps what a part's solve will consume, in case it has to be retaken.
    pub fn keep_start(&mut self, warm: &WarmStarts, record: &StepRecord) {
        self.warm.clone_from(warm);
        self.record.clone_from(record);
    }

    /// Records the failed attempt of length `h` that `record` describes and
    /// puts back the warm starts and record it started from.
    pub fn undo_failed(&mut self, warm: &mut WarmStarts, record: &mut StepRecord, h: f64) {
        self.pivots += record.pivots;
        // the failed record is dropped below (its buffers become the kept start's): its islands move out
        let islands = std::mem::take(&mut record.islands);
        self.retakes.push(Retake { time: record.time, h, pivots: record.pivots, islands });
        std::mem::swap(warm, &mut self.warm);
        std::mem::swap(record, &mut self.record);
    }

    /// Adds an integrated part (its record's pivots, energy and failure).
    pub fn add(&mut self, record: &StepRecord) {
        self.count += 1;
        self.pivots += record.pivots;
        if !record.ok() && self.failed.is_none() {
            self.failed = record.status;
        }
        self.zeroed |= record.zeroed;
        self.energy = Some(self.energy.map_or(record.energy, |s| s.then(record.energy)));
    }

    /// Writes the step's totals into the last part's record: its index, the
    /// parts, every attempt's pivots, the retakes, the whole step's energy,
    /// and a failure of any part (the step is solved only if every part was).
    pub fn finish(&mut self, record: &mut StepRecord, step: u64) {
        record.step = step;
        if record.ok() && self.failed.is_some() {
            record.status = self.failed;
        }
        record.zeroed |= self.zeroed;
        record.parts = self.count;
        record.pivots = self.pivots;
        record.retakes.clear();
        record.retakes.append(&mut self.retakes);
        if let Some(e) = self.energy {
            record.energy = e;
        }
    }
}
