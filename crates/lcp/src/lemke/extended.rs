//! Lemke's method in double-double arithmetic: the rung between the `f64`
//! ladder and exact Lemke.
//!
//! A heavy body resting on a light one makes contact LCPs whose bases mix the
//! light body's mobility (~1) with the heavy one's (~1/mass ratio): at a
//! mass ratio of 1e7–1e8 with statically indeterminate contact, `C` of the
//! bases on Lemke's path has cond ~1e17 and more, so `f64` pivoting cannot
//! tell a tie from a step or get the final values right, while exact Lemke
//! (`exact`) solves them but at n = 80 takes ~0.8 s. Here the same method
//! runs in [`Dd`] (~106 bits) on the working problem of the first rung
//! (equilibrated by powers of two, so the scaling adds no round-off): a dense
//! tableau `B⁻¹[I | −M | −d | q]` pivoted from the all-slack basis (`d = 1`)
//! with the lexicographic ratio test of the `f64` rule (relative ties, z0
//! first), its final basis re-solved with refinement
//! ([`dd_solve`](super::dd_solve)). Measured on twelve such LCPs (n = 60–80,
//! 1e6–1e8 kg on 1 kg): all solved in 38–160 pivots. Re-solving the `f64`
//! rungs' final bases in double-double instead solved none of them: their
//! paths, not only their values, had gone wrong.
//!
//! Each answer, rounded to `f64`, must pass the acceptance rule in the units
//! given. The tableau costs `n·(2n + 2)` double-double operations a pivot at
//! most (zeros are skipped): milliseconds at n = 80.

use super::basis::key;
use super::dd_solve::solve_basis;
use crate::ddouble::Dd;
use crate::problem::Lcp;
use std::collections::HashSet;

/// Largest problem the rung is tried on (a tableau of 2 MB); its time is
/// bounded by the caller's operation budget at any n.
pub(crate) const MAX_N: usize = 256;

/// Entering-column entries below this fraction of the column's largest are
/// zero. Measured on heavy-on-light LCPs (1e7, 1e8 kg on 1 kg): with 1e-20
/// one ends on a false ray, another cycles (true pivots of ~1e-21 of their
/// column are dropped); 1e-24 and 1e-28 solve both.
const PIV_REL: f64 = 1e-24;

/// Ratios tie within this fraction of the largest basic value (see
/// `ratio::lexicographic`; the `f64` rule uses 1e-13).
const TIE_TOL: f64 = 1e-24;

/// How the rung ended.
pub(crate) enum ExtEnd {
    /// `z` in the working units of the problem given to [`solve`] and its basis.
    Solved(Vec<f64>, Vec<bool>),
    /// A ray, a cycle, the pivot limit: no answer.
    Failed,
}

/// The dense tableau: row `i` holds `2n + 2` entries (columns `w_0..w_{n-1}`,
/// `z_0..z_{n-1}`, `z0`, right side); `basic[i]` is row `i`'s variable.
struct Tableau {
    n: usize,
    width: usize,
    t: Vec<Dd>,
    basic: Vec<usize>,
    /// Scratch: the nonzero columns of the pivot row.
    nz: Vec<usize>,
}

impl Tableau {
    /// `[I | −M | −1 | q]`, basis `w`.
    fn new(lcp: &Lcp) -> Tableau {
        let (n, width) = (lcp.n(), 2 * lcp.n() + 2);
        let mut t = vec![Dd::ZERO; n * width];
        for i in 0..n {
            let row = &mut t[i * width..(i + 1) * width];
            row[i] = Dd::ONE;
            for (x, m) in row[n..2 * n].iter_mut().zip(lcp.row(i)) {
                *x = Dd::of(-m);
            }
            row[2 * n] = Dd::of(-1.0);
            row[2 * n + 1] = Dd::of(lcp.q()[i]);
        }
        Tableau { n, width, t, basic: (0..n).collect(), nz: Vec::new() }
    }

    #[inline]
    fn at(&self, i: usize, c: usize) -> Dd {
        self.t[i * self.width + c]
    }

    fn rhs(&self, i: usize) -> Dd {
        self.at(i, 2 * self.n + 1)
    }

