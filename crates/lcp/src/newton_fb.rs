//! Damped semismooth Newton on the Fischer–Burmeister function.
//!
//! With `φ(a, b) = √(a² + b²) − a − b`, which is zero exactly when
//! `a ≥ 0, b ≥ 0, ab = 0`, the LCP becomes the nonsmooth equation
//! `Φ(z) = φ(z, M z + q) = 0` (componentwise). Each iteration
//!
//! 1. builds an element `H = D_a + D_b M` of the generalized Jacobian of `Φ`
//!    (`D_a = a/r − 1`, `D_b = b/r − 1` with `r = √(a² + b²)`; at the kink
//!    `a = b = 0` the standard De Luca–Facchinei–Kanzow choice with the
//!    direction `e_β`, `β` the set of kink indices);
//! 2. solves for the step by dense LU with partial pivoting (faer): the
//!    semismooth Newton step `H d = −Φ`, or by default its Levenberg–Marquardt
//!    regularization `(HᵀH + ν I) d = −HᵀΦ`, `ν = c·min(1, ‖Φ‖)` (Fan–Yuan,
//!    capped so that far from a solution it stays a Gauss–Newton step), which
//!    tends to the Newton step as `Φ → 0` but keeps converging fast where the
//!    solution is not isolated and `H` is singular there (the contact LCP:
//!    redundant friction directions, zero λ diagonal);
//! 3. falls back to the steepest-descent direction `d = −∇Ψ = −Hᵀ Φ` when the
//!    solve fails or `d` is not a sufficient descent direction
//!    (`∇Ψᵀ d > −ρ ‖d‖^p`, `p = 2.1`);
//! 4. backtracks (Armijo) on the merit function `Ψ = ½ ‖Φ‖²`.
//!
//! By default the iteration runs on the Ruiz-equilibrated problem
//! ([`Scaling::ruiz`], power-of-two factors, so exact), since FB's merit
//! function is not scale invariant: on the contact LCP with a small cone
//! scale `s` the unscaled iteration almost never converges. Convergence is
//! always judged on the natural residual `‖min(z, w)‖∞` of the problem as
//! given, the measure shared by all solvers, not on `Ψ`.
//!
//! For a P-matrix (in particular positive definite `M`) `Ψ` has bounded level
//! sets and every stationary point solves the LCP, so the method converges
//! globally. For other matrices `Ψ` may have stationary points that are no
//! solution; the method then stops with `MaxIterations`.
//!
//! The iterate always stays finite: a trial point whose merit is not finite
//! is never accepted, so `z` never holds NaN.

use crate::problem::{dot, Lcp};
use crate::scaling::Scaling;
use crate::solution::{Solution, Status};

/// Exponent `p` of the sufficient-descent test `∇Ψᵀ d ≤ −ρ ‖d‖^p` (De Luca–Facchinei–Kanzow).
const DESCENT_P: f64 = 2.1;

/// Ruiz rounds used when `equilibrate` is on (it stops earlier once stable).
const RUIZ_ITERATIONS: usize = 20;

/// Options of the damped Newton–Fischer–Burmeister method.
#[derive(Clone, Debug, PartialEq)]
pub struct NewtonFbOptions {
    /// Newton step limit. Default 100.
    pub max_iterations: usize,
    /// Stop when the natural residual ‖min(z, w)‖∞ ≤ tol. Default 1e-12.
    pub tol: f64,
    /// Armijo constant σ in (0, ½): accept step t when
    /// `Ψ(z + t d) ≤ Ψ(z) + σ t ∇Ψᵀ d`. Default 1e-4.
    pub armijo_sigma: f64,
    /// Backtracking factor β in (0, 1): trial steps are 1, β, β², …. Default 0.5.
    pub backtrack: f64,
    /// Backtracking steps per line search before giving up on a direction. Default 40.
    pub max_backtracks: usize,
    /// ρ > 0 of the sufficient-descent test `∇Ψᵀ d ≤ −ρ ‖d‖^2.1`; a Newton
    /// direction failing it is replaced by the gradient step. Default 1e-10.
    pub descent_rho: f64,
    /// Levenberg–Marquardt factor `c`: the step solves
    /// `(HᵀH + c·min(1, ‖Φ‖) I) d = −HᵀΦ`; 0 gives the plain semismooth Newton
    /// step `H d = −Φ`. Default 0.01 (measured on 100 random contact LCPs per
    /// cell, nc ∈ {1, 2, 4, 8}, s ∈ {1, 1e-3, 1e-6}, equilibrated: solves
    /// 82–100 % where the plain step solves 61–97 %; same steps on P-matrices).
    pub lm_factor: f64,
    /// Iterate on the Ruiz-equilibrated problem and map back (exact). Default true.
    pub equilibrate: bool,
}

