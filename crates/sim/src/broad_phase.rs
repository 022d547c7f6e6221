//! Broad phase: which pairs of bodies the narrow phase looks at.
//!
//! A pair is kept when its bounding spheres come within the pair's margin,
//! `|p_i − p_j| ≤ r_i + r_j + margin_ij` (see [`PairMargin`]), and not both
//! bodies are static; a pair with an unbounded shape (a plane) is always kept.
//! That is the rule of the all-pairs loop ([`brute_force_pairs`], kept as the
//! reference for tests and benchmarks), found here by sweep and prune in
//! O(B log B + pairs) instead of O(B²):
//!
//! 1. every bounded body gets the interval `[x − R, x + R]` of its centre
//!    along the axis where the centres spread most, with `R = r + margin/2 +
//!    h·reach` (plus a little round-off slack), so that two spheres within
//!    their pair margin always have overlapping intervals;
//! 2. the intervals are sorted by their lower end and swept: each interval is
//!    paired with the following ones that start before it ends, and each
//!    candidate is checked with the exact sphere test above (the same
//!    floating-point expression as the reference, hence the same pairs);
//! 3. unbounded bodies pair with every body (planes are static, so with
//!    every dynamic one).
//!
//! The pairs come out sorted by `(i, j)`, `i < j` — the order of the
//! all-pairs loop — so contacts, and everything after them, are in the same
//! order whichever broad phase found them.

use crate::dynamics::Body;
use crate::math::Vec3;

/// The margin of a pair: `base + h·(reach_i + reach_j)` when velocity margins
/// are on (`reach_k = |v*_k| + |ω*_k|·r_k`: how fast body k's surface can
/// move), else `base`.
#[derive(Clone, Copy, Debug)]
pub struct PairMargin<'a> {
    /// `WorldParams::margin` (m).
    pub base: f64,
    /// Time step (s).
    pub h: f64,
    /// Reach per body (m/s), or `None` without velocity margins.
    pub reach: Option<&'a [f64]>,
}

impl PairMargin<'_> {
    /// The margin of pair `(i, j)`.
    #[inline]
    pub fn of(&self, i: usize, j: usize) -> f64 {
        let mut margin = self.base;
        if let Some(r) = self.reach {
            margin += self.h * (r[i] + r[j]);
        }
        margin
    }

    /// Body `k`'s share of any of its pair margins: half the base plus its own reach.
    fn half(&self, k: usize) -> f64 {
        0.5 * self.base + self.reach.map_or(0.0, |r| self.h * r[k])
    }
}

/// How fast body `b`'s surface can move with free velocities `v`, `w`: `|v| + |ω|·r`.
pub fn reach(b: &Body, v: Vec3, w: Vec3) -> f64 {
    let r = b.shape.bounding_radius();
    let wn = w.norm();
    v.norm() + if wn > 0.0 { wn * r } else { 0.0 }
}

/// Whether the pair passes the bounding-sphere test (the rule of the module docs).
#[inline]
fn near(bi: &Body, bj: &Body, margin: f64) -> bool {
    let (ri, rj) = (bi.shape.bounding_radius(), bj.shape.bounding_radius());
    !(ri.is_finite() && rj.is_finite() && (bi.position - bj.position).norm() > ri + rj + margin)
}

/// The reference: every pair `i < j` tested, in that order.
pub fn brute_force_pairs(bodies: &[Body], margin: &PairMargin<'_>, out: &mut Vec<(usize, usize)>) {
    out.clear();
    for i in 0..bodies.len() {
        for j in (i + 1)..bodies.len() {
            let (bi, bj) = (&bodies[i], &bodies[j]);
            if !(bi.is_static && bj.is_static) && near(bi, bj, margin.of(i, j)) {
                out.push((i, j));
            }
        }
    }
}