    /// Gauss–Jordan pivot on row `r`, column `c`; returns the double-double
    /// operations spent.
    fn pivot(&mut self, r: usize, c: usize) -> usize {
        let w = self.width;
        let inv = Dd::ONE / self.at(r, c);
        self.nz.clear();
        for k in 0..w {
            let v = &mut self.t[r * w + k];
            if !v.is_zero() {
                *v = *v * inv;
                self.nz.push(k);
            }
        }
        self.t[r * w + c] = Dd::ONE;
        let (head, tail) = self.t.split_at_mut(r * w);
        let (prow, tail) = tail.split_at_mut(w);
        let mut ops = self.nz.len();
        for row in head.chunks_exact_mut(w).chain(tail.chunks_exact_mut(w)) {
            let f = row[c];
            if f.is_zero() {
                continue;
            }
            for &k in &self.nz {
                row[k] = row[k].sub_mul(f, prow[k]);
            }
            row[c] = Dd::ZERO;
            ops += self.nz.len();
        }
        self.basic[r] = c;
        ops
    }

    /// The leaving row for entering column `c` (lexicographic, relative ties,
    /// z0 first), or `None` for a ray.
    fn leaving(&self, c: usize) -> Option<usize> {
        let n = self.n;
        let xmax = (0..n).fold(0.0f64, |m, i| m.max(self.at(i, c).hi.abs()));
        let thresh = PIV_REL * xmax;
        let cands: Vec<usize> = (0..n).filter(|&i| self.at(i, c).hi > thresh).collect();
        let theta = cands.iter().map(|&i| self.rhs(i) / self.at(i, c)).fold(None, |m: Option<Dd>, r| match m {
            Some(m) if m <= r => Some(m),
            _ => Some(r),
        })?;
        let vmax = (0..n).fold(0.0f64, |m, i| m.max(self.rhs(i).hi.abs()));
        // Rows that reach zero within TIE_TOL·vmax at step theta.
        let mut tied: Vec<usize> =
            cands.into_iter().filter(|&i| self.rhs(i).sub_mul(theta, self.at(i, c)).hi <= TIE_TOL * vmax).collect();
        if let Some(&z0) = tied.iter().find(|&&i| self.basic[i] == 2 * n) {
            return Some(z0);
        }
        // Break ties on the rows of B⁻¹ (the w columns) over the pivot.
        for k in 0..n {
            if tied.len() <= 1 {
                break;
            }
            let v: Vec<Dd> = tied.iter().map(|&i| self.at(i, k) / self.at(i, c)).collect();
            let min = v.iter().copied().fold(v[0], |a, x| if x < a { x } else { a });
            let scale = v.iter().fold(0.0f64, |a, x| a.max(x.hi.abs()));
            let mut it = v.iter();
            tied.retain(|_| (*it.next().expect("one value per row") - min).hi <= TIE_TOL * scale);
        }
        tied.into_iter().max_by(|&a, &b| self.at(a, c).hi.total_cmp(&self.at(b, c).hi))
    }
}

/// Re-solves the complementary basis `mask` of `work` in double-double: `z`
/// (working units, negatives of round-off size clipped) if it is finite.
pub(crate) fn resolve(work: &Lcp, mask: &[bool]) -> Option<Vec<f64>> {
    let alpha: Vec<usize> = (0..mask.len()).filter(|&j| mask[j]).collect();
    let za = solve_basis(work, &alpha)?;
    let mut z = vec![0.0; work.n()];
    for (&j, v) in alpha.iter().zip(&za) {
        z[j] = v.to_f64();
    }
    Some(z)
}

