//! Properties every solver keeps on any input, and the decoder that turns
//! arbitrary bytes into a small LCP and a method. Shared by the property tests
//! (`tests/properties_any_input.rs`, proptest) and the fuzz target
//! `fuzz/fuzz_targets/lcp_solvers.rs` (`cargo +nightly fuzz`), so both check
//! the same thing on the same decoding.
//!
//! The properties:
//! - `Lcp::new` accepts exactly the well-formed data (n ≥ 1, `M` n × n, all finite);
//! - every solver returns without panicking, with `z`, `w` (and a Lemke basis)
//!   of length n and no more pivots or iterations than its budget;
//! - `Solved` only for an answer within the documented rule of that method
//!   ([`documented_rule`]).

#![allow(dead_code)]

use lcp::{Lcp, LemkeOptions, Method, NewtonFbOptions, PgsOptions, Pivoting, Residuals, Solution, Status};

mod bytes;
pub use bytes::Bytes;

/// One decoded input: the data for `Lcp::new`, a method and a warm basis.
#[derive(Clone, Debug)]
pub struct Case {
    pub m: Vec<f64>,
    pub q: Vec<f64>,
    pub method: Method,
    pub warm: Option<Vec<bool>>,
}

/// Decodes a case: n in 1..=6; `M` arbitrary, symmetric positive semidefinite
/// (`A Aᵀ`), triangular with unit diagonal (a P-matrix) or with a wrong shape.
pub fn decode(data: &[u8]) -> Case {
    let mut b = Bytes::new(data);
    let n = 1 + (b.u8() % 6) as usize;
    let shape = b.u8() % 8;
    let raw: Vec<f64> = (0..n * n).map(|_| b.f64()).collect();
    let m = match shape {
        // A Aᵀ: positive semidefinite.
        0 | 1 => (0..n * n).map(|ij| (0..n).map(|k| raw[(ij / n) * n + k] * raw[(ij % n) * n + k]).sum()).collect(),
        // Unit upper triangular: a P-matrix, one solution.
        2 => (0..n * n)
            .map(|ij| {
                if ij / n == ij % n {
                    1.0
                } else if ij % n > ij / n {
                    raw[ij]
                } else {
                    0.0
                }
            })
            .collect(),
        // A wrong shape (Lcp::new must refuse it).
        3 if b.u8() % 8 == 0 => raw[..n * n - 1].to_vec(),
        _ => raw,
    };
    let q = (0..n).map(|_| b.f64()).collect();
    let method = decode_method(&mut b);
    let warm = b.bool().then(|| (0..n).map(|_| b.bool()).collect());
    Case { m, q, method, warm }
}

/// A method with options inside their documented ranges.
pub fn decode_method(b: &mut Bytes<'_>) -> Method {
    let max_pivots = if b.bool() { Some(b.u8() as usize % 40) } else { None };
    match b.u8() % 5 {
        0 | 1 => Method::Lemke(LemkeOptions {
            max_pivots,
            equilibrate: b.u8() % 4 != 0,
            fallback: b.u8() % 4 != 0,
            warm_start: b.bool(),
            piv_tol: b.pick(&[1e-12, 1e-9, 1e-6]),
            zero_tol: b.pick(&[1e-6, 1e-9, 1e-13]),
            ..LemkeOptions::default()
        }),
        2 => Method::Lemke(LemkeOptions {
            max_pivots,
            piv_tol: b.pick(&[1e-12, 1e-9, 1e-6]),
            zero_tol: b.pick(&[1e-6, 1e-9, 1e-12]),
            ..LemkeOptions::classic()
        }),
        3 => Method::Pgs(PgsOptions {
            omega: 0.1 + 1.8 * b.u8() as f64 / 255.0,
            max_iterations: b.u8() as usize * 4,
            tol: b.pick(&[1e-10, 1e-6]),
        }),
        _ => Method::NewtonFb(NewtonFbOptions {
            max_iterations: b.u8() as usize % 60,
            tol: b.pick(&[1e-12, 1e-8]),
            equilibrate: b.bool(),
            ..NewtonFbOptions::default()
        }),
    }
}

/// Whether `Lcp::new` must accept the data.
pub fn well_formed(m: &[f64], q: &[f64]) -> bool {
    !q.is_empty() && m.len() == q.len() * q.len() && m.iter().chain(q).all(|v| v.is_finite())
}

