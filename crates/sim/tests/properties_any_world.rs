//! Issue 15, item 6: the `world` fuzz target's properties
//! (`tests/properties/mod.rs`) in the normal test suite — any bodies and
//! parameters give `Ok` or a `SimError`, never a panic, and consistent records.

mod properties;

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use std::sync::atomic::{AtomicUsize, Ordering};

static STEPS: AtomicUsize = AtomicUsize::new(0);
static SOLVED: AtomicUsize = AtomicUsize::new(0);

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn any_world_steps_without_panicking(data in proptest::collection::vec(any::<u8>(), 0..300)) {
        match properties::check(&data) {
            Ok(s) => {
                STEPS.fetch_add(s.steps, Ordering::Relaxed);
                SOLVED.fetch_add(s.solved, Ordering::Relaxed);
            }
            Err(e) => prop_assert!(false, "{}", e),
        }
    }
}

/// The decoder reaches real stepping: over random inputs, many steps run and
/// many contact LCPs are solved (not only refusals of invalid input).
#[test]
fn random_worlds_reach_contact() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut steps, mut solved) = (0, 0);
    for _ in 0..400 {
        let data = proptest::collection::vec(any::<u8>(), 0..300).new_tree(&mut runner).unwrap().current();
        let s = properties::check(&data).unwrap();
        steps += s.steps;
        solved += s.solved;
    }
    eprintln!("random worlds: {steps} steps, {solved} with contacts solved");
    assert!(steps > 400 && solved > 50, "{steps} steps, {solved} solved contact steps");
}
