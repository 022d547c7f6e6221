//! The `shapes` fuzz target's properties (`tests/shape_properties/mod.rs`) in
//! the normal test suite: any hull points, mesh vertices and faces, compound parts and height grids give a
//! shape or a `BadGeometry` naming the field, never a panic, and a world with
//! the shape steps cleanly.

mod properties;
mod shape_properties;

use proptest::prelude::*;
use proptest::strategy::ValueTree;

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn any_hull_or_mesh_is_a_shape_or_a_named_refusal(data in proptest::collection::vec(any::<u8>(), 0..400)) {
        if let Err(e) = shape_properties::check(&data) {
            prop_assert!(false, "{}", e);
        }
    }
}

/// The decoder reaches both sides: random inputs give accepted hulls and
/// meshes that step, and refusals.
#[test]
fn random_shapes_are_accepted_and_refused_and_step() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut accepted, mut refused, mut steps) = (0, 0, 0);
    let mut compounds = [0usize; 2]; // refused, accepted
    let mut fields = [0usize; 2];
    for _ in 0..300 {
        let data = proptest::collection::vec(any::<u8>(), 0..400).new_tree(&mut runner).unwrap().current();
        let s = shape_properties::check(&data).unwrap();
        if s.accepted {
            accepted += 1;
        } else {
            refused += 1;
        }
        steps += s.steps;
        if s.kind == 2 {
            compounds[s.accepted as usize] += 1;
        }
        if s.kind == 3 {
            fields[s.accepted as usize] += 1;
        }
    }
    assert!(compounds[0] >= 10 && compounds[1] >= 10, "compounds refused, accepted: {compounds:?}");
    assert!(fields[0] >= 10 && fields[1] >= 10, "height fields refused, accepted: {fields:?}");
    assert!(accepted >= 30 && refused >= 30 && steps >= 100, "accepted {accepted}, refused {refused}, steps {steps}");
}
