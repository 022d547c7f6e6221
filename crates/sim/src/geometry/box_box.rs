//! Box–box: separating-axis test over the 15 axes, then face clipping.
//!
//! The axis of least penetration (largest separation) decides the contact
//! normal. Face axes are preferred over edge–edge axes unless an edge axis is
//! clearly better, so resting face-on-face contacts never flicker to an edge.
//! For a face axis the *incident* face of the other box is clipped
//! (Sutherland–Hodgman) against the side planes of the *reference* face, and
//! every clipped vertex within the margin becomes a contact (up to 8: a square
//! clipped by a square; a manifold lying flat is cut to the 4 that span it).
//! For an edge–edge axis the two faces turned towards
//! each other are clipped the same way but along the axis itself, so an edge
//! or face coming down nearly flat gets its far end's points too; edges that
//! cross at an angle give the one point where they cross.

use super::{BoxShape, GeomContact, Placement};
use crate::math::Vec3;

/// Which axis separated least.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Axis {
    FaceA(usize),
    FaceB(usize),
    Edge(usize, usize),
}

/// A placed box as the axis tests read it: centre, axes (unit columns of its
/// rotation) and half extents.
#[derive(Clone, Copy, Debug)]
struct BoxFrame {
    c: Vec3,
    axes: [Vec3; 3],
    h: [f64; 3],
}

impl BoxFrame {
    fn new(shape: &BoxShape, p: &Placement) -> Self {
        let axes = [p.rotation.col(0), p.rotation.col(1), p.rotation.col(2)];
        BoxFrame { c: p.center, axes, h: shape.half_extents.to_array() }
    }

    /// Support radius along unit `u`.
    fn radius(&self, u: Vec3) -> f64 {
        let (h, axes) = (&self.h, &self.axes);
        h[0] * axes[0].dot(u).abs() + h[1] * axes[1].dot(u).abs() + h[2] * axes[2].dot(u).abs()
    }
}

/// Separation of A and B along unit `u`, and `u` oriented from B to A.
fn separation(a: &BoxFrame, b: &BoxFrame, u: Vec3) -> (f64, Vec3) {
    let du = (a.c - b.c).dot(u);
    let s = du.abs() - a.radius(u) - b.radius(u);
    (s, if du >= 0.0 { u } else { -u })
}

/// The axis of least penetration: its separation, normal (from B to A) and
/// which it is; `None` when an axis separates the boxes by more than `margin`.
///
/// Face axes: A's first, then B's only if clearly better (deterministic
/// ties); an edge axis must beat the best face by a margin (ODE uses a
/// similar fudge). The 15 separations come from the 9 cosines `r[i][j] =
/// a_i·b_j` and `d = c_A − c_B` in both frames (each axis's support radii
/// read off `|r|`): the separations of [`separation`] to round-off, a fifth
/// of its flops. For `c = a_i × b_j`, in A's frame `c = e_i × r[·][j]`:
/// `|c|² = r[i1][j]² + r[i2][j]²`, `d·c = ta[i2] r[i1][j] − ta[i1] r[i2][j]`,
/// A's radius `ha[i1] |r[i2][j]| + ha[i2] |r[i1][j]|` and B's (`b_j1·c =
/// r[i][j2]`, `b_j2·c = −r[i][j1]`) `hb[j1] |r[i][j2]| + hb[j2] |r[i][j1]|`.
/// The chosen axis's normal (and an edge's separation) are [`separation`]'s.
fn least_separating_axis(a: &BoxFrame, b: &BoxFrame, margin: f64, scale: f64) -> Option<(f64, Vec3, Axis)> {
    let (ha, hb, d) = (&a.h, &b.h, a.c - b.c);
    let r: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| a.axes[i].dot(b.axes[j])));
    let ar = r.map(|row| row.map(f64::abs));
    let (ta, tb) = (a.axes.map(|u| d.dot(u)), b.axes.map(|u| d.dot(u)));

    let face_tol = 1e-9 * scale;
    let mut best = (f64::NEG_INFINITY, Axis::FaceA(0));
    for i in 0..3 {
        let s = ta[i].abs() - ha[i] - (hb[0] * ar[i][0] + hb[1] * ar[i][1] + hb[2] * ar[i][2]);
        if s > margin {
            return None;
        }
        if s > best.0 + face_tol {
            best = (s, Axis::FaceA(i));
        }
    }
    for j in 0..3 {
        let s = tb[j].abs() - (ha[0] * ar[0][j] + ha[1] * ar[1][j] + ha[2] * ar[2][j]) - hb[j];
        if s > margin {
            return None;
        }
        if s > best.0 + face_tol {
            best = (s, Axis::FaceB(j));
        }
    }
    let face_sep = best.0;
    let edge_tol = 1e-5 * scale + 0.05 * face_sep.abs();
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let len = (r[i1][j] * r[i1][j] + r[i2][j] * r[i2][j]).sqrt();
            if len < 1e-6 {
                continue; // parallel edges: covered by the face axes
            }
            let dc = ta[i2] * r[i1][j] - ta[i1] * r[i2][j];
            let ra = ha[i1] * ar[i2][j] + ha[i2] * ar[i1][j];
            let rb = hb[j1] * ar[i][j2] + hb[j2] * ar[i][j1];
            let s = (dc.abs() - ra - rb) / len;
            if s > margin {
                return None;
            }
            if s > face_sep + edge_tol && s > best.0 {
                best = (s, Axis::Edge(i, j));
            }
        }
    }
    Some(match best.1 {
        Axis::FaceA(i) => (best.0, if ta[i] >= 0.0 { a.axes[i] } else { -a.axes[i] }, best.1),
        Axis::FaceB(j) => (best.0, if tb[j] >= 0.0 { b.axes[j] } else { -b.axes[j] }, best.1),
        Axis::Edge(i, j) => {
            let c = a.axes[i].cross(b.axes[j]);
            let (s, n) = separation(a, b, c / c.norm());
            (s, n, best.1)
        }
    })
}