/// Lemke on `work` in double-double from the all-slack basis, at most
/// `max_pivots` pivots and `max_ops` double-double operations; the final
/// basis re-solved by [`resolve`]. Returns how it ended and the pivots taken.
pub(crate) fn solve(work: &Lcp, max_pivots: usize, max_ops: usize) -> (ExtEnd, usize) {
    let n = work.n();
    let mut t = Tableau::new(work);
    if (0..n).all(|i| t.rhs(i).hi >= 0.0) {
        return (ExtEnd::Solved(vec![0.0; n], vec![false; n]), 0);
    }
    if max_pivots == 0 {
        return (ExtEnd::Failed, 0);
    }
    let z0 = 2 * n;
    // z0 enters; the most negative q_i leaves (largest index on ties, as in `ratio::first_leaving`).
    let qmin = (0..n).map(|i| t.rhs(i).hi).fold(f64::INFINITY, f64::min);
    let r = (0..n).rev().find(|&i| t.rhs(i).hi == qmin).unwrap_or(0);
    let mut ops = t.pivot(r, z0);
    let mut entering = n + r;
    let mut hash = (0..n).fold(0u64, |h, i| h ^ key(i)) ^ key(r) ^ key(z0);
    let mut seen = HashSet::from([hash]);
    for pivots in 1..max_pivots {
        let Some(r) = t.leaving(entering) else { return (ExtEnd::Failed, pivots) };
        let left = t.basic[r];
        ops += t.pivot(r, entering);
        if left == z0 {
            let mask: Vec<bool> = (0..n).map(|j| t.basic.contains(&(n + j))).collect();
            return match resolve(work, &mask) {
                Some(z) => (ExtEnd::Solved(z, mask), pivots + 1),
                None => (ExtEnd::Failed, pivots + 1),
            };
        }
        hash ^= key(entering) ^ key(left);
        if !seen.insert(hash) || ops > max_ops {
            return (ExtEnd::Failed, pivots + 1);
        }
        entering = if left < n { left + n } else { left - n };
    }
    (ExtEnd::Failed, max_pivots)
}

#[cfg(test)]
mod tests {
    use super::super::frame::Frame;
    use super::*;

    /// Reads `tests/data/repros/NAME` (`.lcpsparse`; layout in `tests/common/sparse.rs`).
    fn repro(name: &str) -> Lcp {
        let path = format!("{}/../../tests/data/repros/{name}", env!("CARGO_MANIFEST_DIR"));
        let b = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let u64_at = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize;
        let f64_at = |at: usize| f64::from_le_bytes(b[at..at + 8].try_into().unwrap());
        let (n, nnz) = (u64_at(10), u64_at(18));
        let mut m = vec![0.0; n * n];
        for k in 0..nnz {
            let i = u32::from_le_bytes(b[26 + 4 * k..30 + 4 * k].try_into().unwrap()) as usize;
            m[i] = f64_at(26 + 4 * nnz + 8 * k);
        }
        let q = (0..n).map(|i| f64_at(26 + 12 * nnz + 8 * i)).collect();
        Lcp::new(m, q).unwrap()
    }

    /// The heavy-on-light LCP of `tests/heavy_on_light_regression.rs`: this
    /// rung alone solves it, within the acceptance rule, in the units given.
    #[test]
    fn solves_a_heavy_body_on_a_light_one() {
        let lcp = repro("heavy1e6_slide_step1876.lcpsparse");
        let mut frame = Frame::default();
        frame.reset(&lcp, true, crate::accept::DEFAULT_TOL);
        let (end, pivots) = solve(&frame.work, 4000, 20_000_000);
        let ExtEnd::Solved(z, _) = end else { panic!("not solved ({pivots} pivots)") };
        let sol = frame.solution(&lcp, &z, crate::Status::Solved, pivots);
        assert!(sol.accepted, "residual {:e}", sol.residuals.residual);
        assert!(pivots < 400, "{pivots} pivots");
    }

    /// Per-solve time of the rung (release):
    /// `cargo test --release -p lcpsim-lcp --lib extended::tests::timing -- --ignored --nocapture`
    #[test]
    #[ignore]
    fn timing() {
        let lcp = repro("heavy1e6_slide_step1876.lcpsparse");
        let mut frame = Frame::default();
        frame.reset(&lcp, true, crate::accept::DEFAULT_TOL);
        let reps = 50;
        let t = std::time::Instant::now();
        let mut pivots = 0;
        for _ in 0..reps {
            pivots = solve(&frame.work, 4000, 20_000_000).1;
        }
        let ms = t.elapsed().as_secs_f64() * 1e3 / reps as f64;
        println!("n = {}: {pivots} pivots, {ms:.2} ms per solve", lcp.n());
    }
}
