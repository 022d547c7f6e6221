//! Lemke options, with the defaults documented on each field.

/// How the leaving variable is chosen and how tolerances are judged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pivoting {
    /// Robust default: the problem is equilibrated first; ratio ties are
    /// detected with a *relative* tolerance and broken lexicographically
    /// (z0 preferred); bases are hashed to catch cycling; the final basis is
    /// re-solved and the answer judged by the acceptance rule
    /// ([`crate::accept`]); an exact-arithmetic Lemke is the ladder's last rung.
    Lexicographic,
    /// The source note's Lemke: absolute `piv_tol` and `zero_tol` applied to the
    /// problem exactly as given, Harris-style ratio test with `zero_tol` slack,
    /// first index on ties. Kept to reproduce the source note's findings. Its
    /// `Solved` is its own absolute check (`|z_i w_i| < zero_tol`, …); only
    /// `Solution::ok()` says whether the acceptance rule holds too.
    Classic,
}

impl Pivoting {
    pub fn as_str(self) -> &'static str {
        match self {
            Pivoting::Lexicographic => "lexicographic",
            Pivoting::Classic => "classic",
        }
    }
}

/// Options of Lemke's method.
#[derive(Clone, Debug, PartialEq)]
pub struct LemkeOptions {
    /// Pivoting rule. Default `Lexicographic`.
    pub pivoting: Pivoting,
    /// Smallest pivot accepted. `Classic`: absolute, on the problem as given.
    /// `Lexicographic`: relative to the entering column's largest entry, on
    /// the equilibrated problem, and never below 1e-9 (below that a computed
    /// entry is round-off). Default 1e-12.
    pub piv_tol: f64,
    /// The user zero. `Classic`: the Harris slack of the ratio test, absolute.
    /// `Lexicographic`: an upper bound on the relative tolerance under which
    /// two ratios count as tied (it uses `min(zero_tol, 1e-13)`, and 1e-10 on
    /// one rung of its repair ladder). Default 1e-6 (the source note's value).
    pub zero_tol: f64,
    /// Pivot limit; `None` means `max(1000, 50·n)` (Murty's 2ⁿ examples need more).
    pub max_pivots: Option<usize>,
    /// `Lexicographic` only: the tolerance of the acceptance rule
    /// ([`crate::accept`]: each row's backward error on its own scale). The
    /// ladder stops at the first answer the rule accepts whose natural
    /// residual is also ≤ `accept_tol·(1 + ‖q‖∞)`, else returns the first the
    /// rule accepts. Default 1e-9 ([`crate::accept::DEFAULT_TOL`]).
    pub accept_tol: f64,
    /// `Lexicographic` only: Ruiz-equilibrate `M` and normalize `q` before
    /// pivoting. Default true.
    pub equilibrate: bool,
    /// `Lexicographic` only: when a run fails its check, climb the repair
    /// ladder (coarser pivot tolerance, another covering vector, the other
    /// scaling) before reporting failure. Default true.
    pub fallback: bool,
    /// `Lexicographic` only: start from the basis guess passed to
    /// `solve_warm` (e.g. the simulator's previous step). Default true.
    pub warm_start: bool,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        LemkeOptions {
            pivoting: Pivoting::Lexicographic,
            piv_tol: 1e-12,
            zero_tol: 1e-6,
            max_pivots: None,
            accept_tol: 1e-9,
            equilibrate: true,
            fallback: true,
            warm_start: true,
        }
    }
}

impl LemkeOptions {
    /// The source note's settings: classic pivoting, piv_tol 1e-12, zero_tol 1e-6.
    pub fn classic() -> Self {
        LemkeOptions { pivoting: Pivoting::Classic, equilibrate: false, ..Default::default() }
    }

    /// Pivot limit for a problem of size `n`.
    pub fn pivot_limit(&self, n: usize) -> usize {
        self.max_pivots.unwrap_or_else(|| (50 * n).max(1000))
    }
}