/// Appends the contacts of box A with box B (normal from B to A) whose gap `≤ margin`.
pub fn box_box(a: &BoxShape, pa: &Placement, b: &BoxShape, pb: &Placement, margin: f64, out: &mut Vec<GeomContact>) {
    let (fa, fb) = (BoxFrame::new(a, pa), BoxFrame::new(b, pb));
    let scale = a.half_extents.max_abs().max(b.half_extents.max_abs());
    if let Some(axis) = least_separating_axis(&fa, &fb, margin, scale) {
        manifold(&fa, &fb, axis, margin, scale, out);
    }
}

/// The contacts of the boxes on their axis of least penetration `(sep, n, axis)`.
fn manifold(
    a: &BoxFrame,
    b: &BoxFrame,
    (sep, n, axis): (f64, Vec3, Axis),
    margin: f64,
    scale: f64,
    out: &mut Vec<GeomContact>,
) {
    let (ha, hb, axes_a, axes_b) = (&a.h, &b.h, &a.axes, &b.axes);
    // The reference face (its centre, side axes and outward normal s·n: s = 1
    // for B's face facing A, −1 for A's facing B) and the other box's
    // incident face, facing −s·n.
    let (fc, (u1, e1, u2, e2), poly, s) = match axis {
        Axis::FaceB(j) => (b.c + n * hb[j], side_axes(axes_b, hb, j), incident_face(axes_a, ha, a.c, -n), 1.0),
        Axis::FaceA(i) => (a.c - n * ha[i], side_axes(axes_a, ha, i), incident_face(axes_b, hb, b.c, n), -1.0),
        Axis::Edge(i, j) => {
            let first = out.len();
            edge_manifold((a.c, axes_a, ha), (b.c, axes_b, hb), n, margin, scale, out);
            if out.len() == first {
                let point = edge_point((a.c, axes_a, ha, i), (b.c, axes_b, hb, j), n);
                out.push(GeomContact { point, normal: n, gap: sep });
            }
            return;
        }
    };
    let gap_point = |p: Vec3| {
        let gap = s * n.dot(p - fc);
        (gap, p - n * (s * 0.5 * gap))
    };
    let planes = [(u1, e1), (-u1, e1), (u2, e2), (-u2, e2)];
    let first = out.len();
    clip_and_emit(&poly, fc, planes, margin, scale, out, gap_point, n);
    keep_four_if_flat(out, first, n, scale);
}

