//! The solve chain: how one island's LCP is solved. Each stage answers, or
//! passes the island on to the next; the first answer is the island's.
//!
//! ```text
//! previous_basis    the previous step's basis, solved in body space (no pivot, no dense M)
//! guessed_basis     a basis guessed from the previous impulses, solved the same way
//! structured_lemke  Lemke on M = G H + K in sparse factors (first on loaded_friction's sub-LCPs)
//! dense_lemke       the method's solver on the dense M (Lemke: its repair ladder)
//! answer_check      the answer judged once more in body space, re-solved in double-double if it fails
//! ```
//!
//! - [`previous_basis`]: a simulator's LCP changes little from step to step,
//!   and on most steps of a resting scene the previous basis still solves: no
//!   pivot, and `M` never formed.
//! - [`guessed_basis`]: when the previous vertex has drifted a hair
//!   infeasible, a few sweeps of body-space Gauss–Seidel usually land on the
//!   new one, where the dense Lemke would pivot hundreds of times.
//! - [`structured_lemke`]: large islands, whose dense `M` costs too much, and
//!   small ones whose two bases failed; it tries the sub-LCP with friction
//!   only for loaded contacts first ([`loaded_friction`], an exact reduction).
//! - [`dense_lemke`]: the method as the caller chose it; for Lemke its
//!   ladder ends in double-double and exact rungs inside `lcp::lemke`.
//! - [`answer_check`]: an `f64` answer can pass the LCP's acceptance rule and
//!   still be wrong in the velocities of a heavy body on a light one.
//!
//! The first three apply only where [`basis_check_applies`] (the robust Lemke
//! with warm starts); an island of one dynamic body gets only the first. An
//! island solved on its dense `M` (joints, a torsion patch) gets its previous
//! basis solved on that `M` instead ([`dense_previous`]).
//! Which of them apply to an island is written once, in [`IslandLcp::solve`].
//! Where the previous basis comes from: [`warm_starts`] (the previous step's
//! island with the same bodies and contact count) and [`warm_by_contact`]
//! (large islands whose contacts changed). [`replay`] saves the structured
//! stage's problems to files and solves them again.
//!
//! Adding a stage: a file with `attempt(&mut IslandLcp, &Attempt) -> Option<Found>`
//! (a [`stage::Stage`]) and one row, with when it applies, in the list of
//! [`IslandLcp::solve`].

pub(crate) mod answer_check;
mod dense_lemke;
mod dense_loaded;
mod dense_previous;
mod guessed_basis;
pub mod kept_factors;
pub(crate) mod loaded_friction;
mod previous_basis;
pub mod replay;
pub(crate) mod stage;
pub mod stage_name;
pub mod structured_lemke;
pub(crate) mod warm_by_contact;
pub(crate) mod warm_starts;

use crate::contact::{BodyCheck, BodySpaceLcp};
use crate::pipeline::island::{IslandLcp, IslandSolver};
use lcp::operator::LcpOperator;
use lcp::{LemkeOptions, Method, Pivoting, Residuals, Status};
use stage::{Attempt, Found, Stage};
use stage_name::SolveStage;

