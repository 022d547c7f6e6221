//! One island's LCP from assembly to the impulses it applies: the unit of
//! work of a solver thread. Its buffers are kept from step to step (one per
//! island slot), so a warm step allocates only what the solver allocates.

use crate::contact::assembly::{AssemblyParams, BodyDynamics};
use crate::contact::{BodyCheck, BodySpaceLcp, ContactLcp};
use crate::geometry::Contact;
use lcp::contact::ContactLayout;
use lcp::on_basis::{BasisTolerances, BasisWorkspace};
use lcp::operator::LcpOperator;
use lcp::structured::guess::GuessOptions;
use lcp::{Lcp, LcpError, LemkeOptions, Method, Pivoting, Residuals, Solution, Status};

/// A solver for one LCP, started from a basis when one is given.
pub type IslandSolver<'a> = dyn FnMut(&Lcp, Option<&[bool]>) -> Solution + 'a;

/// An island's contacts, LCP and answer.
#[derive(Clone, Debug, Default)]
pub struct IslandLcp {
    /// The island's contacts, in global contact order.
    pub contacts: Vec<Contact>,
    pub lcp: ContactLcp,
    /// The basis to start from: the previous step's answer for the same island, if any.
    pub warm: Option<Vec<bool>>,
    /// The previous step's island with the same bodies and contact count
    /// (`pipeline::warm::WarmStarts`), whose impulses start the guessed basis.
    pub previous: Option<usize>,
    /// Whether this step's solve started from such a basis.
    pub warmed: bool,
    /// Unknowns the answer had to bring into the basis (`IslandRecord::entered`).
    pub entered: Option<usize>,
    /// The solver's answer (scaled LCP), `None` before the solve or when the LCP was invalid.
    pub sol: Option<Solution>,
    /// Set when the LCP could not be handed to the solver (non-finite data).
    pub error: Option<LcpError>,
    /// Physical `z` (λ = s·λ_scaled) and `w` of the unscaled LCP, island order.
    pub z: Vec<f64>,
    pub w: Vec<f64>,
    /// Residuals of that `z` on the unscaled LCP.
    pub residuals: Residuals,
    /// The solver's answer was not applied: the solve failed or its `z` was unusable.
    pub zeroed: bool,
    /// Impulses applied (physical `z` clamped at 0; after a failure, what the
    /// failed-solve policy of `pipeline::energy` applies, set by `integrate`).
    pub z_apply: Vec<f64>,
    /// Buffers of the body-space check of the previous basis.
    pub support: BasisWorkspace,
    /// Options of the body-space check of the answer and its double-double
    /// re-solve (`pipeline::body_check`), `None` for no check; set per solve.
    pub body_check: Option<LemkeOptions>,
    /// The answer's body-space error `η_body` (`contact::body_check`; 0 unchecked).
    pub body_eta: f64,
    /// Buffers of that check.
    pub check: BodyCheck,
}

impl IslandLcp {
    /// Assembles the island's LCP: its rows and `q`, and the dense `M` if `matrix`.
    pub fn assemble(&mut self, dynamics: &BodyDynamics<'_>, p: &AssemblyParams, matrix: bool) {
        self.lcp.assemble_rows(&self.contacts, dynamics, p);
        if matrix {
            self.lcp.assemble_matrix();
        }
    }