/// A bounded body's box: `[lo, hi]` along the sweep axis, and a cube of half
/// width `ext` about its centre (read in sequence by the sweep: no lookup
/// into the bodies before the boxes overlap).
#[derive(Clone, Copy, Debug)]
struct Span {
    lo: f64,
    hi: f64,
    centre: [f64; 3],
    ext: f64,
    body: usize,
    is_static: bool,
}

impl Span {
    /// Whether the boxes overlap on every axis.
    #[inline]
    fn overlaps(&self, o: &Span) -> bool {
        let e = self.ext + o.ext;
        let (c, d) = (&self.centre, &o.centre);
        // Non-short-circuit `&`: one hard-to-predict branch instead of three.
        ((c[0] - d[0]).abs() <= e) & ((c[1] - d[1]).abs() <= e) & ((c[2] - d[2]).abs() <= e)
    }
}

/// Sweep and prune with reusable buffers (allocation-free once warm).
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// Every bounded body's box, sorted along the sweep axis.
    spans: Vec<Span>,
    /// Bodies with an unbounded shape.
    unbounded: Vec<usize>,
    pairs: Vec<(usize, usize)>,
}

impl BroadPhase {
    pub fn new() -> Self {
        Self::default()
    }

    /// The pairs of the last [`BroadPhase::find`], sorted by `(i, j)`, `i < j`.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// Finds the pairs of `bodies` (the same set as [`brute_force_pairs`]).
    pub fn find(&mut self, bodies: &[Body], margin: &PairMargin<'_>) -> &[(usize, usize)] {
        self.pairs.clear();
        self.unbounded.clear();
        let axis = sweep_axis(bodies);
        self.spans.clear();
        for (k, b) in bodies.iter().enumerate() {
            let r = b.shape.bounding_radius();
            if !r.is_finite() {
                self.unbounded.push(k);
                continue;
            }
            let centre = b.position.to_array();
            // Round-off slack: the exact test decides, the boxes must only not miss.
            let ext = r + margin.half(k);
            let ext = ext + 1e-9 * (ext + centre[0].abs() + centre[1].abs() + centre[2].abs());
            let (lo, hi) = (centre[axis] - ext, centre[axis] + ext);
            self.spans.push(Span { lo, hi, centre, ext, body: k, is_static: b.is_static });
        }
        self.spans.sort_unstable_by(|a, b| a.lo.total_cmp(&b.lo).then(a.body.cmp(&b.body)));
        for (a, sa) in self.spans.iter().enumerate() {
            for sb in &self.spans[a + 1..] {
                if sb.lo > sa.hi {
                    break;
                }
                if !sa.overlaps(sb) || sa.is_static && sb.is_static {
                    continue;
                }
                let (i, j) = (sa.body.min(sb.body), sa.body.max(sb.body));
                if near(&bodies[i], &bodies[j], margin.of(i, j)) {
                    self.pairs.push((i, j));
                }
            }
        }
        for (u, &i) in self.unbounded.iter().enumerate() {
            let with_bounded = self.spans.iter().map(|s| s.body);
            let with_unbounded = self.unbounded[u + 1..].iter().copied();
            for j in with_bounded.chain(with_unbounded) {
                if !(bodies[i].is_static && bodies[j].is_static) {
                    self.pairs.push((i.min(j), i.max(j)));
                }
            }
        }
        self.pairs.sort_unstable();
        &self.pairs
    }
}

/// The axis (0, 1, 2) along which the centres of the bounded bodies spread most.
fn sweep_axis(bodies: &[Body]) -> usize {
    let (mut n, mut sum, mut sq) = (0.0, [0.0; 3], [0.0; 3]);
    for b in bodies.iter().filter(|b| b.shape.bounding_radius().is_finite()) {
        n += 1.0;
        for (a, x) in b.position.to_array().into_iter().enumerate() {
            sum[a] += x;
            sq[a] += x * x;
        }
    }
    if n == 0.0 {
        return 0;
    }
    let var = |a: usize| sq[a] / n - (sum[a] / n) * (sum[a] / n);
    (0..3).fold(0, |best, a| if var(a) > var(best) { a } else { best })
}
