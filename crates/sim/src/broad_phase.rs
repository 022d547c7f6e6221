//! Broad phase: which pairs of bodies the narrow phase looks at.
//!
//! A pair is kept when its bounding spheres come within the pair's margin,
//! `|p_i − p_j| ≤ r_i + r_j + margin_ij` (see [`PairMargin`]), its
//! world-aligned bounding boxes too (`|p_i − p_j|_k ≤ e_ik + e_jk + margin_ij`
//! on each axis `k`, `e` the half widths of the rotated shape), and not both
//! bodies are static; a pair with an unbounded shape (a plane) is always kept.
//! Both tests only drop pairs farther apart than their margin, which the
//! narrow phase would not give a contact: the box test matters for boxes side
//! by side (cubes 1.5 m apart in a grid of towers are within their spheres'
//! reach, 2·0.87 m, but not of their boxes').
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
//!
//! [`BroadMethod::Bvh`] finds the same pairs with parry's bounding volume
//! hierarchy instead of the sweep (step 2): the same boxes as leaves, built
//! once and refitted as the bodies move, its overlapping leaf pairs checked
//! by the same exact test. The default, [`BroadMethod::Auto`], takes the BVH
//! from [`BVH_MIN_BODIES`] bodies on: measured by `cargo run --release -p
//! lcpsim-sim --example broad_phase_bvh` (the time of one `find` on moving
//! random bodies and on resting towers), the BVH is 0.83–0.88× the sweep's
//! speed at 10–30 bodies, even at 50, and 1.1–6.4× faster from 100 to 10,000.

use crate::dynamics::Body;
use crate::geometry::Shape;
use crate::math::Vec3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

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

/// What the pair test reads of a body: its centre, bounding radius (∞ for a
/// plane) and the half widths of its world-aligned bounding box.
#[derive(Clone, Copy, Debug)]
struct Bound {
    centre: Vec3,
    radius: f64,
    half: [f64; 3],
}

impl Bound {
    fn of(b: &Body) -> Bound {
        let radius = b.shape.bounding_radius();
        let half = match &b.shape {
            // e_k = Σ_j |R_kj| h_j, widened by a round-off's worth: a bound, never short.
            Shape::Box(x) => {
                let (r, h) = (b.rotation(), x.half_extents);
                std::array::from_fn(|k| {
                    let e = r.row(k).abs().dot(h);
                    (e + 1e-12 * radius).min(radius)
                })
            }
            // The axis z turned: e_k = |R_kz| h + r (capsule), |R_kz| h + r √(1 − R_kz²) (cylinder).
            Shape::Capsule { radius: r, half_length: h } | Shape::Cylinder { radius: r, half_length: h } => {
                let (rot, capsule) = (b.rotation(), matches!(b.shape, Shape::Capsule { .. }));
                std::array::from_fn(|k| {
                    let a = rot.m[k][2].abs().min(1.0);
                    let e = a * h + if capsule { *r } else { r * (1.0 - a * a).sqrt() };
                    (e + 1e-12 * radius).min(radius)
                })
            }
            _ => [radius; 3],
        };
        Bound { centre: b.position, radius, half }
    }

    /// Half-widths of the box the sweep and the BVH use: the bound widened by
    /// the body's share of the pair margin and a round-off's slack (the exact
    /// test decides; the box must only never miss).
    fn widened(&self, share: f64) -> [f64; 3] {
        let c = self.centre.to_array();
        let slack = 1e-9 * (self.radius + share + c[0].abs() + c[1].abs() + c[2].abs());
        std::array::from_fn(|a| self.half[a] + share + slack)
    }
}