impl IslandLcp {
    /// Solves the assembled LCP, maps the answer to physical units and
    /// decides the impulses. A failed solve's answer is not applied as it
    /// stands (its last iterate can be anything): `integrate` applies its
    /// admissible part scaled not to add energy (`pipeline::energy`); the
    /// answer is kept for the record.
    ///
    /// With `basis_check` ([`basis_check_applies`]), an island under
    /// [`STRUCTURED_MIN_N`] first tries its previous basis in body space
    /// (from [`PREVIOUS_BASIS_MAX_N`] up only where it stood on the last
    /// step), then, if it couples two or more dynamic bodies (with Lemke's
    /// full ladder, [`BasisCheck::rungs`]), a basis guessed from its previous
    /// impulses ([`guessed_basis`]) and the structured Lemke; the dense `M`
    /// is formed only when all fail (or the island has no previous basis).
    /// `z_prev`: the previous step's physical impulses of this island (empty
    /// when there were none).
    pub fn solve(&mut self, solver: &mut IslandSolver<'_>, basis_check: Option<BasisCheck>, z_prev: &[f64]) {
        let n = self.lcp.n();
        // The last answer's vectors serve this one's (no allocation in a steady step).
        if let Some(old) = self.sol.take() {
            self.basis_ws.recycle([old.z, old.w], old.basis);
        }
        self.error = None;
        self.entered = None;
        self.stage = None;
        let warm = self.warm.take().filter(|b| b.len() == n);
        self.warmed = warm.is_some();
        // Whether the body-space check judges this island's answer (bodies of
        // very different mobilities): the previous basis's answer then gets
        // its last digits, and `check_in_body_space` its check.
        let mixed = self.lcp.dynamic_body_count() >= 2 && BodyCheck::applies(&self.lcp);
        let coupled = self.lcp.dynamic_body_count() >= 2;
        let rungs = coupled && basis_check.is_some_and(|c| c.rungs);
        let size = Size { n, contacts: self.lcp.layout().nc };
        let stages = chain(size, coupled, warm.is_some(), rungs, self.previous_stood);
        let dense = self.dense_only();
        let found = basis_check.and_then(|c| {
            if dense {
                let found = dense_previous::attempt(self, warm.as_deref(), c.accept_tol);
                return found.map(|f| (SolveStage::PreviousBasis, f));
            }
            let a = Attempt {
                warm: warm.as_deref(),
                z_prev,
                accept_tol: c.accept_tol,
                mixed,
                dense_fits: n <= DENSE_FALLBACK_MAX_N,
                previous_tried: stages[0].0,
            };
            stages.iter().filter(|(applies, ..)| *applies).find_map(|&(_, id, stage)| Some((id, stage(self, &a)?)))
        });
        let (stage, Found { sol, physical }) = match found {
            Some(found) => found,
            None => match dense_lemke::solve(self, solver, warm.as_deref()) {
                Ok(sol) => (SolveStage::Dense, Found { sol, physical: None }),
                Err(e) => {
                    self.error = Some(e);
                    return;
                }
            },
        };
        // Physical z, or zeros if the solver's z is unusable — also when
        // undoing the cone scale overflows it: a "solved" z is then no answer.
        self.zeroed = false;
        let mut sol = sol;
        let checked = physical.is_some();
        let usable = match physical {
            Some((z, w)) => {
                (self.z, self.w) = (z, w);
                true
            }
            None => {
                sol.z.len() == n && sol.z.iter().all(|v| v.is_finite()) && {
                    self.lcp.unscale_z(&sol.z, &mut self.z);
                    self.z.iter().all(|v| v.is_finite())
                }
            }
        };
        if !usable {
            if sol.status == Status::Solved {
                sol.status = Status::Numerical;
            }
            self.zeroed = true;
            self.z.clear();
            self.z.resize(n, 0.0);
        }
        // Residuals on the unscaled LCP, in physical units (a body-space
        // answer's w is that of its check).
        if checked {
            // Nothing to form.
        } else if self.lcp.has_matrix() {
            self.lcp.unscaled_w(&self.z, &mut self.w);
        } else {
            self.w.clear();
            self.w.resize(n, 0.0);
            BodySpaceLcp::at_scale(&self.lcp, 1.0).w_of(&self.z, &mut self.w);
        }
        // (At scale 1 a body-space stage's physical z and w are its
        // solution's own, whose residuals it computed.)
        self.residuals = if checked && usable && self.lcp.scale() == 1.0 {
            debug_assert!(self.z == sol.z && self.w == sol.w);
            sol.residuals
        } else {
            Residuals::of(&self.z, &self.w)
        };
        // A physical w that overflows cannot be checked: not solved either.
        if sol.status == Status::Solved && !self.residuals.residual.is_finite() {
            sol.status = Status::Numerical;
        }
        self.body_eta = 0.0;
        if let Some(o) = self.body_check.take() {
            self.check_in_body_space(&mut sol, &o, warm.as_deref(), mixed);
        }
        self.z_apply.clear();
        if sol.status == Status::Solved {
            self.z_apply.extend(self.z.iter().map(|v| v.max(0.0)));
        } else {
            self.zeroed = true;
            self.z_apply.resize(n, 0.0);
        }
        // Positive z_j that the start basis (the warm one, or every w basic) had nonbasic.
        self.entered = (sol.status == Status::Solved).then(|| {
            let outside = |j: usize| warm.as_deref().is_none_or(|b| !b[j]);
            self.z.iter().enumerate().filter(|&(j, &v)| v > 0.0 && outside(j)).count()
        });
        self.sol = Some(sol);
        self.stage = Some(stage);
        self.basis_ws.recycle([], warm);
    }
}

