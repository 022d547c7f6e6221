//! The reference sweep-and-prune: the plain textbook broad phase the
//! simulator's own one is compared with.
//!
//! Boxes are kept in an order sorted by their lower x bound. An update
//! re-sorts that order by insertion sort — between steps the bounds move a
//! little, so the order is nearly sorted and the sort costs O(n + swaps) —
//! then sweeps it once: each box is tested against the boxes after it whose
//! lower x bound is not past its upper x bound, and a pair is reported when
//! the y and z intervals overlap too (closed intervals: touching counts).
//! Cost O(n + swaps + k_x), k_x the pairs overlapping in x.

/// An axis-aligned box: `min`, `max` corners.
#[derive(Clone, Copy, Debug)]
pub struct Aabb3 {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// Sweep-and-prune state: the order of the boxes along x, kept between updates.
#[derive(Default)]
pub struct SweepAndPrune {
    order: Vec<u32>,
}

impl SweepAndPrune {
    /// Re-sorts for the new bounds and writes every overlapping pair (i < j) to `pairs`.
    pub fn update(&mut self, boxes: &[Aabb3], pairs: &mut Vec<(u32, u32)>) {
        if self.order.len() != boxes.len() {
            self.order = (0..boxes.len() as u32).collect();
        }
        insertion_sort_by_min_x(&mut self.order, boxes);
        pairs.clear();
        for (a, &i) in self.order.iter().enumerate() {
            let bi = &boxes[i as usize];
            for &j in &self.order[a + 1..] {
                let bj = &boxes[j as usize];
                if bj.min[0] > bi.max[0] {
                    break;
                }
                if overlap(bi, bj, 1) && overlap(bi, bj, 2) {
                    pairs.push((i.min(j), i.max(j)));
                }
            }
        }
    }
}

fn overlap(a: &Aabb3, b: &Aabb3, axis: usize) -> bool {
    a.min[axis] <= b.max[axis] && b.min[axis] <= a.max[axis]
}

fn insertion_sort_by_min_x(order: &mut [u32], boxes: &[Aabb3]) {
    for k in 1..order.len() {
        let v = order[k];
        let key = boxes[v as usize].min[0];
        let mut j = k;
        while j > 0 && boxes[order[j - 1] as usize].min[0] > key {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = v;
    }
}

/// Every overlapping pair by testing all of them (the check for small n).
pub fn brute_force(boxes: &[Aabb3]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            if (0..3).all(|ax| overlap(&boxes[i], &boxes[j], ax)) {
                pairs.push((i as u32, j as u32));
            }
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sap_finds_the_brute_force_pairs_after_moves() {
        let mut boxes: Vec<Aabb3> = (0..200)
            .map(|i| {
                let x = (i * 37 % 101) as f64 * 0.1;
                let y = (i * 53 % 89) as f64 * 0.1;
                let z = (i * 17 % 7) as f64 * 0.3;
                Aabb3 { min: [x, y, z], max: [x + 0.6, y + 0.5, z + 0.4] }
            })
            .collect();
        let mut sap = SweepAndPrune::default();
        let mut pairs = Vec::new();
        for step in 0..3 {
            for (i, b) in boxes.iter_mut().enumerate() {
                let dx = ((i + step) % 5) as f64 * 0.05 - 0.1;
                b.min[0] += dx;
                b.max[0] += dx;
            }
            sap.update(&boxes, &mut pairs);
            pairs.sort_unstable();
            assert_eq!(pairs, brute_force(&boxes));
            assert!(!pairs.is_empty());
        }
    }
}