/// The contacts of an edge–edge axis `n` (from B to A): the two boxes' faces
/// turned most towards each other along `n`, one clipped against the prism
/// that the other sweeps along `n`, every clipped point within the margin
/// (gap measured along `n`). Where a tumbling box's edge or face comes down
/// nearly flat on the other's face, the axis is an edge–edge one, and the
/// points at its far end (a few mm up) must enter the LCP now: a single point
/// where the edges cross lets the box turn about it into the face within the
/// step. For edges that cross at an angle this gives the crossing point alone.
fn edge_manifold(
    a: (Vec3, &[Vec3; 3], &[f64; 3]),
    b: (Vec3, &[Vec3; 3], &[f64; 3]),
    n: Vec3,
    margin: f64,
    scale: f64,
    out: &mut Vec<GeomContact>,
) {
    let ((ca, axes_a, ha), (cb, axes_b, hb)) = (a, b);
    let most =
        |axes: &[Vec3; 3]| (0..3).fold(0, |k, m| if axes[m].dot(n).abs() > axes[k].dot(n).abs() { m } else { k });
    let (ka, kb) = (most(axes_a), most(axes_b));
    // The reference face is the one whose normal is closer to ±n (outward
    // normal `nr`; s = 1 for B's face, −1 for A's); n ⟂ both edges, so
    // |nr·n| ≥ 1/√2 and the prism's side planes are well conditioned.
    let (k, axes, h, c, s, poly) = if axes_b[kb].dot(n).abs() >= axes_a[ka].dot(n).abs() {
        (kb, axes_b, hb, cb, 1.0, incident_face(axes_a, ha, ca, -n))
    } else {
        (ka, axes_a, ha, ca, -1.0, incident_face(axes_b, hb, cb, n))
    };
    let nr = axes[k] * sign(axes[k].dot(n) * s);
    let fc = c + nr * h[k];
    let (u1, e1, u2, e2) = side_axes(axes, h, k);
    // A side plane holds its face edge (along w) and n; it keeps u·(p − fc) ≤ e
    // for u its unit normal turned outward (towards the in-face axis ±v).
    let side = |v: Vec3, e: f64, w: Vec3| {
        let m = w.cross(n);
        let m = m * (sign(m.dot(v)) / m.norm());
        (m, m.dot(v) * e)
    };
    let planes = [side(u1, e1, u2), side(-u1, e1, u2), side(u2, e2, u1), side(-u2, e2, u1)];
    let cos = nr.dot(n).abs();
    let gap_point = |p: Vec3| {
        let gap = nr.dot(p - fc) / cos;
        (gap, p - n * (s * 0.5 * gap))
    };
    clip_and_emit(&poly, fc, planes, margin, scale, out, gap_point, n);
}

/// Edge `i` of box A and edge `j` of box B (each given as centre, axes, half
/// extents and edge axis), for the separating direction `n` from B to A: the
/// midpoint of their closest points, each clamped to its edge.
fn edge_point(a: (Vec3, &[Vec3; 3], &[f64; 3], usize), b: (Vec3, &[Vec3; 3], &[f64; 3], usize), n: Vec3) -> Vec3 {
    let ((mut pa0, axes_a, ha, i), (mut pb0, axes_b, hb, j)) = (a, b);
    // The edge of A deepest towards B and the edge of B deepest towards A.
    for k in 0..3 {
        if k != i {
            pa0 -= axes_a[k] * (ha[k] * sign(axes_a[k].dot(n)));
        }
        if k != j {
            pb0 += axes_b[k] * (hb[k] * sign(axes_b[k].dot(n)));
        }
    }
    let (ea, eb) = (axes_a[i], axes_b[j]);
    // Closest points of the two edge lines, clamped to the edges.
    let r = pa0 - pb0;
    let bb = ea.dot(eb);
    let (c, f) = (ea.dot(r), eb.dot(r));
    let denom = (1.0 - bb * bb).max(1e-12);
    let s = ((bb * f - c) / denom).clamp(-ha[i], ha[i]);
    let t = (f + s * bb).clamp(-hb[j], hb[j]);
    (pa0 + ea * s + pb0 + eb * t) * 0.5
}