/// The stages before the dense Lemke, in order, each with whether it
/// applies to an island of `n` unknowns: the islands of the robust Lemke with
/// warm starts only; a single body's island only to its previous basis.
/// `stood`: the previous step's island with the same bodies and contact
/// count did not pivot away from its warm basis.
fn chain(size: Size, coupled: bool, warmed: bool, rungs: bool, stood: bool) -> [(bool, SolveStage, Stage); 3] {
    let n = size.n;
    let small = n < STRUCTURED_MIN_N;
    // With the structured Lemke behind it, the previous basis in body space
    // from PREVIOUS_BASIS_MAX_N up only where it stood on the last step.
    // From STOOD_MAX_CONTACTS up not even there: its dense factorization costs more
    // than the structured stage's kept factors.
    let stood_checked = stood && size.contacts < STOOD_MAX_CONTACTS;
    let previous = small && warmed && (!rungs || n < PREVIOUS_BASIS_MAX_N || stood_checked);
    [
        // A small island with a previous basis (a single body's too).
        (previous, SolveStage::PreviousBasis, previous_basis::attempt),
        // The same, with Lemke's full ladder, under GUESSED_MAX_N unknowns.
        (
            small && warmed && rungs && n < guessed_basis::GUESSED_MAX_N,
            SolveStage::GuessedBasis,
            guessed_basis::attempt,
        ),
        // A large coupled island, or a small one whose previous and guessed
        // bases failed (a small island's failure goes on to the dense Lemke).
        (coupled && (!small || (warmed && rungs)), SolveStage::StructuredLemke, structured_lemke::attempt),
    ]
}

/// From this LCP size up, a coupled island (with Lemke's full ladder) whose
/// basis did not stand on the last step — its answer pivoted away from its
/// warm basis, or its bodies or contact count changed — skips the previous basis in body space and
/// goes to the structured Lemke, whose warm run starts from the same basis
/// (on the kept factors when its contacts join the same bodies). On a
/// forming pile that check rarely answers there and its dense factorization
/// of the support and exchange rounds cost more than the structured solve
/// after it: 45-cube pour, seed 0, steps 0–2,000, each island of n < 1,500
/// solved by every variant of the chain on copies (order rotated; docs/heaps.md),
/// the previous basis answered 23 of 106 islands of n = 600–800, 5 of 153 of
/// n = 800–1,000, 1 of 197 of n = 1,000–1,500, and the variants' summed
/// times were, with the guess under 100 unknowns, 10.0 s (previous basis
/// under 1,500), 8.9 s (600), 8.6 s (300), 7.8 s (200), against 11.2 s
/// before (1,500, the guess under 300). Where the basis stood, the check
/// stays: without that exception a resting 10-box stack (n = 400) pivoted
/// 26 times a step instead of 0.2, at a twelfth of its rate; and a cold
/// start's pivots do not count (counted, the 10×10×10 towers' first warm
/// step, 100 islands of n = 400, went to the structured Lemke, 0.93 s, and
/// `many_bodies pile10 300 1` fell from 45.5 to 31 steps/s).
pub const PREVIOUS_BASIS_MAX_N: usize = 200;

