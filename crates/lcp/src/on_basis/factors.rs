//! A fresh factorization of the block `M_SS` on the regular block `β`.
//!
//! Statically indeterminate contact (four corners of a box on a box bear a
//! load that three constraints fix) makes a guessed basis rank-deficient. The
//! block is factored by the principal rank-revealing LU of [`principal`]
//! (shared with the dense Lemke's warm start); dependent indices leave the
//! support (`z_j = 0`, `w_j` basic instead), which keeps the previous vertex
//! of the solution set instead of jumping to another — the reason a resting
//! stack needs no pivot.

use super::principal;
use super::refine::{correct, first_solve};
use super::workspace::{BasisWorkspace, Factors};
use crate::kernels::max_abs_finite;
use crate::operator::LcpOperator;

/// Factors `M_SS` of the support `ws.mask`: when the support is the factored
/// `β` and the index `entered`, by bordering `β`'s factors ([`border`]),
/// else afresh ([`principal::factor`], `entered` pivoted first so that it
/// stays basic); then `z` on its regular block `β` with one refinement step
/// and `w = M z + q`, unclipped. `false` if the block or `z` is not finite.
///
/// Bordering, measured on resting stacks (`stack_steps 2000 4 … 16`): the
/// exchange rounds' fresh factorizations were ~11 % of the run; with it
/// steps that pivot 42 → 24, pivots 9,001 → 3,871, 26,000 steps 2.6 → 1.9 s
/// (the values differ from a fresh factorization's in their last digits, and
/// which steps pivot is chaotic: judged on the family).
pub(super) fn solve_fresh(op: &dyn LcpOperator, ws: &mut BasisWorkspace, entered: Option<usize>) -> bool {
    let n = op.n();
    // The factors of β when the new support is β and the entering index.
    let grown = entered.filter(|&i| {
        ws.f.factored.len() == n && !ws.f.factored[i] && (0..n).all(|j| ws.mask[j] == (ws.f.factored[j] || j == i))
    });
    // β's factors move aside (into `grown_from`, whose buffers `ws` takes over).
    let old = grown.is_some().then(|| {
        let mut old = std::mem::take(&mut ws.grown_from);
        ws.swap_factors(&mut old);
        old
    });
    ws.f.factored.clear();
    // (New factors: no inverse of them yet.)
    ws.f.inverse = None;
    ws.f.support.clear();
    ws.f.support.extend((0..n).filter(|&j| ws.mask[j]));
    let m = ws.f.support.len();
    form_block(op, ws);
    // (One pass over lanes: the block is `k²` entries.)
    if !max_abs_finite(&ws.block, 0.0).1 {
        return false;
    }
    let bordered = matches!((grown, &old), (Some(i), Some(f)) if border(ws, i, f));
    if let Some(old) = old {
        ws.grown_from = old;
    }
    if !bordered {
        ws.f.lu.clone_from(&ws.block);
        let first = entered.and_then(|i| ws.f.support.binary_search(&i).ok());
        ws.f.rank = principal::factor(&mut ws.f.lu, m, &mut ws.f.order, first);
    }
    first_solve(op, ws);
    op.w_of(&ws.z, &mut ws.w);
    correct(ws);
    if !ws.z.iter().all(|v| v.is_finite()) {
        return false;
    }
    op.w_of(&ws.z, &mut ws.w);
    ws.f.factored.resize(n, false);
    for &p in &ws.f.order[..ws.f.rank] {
        ws.f.factored[ws.f.support[p]] = true;
    }
    true
}

