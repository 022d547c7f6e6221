//! Issue 15, item 6: the `world` fuzz target's properties
//! (`tests/properties/mod.rs`) in the normal test suite — any bodies and
//! parameters give `Ok` or a `SimError`, never a panic, and consistent records.

mod properties;

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn any_world_steps_without_panicking(data in proptest::collection::vec(any::<u8>(), 0..300)) {
        if let Err(e) = properties::check(&data) {
            prop_assert!(false, "{}", e);
        }
    }
}

/// A resting box, decoded from fixed bytes, solves every step (the decoder's plausible path works).
#[test]
fn a_plausible_world_solves() {
    let mut data = vec![0u8; 300];
    data[0] = 0; // default Lemke
    properties::check(&data).unwrap();
}
