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
//! parent's) read from a compiled model. And pairs can be made to touch one by
//! one, past the bits and the exclusions, with their own μ ([`ContactPairs`],
//! `World::add_contact_pair`): MJCF's `<contact><pair>`.

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

/// Values keyed by unordered pairs of bodies; kept sorted (lower index first)
/// and without repeats, so a look-up is a binary search.
#[derive(Clone, Debug, PartialEq)]
pub struct PairMap<V> {
    keys: Vec<(usize, usize)>,
    values: Vec<V>,
}

impl<V> Default for PairMap<V> {
    fn default() -> Self {
        PairMap { keys: Vec::new(), values: Vec::new() }
    }
}

impl<V> PairMap<V> {
    /// Sets the value of the pair `a`, `b` (either order; a pair given again takes the new value).
    pub fn insert(&mut self, a: usize, b: usize, value: V) {
        let p = (a.min(b), a.max(b));
        match self.keys.binary_search(&p) {
            Ok(k) => self.values[k] = value,
            Err(k) => {
                self.keys.insert(k, p);
                self.values.insert(k, value);
            }
        }
    }

    /// The value of the pair `a`, `b` (either order).
    #[inline]
    pub fn get(&self, a: usize, b: usize) -> Option<&V> {
        if self.keys.is_empty() {
            return None;
        }
        self.keys.binary_search(&(a.min(b), a.max(b))).ok().map(|k| &self.values[k])
    }

    /// Whether the pair `a`, `b` is in the map (either order).
    #[inline]
    pub fn contains(&self, a: usize, b: usize) -> bool {
        self.get(a, b).is_some()
    }

    /// The pairs, lower index first, sorted.
    pub fn as_slice(&self) -> &[(usize, usize)] {
        &self.keys
    }

    /// The values, in the order of [`PairMap::as_slice`].
    pub fn values(&self) -> &[V] {
        &self.values
    }
}

/// Pairs of bodies that get no contact whatever their collision bits.
pub type ExcludedPairs = PairMap<()>;

/// Pairs of bodies that touch whatever their collision bits and exclusions,
/// each with its own μ (which replaces the bodies' combined one).
pub type ContactPairs = PairMap<f64>;

#[cfg(test)]
mod tests {
    use super::CollisionFilter as F;
    use super::{ContactPairs, ExcludedPairs};

    #[test]
    fn excluded_pairs_are_unordered_and_kept_once() {
        let mut x = ExcludedPairs::default();
        assert!(!x.contains(0, 1));
        x.insert(5, 2, ());
        x.insert(2, 5, ());
        x.insert(0, 7, ());
        assert!(x.contains(2, 5) && x.contains(5, 2) && x.contains(7, 0));
        assert!(!x.contains(2, 7) && !x.contains(5, 5));
        assert_eq!(x.as_slice(), &[(0, 7), (2, 5)]);
    }

    #[test]
    fn a_contact_pair_given_again_takes_the_new_mu() {
        let mut x = ContactPairs::default();
        x.insert(4, 1, 0.3);
        x.insert(0, 2, 0.0);
        x.insert(1, 4, 0.7);
        assert_eq!(x.get(4, 1), Some(&0.7));
        assert_eq!(x.get(2, 0), Some(&0.0));
        assert_eq!(x.get(1, 2), None);
        assert_eq!((x.as_slice(), x.values()), (&[(0, 2), (1, 4)][..], &[0.0, 0.7][..]));
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