/// From this many contacts up, a coupled island (with Lemke's full ladder) skips
/// the previous basis in body space even where its basis stood on the last
/// step: its dense factorization of the support (`k³` for `k` basic
/// unknowns, `k` ≈ 300–400 here) and its exchange rounds cost more than the
/// structured stage, which solves the same warm basis on the island's kept
/// sparse operator and factors ([`kept_factors`]). Measured on the mixed
/// bin (`benchmarks/mjcf_bin.md`, steps 250–1,500, 8 friction directions):
/// islands of n = 1,000–1,500 whose basis stood took the body-space check
/// 341 times, 223 of them in vain (4 ms each, then the structured stage
/// anyway), 0.88 s of the window's 3.1 s; the whole run's user time 3.39 →
/// 1.85 s. Below it the resting stacks and towers (islands of 40 contacts,
/// n = 400) keep their check. Counted in contacts, not unknowns: the support
/// grows with the loaded contacts, whatever the friction directions (the
/// bound was n = 800 at 8 directions, 10 unknowns a contact, and is the
/// same there); at 4 directions (6 unknowns, the bin under MuJoCo's
/// pyramidal cone) n = 800 let islands of up to 133 contacts through: the
/// bin's stood islands of n = 400–800 took the check 1,565 times, 104 of
/// them in vain at 4–11 ms each (0.7 s), and where it answered (0.34 ms)
/// the kept sparse factors answer in 0.21 ms; the run's user time 2.27 →
/// 1.40 s (d4697cf + this, `World.run(2500)`).
pub const STOOD_MAX_CONTACTS: usize = 80;

/// An island's size: its LCP's unknowns and its contacts.
#[derive(Clone, Copy, Debug)]
struct Size {
    n: usize,
    contacts: usize,
}

/// Coupled islands from this LCP size up go to the structured Lemke
/// (`lcp::structured`, see [`structured_lemke`]) when the robust Lemke
/// with warm starts is the method; they skip the body-space check of the
/// previous basis (its dense factorization of the support, `|α|³`, was 48 % of
/// a forming 200-cube heap's time; the structured Lemke's warm run checks the
/// same basis at 0 pivots). Measured on heap LCPs (`structured_scaling`,
/// CPU time of a cold solve): n = 1,120 dense 0.09 s, structured 0.07 s;
/// n = 1,800: 0.73 s, 0.20 s; n = 3,030: 4.9 s, 0.57 s. Below, an island
/// with a warm basis that neither it nor the guessed basis solves in body
/// space goes to the structured Lemke too (its warm run, the loaded-friction
/// sub-LCPs, the guess: [`structured_lemke`]), then to the dense Lemke if
/// that fails. Measured on resting stacks of 4–16 boxes (`stack_steps 2000 4
/// … 16`): pivoting steps 301 → 200, pivots 114,909 → 49,596 against the
/// dense Lemke there. A cold island (no warm basis) stays on the dense Lemke:
/// on the 10×10×10 towers the structured answers of step 0 (each at 0
/// pivots, from its guess) sent the next steps to other vertices and the
/// run from 207 to 123 steps/s (`many_bodies -- pile10 300 1`).
pub const STRUCTURED_MIN_N: usize = 1500;

/// Above this size a failed structured solve is reported as it is: the dense
/// fallback's `M` would take `n²·8` bytes (0.5 GB here).
pub const DENSE_FALLBACK_MAX_N: usize = 8000;