impl Default for NewtonFbOptions {
    fn default() -> Self {
        NewtonFbOptions {
            max_iterations: 100,
            tol: 1e-12,
            armijo_sigma: 1e-4,
            backtrack: 0.5,
            max_backtracks: 40,
            descent_rho: 1e-10,
            lm_factor: 0.01,
            equilibrate: true,
        }
    }
}

/// `φ(a, b) = √(a² + b²) − a − b`; `hypot` avoids overflow and underflow.
#[inline]
fn fb(a: f64, b: f64) -> f64 {
    a.hypot(b) - a - b
}

/// `Φ(z)` for `w = M z + q`, and the merit `Ψ = ½ ‖Φ‖²`.
fn fb_vector(z: &[f64], w: &[f64], phi: &mut [f64]) -> f64 {
    let mut psi = 0.0;
    for ((p, &a), &b) in phi.iter_mut().zip(z).zip(w) {
        *p = fb(a, b);
        psi += *p * *p;
    }
    0.5 * psi
}

/// Solves the dense system `A x = b` (`A` row-major n×n) by LU with partial
/// pivoting. `None` when `A` is numerically singular (a pivot below
/// `n·ε·max|A|`) or the solution is not finite. Shared with [`crate::enumerate`].
pub(crate) fn lu_solve(a: &[f64], n: usize, b: &[f64]) -> Option<Vec<f64>> {
    use faer::linalg::solvers::Solve;
    if n == 0 || a.len() != n * n || b.len() != n || !a.iter().chain(b).all(|v| v.is_finite()) {
        return None;
    }
    let amax = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if amax == 0.0 {
        return None;
    }
    let mat = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let lu = mat.partial_piv_lu();
    // Partial pivoting does not report rank deficiency itself: check U's diagonal.
    let u = lu.U();
    let pivot_floor = (n as f64) * f64::EPSILON * amax;
    if (0..n).any(|k| {
        let pivot = u[(k, k)].abs();
        pivot.is_nan() || pivot <= pivot_floor
    }) {
        return None;
    }
    let rhs = faer::Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
    let x = lu.solve(&rhs);
    let x: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Solves `lcp` from `z = 0`. Never panics; `z` is always finite.
///
/// Status: `Solved` when the natural residual of the problem as given is
/// ≤ `o.tol` and the iterate (round-off negatives clipped, unreached zeros
/// snapped: [`crate::accept::snap`]) passes the acceptance rule at [`crate::accept::DEFAULT_TOL`] (the iteration goes on
/// until both hold); `Numerical` when the merit function of the current iterate is
/// not finite (overflow), or when an answer that converged on the equilibrated
/// problem does not hold on the problem as given (entries near both ends of
/// the exponent range, which the scaled products round otherwise); otherwise `MaxIterations` (also when the line search
/// stalls before the limit, at a stationary point of `Ψ` that is no solution).
pub fn solve(lcp: &Lcp, o: &NewtonFbOptions) -> Solution {
    run(lcp, None, o)
}

/// As [`solve`], warm-started from `z0` (e.g. to polish another solver's
/// answer). A `z0` of the wrong length or with non-finite entries is ignored
/// (the start is then `z = 0`).
pub fn solve_from(lcp: &Lcp, z0: &[f64], o: &NewtonFbOptions) -> Solution {
    let usable = z0.len() == lcp.n() && z0.iter().all(|v| v.is_finite());
    run(lcp, usable.then_some(z0), o)
}

fn run(lcp: &Lcp, z0: Option<&[f64]>, o: &NewtonFbOptions) -> Solution {
    let n = lcp.n();
    // Equilibrate (exact: powers of two); fall back to the problem as given if scaling overflows.
    let scaled = o
        .equilibrate
        .then(|| {
            let s = Scaling::ruiz(lcp, RUIZ_ITERATIONS);
            s.try_apply(lcp).ok().map(|l| (s, l))
        })
        .flatten();
    let (scaling, work) = match &scaled {
        Some((s, l)) => (s.clone(), l),
        None => (Scaling::identity(n), lcp),
    };
    let z_start = match z0 {
        Some(z0) => scaling.z_forward(z0),
        None => vec![0.0; n],
    };
    let (z_scaled, status, iterations) = iterate(work, &scaling, z_start, o);
    let mut sol = Solution::from_z(lcp, scaling.z_back(&z_scaled), status, iterations);
    // Converged on the working problem, the answer must hold as given too:
    // with entries near both ends of the exponent range the equilibrated
    // products round otherwise (found by `cargo fuzz`: 1e-300 beside 1e308,
    // natural residual 1.0 as given, `solved` on the working problem).
    if sol.status == Status::Solved && !(sol.residuals.residual <= o.tol && sol.accepted) {
        sol.status = Status::Numerical;
    }
    sol
}

/// `‖min(z, w)‖∞` in the units of the original problem, from scaled `z', w'`:
/// `z = D_c z'`, `w = D_r⁻¹ w'` (exact for power-of-two factors).
fn natural_residual(z: &[f64], w: &[f64], s: &Scaling) -> f64 {
    let mut r = 0.0f64;
    for i in 0..z.len() {
        r = r.max((s.col[i] * z[i]).min(w[i] / s.row[i]).abs());
    }
    r
}

/// The damped Newton iteration on `lcp` (possibly equilibrated); convergence
/// is measured after mapping back through `s`. Returns `(z, status, iterations)`.
fn iterate(lcp: &Lcp, s: &Scaling, mut z: Vec<f64>, o: &NewtonFbOptions) -> (Vec<f64>, Status, usize) {
    let n = lcp.n();
    let mut w = lcp.w_of(&z);
    let mut phi = vec![0.0; n];
    let mut psi = fb_vector(&z, &w, &mut phi);

    let mut da = vec![0.0; n];
    let mut db = vec![0.0; n];
    let mut h = vec![0.0; n * n];
    let mut grad = vec![0.0; n];
    let mut z_trial = vec![0.0; n];
    let mut w_trial = vec![0.0; n];
    let mut phi_trial = vec![0.0; n];
    let mut kink = vec![false; n];

    for it in 0..=o.max_iterations {
        // Converged, and inside the acceptance rule (scale invariant, so
        // judged here on the working problem), round-off negatives clipped
        // and unreached zeros snapped (`accept::snap`)?
        if natural_residual(&z, &w, s) <= o.tol {
            match crate::accept::snap(lcp, &z, None, crate::accept::DEFAULT_TOL) {
                Some((zs, ws)) if natural_residual(&zs, &ws, s) <= o.tol => return (zs, Status::Solved, it),
                _ => {}
            }
        }
        if !psi.is_finite() {
            return (z, Status::Numerical, it);
        }
        if it == o.max_iterations {
            break;
        }

        // Generalized Jacobian H = diag(da) + diag(db) M.
        for i in 0..n {
            let r = z[i].hypot(w[i]);
            kink[i] = r == 0.0;
            if !kink[i] {
                da[i] = z[i] / r - 1.0;
                db[i] = w[i] / r - 1.0;
            }
        }
        if kink.iter().any(|&k| k) {
            // Kink: the limit along z + t e_β, i.e. (a, b) ∝ (1, (M e_β)_i).
            for i in (0..n).filter(|&i| kink[i]) {
                let c: f64 = (0..n).filter(|&j| kink[j]).map(|j| lcp.at(i, j)).sum();
                let r = 1.0f64.hypot(c);
                da[i] = 1.0 / r - 1.0;
                db[i] = c / r - 1.0;
            }
        }
        for i in 0..n {
            let hrow = &mut h[i * n..(i + 1) * n];
            for (hij, &mij) in hrow.iter_mut().zip(lcp.row(i)) {
                *hij = db[i] * mij;
            }
            hrow[i] += da[i];
        }
        // ∇Ψ = Hᵀ Φ.
        grad.iter_mut().for_each(|g| *g = 0.0);
        for i in 0..n {
            let p = phi[i];
            if p != 0.0 {
                for (g, &hij) in grad.iter_mut().zip(&h[i * n..(i + 1) * n]) {
                    *g += hij * p;
                }
            }
        }
        if !grad.iter().all(|g| g.is_finite()) {
            return (z, Status::Numerical, it);
        }

        // Newton (or Levenberg–Marquardt) direction, kept only if it is a sufficient descent direction.
        let newton = newton_direction(&h, &phi, &grad, psi, o).filter(|d| {
            let slope = dot(&grad, d);
            let dnorm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            slope.is_finite() && slope <= -o.descent_rho * dnorm.powf(DESCENT_P)
        });
        let mut directions = Vec::with_capacity(2);
        directions.extend(newton);
        directions.push(grad.iter().map(|g| -g).collect::<Vec<f64>>());

        // Armijo backtracking; try the gradient step if the Newton step's search fails.
        let mut accepted = false;
        for d in &directions {
            let slope = dot(&grad, d);
            if slope.is_nan() || slope >= 0.0 {
                continue; // ∇Ψ = 0 at a non-solution: a stationary point, no descent possible
            }
            let mut t = 1.0;
            for _ in 0..=o.max_backtracks {
                for ((zt, &zi), &di) in z_trial.iter_mut().zip(&z).zip(d) {
                    *zt = zi + t * di;
                }
                for (i, wt) in w_trial.iter_mut().enumerate() {
                    *wt = dot(lcp.row(i), &z_trial) + lcp.q()[i];
                }
                let psi_trial = fb_vector(&z_trial, &w_trial, &mut phi_trial);
                // NaN compares false, so a non-finite trial point is never accepted.
                if psi_trial <= psi + o.armijo_sigma * t * slope {
                    std::mem::swap(&mut z, &mut z_trial);
                    std::mem::swap(&mut w, &mut w_trial);
                    std::mem::swap(&mut phi, &mut phi_trial);
                    psi = psi_trial;
                    accepted = true;
                    break;
                }
                t *= o.backtrack;
            }
            if accepted {
                break;
            }
        }
        if !accepted {
            // Stalled (stationary point of Ψ or round-off floor above tol).
            return (z, Status::MaxIterations, it);
        }
    }
    (z, Status::MaxIterations, o.max_iterations)
}

/// `H d = −Φ` (`lm_factor = 0`) or `(HᵀH + ν I) d = −HᵀΦ` with `ν = lm_factor · min(1, ‖Φ‖)`;
/// `None` when the system is numerically singular.
fn newton_direction(h: &[f64], phi: &[f64], grad: &[f64], psi: f64, o: &NewtonFbOptions) -> Option<Vec<f64>> {
    let n = phi.len();
    if o.lm_factor.is_nan() || o.lm_factor <= 0.0 {
        let neg_phi: Vec<f64> = phi.iter().map(|p| -p).collect();
        return lu_solve(h, n, &neg_phi);
    }
    let nu = o.lm_factor * (2.0 * psi).sqrt().min(1.0);
    // HᵀH, accumulated row by row of H (contiguous access).
    let mut a = vec![0.0; n * n];
    for r in 0..n {
        let hr = &h[r * n..(r + 1) * n];
        for (i, &hri) in hr.iter().enumerate() {
            if hri != 0.0 {
                for (aij, &hrj) in a[i * n..(i + 1) * n].iter_mut().zip(hr) {
                    *aij += hri * hrj;
                }
            }
        }
    }
    for i in 0..n {
        a[i * n + i] += nu;
    }
    let neg_grad: Vec<f64> = grad.iter().map(|g| -g).collect();
    lu_solve(&a, n, &neg_grad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solve_solves_and_rejects_singular() {
        let a = [4.0, 1.0, 2.0, 3.0];
        let x = lu_solve(&a, 2, &[1.0, 2.0]).expect("nonsingular");
        assert!((4.0 * x[0] + x[1] - 1.0).abs() < 1e-15);
        assert!((2.0 * x[0] + 3.0 * x[1] - 2.0).abs() < 1e-15);
        assert!(lu_solve(&[1.0, 2.0, 2.0, 4.0], 2, &[1.0, 1.0]).is_none());
        assert!(lu_solve(&[0.0], 1, &[1.0]).is_none());
    }

    #[test]
    fn fb_is_zero_exactly_on_complementary_pairs() {
        assert_eq!(fb(0.0, 3.0), 0.0);
        assert_eq!(fb(2.0, 0.0), 0.0);
        assert!(fb(1.0, 1.0) < 0.0);
        assert!(fb(-1.0, 2.0) > 0.0);
    }
}
