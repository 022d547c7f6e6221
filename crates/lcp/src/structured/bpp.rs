//! Block principal pivoting on a structured LCP (Júdice–Pires, with Murty's
//! single exchanges as the safeguard): a complementary basis improved by
//! exchanging many complementary pairs per sparse factorization.
//!
//! From a complementary basis `α` (`z_j` basic for `j ∈ α`, `w_i` for
//! `i ∉ α`) the basic values solve `w_ᾱ − M_ᾱα z_α = q_ᾱ`, `−M_αα z_α = q_α`
//! by one factorization of the augmented basis ([`super::factor`]). Every
//! basic value that is negative (infeasible) has its pair exchanged at once
//! while that lowers the least count of infeasible values seen, or lets it
//! rise for at most [`BppOptions::patience`] rounds; after that a single pair
//! is exchanged (Murty's rule: the largest infeasible index) until the count
//! drops below the least again. On a P-matrix this ends at the answer; a
//! contact LCP is no P-matrix (the `λ` rows have a zero diagonal, many bases
//! are singular), so the rounds are capped and a singular basis is repaired
//! column by column ([`Basis::complementary`]).
//!
//! The result is a basis, not an answer: its values are judged by the
//! acceptance rule by the caller ([`super::solve`]), or it is where Lemke's
//! warm start begins.
//!
//! Not used by the simulator's step: on a forming 200-cube heap's LCPs
//! (steps 175–179, n = 9,900–12,130, `heap_replay solve bpp:previous`) no
//! round lowered the infeasible count of the previous step's basis
//! (686–1,586 negative values; at step 175 690 of 800 below −1e-3 of the
//! largest), so Lemke's pivots from it stayed 2,835–13,472 as without: a
//! flat exchange of every infeasible pair gave singular bases (values
//! ~1e16–1e66), the contact-wise exchange ([`contact_exchange`]) bases
//! singular down to 8–79 moves and, when regular, with as many or more
//! negative values; single exchanges raised the count too. Such heaps are
//! statically indeterminate: most principal submatrices near an answer are
//! singular or nearly so, where block pivoting (a Newton step on a P-matrix)
//! has nothing to stand on.

use super::factor::{Basis, NONBASIC};
use super::guess::Span;
use super::operator::StructuredLcp;
use crate::contact::ContactLayout;
use std::collections::{HashMap, HashSet};

/// Options of the block principal pivoting.
#[derive(Clone, Debug, PartialEq)]
pub struct BppOptions {
    /// Factorizations at most. Default 30.
    pub max_rounds: usize,
    /// Block exchanges in a row that may leave the least infeasible count
    /// unimproved before single exchanges take over. Default 3.
    pub patience: usize,
    /// Column swaps at most to make a singular basis regular. Default 64.
    pub repairs: usize,
}

impl Default for BppOptions {
    fn default() -> Self {
        BppOptions { max_rounds: 30, patience: 3, repairs: 64 }
    }
}

/// What the rounds found.
#[derive(Clone, Debug)]
pub struct BppRun {
    /// The regular complementary basis with the fewest infeasible values seen (`true`: `z_j` basic).
    pub basis: Vec<bool>,
    /// `z` of that basis (its basic values, 0 elsewhere; not clipped).
    pub z: Vec<f64>,
    /// Its count of infeasible values (0: `z`, `w` are feasible and complementary).
    pub infeasible: usize,
    /// The count of the start (after its repair).
    pub infeasible_start: usize,
    /// Factorizations done.
    pub rounds: usize,
}

/// A basic value counts as infeasible below this fraction of the largest
/// (at least 1), as the warm start of [`super::pivot`] counts it.
const NEGATIVE: f64 = 1e-12;