#[inline]
fn sign(x: f64) -> f64 {
    if x >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// The two in-face axes (with half extents) of the face normal to axis `k`.
fn side_axes(axes: &[Vec3; 3], h: &[f64; 3], k: usize) -> (Vec3, f64, Vec3, f64) {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    (axes[i], h[i], axes[j], h[j])
}

/// The 4 vertices (in order around the face) of the box face whose outward
/// normal is closest to `dir`.
fn incident_face(axes: &[Vec3; 3], h: &[f64; 3], center: Vec3, dir: Vec3) -> [Vec3; 4] {
    let mut k = 0;
    for m in 1..3 {
        if axes[m].dot(dir).abs() > axes[k].dot(dir).abs() {
            k = m;
        }
    }
    let fc = center + axes[k] * (h[k] * sign(axes[k].dot(dir)));
    let (u1, e1, u2, e2) = side_axes(axes, h, k);
    let (a, b) = (u1 * e1, u2 * e2);
    [fc + a + b, fc - a + b, fc - a - b, fc + a - b]
}

/// Clips the incident polygon against the reference face's 4 side planes
/// (`u·(p − fc) ≤ e` each) and emits every vertex whose gap (from
/// `gap_point`) is within the margin.
#[allow(clippy::too_many_arguments)]
fn clip_and_emit(
    poly: &[Vec3; 4],
    fc: Vec3,
    planes: [(Vec3, f64); 4],
    margin: f64,
    scale: f64,
    out: &mut Vec<GeomContact>,
    gap_point: impl Fn(Vec3) -> (f64, Vec3),
    n: Vec3,
) {
    // A square clipped by 4 half-planes has at most 8 vertices; 16 leaves room for ties.
    let (mut buf_a, mut buf_b) = ([Vec3::ZERO; 16], [Vec3::ZERO; 16]);
    buf_a[..4].copy_from_slice(poly);
    let (mut cur, mut next) = (&mut buf_a, &mut buf_b);
    let mut len = 4;
    // 1 nm on a 1 m box: far below any physical feature, far above round-off.
    let tol = 1e-9 * scale;
    for (u, e) in planes {
        let Some(clipped) = clip_polygon(&cur[..len], fc, u, e, tol, next) else { continue };
        len = clipped;
        std::mem::swap(&mut cur, &mut next);
        if len == 0 {
            return;
        }
    }
    let first = out.len();
    let dup = 1e-7 * scale;
    for &p in &cur[..len] {
        let (gap, point) = gap_point(p);
        if gap > margin {
            continue;
        }
        if out[first..].iter().any(|c| (c.point - point).max_abs() <= dup) {
            continue;
        }
        out.push(GeomContact { point, normal: n, gap });
        if out.len() - first == 8 {
            break;
        }
    }
}

/// A face manifold whose gaps spread by at most this fraction of the larger
/// box's half extent (0.1 mm on a unit cube) lies flat on the reference face.
const FLAT: f64 = 2e-4;

/// Reduces a face axis's manifold `out[first..]` (normal `n`) to at most 4
/// points when it lies flat ([`FLAT`]): the one farthest along a fixed
/// direction of the face, the one farthest from it, the one making the largest triangle with those two, and the one
/// farthest on the other side of their line — the quadrilateral spanning
/// most of the manifold. A face resting on a face turned against it clips to
/// an octagon whose 8 normal rows have rank 3: the other 4 points add only
/// unknowns to a degenerate LCP (a 45-cube pour's pivots fell 4–66 % on 4
/// seeds). A tilted manifold keeps every point: its far end's points, up in
/// the margin, are what stops the box turning into the face within the step
/// (reduced too, the pours' deepest overlap rose from 0.06–0.12 mm to
/// 0.4–0.7 mm).
fn keep_four_if_flat(out: &mut Vec<GeomContact>, first: usize, n: Vec3, scale: f64) {
    let m = &out[first..];
    if m.len() <= 4 {
        return;
    }
    let (lo, hi) = m.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| (l.min(c.gap), h.max(c.gap)));
    if hi - lo > FLAT * scale {
        return;
    }
    // The first corner by where it lies, not by its depth: in a flat manifold
    // the depths differ by round-off, so the first_pt point (and the four kept
    // with it) changed from step to step on a heap at rest, and its warm
    // starts with them. (A skewed in-plane direction: no ties on symmetric polygons.)
    let u = if n.x.abs() < 0.9 { n.cross(Vec3::X) } else { n.cross(Vec3::Y) };
    let d = u + 0.37 * n.cross(u);
    let first_pt = (0..m.len()).fold(0, |k, i| if m[i].point.dot(d) > m[k].point.dot(d) { i } else { k });
    let p0 = m[first_pt].point;
    let reach = |j: usize| (m[j].point - p0).cross(n).norm();
    let far = (0..m.len()).fold(first_pt, |k, i| if reach(i) > reach(k) { i } else { k });
    let p1 = m[far].point;
    let area = |i: usize| n.dot((p1 - p0).cross(m[i].point - p0));
    let side = (0..m.len()).fold(first_pt, |k, i| if area(i).abs() > area(k).abs() { i } else { k });
    let sign = if area(side) >= 0.0 { -1.0 } else { 1.0 };
    let other = (0..m.len()).fold(first_pt, |k, i| if sign * area(i) > sign * area(k) { i } else { k });
    let mut keep = [first_pt, far, side, other];
    keep.sort_unstable();
    let kept: Vec<GeomContact> =
        keep.iter().enumerate().filter(|&(k, &i)| k == 0 || keep[k - 1] != i).map(|(_, &i)| m[i]).collect();
    out.truncate(first);
    out.extend(kept);
}