/// Lemke's acceptance bound when the body-space basis check serves `method`:
/// the robust Lemke with warm starts (the classic one starts cold, as the
/// source note's did). A single body's island uses only the previous basis:
/// a sliding cube's step then keeps its factorization instead of forming,
/// equilibrating and refactoring `M` (one step: 149k → 31k instructions;
/// answers within 3e-13 m of the dense path's). It does so whether or not an
/// LCP sink is attached (the sink gets `M` formed for it), so a captured run
/// is the uncaptured one.
pub fn basis_check_applies(method: &Method) -> Option<BasisCheck> {
    match method {
        Method::Lemke(LemkeOptions {
            pivoting: Pivoting::Lexicographic,
            warm_start: true,
            accept_tol,
            fallback,
            ..
        }) => Some(BasisCheck { accept_tol: *accept_tol, rungs: *fallback }),
        _ => None,
    }
}

/// What a coupled island tries before the dense Lemke ([`basis_check_applies`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasisCheck {
    /// Lemke's acceptance bound.
    pub accept_tol: f64,
    /// Whether a failed previous basis under [`STRUCTURED_MIN_N`] is followed
    /// by the guessed basis and the structured Lemke: with Lemke's full ladder
    /// (`fallback`) only, so that its first rung alone stays one rung.
    pub rungs: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At 8 friction directions: 10 unknowns a contact.
    fn applies(n: usize, coupled: bool, rungs: bool, stood: bool) -> Vec<SolveStage> {
        applies_sized(Size { n, contacts: n / 10 }, coupled, rungs, stood)
    }

    fn applies_sized(size: Size, coupled: bool, rungs: bool, stood: bool) -> Vec<SolveStage> {
        chain(size, coupled, true, rungs, stood).iter().filter(|s| s.0).map(|s| s.1).collect()
    }

    /// A large coupled island whose answer pivoted on the last step goes to
    /// the structured Lemke without the body-space check of its previous
    /// basis; one whose basis stood (a resting pile) keeps that check up to
    /// `STOOD_MAX_CONTACTS`, and so do a single body and an island without the
    /// structured Lemke behind it.
    #[test]
    fn the_previous_basis_is_checked_where_it_stood_or_the_island_is_small() {
        use SolveStage::*;
        let n = PREVIOUS_BASIS_MAX_N + 100;
        assert_eq!(applies(n, true, true, false), [StructuredLemke]);
        assert_eq!(applies(n, true, true, true), [PreviousBasis, StructuredLemke]);
        assert_eq!(applies(n, false, false, false), [PreviousBasis]);
        assert_eq!(applies(n, true, false, false), [PreviousBasis]);
        assert_eq!(
            applies(guessed_basis::GUESSED_MAX_N - 1, true, true, false),
            [PreviousBasis, GuessedBasis, StructuredLemke]
        );
        assert_eq!(applies(PREVIOUS_BASIS_MAX_N - 1, true, true, false), [PreviousBasis, StructuredLemke]);
        assert_eq!(applies(STRUCTURED_MIN_N, true, true, true), [StructuredLemke]);
        assert_eq!(applies(10 * STOOD_MAX_CONTACTS, true, true, true), [StructuredLemke]);
        assert_eq!(applies(10 * STOOD_MAX_CONTACTS - 10, true, true, true), [PreviousBasis, StructuredLemke]);
    }

    /// The stood island's bound counts contacts: at 4 friction directions (6
    /// unknowns a contact) an island of as many contacts skips the check at
    /// 6/10 of the unknowns.
    #[test]
    fn the_stood_bound_counts_contacts_whatever_the_friction_directions() {
        use SolveStage::*;
        let at = |contacts| Size { n: 6 * contacts, contacts };
        assert_eq!(applies_sized(at(STOOD_MAX_CONTACTS), true, true, true), [StructuredLemke]);
        assert_eq!(applies_sized(at(STOOD_MAX_CONTACTS - 1), true, true, true), [PreviousBasis, StructuredLemke]);
    }
}
