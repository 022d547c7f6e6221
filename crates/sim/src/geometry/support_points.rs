//! One contact manifold cut to the points that hold the shape.
//!
//! parry's manifolds repeat points (a cylinder's rim or a capsule's end
//! against a face comes back as two or three copies of one point) and add
//! the GJK point inside the clipped polygon (a capsule lying on a face gives
//! its two ends and a third point between them). Copies make identical LCP
//! rows, and a point inside the polygon of the others holds nothing the
//! polygon does not; each costs `k + 2` unknowns. What is kept, in the
//! manifold's tangent plane (all its points share one normal): the corners
//! of the points' convex hull — two for a line contact — and a point inside
//! if it is deeper than every corner. Points closer than `tol` count as one,
//! with the smaller gap. (Cutting the corners to the four of largest area, as
//! the box–box routine keeps a face's 4, was measured and not kept: see
//! docs/simulator.md.)

use super::GeomContact;
use crate::geometry::fixed_tangent;

/// Manifolds with more points than this keep them all (parry's convex manifolds have a few).
const MAX_EXAMINED: usize = 16;

/// Cuts the manifold `out[first..]` (one normal) to its support points, in their order.
pub(crate) fn keep_support_points(out: &mut Vec<GeomContact>, first: usize, tol: f64) {
    let n = out.len() - first;
    if n < 2 || n > MAX_EXAMINED {
        return;
    }
    let m = &mut out[first..];
    let mut keep = [true; MAX_EXAMINED];
    // Copies: one point, with the smaller gap.
    for i in 1..n {
        if let Some(j) = (0..i).find(|&j| keep[j] && (m[i].point - m[j].point).norm() <= tol) {
            m[j].gap = m[j].gap.min(m[i].gap);
            keep[i] = false;
        }
    }
    let mut live = Ids::default();
    (0..n).filter(|&i| keep[i]).for_each(|i| live.push(i));
    if live.len > 2 {
        // Tangent-plane coordinates about the first point.
        let (normal, origin) = (m[0].normal, m[0].point);
        let t1 = fixed_tangent(normal);
        let t2 = normal.cross(t1);
        let mut xy = [(0.0, 0.0); MAX_EXAMINED];
        for (k, c) in m.iter().enumerate() {
            xy[k] = ((c.point - origin).dot(t1), (c.point - origin).dot(t2));
        }
        let hull = convex_hull(live, &xy, tol);
        let gap = |i: &usize| m[*i].gap;
        let deepest = live.ids().iter().copied().min_by(|a, b| gap(a).total_cmp(&gap(b))).unwrap_or(0);
        let corner_min = hull.ids().iter().map(gap).fold(f64::INFINITY, f64::min);
        for &i in live.ids() {
            keep[i] = hull.ids().contains(&i) || (i == deepest && m[i].gap < corner_min - tol);
        }
    }
    let mut k = 0;
    out.retain(|_| {
        k += 1;
        k <= first || keep[k - 1 - first]
    });
}

/// Up to `MAX_EXAMINED` point indices, on the stack (the narrow phase allocates nothing per pair).
#[derive(Clone, Copy, Default)]
struct Ids {
    ids: [usize; 2 * MAX_EXAMINED],
    len: usize,
}

impl Ids {
    fn push(&mut self, i: usize) {
        self.ids[self.len] = i;
        self.len += 1;
    }
    fn pop(&mut self) {
        self.len -= 1;
    }
    fn ids(&self) -> &[usize] {
        &self.ids[..self.len]
    }
}

/// Twice the signed area of the triangle `a b c` (positive counter-clockwise).
fn cross(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// The corners of the convex hull of the points `ids` (counter-clockwise; Andrew's monotone
/// chain), a point within `tol` of the line of its neighbours not counting as a corner: two
/// for points on one line.
fn convex_hull(mut s: Ids, xy: &[(f64, f64)], tol: f64) -> Ids {
    s.ids[..s.len].sort_by(|&a, &b| xy[a].0.total_cmp(&xy[b].0).then(xy[a].1.total_cmp(&xy[b].1)));
    let turns_left = |h: &Ids, c: usize| {
        let (a, b) = (xy[h.ids[h.len - 2]], xy[h.ids[h.len - 1]]);
        cross(a, b, xy[c]) > tol * (b.0 - a.0).hypot(b.1 - a.1)
    };
    let mut hull = Ids::default();
    for pass in 0..2 {
        let start = hull.len;
        for &c in s.ids() {
            while hull.len >= start + 2 && !turns_left(&hull, c) {
                hull.pop();
            }
            hull.push(c);
        }
        hull.pop(); // each chain's last point starts the other
        if pass == 0 {
            s.ids[..s.len].reverse();
        }
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn at(x: f64, y: f64, gap: f64) -> GeomContact {
        GeomContact { point: Vec3::new(x, y, 0.0), normal: Vec3::Z, gap }
    }

    fn kept(points: &[GeomContact]) -> Vec<(f64, f64, f64)> {
        let mut out = vec![at(9.0, 9.0, 0.0)]; // another manifold's point, left alone
        out.extend_from_slice(points);
        keep_support_points(&mut out, 1, 1e-9);
        assert_eq!(out[0].point, Vec3::new(9.0, 9.0, 0.0));
        out[1..].iter().map(|c| (c.point.x, c.point.y, c.gap)).collect()
    }

    #[test]
    fn copies_become_one_point_with_the_smaller_gap() {
        assert_eq!(kept(&[at(1.0, 0.0, 0.2), at(1.0, 0.0, 0.1), at(1.0, 1e-12, 0.3)]), [(1.0, 0.0, 0.1)]);
    }

    #[test]
    fn a_line_keeps_its_two_ends_unless_a_point_between_is_deeper() {
        let line = [at(0.0, 0.0, 0.0), at(2.0, 2.0, 0.0), at(1.0, 1.0, 0.0), at(0.5, 0.5, 0.0)];
        assert_eq!(kept(&line), [(0.0, 0.0, 0.0), (2.0, 2.0, 0.0)]);
        let dip = [at(0.0, 0.0, 0.0), at(2.0, 2.0, 0.0), at(1.0, 1.0, -0.01)];
        assert_eq!(kept(&dip).len(), 3);
    }

    #[test]
    fn a_polygon_keeps_its_corners_and_drops_what_is_inside() {
        // A square's corners, a point inside it, a point on an edge and a fifth corner.
        let pts = [
            at(0.0, 0.0, 0.0),
            at(1.0, 0.0, 0.0),
            at(0.5, 0.5, 0.0),
            at(1.0, 1.0, 0.0),
            at(0.5, 1.0, 0.0),
            at(0.0, 1.0, 0.0),
            at(1.02, 0.5, 0.0),
        ];
        let corners = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0), (1.02, 0.5, 0.0)];
        assert_eq!(kept(&pts), corners);
        // Three corners and a point inside: the triangle, unless the point is the deepest.
        let tri = [at(0.0, 0.0, 0.0), at(3.0, 0.0, 0.0), at(0.0, 3.0, 0.0), at(1.0, 1.0, 0.0)];
        assert_eq!(kept(&tri).len(), 3);
        let dip = [at(0.0, 0.0, 0.0), at(3.0, 0.0, 0.0), at(0.0, 3.0, 0.0), at(1.0, 1.0, -1e-3)];
        assert_eq!(kept(&dip).len(), 4);
    }
}
