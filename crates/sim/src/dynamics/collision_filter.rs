//! Which pairs of bodies may touch: MuJoCo's `contype`/`conaffinity` rule.
//!
//! Two bodies collide iff `(contype₁ & conaffinity₂) | (contype₂ & conaffinity₁) ≠ 0`
//! (MuJoCo's `mj_collideGeoms` filter, bit by bit). Both default to 1, so
//! every pair collides unless a user says otherwise; a body with both 0
//! collides with nothing. The filter is applied where the broad phase hands
//! pairs to the narrow phase (`pipeline::detect`): a filtered pair gets no
//! contact, so its bodies pass through each other.
//!
//! Pairs can also be kept apart one by one, whatever their bits
//! ([`ExcludedPairs`], `World::exclude_pair`): MJCF's `<contact><exclude>`
//! and MuJoCo's parent filter (a body never touches its own weld group or its
//! parent's) read from a compiled model.

/// A body's collision bits (MJCF's `contype`, `conaffinity`). Default 1, 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CollisionFilter {
    /// The bits this body brings to a pair. Default 1.
    pub contype: u32,
    /// The bits this body accepts from the other. Default 1.
    pub conaffinity: u32,
}

impl Default for CollisionFilter {
    fn default() -> Self {
        CollisionFilter { contype: 1, conaffinity: 1 }
    }
}

impl CollisionFilter {
    pub fn new(contype: u32, conaffinity: u32) -> Self {
        CollisionFilter { contype, conaffinity }
    }

    /// Whether a body with this filter may touch one with `other`.
    #[inline]
    pub fn collides_with(&self, other: &CollisionFilter) -> bool {
        (self.contype & other.conaffinity) | (other.contype & self.conaffinity) != 0
    }
}

/// Pairs of bodies that get no contact whatever their collision bits; kept
/// sorted (lower index first) and without repeats, so a look-up is a binary search.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExcludedPairs {
    pairs: Vec<(usize, usize)>,
}

impl ExcludedPairs {
    /// Keeps bodies `a` and `b` apart (either order; a pair given twice is kept once).
    pub fn insert(&mut self, a: usize, b: usize) {
        let p = (a.min(b), a.max(b));
        if let Err(k) = self.pairs.binary_search(&p) {
            self.pairs.insert(k, p);
        }
    }

    /// Whether bodies `a` and `b` are kept apart (either order).
    #[inline]
    pub fn contains(&self, a: usize, b: usize) -> bool {
        !self.pairs.is_empty() && self.pairs.binary_search(&(a.min(b), a.max(b))).is_ok()
    }

    /// The pairs, lower index first, sorted.
    pub fn as_slice(&self) -> &[(usize, usize)] {
        &self.pairs
    }
}

#[cfg(test)]
mod tests {
    use super::CollisionFilter as F;
    use super::ExcludedPairs;

    #[test]
    fn excluded_pairs_are_unordered_and_kept_once() {
        let mut x = ExcludedPairs::default();
        assert!(!x.contains(0, 1));
        x.insert(5, 2);
        x.insert(2, 5);
        x.insert(0, 7);
        assert!(x.contains(2, 5) && x.contains(5, 2) && x.contains(7, 0));
        assert!(!x.contains(2, 7) && !x.contains(5, 5));
        assert_eq!(x.as_slice(), &[(0, 7), (2, 5)]);
    }

    #[test]
    fn mujoco_rule_either_direction_suffices_and_is_symmetric() {
        assert!(F::default().collides_with(&F::default()));
        // type 2 meets affinity 2 in one direction only: enough.
        assert!(F::new(2, 0).collides_with(&F::new(0, 2)));
        assert!(F::new(0, 2).collides_with(&F::new(2, 0)));
        // disjoint bits, and the all-zero (visual) filter.
        assert!(!F::new(1, 1).collides_with(&F::new(2, 2)));
        assert!(!F::new(0, 0).collides_with(&F::default()));
        assert!(!F::new(1, 0).collides_with(&F::new(1, 0)));
    }
}