/// Every pair of an unbounded body (a plane, a mesh) with each bounded body and
/// each later unbounded one, except two static bodies.
fn push_unbounded_pairs(unbounded: &[usize], bounded: &[usize], bodies: &[Body], pairs: &mut Vec<(usize, usize)>) {
    for (u, &i) in unbounded.iter().enumerate() {
        for &j in bounded.iter().chain(&unbounded[u + 1..]) {
            if !(bodies[i].is_static && bodies[j].is_static) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
}

/// Whether the pair passes the tests of the module docs (spheres, then boxes).
#[inline]
fn near(bi: &Bound, bj: &Bound, margin: f64) -> bool {
    if !(bi.radius.is_finite() && bj.radius.is_finite()) {
        return true;
    }
    let d = bi.centre - bj.centre;
    let axes = d.to_array();
    // Written as "not farther": a NaN keeps the pair (the narrow phase decides).
    !(d.norm() > bi.radius + bj.radius + margin || (0..3).any(|k| axes[k].abs() > bi.half[k] + bj.half[k] + margin))
}

/// The reference: every pair `i < j` tested, in that order.
pub fn brute_force_pairs(bodies: &[Body], margin: &PairMargin<'_>, out: &mut Vec<(usize, usize)>) {
    out.clear();
    let bounds: Vec<Bound> = bodies.iter().map(Bound::of).collect();
    for i in 0..bodies.len() {
        for j in (i + 1)..bodies.len() {
            if !(bodies[i].is_static && bodies[j].is_static) && near(&bounds[i], &bounds[j], margin.of(i, j)) {
                out.push((i, j));
            }
        }
    }
}

/// A bounded body's box: `[lo, hi]` along the sweep axis, and half widths
/// `ext` about its centre (read in sequence by the sweep: no lookup into the
/// bodies before the boxes overlap).
#[derive(Clone, Copy, Debug)]
struct Span {
    lo: f64,
    hi: f64,
    centre: [f64; 3],
    ext: [f64; 3],
    body: usize,
    is_static: bool,
}

impl Span {
    /// Whether the boxes overlap on every axis.
    #[inline]
    fn overlaps(&self, o: &Span) -> bool {
        let (c, d, e, f) = (&self.centre, &o.centre, &self.ext, &o.ext);
        // Non-short-circuit `&`: one hard-to-predict branch instead of three.
        ((c[0] - d[0]).abs() <= e[0] + f[0])
            & ((c[1] - d[1]).abs() <= e[1] + f[1])
            & ((c[2] - d[2]).abs() <= e[2] + f[2])
    }
}

/// From this many bodies on, [`BroadMethod::Auto`] uses the BVH (see the module docs).
pub const BVH_MIN_BODIES: usize = 64;

/// How [`BroadPhase::find`] finds the candidate pairs (the same pairs either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BroadMethod {
    /// The sweep below [`BVH_MIN_BODIES`] bodies, the BVH from there on. The default.
    #[default]
    Auto,
    /// Sweep and prune along the axis of largest spread.
    Sweep,
    /// parry's BVH of the bodies' boxes, refitted every call.
    Bvh,
}

/// parry's BVH and its buffers (the workspace has no `Debug`).
#[derive(Clone, Default)]
struct BvhState {
    tree: Bvh,
    ws: BvhWorkspace,
    /// Leaf `k` is body `leaf_body[k]` (the bounded bodies, in index order).
    leaf_body: Vec<usize>,
    leaves: Vec<Aabb>,
    /// Whether `tree` holds `leaf_body`'s leaves (else it is built anew).
    built: bool,
    candidates: Vec<(u32, u32)>,
}

impl std::fmt::Debug for BvhState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BvhState").field("leaves", &self.leaf_body.len()).field("built", &self.built).finish()
    }
}

/// Sweep and prune with reusable buffers (allocation-free once warm).
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// Which algorithm finds the candidates.
    pub method: BroadMethod,
    bvh: BvhState,
    /// Every bounded body's box, sorted along the sweep axis.
    spans: Vec<Span>,
    /// Every body's [`Bound`] (the exact test's data).
    bounds: Vec<Bound>,
    /// The bodies in the order of the last sweep, and its axis: bodies move
    /// little in a step, so this step's spans, laid out in that order, are
    /// nearly sorted and an insertion sort finishes them in O(B + swaps).
    order: Vec<usize>,
    axis: usize,
    /// Bodies with an unbounded shape.
    unbounded: Vec<usize>,
    pairs: Vec<(usize, usize)>,
}

impl BroadPhase {
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty broad phase finding its candidates by `method`.
    pub fn with_method(method: BroadMethod) -> Self {
        BroadPhase { method, ..Self::default() }
    }