/// One Sutherland–Hodgman pass: keeps the part of `input` with `u·(p − c) ≤ e`.
///
/// Vertices within `tol` of the clip line count as *on* it and are kept as
/// they are; an intersection is added only for an edge that runs from
/// strictly inside (`d < −tol`) to strictly outside (`d > tol`). Without the
/// band, two nearly coincident faces (stacked boxes, offsets ~1e-12) produce
/// edges almost parallel to the clip line whose "intersection" lands anywhere
/// along them: a valid but redundant extra contact that makes the contact set
/// (and the LCP size) flicker from step to step. `None` when every vertex is
/// on or inside (the pass would keep `input` as it is: a face resting on a
/// face of its size).
fn clip_polygon(input: &[Vec3], c: Vec3, u: Vec3, e: f64, tol: f64, output: &mut [Vec3; 16]) -> Option<usize> {
    // Each vertex's distance past the line, once (an edge reads both ends').
    let mut dist = [0.0; 16];
    for (x, &p) in dist.iter_mut().zip(input) {
        *x = u.dot(p - c) - e;
    }
    let m = input.len();
    if dist[..m].iter().all(|&x| x <= tol) {
        return None;
    }
    let mut len = 0;
    let mut push = |p: Vec3, len: &mut usize| {
        if *len < output.len() {
            output[*len] = p;
            *len += 1;
        }
    };
    for idx in 0..m {
        let next = if idx + 1 == m { 0 } else { idx + 1 };
        let (p, q, dp, dq) = (input[idx], input[next], dist[idx], dist[next]);
        let (p_in, q_in) = (dp <= tol, dq <= tol);
        if p_in {
            push(p, &mut len);
        }
        // A strict crossing of the plane adds the intersection point.
        if (p_in && !q_in && dp < -tol) || (!p_in && q_in && dq < -tol) {
            push(p + (q - p) * (dp / (dp - dq)), &mut len);
        }
    }
    Some(len)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Quat};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn place(c: Vec3, q: Quat) -> Placement {
        Placement { center: c, rotation: q.to_mat3() }
    }

    /// The contacts of two unit cubes placed so, within a margin of 1 mm.
    fn cubes(pa: Placement, pb: Placement) -> Vec<GeomContact> {
        let b = BoxShape::cube(1.0).unwrap();
        let mut out = Vec::new();
        box_box(&b, &pa, &b, &pb, 1e-3, &mut out);
        out
    }

    /// The 15 axes tested one by one, each through [`separation`] along its
    /// unit vector (the test [`least_separating_axis`] reads off the cosines
    /// must choose as this one does).
    fn least_separating_axis_reference(
        a: &BoxFrame,
        b: &BoxFrame,
        margin: f64,
        scale: f64,
    ) -> Option<(f64, Vec3, Axis)> {
        let face_tol = 1e-9 * scale;
        let mut best = (f64::NEG_INFINITY, Vec3::Z, Axis::FaceA(0));
        let faces_a = a.axes.iter().enumerate().map(|(i, &u)| (u, Axis::FaceA(i)));
        let faces_b = b.axes.iter().enumerate().map(|(j, &u)| (u, Axis::FaceB(j)));
        for (u, axis) in faces_a.chain(faces_b) {
            let (s, n) = separation(a, b, u);
            if s > margin {
                return None;
            }
            if s > best.0 + face_tol {
                best = (s, n, axis);
            }
        }
        let face_sep = best.0;
        let edge_tol = 1e-5 * scale + 0.05 * face_sep.abs();
        for (i, &ea) in a.axes.iter().enumerate() {
            for (j, &eb) in b.axes.iter().enumerate() {
                let c = ea.cross(eb);
                let len = c.norm();
                if len < 1e-6 {
                    continue;
                }
                let (s, n) = separation(a, b, c / len);
                if s > margin {
                    return None;
                }
                if s > face_sep + edge_tol && s > best.0 {
                    best = (s, n, Axis::Edge(i, j));
                }
            }
        }
        Some(best)
    }

    /// A unit quaternion turned by up to `max` about a random axis.
    fn turn(rng: &mut ChaCha8Rng, max: f64) -> Quat {
        let angle = rng.random_range(0.0..max);
        let axis = Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        Quat::from_axis_angle(axis.try_normalize().unwrap_or(Vec3::Z), angle)
    }

    #[test]
    fn the_axis_from_cosines_is_the_axis_tested_one_by_one_on_random_poses() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut touching, mut edges) = (0, 0);
        for case in 0..60_000 {
            let size = |rng: &mut ChaCha8Rng| {
                Vec3::new(rng.random_range(0.1..1.0), rng.random_range(0.1..1.0), rng.random_range(0.1..1.0))
            };
            let (sa, sb) = (BoxShape::new(size(&mut rng)).unwrap(), BoxShape::new(size(&mut rng)).unwrap());
            let (ha, hb) = (sa.half_extents, sb.half_extents);
            // Three families: any pose near contact; B resting on A's top face
            // turned by a little (a stack, 1e-14 to 1e-2 rad, offsets down to
            // round-off); A turned 45° about an axis, leaning an edge or corner on B.
            let (qa, qb, ca) = match case % 3 {
                0 => {
                    let (qa, qb) = (turn(&mut rng, 3.2), turn(&mut rng, 3.2));
                    let reach = ha.norm() + hb.norm();
                    let dir = Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    (qa, qb, dir * (reach * rng.random_range(0.3..0.7)))
                }
                1 => {
                    let tiny = 10f64.powf(rng.random_range(-14.0..-2.0));
                    let (qa, qb) = (turn(&mut rng, tiny), turn(&mut rng, tiny));
                    let off = Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), 0.0) * (tiny * 10.0);
                    let gap = rng.random_range(-1.0..1.0) * tiny;
                    (qa, qb, off + Vec3::new(0.0, 0.0, ha.z + hb.z + gap))
                }
                _ => {
                    let axis =
                        [Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0).try_normalize().unwrap()][rng.random_range(0..3)];
                    let qa = Quat::from_axis_angle(axis, std::f64::consts::FRAC_PI_4) * turn(&mut rng, 1e-3);
                    let lift = rng.random_range(-0.05..0.05);
                    let up = qa.to_mat3().transpose() * Vec3::Z;
                    let reach = ha.x * up.x.abs() + ha.y * up.y.abs() + ha.z * up.z.abs();
                    (
                        qa,
                        Quat::IDENTITY,
                        Vec3::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3), hb.z + reach + lift),
                    )
                }
            };
            let (pa, pb) = (place(ca, qa), place(Vec3::ZERO, qb));
            let (fa, fb) = (BoxFrame::new(&sa, &pa), BoxFrame::new(&sb, &pb));
            let (margin, scale) = (1e-3, ha.max_abs().max(hb.max_abs()));
            let fast = least_separating_axis(&fa, &fb, margin, scale);
            let slow = least_separating_axis_reference(&fa, &fb, margin, scale);
            match (fast, slow) {
                (None, None) => continue,
                (Some((s, n, axis)), Some((s_ref, n_ref, axis_ref))) => {
                    assert_eq!(axis, axis_ref, "case {case}: {fa:?} {fb:?}");
                    assert_eq!(n, n_ref, "case {case}");
                    assert!((s - s_ref).abs() <= 1e-12 * scale, "case {case}: {s} against {s_ref}");
                    if matches!(axis, Axis::Edge(..)) {
                        assert_eq!(s, s_ref, "case {case}");
                        edges += 1;
                    }
                    // And so the same contacts, bit for bit.
                    let (mut got, mut want) = (Vec::new(), Vec::new());
                    box_box(&sa, &pa, &sb, &pb, margin, &mut got);
                    manifold(&fa, &fb, (s_ref, n_ref, axis_ref), margin, scale, &mut want);
                    assert_eq!(got, want, "case {case}");
                    touching += usize::from(!got.is_empty());
                }
                (fast, slow) => panic!("case {case}: {fast:?} against {slow:?}"),
            }
        }
        assert!(touching > 40_000 && edges > 5_000, "{touching} touching, {edges} edge axes");
    }

    #[test]
    fn stacked_cubes_touch_at_four_corners() {
        let out =
            cubes(place(Vec3::new(0.0, 0.0, 1.5), Quat::IDENTITY), place(Vec3::new(0.0, 0.0, 0.5), Quat::IDENTITY));
        assert_eq!(out.len(), 4, "{out:?}");
        for c in &out {
            assert_eq!(c.normal, Vec3::Z);
            assert!(c.gap.abs() < 1e-15);
            assert!((c.point.z - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn a_cube_turned_on_a_cube_keeps_four_octagon_corners_around_its_centre() {
        // Turned 45° about z, the faces overlap in a regular octagon (corners at
        // r = 0.5 / cos 22.5° from the axis); 4 of its corners are kept, and they
        // must hold the upper cube's centre and most of the octagon's area.
        let q = Quat::from_axis_angle(Vec3::Z, std::f64::consts::FRAC_PI_4);
        let out = cubes(place(Vec3::new(0.0, 0.0, 1.5), q), place(Vec3::new(0.0, 0.0, 0.5), Quat::IDENTITY));
        assert_eq!(out.len(), 4, "{out:?}");
        assert!(out.iter().all(|c| (c.normal - Vec3::Z).max_abs() < 1e-12 && c.gap.abs() < 1e-12));
        let r = 0.5 / std::f64::consts::FRAC_PI_8.cos();
        assert!(out.iter().all(|c| (c.point.x.hypot(c.point.y) - r).abs() < 1e-12), "{out:?}");
        let mut corners: Vec<(f64, f64)> = out.iter().map(|c| (c.point.x, c.point.y)).collect();
        corners.sort_by(|a, b| a.1.atan2(a.0).total_cmp(&b.1.atan2(b.0)));
        // The centre is inside when every edge turns it to the left.
        let edges = (0..4).map(|k| (corners[k], corners[(k + 1) % 4]));
        assert!(edges.clone().all(|(a, b)| a.0 * b.1 - a.1 * b.0 > 0.0), "{corners:?}");
        let area: f64 = edges.map(|(a, b)| 0.5 * (a.0 * b.1 - a.1 * b.0)).sum();
        let octagon = 2.0 * 2f64.sqrt() * r * r;
        assert!(area >= 0.7 * octagon, "area {area} of the octagon's {octagon}");
    }

    #[test]
    fn a_cube_tilted_over_a_turned_cube_keeps_every_point() {
        // The same octagon with the upper cube tilted by 2 mrad about x: its
        // gaps spread over 2 mm of the margin, and every point stays.
        let q = Quat::from_axis_angle(Vec3::X, 2e-3) * Quat::from_axis_angle(Vec3::Z, std::f64::consts::FRAC_PI_4);
        let (pa, pb) = (place(Vec3::new(0.0, 0.0, 1.5), q), place(Vec3::new(0.0, 0.0, 0.5), Quat::IDENTITY));
        let b = BoxShape::cube(1.0).unwrap();
        let mut out = Vec::new();
        box_box(&b, &pa, &b, &pb, 1e-2, &mut out);
        assert_eq!(out.len(), 8, "{out:?}");
    }

    #[test]
    fn lower_box_first_gives_downward_normal() {
        let out =
            cubes(place(Vec3::new(0.2, 0.0, 0.5), Quat::IDENTITY), place(Vec3::new(0.0, 0.0, 1.49), Quat::IDENTITY));
        assert_eq!(out.len(), 4);
        for c in &out {
            assert_eq!(c.normal, -Vec3::Z);
            assert!((c.gap + 0.01).abs() < 1e-12);
        }
    }

    #[test]
    fn crossed_edges_give_one_contact() {
        // Two cubes balanced edge on edge, edges crossing at right angles.
        let r = 0.5 * 2f64.sqrt();
        let qa = Quat::from_axis_angle(Vec3::X, std::f64::consts::FRAC_PI_4);
        let qb = Quat::from_axis_angle(Vec3::Y, std::f64::consts::FRAC_PI_4);
        let out = cubes(place(Vec3::new(0.0, 0.0, 2.0 * r - 1e-4), qa), place(Vec3::ZERO, qb));
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((out[0].normal - Vec3::Z).max_abs() < 1e-9);
        assert!((out[0].gap + 1e-4).abs() < 1e-9);
        assert!((out[0].point - Vec3::new(0.0, 0.0, r - 0.5e-4)).max_abs() < 1e-9);
    }

    /// A cube whose bottom edge (direction e = (cos α, 0, −sin α)) crosses the
    /// top edge x = 0.5 of the axis-aligned cube below at height 0.5 + g,
    /// sloping down past it, its bottom face rising by γ towards +y: the
    /// edge–edge axis n = (sin α, 0, cos α) separates them. Returns the upper
    /// cube's placement, n, and the two points of its edge at the crossing
    /// and at the inner end (0.8 back along the edge).
    fn edge_across_edge(alpha: f64, gamma: f64, g: f64) -> (Placement, Vec3, Vec3, Vec3) {
        let (sa, ca, sg, cg) = (alpha.sin(), alpha.cos(), gamma.sin(), gamma.cos());
        let e = Vec3::new(ca, 0.0, -sa);
        let f = Vec3::new(sg * sa, cg, sg * ca); // in the bottom face, away from the edge
        let up = e.cross(f); // the bottom face's inward normal
        let cross = Vec3::new(0.5, 0.0, 0.5 + g);
        let center = cross - e * 0.3 + f * 0.5 + up * 0.5;
        let n = Vec3::new(sa, 0.0, ca);
        (Placement { center, rotation: Mat3::from_cols(e, f, up) }, n, cross, cross - e * 0.8)
    }

    #[test]
    fn an_edge_coming_down_nearly_flat_across_an_edge_gets_both_ends() {
        // α = 5 mrad: the inner end is 4 mm up, within a 1 cm margin; the far
        // side of the bottom face (γ = 0.05) is 5 cm up, outside it.
        let (alpha, g) = (5e-3, 1e-4);
        let (pa, n, cross, inner) = edge_across_edge(alpha, 0.05, g);
        let pb = place(Vec3::ZERO, Quat::IDENTITY);
        let b = BoxShape::cube(1.0).unwrap();
        let mut out = Vec::new();
        box_box(&b, &pa, &b, &pb, 1e-2, &mut out);
        assert_eq!(out.len(), 2, "{out:?}");
        assert!(out.iter().all(|c| (c.normal - n).max_abs() < 1e-12), "{out:?}");
        // Where the edges cross: the lines' distance g·cos α, their closest
        // points' midpoint (the upper one is g·sin α along the edge from `cross`).
        let upper = cross + Vec3::new(alpha.cos(), 0.0, -alpha.sin()) * (g * alpha.sin());
        let mid = (upper + Vec3::new(0.5, 0.0, 0.5)) * 0.5;
        let at_cross = out.iter().find(|c| (c.point - mid).max_abs() < 1e-9).expect("a contact where the edges cross");
        assert!((at_cross.gap - g * alpha.cos()).abs() < 1e-12, "{at_cross:?}");
        // The inner end, above the top face z = 0.5: its gap along n.
        let gap = (inner.z - 0.5) / alpha.cos();
        let at_end = out.iter().find(|c| (c.point - (inner - n * (0.5 * gap))).max_abs() < 1e-9);
        let at_end = at_end.expect("a contact at the edge's inner end");
        assert!((at_end.gap - gap).abs() < 1e-12 && gap > 4e-3, "{at_end:?}, expected gap {gap}");
        // Swapped (the lower cube as A): the same points and gaps, the normal reversed.
        let mut swapped = Vec::new();
        box_box(&b, &pb, &b, &pa, 1e-2, &mut swapped);
        assert_eq!(swapped.len(), 2, "{swapped:?}");
        for c in &out {
            let twin = swapped.iter().find(|d| (d.point - c.point).max_abs() < 1e-12).expect("the same point");
            assert!((twin.gap - c.gap).abs() < 1e-12 && (twin.normal + c.normal).max_abs() < 1e-12);
        }
    }

    #[test]
    fn an_edge_across_an_edge_keeps_only_the_points_within_the_margin() {
        // With a 1 mm margin the inner end (4 mm up) is left out.
        let (pa, n, ..) = edge_across_edge(5e-3, 0.05, 1e-4);
        let b = BoxShape::cube(1.0).unwrap();
        let mut out = Vec::new();
        box_box(&b, &pa, &b, &place(Vec3::ZERO, Quat::IDENTITY), 1e-3, &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((out[0].normal - n).max_abs() < 1e-12 && (out[0].gap - 1e-4 * 5e-3f64.cos()).abs() < 1e-12);
    }

    #[test]
    fn nearly_coincident_faces_give_exactly_four_corners() {
        // Stacked cubes off by round-off (the state of a resting stack after
        // many steps): the clipping must not invent points along the edges.
        let qa = Quat::new(1.0, 5e-14, -5e-14, -7e-14).try_normalize().unwrap();
        let qb = Quat::new(1.0, -2e-14, 2e-14, 2e-13).try_normalize().unwrap();
        for (dx, dy) in [(0.0, 0.0), (-3e-13, -2.5e-12), (1e-12, -1e-12), (2e-10, 3e-10)] {
            let out = cubes(place(Vec3::new(-1.6e-13, -1.0e-12, 0.5), qa), place(Vec3::new(dx, dy, 1.5), qb));
            assert_eq!(out.len(), 4, "offset ({dx}, {dy}): {out:?}");
        }
    }

    #[test]
    fn separated_boxes_give_nothing() {
        let out = cubes(
            place(Vec3::new(1.1, 0.0, 0.0), Quat::IDENTITY),
            Placement { center: Vec3::ZERO, rotation: Mat3::IDENTITY },
        );
        assert!(out.is_empty());
    }
}