/// The factors of `β ∪ {i}` from those of the regular block `β` (`old`, its
/// `rank` pivots; the new support `ws.f.support` is exactly `β` and `i`, its
/// block in `ws.block`): `i` bordered on as the last pivot, `L⁻¹ M_βi` its
/// column of `U`, `M_iβ U⁻¹` its row of `L` and `M_ii − M_iβ M_ββ⁻¹ M_βi` its
/// pivot — `O(k²)` where a fresh factorization costs `O(k³)`. `false` (`ws`'s
/// factors unset) when that pivot is below the rank tolerance of
/// [`principal::factor`]: `i` depends on `β`, and the fresh factorization
/// decides which index leaves. (`ws.y` holds the new column of U meanwhile.)
pub(super) fn border(ws: &mut BasisWorkspace, i: usize, old: &Factors) -> bool {
    let (m, r, k) = (ws.f.support.len(), old.rank, old.support.len());
    if m != r + 1 {
        return false;
    }
    let at = |j: usize| ws.f.support.binary_search(&j).ok();
    let Some(pi) = at(i) else { return false };
    // The new support's position of each pivot of β, in pivot order.
    let BasisWorkspace { block, f: Factors { lu, order, .. }, y: col, .. } = ws;
    order.clear();
    for &p in &old.order[..r] {
        let Some(a) = at(old.support[p]) else { return false };
        order.push(a);
    }
    // (Every entry is written below.)
    lu.resize(m * m, 0.0);
    for t in 0..r {
        lu[t * m..t * m + r].copy_from_slice(&old.lu[t * k..t * k + r]);
    }
    // y = L⁻¹ M_βi (the new column of U), x = M_iβ U⁻¹ (the new row of L).
    // (The column is built in `col` as well, so that each row's sum reads
    // it contiguously: the same products summed in the same order.)
    col.clear();
    for t in 0..r {
        let sum = lu[t * m..t * m + t].iter().zip(col.iter()).map(|(l, u)| l * u).sum::<f64>();
        let u = block[order[t] * m + pi] - sum;
        lu[t * m + r] = u;
        col.push(u);
    }
    for t in 0..r {
        // (Column t of U read by a stride: `lu[s·m + t]`, s < t.)
        let sum = lu[r * m..r * m + t].iter().zip(lu[t..].iter().step_by(m)).map(|(l, u)| l * u).sum::<f64>();
        let l = block[pi * m + order[t]] - sum;
        lu[r * m + t] = l / lu[t * m + t];
    }
    let pivot = block[pi * m + pi] - (0..r).map(|t| lu[r * m + t] * lu[t * m + r]).sum::<f64>();
    // (The block is finite: its largest entry as a lane max is the same.)
    let amax = max_abs_finite(block, 0.0).0;
    if !(pivot.abs() > principal::RANK_TOL * amax) {
        return false;
    }
    lu[r * m + r] = pivot;
    order.push(pi);
    ws.f.rank = m;
    true
}

/// `ws.block` ← `M_SS` for the support `ws.f.support`. Within a call, the
/// entries of the previous block are copied and only the rows and columns of
/// indices new to the support are formed: an exchange round adds or removes
/// one index, so a round forms `2k` entries instead of `k²` (on a resting
/// 10-box stack forming the block was 11 % of the run, a fresh
/// factorization's share 12 %).
pub(super) fn form_block(op: &dyn LcpOperator, ws: &mut BasisWorkspace) {
    let m = ws.f.support.len();
    let BasisWorkspace {
        f: Factors { support, .. },
        block,
        block_support,
        blocked,
        block_pos,
        block_prev,
        block_fresh,
        fresh_at,
        fresh,
        block_runs,
        ..
    } = ws;
    // (Every entry of the block is written below: it is sized, not cleared.)
    if !*blocked {
        block.resize(m * m, 0.0);
        op.block(support, support, block);
        block_support.clone_from(support);
        *blocked = true;
        return;
    }
    std::mem::swap(block, block_prev);
    let (old, k) = (&*block_prev, block_support.len());
    if block_pos.len() != op.n() {
        block_pos.clear();
        block_pos.resize(op.n(), NOT_IN_BLOCK);
    }
    block_support.iter().enumerate().for_each(|(p, &j)| block_pos[j] = p);
    // Positions in the new support of the indices new to it.
    fresh_at.clear();
    fresh_at.extend((0..m).filter(|&a| block_pos[support[a]] == NOT_IN_BLOCK));
    block.resize(m * m, 0.0);
    // The kept columns in runs consecutive in both blocks (an exchange
    // adds or removes one index: at most two runs), each row's copied run
    // by run.
    block_runs.clear();
    for (b, &j) in support.iter().enumerate() {
        let p = block_pos[j];
        if p == NOT_IN_BLOCK {
            continue;
        }
        match block_runs.last_mut() {
            Some((b0, p0, len)) if *b0 + *len == b && *p0 + *len == p => *len += 1,
            _ => block_runs.push((b, p, 1)),
        }
    }
    for (a, &i) in support.iter().enumerate() {
        if block_pos[i] != NOT_IN_BLOCK {
            let row = &old[block_pos[i] * k..(block_pos[i] + 1) * k];
            let out = &mut block[a * m..(a + 1) * m];
            for &(b, p, len) in block_runs.iter() {
                out[b..b + len].copy_from_slice(&row[p..p + len]);
            }
        }
    }
    if !fresh_at.is_empty() {
        // The new indices' columns (every row), then their rows (every column).
        let f = fresh_at.len();
        fresh.clear();
        fresh.extend(fresh_at.iter().map(|&a| support[a]));
        block_fresh.resize(m * f, 0.0);
        op.block(support, fresh, block_fresh);
        for a in 0..m {
            for (t, &b) in fresh_at.iter().enumerate() {
                block[a * m + b] = block_fresh[a * f + t];
            }
        }
        op.block(fresh, support, block_fresh);
        for (t, &a) in fresh_at.iter().enumerate() {
            block[a * m..(a + 1) * m].copy_from_slice(&block_fresh[t * m..(t + 1) * m]);
        }
    }
    block_support.iter().for_each(|&j| block_pos[j] = NOT_IN_BLOCK);
    block_support.clone_from(support);
}