    /// The pairs of the last [`BroadPhase::find`], sorted by `(i, j)`, `i < j`.
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// Finds the pairs of `bodies` (the same set as [`brute_force_pairs`]).
    pub fn find(&mut self, bodies: &[Body], margin: &PairMargin<'_>) -> &[(usize, usize)] {
        let bvh = match self.method {
            BroadMethod::Auto => bodies.len() >= BVH_MIN_BODIES,
            m => m == BroadMethod::Bvh,
        };
        if bvh {
            return self.find_bvh(bodies, margin);
        }
        self.pairs.clear();
        self.unbounded.clear();
        let axis = sweep_axis(bodies, self.axis);
        let reuse = axis == self.axis && self.order.len() == bodies.len();
        if !reuse {
            self.order.clear();
            self.order.extend(0..bodies.len());
        }
        self.axis = axis;
        self.spans.clear();
        self.bounds.clear();
        self.bounds.extend(bodies.iter().map(Bound::of));
        for &k in &self.order {
            let (b, bound) = (&bodies[k], &self.bounds[k]);
            if !bound.radius.is_finite() {
                self.unbounded.push(k);
                continue;
            }
            let (centre, ext) = (b.position.to_array(), bound.widened(margin.half(k)));
            let (lo, hi) = (centre[axis] - ext[axis], centre[axis] + ext[axis]);
            self.spans.push(Span { lo, hi, centre, ext, body: k, is_static: b.is_static });
        }
        // (lo, body) is a total order: the sorted spans do not depend on the start order.
        let order = |a: &Span, b: &Span| a.lo.total_cmp(&b.lo).then(a.body.cmp(&b.body));
        if reuse {
            insertion_sort(&mut self.spans, |a, b| order(a, b).is_lt());
        } else {
            self.spans.sort_unstable_by(order);
        }
        self.order.clear();
        self.order.extend(self.spans.iter().map(|s| s.body));
        let bounded = self.spans.len();
        self.order.extend(&self.unbounded);
        for (a, sa) in self.spans.iter().enumerate() {
            for sb in &self.spans[a + 1..] {
                if sb.lo > sa.hi {
                    break;
                }
                if !sa.overlaps(sb) || sa.is_static && sb.is_static {
                    continue;
                }
                let (i, j) = (sa.body.min(sb.body), sa.body.max(sb.body));
                if near(&self.bounds[i], &self.bounds[j], margin.of(i, j)) {
                    self.pairs.push((i, j));
                }
            }
        }
        push_unbounded_pairs(&self.unbounded, &self.order[..bounded], bodies, &mut self.pairs);
        self.pairs.sort_unstable();
        &self.pairs
    }
}

impl BroadPhase {
    /// [`BroadPhase::find`] by parry's BVH: the sweep's boxes as leaves, its
    /// overlapping leaf pairs through the same exact test.
    fn find_bvh(&mut self, bodies: &[Body], margin: &PairMargin<'_>) -> &[(usize, usize)] {
        self.pairs.clear();
        self.unbounded.clear();
        self.bounds.clear();
        self.bounds.extend(bodies.iter().map(Bound::of));
        let BvhState { tree, ws, leaf_body, leaves, built, candidates } = &mut self.bvh;
        let count = leaf_body.len();
        leaf_body.clear();
        leaves.clear();
        for (k, b) in bodies.iter().enumerate() {
            let bound = &self.bounds[k];
            if !bound.radius.is_finite() {
                self.unbounded.push(k);
                continue;
            }
            // The sweep's box: a bound the exact test then decides on.
            let (c, e) = (b.position.to_array(), bound.widened(margin.half(k)));
            leaf_body.push(k);
            leaves.push(Aabb::new(
                PVec::new(c[0] - e[0], c[1] - e[1], c[2] - e[2]),
                PVec::new(c[0] + e[0], c[1] + e[1], c[2] + e[2]),
            ));
        }
        // Bodies are only ever added: the same count is the same leaves.
        if !*built || count != leaf_body.len() {
            *tree = Bvh::from_leaves(BvhBuildStrategy::Binned, leaves);
            *built = true;
        } else {
            for (k, a) in leaves.iter().enumerate() {
                tree.insert_or_update_partially(*a, k as u32, 0.0);
            }
            tree.refit(ws);
        }
        candidates.clear();
        tree.traverse_bvtt_single_tree::<false>(ws, &mut |a, b| candidates.push((a, b)));
        for &(a, b) in candidates.iter() {
            let (p, q) = (leaf_body[a as usize], leaf_body[b as usize]);
            let (i, j) = (p.min(q), p.max(q));
            if bodies[i].is_static && bodies[j].is_static {
                continue;
            }
            if near(&self.bounds[i], &self.bounds[j], margin.of(i, j)) {
                self.pairs.push((i, j));
            }
        }
        push_unbounded_pairs(&self.unbounded, leaf_body, bodies, &mut self.pairs);
        self.pairs.sort_unstable();
        &self.pairs
    }
}

/// Sorts `v` by `before` (a strict total order), moving each element left past
/// the ones it precedes: linear on a nearly sorted `v`.
fn insertion_sort<T: Copy>(v: &mut [T], before: impl Fn(&T, &T) -> bool) {
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && before(&x, &v[j - 1]) {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
    }
}

/// The axis (0, 1, 2) along which the centres of the bounded bodies spread
/// most — `last` (the previous sweep's) unless another spreads 10 % more, so
/// that a grid whose x and y spreads tie does not switch axes (and lose the
/// previous order) on round-off from step to step.
fn sweep_axis(bodies: &[Body], last: usize) -> usize {
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
    let best = (0..3).fold(0, |best, a| if var(a) > var(best) { a } else { best });
    if last < 3 && var(best) <= 1.1 * var(last) {
        last
    } else {
        best
    }
}
