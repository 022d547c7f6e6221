//! Which pairs of bodies may touch: MuJoCo's `contype`/`conaffinity` rule.
//!
//! Two bodies collide iff `(contype₁ & conaffinity₂) | (contype₂ & conaffinity₁) ≠ 0`
//! (MuJoCo's `mj_collideGeoms` filter, bit by bit). Both default to 1, so
//! every pair collides unless a user says otherwise; a body with both 0
//! collides with nothing. The filter is applied where the broad phase hands
//! pairs to the narrow phase (`pipeline::detect`): a filtered pair gets no
//! contact, so its bodies pass through each other.

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

#[cfg(test)]
mod tests {
    use super::CollisionFilter as F;

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