/// Block principal pivoting from the complementary basis `start` (module
/// docs), on a contact LCP with its layout `lay` when given (the exchange of
/// [`contact_exchange`]). `None` when no regular basis was found from it.
///
/// An exchange whose basis is singular, or whose values blow up past
/// [`BLOWUP`] times the start's (singular but for round-off), is retried
/// with the first half of its moves (a move: one contact's changes, or one
/// pair's without a layout; the most infeasible first), down to one move;
/// when even that fails the rounds end.
pub fn improve(op: &StructuredLcp, start: &[bool], o: &BppOptions, lay: Option<ContactLayout>) -> Option<BppRun> {
    let n = op.n();
    if start.len() != n {
        return None;
    }
    let d = vec![0.0; n];
    let lay = lay.filter(|l| l.n() == n);
    let mut inz = start.to_vec();
    let mut b = factored(op, &d, &mut inz, o.repairs)?;
    let first_top = top_of(&b.val);
    let mut rounds = 1;
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let (mut z, mut w) = (Vec::new(), vec![0.0; n]);
    let mut best: Option<BppRun> = None;
    let mut stalls = 0;
    loop {
        seen.insert(inz.clone());
        let top = top_of(&b.val);
        let tol = NEGATIVE * top;
        let count = b.val.iter().filter(|&&v| v < -tol).count();
        b.z_into(&mut z);
        let start_count = best.as_ref().map_or(count, |r| r.infeasible_start);
        if best.as_ref().is_none_or(|r| count < r.infeasible) {
            best = Some(BppRun {
                basis: inz.clone(),
                z: z.clone(),
                infeasible: count,
                infeasible_start: start_count,
                rounds,
            });
            stalls = 0;
        } else {
            stalls += 1;
        }
        if count == 0 || rounds >= o.max_rounds {
            break;
        }
        op.w_of(&z, &mut w);
        let block = match lay {
            Some(lay) => contact_exchange(op, lay, &inz, &z, &w, tol),
            None => (0..n).map(|i| inz[i] != (if inz[i] { z[i] } else { w[i] } < -tol)).collect(),
        };
        // Moves: the changes grouped by contact (by pair without a layout), most infeasible first.
        let group = |i: usize| lay.map_or(i, |l| if i < l.n() { l.contact_of(i) } else { i });
        let mut moves: HashMap<usize, (f64, Vec<usize>)> = HashMap::new();
        for i in (0..n).filter(|&i| block[i] != inz[i]) {
            let bad = -(if inz[i] { z[i] } else { w[i] });
            let m = moves.entry(group(i)).or_insert((0.0, Vec::new()));
            m.0 = m.0.max(bad);
            m.1.push(i);
        }
        let mut moves: Vec<(usize, (f64, Vec<usize>))> = moves.into_iter().collect();
        moves.sort_by(|a, b| b.1 .0.total_cmp(&a.1 .0).then(a.0.cmp(&b.0)));
        // Patience out: single moves; without a layout Murty's (the largest
        // infeasible index: finite on a P-matrix), with one the most infeasible contact's.
        let murty = stalls > o.patience;
        if murty && lay.is_none() {
            moves.sort_by_key(|m| std::cmp::Reverse(m.0));
        }
        let mut m = if murty { 1 } else { moves.len() };
        let accepted = loop {
            if m == 0 || rounds >= o.max_rounds {
                break None;
            }
            let mut cand = inz.clone();
            moves[..m].iter().flat_map(|(_, (_, is))| is).for_each(|&i| cand[i] = !cand[i]);
            if seen.contains(&cand) {
                m /= 2;
                continue;
            }
            set_alpha(&mut b, &cand);
            rounds += 1;
            let ok = b.refactor() && top_of(&b.val) <= BLOWUP * first_top;
            if ok {
                break Some(cand);
            }
            seen.insert(cand);
            m /= 2;
        };
        match accepted {
            Some(cand) => inz = cand,
            None => break,
        }
    }
    best.map(|r| BppRun { rounds, ..r })
}

/// The largest basic value's magnitude, at least 1.
fn top_of(val: &[f64]) -> f64 {
    val.iter().fold(1.0f64, |a, v| a.max(v.abs()))
}

/// Sets `b`'s positions to the complementary basis `inz` (not refactored).
fn set_alpha(b: &mut Basis, inz: &[bool]) {
    let n = inz.len();
    for (i, &z) in inz.iter().enumerate() {
        let v = if z { n + i } else { i };
        if b.var[i] != v {
            b.pos[b.var[i]] = NONBASIC;
            b.var[i] = v;
            b.pos[v] = i;
        }
    }
}

/// Basic values above this multiple of the first basis's largest are taken for a singular basis.
const BLOWUP: f64 = 1e6;