/// The acceptance rule the documentation gives for `Solved`, judged on `z`
/// with `w = M z + q` recomputed here: robust Lemke — the crate's own check,
/// `lcp::accept::accepts(…, accept_tol)` (componentwise); classic Lemke — its own word, Moby's check with
/// the user zero (`z, w ≥ −zero_tol`, `|z_i w_i| < zero_tol`); PGS and
/// Newton–FB — `‖min(z, w)‖∞ ≤ tol`. (When the acceptance rule changes, this
/// is the one place to change; a public check in `lcp` would replace it.)
/// Recomputing `w` may differ from the solver's own by round-off, hence the
/// slack of a few ulps of the terms.
pub fn documented_rule(lcp: &Lcp, method: &Method, z: &[f64]) -> Result<(), String> {
    let (w, r) = Residuals::compute(lcp, z);
    let q_norm = lcp.q_norm_inf();
    let terms = 1.0
        + q_norm
        + (0..lcp.n()).map(|i| lcp.row(i).iter().zip(z).map(|(a, b)| (a * b).abs()).sum::<f64>()).fold(0.0, f64::max);
    let slack = 8.0 * f64::EPSILON * terms;
    let (ok, rule) = match method {
        // The crate's own acceptance check (componentwise, lcp::accept).
        Method::Lemke(o) if o.pivoting == Pivoting::Lexicographic => {
            (lcp::accept::accepts(lcp, z, &w, o.accept_tol), format!("lcp::accept::accepts at {:e}", o.accept_tol))
        }
        Method::Lemke(o) => (
            r.min_z >= -o.zero_tol - slack
                && r.min_w >= -o.zero_tol - slack
                && r.max_complementarity < o.zero_tol + slack,
            format!("z, w ≥ −{0:e}, |z_i w_i| < {0:e}", o.zero_tol),
        ),
        Method::Pgs(PgsOptions { tol, .. }) | Method::NewtonFb(NewtonFbOptions { tol, .. }) => {
            (r.residual <= tol + slack, format!("‖min(z, w)‖∞ ≤ {tol:e}"))
        }
    };
    if ok {
        Ok(())
    } else {
        Err(format!("solved outside the documented rule ({rule}): residuals {r:?}, z = {z:?}, w = {w:?}"))
    }
}

/// The budget of pivots (Lemke) or iterations a method may report.
fn budget(method: &Method, n: usize) -> usize {
    match method {
        Method::Lemke(o) => o.pivot_limit(n),
        Method::Pgs(o) => o.max_iterations,
        Method::NewtonFb(o) => o.max_iterations,
    }
}

/// Checks a solver's answer on `lcp`.
pub fn check_solution(lcp: &Lcp, method: &Method, sol: &Solution) -> Result<(), String> {
    let n = lcp.n();
    if sol.z.len() != n || sol.w.len() != n {
        return Err(format!("z, w have lengths {}, {} for n = {n}", sol.z.len(), sol.w.len()));
    }
    if let Some(b) = &sol.basis {
        if b.len() != n {
            return Err(format!("basis of length {} for n = {n}", b.len()));
        }
    }
    if sol.pivots > budget(method, n) {
        return Err(format!(
            "{} pivots/iterations beyond the budget {} ({:?})",
            sol.pivots,
            budget(method, n),
            sol.status
        ));
    }
    if sol.status == Status::Solved {
        if !sol.z.iter().all(|v| v.is_finite()) {
            return Err(format!("solved with a non-finite z = {:?}", sol.z));
        }
        documented_rule(lcp, method, &sol.z)?;
    }
    Ok(())
}

/// The whole property on one case.
pub fn check(case: &Case) -> Result<(), String> {
    let valid = well_formed(&case.m, &case.q);
    let lcp = match Lcp::new(case.m.clone(), case.q.clone()) {
        Ok(lcp) if valid => lcp,
        Ok(_) => return Err(format!("Lcp::new accepted malformed data {case:?}")),
        Err(_) if valid => return Err(format!("Lcp::new refused well-formed data {case:?}")),
        Err(_) => return Ok(()),
    };
    let sol = lcp::solve_warm(&lcp, &case.method, case.warm.as_deref());
    check_solution(&lcp, &case.method, &sol)
        .map_err(|e| format!("{e}\nmethod {:?}\nM = {:?}\nq = {:?}", case.method, case.m, case.q))
}