/// [`form_block`]'s mark of an index outside the previous block.
pub(super) const NOT_IN_BLOCK: usize = usize::MAX;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Lcp;

    /// Bordering an index onto the factors of a regular block solves the grown
    /// block as a fresh factorization does (to round-off), and refuses an
    /// index that depends on the block.
    #[test]
    fn a_bordered_index_solves_the_grown_block() {
        for seed in 0..10 {
            let lcp = crate::generate::p_matrix_lcp(24, seed);
            let (mut ws, old) = factored(&lcp, (0..24).filter(|j| j % 4 != 1).collect());
            let m = old.support.len();
            assert_eq!(ws.f.rank, m, "a P-matrix's principal blocks are regular");
            let i = 5;
            ws.f.support = (0..24).filter(|&j| j % 4 != 1 || j == i).collect();
            ws.blocked = true;
            form_block(&lcp, &mut ws);
            assert!(border(&mut ws, i, &old), "seed {seed}");
            let b: Vec<f64> = (0..m + 1).map(|t| (t as f64 * 0.37).sin()).collect();
            let (mut x, mut y) = (b.clone(), Vec::new());
            principal::solve(&ws.f.lu, m + 1, &ws.f.order, ws.f.rank, &mut x, &mut y);
            let mut fresh = ws.block.clone();
            let mut order = Vec::new();
            let rank = principal::factor(&mut fresh, m + 1, &mut order, None);
            let mut x0 = b.clone();
            principal::solve(&fresh, m + 1, &order, rank, &mut x0, &mut y);
            for (u, v) in x.iter().zip(&x0) {
                assert!((u - v).abs() <= 1e-10 * (1.0 + v.abs()), "seed {seed}: {u} vs {v}");
            }
        }
        // An index equal to one of the block's columns is refused.
        let m = vec![2.0, 1.0, 2.0, 1.0, 3.0, 1.0, 2.0, 1.0, 2.0];
        let lcp = Lcp::new(m, vec![-1.0; 3]).unwrap();
        let (mut ws, old) = factored(&lcp, vec![0, 1]);
        ws.f.support = vec![0, 1, 2];
        form_block(&lcp, &mut ws);
        assert!(!border(&mut ws, 2, &old), "column 2 is column 0");
    }

    /// A workspace holding the factors of `lcp`'s block on `support`, and a copy of them.
    fn factored(lcp: &Lcp, support: Vec<usize>) -> (BasisWorkspace, Factors) {
        let mut ws =
            BasisWorkspace { f: Factors { support: support.clone(), ..Default::default() }, ..Default::default() };
        form_block(lcp, &mut ws);
        ws.f.lu.clone_from(&ws.block);
        ws.f.rank = principal::factor(&mut ws.f.lu, support.len(), &mut ws.f.order, None);
        let held =
            Factors { lu: ws.f.lu.clone(), support, order: ws.f.order.clone(), rank: ws.f.rank, ..Default::default() };
        (ws, held)
    }

    /// The block grown from the previous one, index by index in and out, is
    /// the block formed afresh, bit for bit.
    #[test]
    fn a_grown_block_is_the_block_formed_afresh() {
        let lcp = crate::generate::p_matrix_lcp(30, 7);
        let mut ws = BasisWorkspace::default();
        let mut mask: Vec<bool> = (0..30).map(|j| j % 3 != 0).collect();
        for (round, toggle) in [None, Some(0), Some(4), Some(29), Some(3), Some(0), Some(12)].into_iter().enumerate() {
            if let Some(j) = toggle {
                mask[j] = !mask[j];
            }
            ws.blocked = round > 0;
            ws.f.support = (0..30).filter(|&j| mask[j]).collect();
            form_block(&lcp, &mut ws);
            let m = ws.f.support.len();
            let mut afresh = vec![0.0; m * m];
            lcp.block(&ws.f.support, &ws.f.support, &mut afresh);
            assert_eq!(ws.block, afresh, "round {round}");
            assert_eq!(ws.block_support, ws.f.support);
        }
    }
}