    /// Solves the assembled LCP, maps the answer to physical units and
    /// decides the impulses. A failed solve's answer is not applied as it
    /// stands (its last iterate can be anything): `integrate` applies its
    /// admissible part scaled not to add energy (`pipeline::energy`); the
    /// answer is kept for the record.
    ///
    /// With `basis_check` ([`basis_check_applies`]), a coupled island under
    /// [`STRUCTURED_MIN_N`] first tries its previous basis in body space,
    /// then (with Lemke's full ladder, [`BasisCheck::rungs`]) a basis guessed
    /// from its previous impulses ([`try_guessed_basis`]) and the structured
    /// Lemke; the dense `M` is formed only when all fail (or the island has no
    /// previous basis). `z_prev`: the previous step's physical impulses of
    /// this island (empty when there were none).
    pub fn solve(&mut self, solver: &mut IslandSolver<'_>, basis_check: Option<BasisCheck>, z_prev: &[f64]) {
        let n = self.lcp.n();
        self.sol = None;
        self.error = None;
        self.entered = None;
        let warm = self.warm.take().filter(|b| b.len() == n);
        self.warmed = warm.is_some();
        // Whether the body-space check judges this island's answer (bodies of
        // very different mobilities): the previous basis's answer then gets
        // its last digits, and `check_in_body_space` its check.
        let mixed = self.lcp.dynamic_body_count() >= 2 && BodyCheck::applies(&self.lcp);
        // The body-space answer comes with its physical z and w, as checked.
        let mut physical = None;
        let fast = match (basis_check, warm.as_deref()) {
            (Some(BasisCheck { accept_tol: tol, rungs }), Some(basis))
                if self.lcp.dynamic_body_count() >= 2 && n < STRUCTURED_MIN_N =>
            {
                try_previous_basis(&self.lcp, basis, tol, mixed, &mut self.support)
                    .or_else(|| rungs.then(|| try_guessed_basis(&self.lcp, z_prev, tol, mixed, &mut self.support))?)
                    .map(|(sol, zw)| {
                        physical = Some(zw);
                        sol
                    })
            }
            _ => None,
        };
        // A large coupled island, or a small one whose previous and guessed
        // bases failed: the structured Lemke, without the dense M (a small
        // island's failure goes on to the dense Lemke).
        let fast = fast.or_else(|| {
            let c = basis_check.filter(|_| self.lcp.dynamic_body_count() >= 2)?;
            if n < STRUCTURED_MIN_N && (warm.is_none() || !c.rungs) {
                return None;
            }
            super::structured::solve(&self.lcp, warm.as_deref(), c.accept_tol, n > DENSE_FALLBACK_MAX_N)
        });
        let sol = match fast {
            Some(sol) => sol,
            None => {
                if !self.lcp.has_matrix() {
                    self.lcp.assemble_matrix();
                }
                // Lend the buffers to an Lcp, solve, and take them back.
                let lcp = match self.lcp.take_lcp() {
                    Ok(lcp) => lcp,
                    Err(e) => {
                        self.error = Some(e);
                        return;
                    }
                };
                let sol = solver(&lcp, warm.as_deref());
                self.lcp.restore(lcp);
                sol
            }
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
        self.residuals = Residuals::of(&self.z, &self.w);
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
    }
}

/// Copies an island's `[fn; fd; λ]` (`m` contacts, layout of its own LCP)
/// into the step's layout (`nc` contacts), contact `c` of the island being
/// the step's contact `ids[c]`.
pub fn scatter<T: Copy>(ids: &[usize], nc: usize, k: usize, src: &[T], dst: &mut [T]) {
    let (island, step) = (ContactLayout::new(ids.len(), k), ContactLayout::new(nc, k));
    for (c, &g) in ids.iter().enumerate() {
        dst[step.fn_index(g)] = src[island.fn_index(c)];
        dst[step.fd_of(g)].copy_from_slice(&src[island.fd_of(c)]);
        dst[step.lambda_index(g)] = src[island.lambda_index(c)];
    }
}

/// Coupled islands from this LCP size up go to the structured Lemke
/// (`lcp::structured`, see `pipeline::structured`) when the robust Lemke
/// with warm starts is the method; they skip the body-space check of the
/// previous basis (its dense factorization of the support, `|α|³`, was 48 % of
/// a forming 200-cube heap's time; the structured Lemke's warm run checks the
/// same basis at 0 pivots). Measured on heap LCPs (`structured_scaling`,
/// CPU time of a cold solve): n = 1,120 dense 0.09 s, structured 0.07 s;
/// n = 1,800: 0.73 s, 0.20 s; n = 3,030: 4.9 s, 0.57 s. Below, an island
/// with a warm basis that neither it nor the guessed basis solves in body
/// space goes to the structured Lemke too (its warm run, the loaded-friction
/// sub-LCPs, the guess: `pipeline::structured`), then to the dense Lemke if
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

/// The body-space check accepts a previous basis only if its residual is this
/// fraction of Lemke's acceptance bound: pivoting ends on answers refined to
/// round-off, and a resting stack must not creep at the bound's 1e-9 m/s
/// (at 1e-2 a 3-box stack keeps its velocities below 1e-9 m/s over 500 steps;
/// at 1e-4 most stack steps went back to pivoting).
const BASIS_CHECK_TOL: f64 = 1e-2;

/// Lemke's acceptance bound when the body-space basis check serves `method`:
/// the robust Lemke with warm starts (the classic one starts cold, as the
/// seed's did). Only islands of two or more dynamic bodies use it; a single
/// body's LCP stays on the dense path, where it is fastest and bit-identical
/// to earlier releases (the seed corpus is made of such LCPs).
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

/// Physical `z` and `w` of an island's answer.
type PhysicalZw = (Vec<f64>, Vec<f64>);

/// Sweeps of the guessed basis tried when the previous basis fails ([`try_guessed_basis`]).
/// Measured on resting stacks (`stack_steps 2000 …`, 2,000 steps each; which
/// steps pivot is chaotic in the stack's size and in the sweeps): on 4–16
/// boxes the steps that pivot fall 777 → 301; on 5, 7–12, 14 and 16 boxes
/// 550 → 218 with 60 sweeps (and, before `fresh_attempt` kept the back-off,
/// 216 with 60, 314 with 20, 326 with 120, 275 with 600 more
/// when 60 fail, 459 with 60 from zero impulses).
pub const GUESS_SWEEPS_PREVIOUS: usize = 60;

/// When the previous step's basis fails in body space (after its exchange
/// rounds, or none when the back-off of `lcp::on_basis` skips them), the
/// basis read from [`GUESS_SWEEPS_PREVIOUS`] sweeps of body-space projected
/// Gauss–Seidel (`lcp::structured::guess`) started at the previous
/// step's impulses `z_prev` (physical; from zero when it is not of this
/// size), solved and checked as the previous one is ([`try_previous_basis`],
/// with every exchange round). On a resting stack the previous basis fails
/// when its answer has drifted to a vertex that round-off leaves a hair
/// infeasible; the dense Lemke then pivots a few hundred times from it to
/// another vertex, where the guess usually lands on one at once.
pub(super) fn try_guessed_basis(
    lcp: &ContactLcp,
    z_prev: &[f64],
    accept_tol: f64,
    mixed: bool,
    ws: &mut BasisWorkspace,
) -> Option<(Solution, PhysicalZw)> {
    let (lay, s) = (lcp.layout(), lcp.scale());
    let op = crate::contact::structured::structured_lcp(lcp, s).ok()?;
    // The sweeps work in the units solved: λ / s.
    let z0 = (z_prev.len() == lay.n()).then(|| {
        let mut z = z_prev.to_vec();
        z[lay.lambda_range()].iter_mut().for_each(|v| *v /= s);
        z
    });
    let o = GuessOptions { sweeps: GUESS_SWEEPS_PREVIOUS, ..Default::default() };
    let guess = lcp::structured::guess::guess_basis(&op, lay, &o, z0.as_deref());
    ws.fresh_attempt(|ws| try_previous_basis(lcp, &guess, accept_tol, mixed, ws))
}

/// The previous step's basis solved on this step's LCP in body space. Every
/// answer is accepted by the acceptance rule (`lcp::accept`, rows read
/// through the body-space operator) at `accept_tol` on the LCP as scaled and
/// in physical units, as the dense Lemke's answers are; its natural residual
/// is within [`BASIS_CHECK_TOL`] of Lemke's bound if some exchange round gets
/// there, else within the bound itself (what the dense Lemke's warm start
/// would accept at 0 pivots) — the same answer without forming `M`.
/// With it the physical `z` and `w` it was checked with. `mixed`: the
/// body-space check will judge the answer ([`BodyCheck::applies`]).
pub(super) fn try_previous_basis(
    lcp: &ContactLcp,
    basis: &[bool],
    accept_tol: f64,
    mixed: bool,
    ws: &mut BasisWorkspace,
) -> Option<(Solution, PhysicalZw)> {
    let scaled = BodySpaceLcp::new(lcp);
    let physical = BodySpaceLcp::at_scale(lcp, 1.0);
    let to_physical = |z: &[f64], out: &mut Vec<f64>| lcp.unscale_z(z, out);
    // At scale 1 the physical LCP is the one solved: one check does.
    let also =
        (lcp.scale() != 1.0).then_some((&physical as &dyn LcpOperator, &to_physical as &dyn Fn(&[f64], &mut Vec<f64>)));
    // Exchanges within the bound and the loose last resort for every coupled
    // island. (They were once kept from islands of two dynamic bodies: before
    // the body-space check, a 1e8 kg box sliding on a 1 kg one met a step no
    // Lemke rung solved with them. With the check, `mass_ratio_failures`
    // (12 heavy-on-light cases, 2,000 steps): 0 failures with and without
    // them; answers left outside the body-space rule 11 → 7, the largest
    // energy a step created 2.2e-8 → 1.3e-12 of E₀ on the box–box cases; the
    // run took 90 s → 12 s.)
    let tol = BasisTolerances {
        accept_tol,
        tight: accept_tol * BASIS_CHECK_TOL,
        loose: true,
        // The last digits only where the body-space check will judge them.
        polish: mixed,
        // Not there either the extra exchange rounds of a small block: on a
        // 1e8 kg box sliding on a 1 kg one (`mass_ratio_failures`) the answers
        // they found were left outside the body-space rule on 10 of 2,000
        // steps (η_body up to 3.8e-8), against 1 (1.5e-8) with 8 rounds.
        more_rounds: !mixed,
    };
    let a = lcp::on_basis::solve_on_basis_ruled(&scaled, basis, tol, also, ws)?;
    // At scale 1, z and w are the physical ones (λ·1 and the same products).
    let zw = a.other.unwrap_or_else(|| (a.solution.z.clone(), a.solution.w.clone()));
    Some((a.solution, zw))
}
