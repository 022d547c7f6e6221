//! One island's LCP from assembly to the impulses it applies: the unit of
//! work of a solver thread. Its buffers are kept from step to step (one per
//! island slot), so a warm step allocates only what the solver allocates.
//! How it is solved ([`IslandLcp::solve`]) is the solve chain, [`crate::solve_chain`].

use crate::contact::assembly::{AssemblyParams, BodyDynamics};
use crate::contact::{BodyCheck, ContactLcp};
use crate::geometry::Contact;
use crate::solve_chain::stage_name::SolveStage;
use lcp::contact::ContactLayout;
use lcp::on_basis::BasisWorkspace;
use lcp::{Lcp, LcpError, LemkeOptions, Residuals, Solution};

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
    /// (`solve_chain::warm_starts::WarmStarts`), whose impulses start the guessed basis.
    pub previous: Option<usize>,
    /// Whether there is such an island and its answer did not leave the
    /// warm basis it started from (`WarmStarts::moved`).
    pub previous_stood: bool,
    /// The previous step's physical impulses mapped contact by contact
    /// (`solve_chain::warm_by_contact`), when there is no `previous` island.
    pub z_mapped: Vec<f64>,
    /// Whether this step's solve started from such a basis.
    pub warmed: bool,
    /// The stage of the solve chain that answered (`None` before the solve or when the LCP was invalid).
    pub stage: Option<SolveStage>,
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
    pub basis_ws: BasisWorkspace,
    /// The structured stage's operators and basis factors from this slot's
    /// last solve (`solve_chain::kept_factors`).
    pub kept: crate::solve_chain::kept_factors::KeptFactors,
    /// Options of the body-space check of the answer and its double-double
    /// re-solve (`solve_chain::answer_check`), `None` for no check; set per solve.
    pub body_check: Option<LemkeOptions>,
    /// The answer's body-space error `η_body` (`contact::body_rule`; 0 unchecked).
    pub body_eta: f64,
    /// Buffers of that check.
    pub check: BodyCheck,
    /// A joint holds one of its bodies: its `M` is coupled through the
    /// joints (`joints::elimination`) and it is solved on the dense path.
    pub jointed: bool,
    /// Its coupling through the joints (`joints::elimination`), empty when
    /// `jointed` is not set: the dense `M` gets it when it is formed
    /// ([`IslandLcp::form_matrix`]), the operator of the previous basis reads it.
    pub coupling: crate::joints::JointCoupling,
    /// It holds a patch's torsional friction (`contact::torsion`), whose cone
    /// row the body-space stages do not model: it is solved on the dense path.
    pub torsion: bool,
}

impl IslandLcp {
    /// Solved on the dense `M` only (jointed, or holding a torsion patch).
    pub fn dense_only(&self) -> bool {
        self.jointed || self.torsion
    }

    /// Forms the dense `M` if it is not formed: `J M_b⁻¹ Jᵀ` and the cone
    /// rows, minus the joints' coupling of a jointed island.
    pub fn form_matrix(&mut self) {
        if !self.lcp.has_matrix() {
            self.lcp.assemble_matrix();
            self.coupling.subtract_from(&mut self.lcp);
        }
    }

    /// Assembles the island's LCP: its rows and `q`, and the dense `M` if `matrix`.
    pub fn assemble(&mut self, dynamics: &BodyDynamics<'_>, p: &AssemblyParams, matrix: bool) {
        self.lcp.assemble_rows(&self.contacts, dynamics, p);
        if matrix {
            self.lcp.assemble_matrix();
        }
    }
}

/// Copies an island's `[fn; fd; λ]` (`m` contacts, layout of its own LCP)
/// into the step's layout (`nc` contacts), contact `c` of the island being
/// the step's contact `ids[c]`.
pub fn scatter<T: Copy>(ids: &[usize], nc: usize, k: usize, src: &[T], dst: &mut [T]) {
    if in_step_order(ids, nc) {
        dst.copy_from_slice(src);
        return;
    }
    let (island, step) = (ContactLayout::new(ids.len(), k), ContactLayout::new(nc, k));
    for (c, &g) in ids.iter().enumerate() {
        dst[step.fn_index(g)] = src[island.fn_index(c)];
        dst[step.fd_of(g)].copy_from_slice(&src[island.fd_of(c)]);
        dst[step.lambda_index(g)] = src[island.lambda_index(c)];
    }
}

/// Whether an island's contacts `ids` are all `nc` of the step's, in order
/// (the step's only island, a stack's): its layout is the step's.
pub fn in_step_order(ids: &[usize], nc: usize) -> bool {
    ids.len() == nc && ids.iter().enumerate().all(|(c, &g)| c == g)
}