/// The block exchange on a contact LCP (layout `lay`): the infeasible pairs
/// exchanged contact by contact in ways that keep the basis regular where
/// its structure shows how (a flat exchange of every infeasible pair made
/// the bases of a forming heap's LCPs singular at once):
/// - a loaded contact whose `z_fn < 0` is unloaded: its friction becomes a
///   separating contact's (`λ` and the most opposed `fd` basic when the
///   tangential velocity opposes a direction, else none);
/// - within a loaded contact (staying or entering) the friction pairs are
///   exchanged, then `λ` basic with no `fd` basic takes the most opposed
///   `fd` (the `λ` column has entries only in its `fd` rows);
/// - normal and friction columns enter only while independent of the
///   basic impulse columns of their body pair (rows over the same columns
///   of `G`), those staying first.
fn contact_exchange(op: &StructuredLcp, lay: ContactLayout, inz: &[bool], z: &[f64], w: &[f64], tol: f64) -> Vec<bool> {
    let mut next = inz.to_vec();
    let neg = |i: usize| if inz[i] { z[i] < -tol } else { w[i] < -tol };
    let most_opposed = |c: usize| lay.fd_of(c).min_by(|&a, &b| w[a].total_cmp(&w[b]));
    // Entering impulse columns, checked against their pair's span below.
    let mut entering: Vec<(usize, f64)> = Vec::new();
    for c in 0..lay.nc {
        let (i, l, fd) = (lay.fn_index(c), lay.lambda_index(c), lay.fd_of(c));
        if !(std::iter::once(i).chain(fd.clone()).chain(std::iter::once(l)).any(neg)) {
            continue;
        }
        let loaded = if inz[i] { z[i] >= -tol } else { w[i] < -tol };
        if !loaded {
            next[i] = false;
            fd.clone().for_each(|f| next[f] = false);
            next[l] = false;
            // Opposed: w_fd below λ's shift s·λ (all directions share it).
            if let Some(f) = most_opposed(c) {
                let shift = op.at(f, l) * if inz[l] { z[l] } else { 0.0 };
                if w[f] - shift < -tol {
                    next[f] = true;
                    next[l] = true;
                }
            }
            continue;
        }
        if !inz[i] {
            next[i] = false;
            entering.push((i, -w[i]));
        }
        for f in fd.clone().filter(|&f| neg(f)) {
            if inz[f] {
                next[f] = false;
            } else {
                entering.push((f, -w[f]));
            }
        }
        if neg(l) {
            next[l] = !inz[l];
        }
        if next[l] && !fd.clone().any(|f| next[f] || entering.iter().any(|e| e.0 == f)) {
            if let Some(f) = most_opposed(c) {
                entering.push((f, f64::INFINITY));
            }
        }
    }
    // Body pairs' spans: the basic impulse columns that stay, then the entering ones, most negative first.
    let mut spans: HashMap<Vec<usize>, Span> = HashMap::new();
    let pair = |i: usize| op.g_rows.iter(lay.fn_index(lay.contact_of(i))).map(|(j, _)| j).collect::<Vec<usize>>();
    for i in (0..lay.impulses()).filter(|&i| next[i]) {
        let cols = pair(i);
        spans.entry(cols.clone()).or_insert_with(|| Span::new(cols)).add(op, i);
    }
    entering.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    for (i, _) in entering {
        let cols = pair(i);
        if !next[i] && spans.entry(cols.clone()).or_insert_with(|| Span::new(cols)).add(op, i) {
            next[i] = true;
        }
    }
    // λ basic needs an fd basic of its contact.
    for c in 0..lay.nc {
        let l = lay.lambda_index(c);
        if next[l] && !lay.fd_of(c).any(|f| next[f]) {
            next[l] = false;
        }
    }
    next
}

/// The basis `inz` factored, repaired if singular (`inz` updated to the repaired basis).
fn factored<'a>(op: &'a StructuredLcp, d: &'a [f64], inz: &mut [bool], repairs: usize) -> Option<Basis<'a>> {
    let n = op.n();
    let alpha: Vec<usize> = (0..n).filter(|&j| inz[j]).collect();
    let mut b = Basis::complementary(op, &alpha, repairs)?;
    b.set_cover(d);
    inz.iter_mut().for_each(|v| *v = false);
    b.alpha().iter().for_each(|&j| inz[j] = true);
    Some(b)
}
