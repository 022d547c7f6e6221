//! `StepRecord`: what one step did — contacts, the LCP's size and outcome,
//! residuals in physical units, and the impulses per contact.

use crate::contact::FrictionBasis;
use crate::geometry::Contact;
use crate::math::Vec3;
use lcp::contact::ZeroLevels;
use lcp::{ContactLayout, Residuals, Status};

/// The record of one step. Its buffers are reused from step to step; clone
/// it to keep it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepRecord {
    /// Index of the step (0 for the first).
    pub step: u64,
    /// Time at the start of the step (s).
    pub time: f64,
    /// Time step `h` (s).
    pub dt: f64,
    /// Contacts that entered the LCP, in LCP order.
    pub contacts: Vec<Contact>,
    /// Friction directions per contact `k`.
    pub friction_dirs: usize,
    /// LCP size `nc·(k + 2)` (0 without contacts).
    pub lcp_size: usize,
    /// Friction-cone scale `s` of the LCP that was solved.
    pub scale: f64,
    /// How the solve ended; `None` when there was no contact (nothing solved).
    pub status: Option<Status>,
    /// Pivots (Lemke) or iterations (iterative solvers).
    pub pivots: usize,
    /// Residuals of the physical `z` on the unscaled (`s = 1`) LCP.
    pub residuals: Residuals,
    /// Residuals as the solver reported them (scaled LCP).
    pub solver_residuals: Residuals,
    /// The solve failed (status other than solved, or a `z` of the wrong
    /// length or not finite): the solver's answer was not applied; the
    /// failed-solve policy (`pipeline::energy`) applied its admissible part,
    /// scaled so that the step adds no energy (zero for an unusable `z`).
    pub zeroed: bool,
    /// Energy before and after the step and the work of the applied forces
    /// (`created()`: energy the step added; see `pipeline::energy`).
    pub energy: super::energy::EnergyAudit,
    /// Physical `z = [fn (nc); fd (nc·k); λ (nc)]` (N·s; λ in m/s), `λ = s·λ_scaled`.
    pub z: Vec<f64>,
    /// `w = M₁ z + q` of the unscaled LCP: normal velocities, tangential velocities + λ, cone slacks.
    pub w: Vec<f64>,
    /// Lemke's final complementary basis (which `z_j` were basic, global
    /// layout), when the solver reported one for every island.
    pub basis: Option<Vec<bool>>,
    /// The contact islands, each solved as its own LCP, in the order of their
    /// first contact (how `status`, `pivots` and the residuals summarise
    /// them: `pipeline::solve`).
    pub islands: Vec<IslandRecord>,
    /// Each joint's reaction over the step (`JointId` order; empty without joints).
    pub joints: Vec<crate::joints::JointReaction>,
    /// Dynamic bodies of every island, island after island (see [`IslandRecord::bodies`]).
    pub island_bodies: Vec<usize>,
    /// Contact indices of every island, island after island (see [`IslandRecord::contacts`]).
    pub island_contacts: Vec<usize>,
    /// Parts the step was taken in: 1, or more when a failed LCP had a part
    /// taken again in halves (`WorldParams::max_halvings`). Then the fields
    /// above (`time`, `dt`, contacts, impulses, islands) are the last part's,
    /// except that `status` and `zeroed` tell a failure left in any part (the
    /// step is solved only if every part was), `pivots` counts every attempt
    /// and `energy` spans the whole step.
    pub parts: usize,
    /// The attempts that failed and were taken again in halves, in the order they were made.
    pub retakes: Vec<Retake>,
}

/// An attempt at (a part of) a step whose LCP failed, taken again as two parts of `h/2`.
#[derive(Clone, Debug, PartialEq)]
pub struct Retake {
    /// Its start (s) and its `h` (s).
    pub time: f64,
    pub h: f64,
    /// Pivots of its solves.
    pub pivots: usize,
    /// Its islands, as they ended (at least one not solved).
    pub islands: Vec<IslandRecord>,
}

impl Retake {
    /// Its islands that were not solved.
    pub fn unsolved(&self) -> impl Iterator<Item = &IslandRecord> {
        self.islands.iter().filter(|i| i.status != Status::Solved)
    }
}

