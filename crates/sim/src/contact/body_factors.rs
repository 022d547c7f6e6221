//! The contact LCP handed to [`lcp::structured`]: `M = G H + K` with
//! `G = J` (the Jacobian rows over the dynamic bodies' 6 dofs each),
//! `H = M_b⁻¹ Jᵀ` and `K` the cone blocks at scale `s`:
//!
//! ```text
//! K[fd, λ] = s·E      K[λ, fn] = s·μ      K[λ, fd] = −s·Eᵀ
//! ```
//!
//! Only the dynamic bodies the contacts touch get dofs (numbered in order of
//! first appearance), so an island's operator does not grow with the world.

use super::assembly::{ContactLcp, Row6};
use lcp::structured::{Entry, StructuredLcp};
use lcp::LcpError;

/// The structured LCP of `lcp`'s rows at cone scale `s` (`lcp.scale()`: the
/// LCP the dense path solves; 1: the physical one).
pub fn structured_lcp(lcp: &ContactLcp, s: f64) -> Result<StructuredLcp, LcpError> {
    let mut e = Factors::default();
    let p = e.fill(lcp, s);
    StructuredLcp::new(p, &e.g, &e.h, &e.k, lcp.q().to_vec())
}

/// The entries of `G`, `H` and `K` of [`structured_lcp`], in the order it
/// gives them (the same order for the same contacts' bodies, so that
/// `StructuredLcp::refill` can take them), with their buffers.
#[derive(Clone, Debug, Default)]
pub struct Factors {
    pub g: Vec<Entry>,
    pub h: Vec<Entry>,
    pub k: Vec<Entry>,
}

impl Factors {
    /// The entries of `lcp`'s rows at cone scale `s`; returns `p`, the dofs.
    pub fn fill(&mut self, lcp: &ContactLcp, s: f64) -> usize {
        let lay = lcp.layout();
        let Factors { g, h, k } = self;
        (g.clear(), h.clear(), k.clear());
        // Compact dof numbering of the dynamic bodies.
        let mut slot = vec![usize::MAX; lcp.body_count()];
        let mut bodies = 0;
        let dir = |r: &[Row6; 3], j: usize| -> Row6 {
            let (c, sn) = lcp.cos_sin(j);
            std::array::from_fn(|m| c * r[1][m] + sn * r[2][m])
        };
        for c in 0..lay.nc {
            for side in 0..2 {
                let Some(b) = lcp.side_body(c, side) else { continue };
                if slot[b] == usize::MAX {
                    slot[b] = bodies;
                    bodies += 1;
                }
                let base = 6 * slot[b];
                let (jac, minv) = lcp.side_rows(c, side);
                let mut put = |i: usize, jrow: &Row6, mrow: &Row6| {
                    for m in 0..6 {
                        g.push((i, base + m, jrow[m]));
                        h.push((base + m, i, mrow[m]));
                    }
                };
                put(lay.fn_index(c), &jac[0], &minv[0]);
                for (j, f) in lay.fd_of(c).enumerate() {
                    put(f, &dir(jac, j), &dir(minv, j));
                }
            }
            let l = lay.lambda_index(c);
            for f in lay.fd_of(c) {
                k.push((f, l, s));
                k.push((l, f, -s));
            }
            k.push((l, lay.fn_index(c), s * lcp.mu()[c]));
        }
        6 * bodies
    }
}