/// One island of a step: which bodies and contacts, and how its LCP went.
#[derive(Clone, Debug, PartialEq)]
pub struct IslandRecord {
    /// Range of [`StepRecord::island_bodies`] holding its dynamic bodies (ascending).
    pub bodies: std::ops::Range<usize>,
    /// Range of [`StepRecord::island_contacts`] holding its contacts (indices into
    /// `StepRecord::contacts`, ascending; they are its LCP's contacts in order).
    pub contacts: std::ops::Range<usize>,
    /// Its LCP's size, `contacts·(k + 2)`.
    pub lcp_size: usize,
    pub status: Status,
    /// Pivots (Lemke) or iterations.
    pub pivots: usize,
    /// Natural residual of its physical `z` on its unscaled LCP.
    pub residual: f64,
    /// Natural residual as the solver reported it (scaled LCP).
    pub solver_residual: f64,
    /// Body-space backward error of its applied answer (`contact::body_rule`:
    /// each contact row on the scale of the velocities it relates); 0 when not
    /// checked (another method than the robust Lemke, or a failed solve).
    pub body_eta: f64,
    /// The solver's answer was not applied (failed solve or unusable `z`):
    /// the failed-solve policy was (see `StepRecord::zeroed`).
    pub zeroed: bool,
    /// The solve started from the previous step's basis of the same island.
    pub warm: bool,
    /// When solved: how many `z_j` are positive in the answer that the basis
    /// the solve started from (the previous step's, or every `w_j` basic)
    /// had nonbasic. Each had to enter the basis, and a complementary pivot
    /// brings one variable in, so any pivoting run from that start to that
    /// answer takes at least this many pivots: the distance the island had
    /// to go, beside `pivots`, the way it went (`pivots` can be fewer when a
    /// basis guessed from the previous impulses was the start that solved).
    pub entered: Option<usize>,
    /// The stage of the solve chain that answered (`None` if nothing was solved).
    pub stage: Option<crate::solve_chain::stage_name::SolveStage>,
}

impl StepRecord {
    /// Dynamic bodies of island `i`.
    pub fn island_bodies_of(&self, i: usize) -> &[usize] {
        &self.island_bodies[self.islands[i].bodies.clone()]
    }

    /// Contacts (indices into `contacts`) of island `i`.
    pub fn island_contacts_of(&self, i: usize) -> &[usize] {
        &self.island_contacts[self.islands[i].contacts.clone()]
    }

    /// Number of contacts.
    pub fn nc(&self) -> usize {
        self.contacts.len()
    }

    /// Where `fn`, `fd`, `λ` of each contact live in `z`.
    pub fn layout(&self) -> ContactLayout {
        ContactLayout::new(self.nc(), self.friction_dirs)
    }

    /// `true` when there was no LCP or it was solved.
    pub fn ok(&self) -> bool {
        matches!(self.status, None | Some(Status::Solved))
    }

    /// Normal impulses `fn` (N·s), one per contact.
    pub fn normal_impulses(&self) -> &[f64] {
        &self.z[..self.nc()]
    }

    /// Friction impulses `fd` (N·s), contact-major: `[i·k + j]` is contact `i` along `d_j`.
    pub fn friction_impulses(&self) -> &[f64] {
        &self.z[self.layout().fd_range()]
    }

    /// Friction impulses of contact `i` (length `k`).
    pub fn friction_of(&self, i: usize) -> &[f64] {
        &self.z[self.layout().fd_of(i)]
    }

    /// `λ` per contact in physical units (≈ sliding speed, m/s).
    pub fn lambdas(&self) -> &[f64] {
        &self.z[self.layout().lambda_range()]
    }

    /// Sum of the normal impulses (N·s).
    pub fn total_normal_impulse(&self) -> f64 {
        self.normal_impulses().iter().sum()
    }

    /// Friction impulse of contact `i` as a vector, `Σ_j fd_j d_j` (acting on body A).
    pub fn friction_impulse(&self, i: usize) -> Vec3 {
        let c = &self.contacts[i];
        let basis = FrictionBasis::new(self.friction_dirs);
        self.friction_of(i)
            .iter()
            .enumerate()
            .map(|(j, &f)| basis.direction(c.normal, c.tangent, j) * f)
            .fold(Vec3::ZERO, |a, b| a + b)
    }

    /// Total contact impulse on body A of all contacts, `Σ (n fn + Σ d_j fd_j)`.
    pub fn total_impulse(&self) -> Vec3 {
        (0..self.nc())
            .map(|i| self.contacts[i].normal * self.z[i] + self.friction_impulse(i))
            .fold(Vec3::ZERO, |a, b| a + b)
    }

    /// The source note's contact pattern of contact `i`: whether `fn`, `Σ fd`, `λ`
    /// exceed `zero` (`ContactLayout::pattern` with one absolute threshold).
    pub fn pattern(&self, i: usize, zero: f64) -> [bool; 3] {
        let p = self.layout().pattern(&self.z, i, ZeroLevels::absolute(zero));
        [p.normal, p.friction, p.sliding]
    }
}
