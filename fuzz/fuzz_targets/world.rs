//! `World` on arbitrary bodies, parameters and forces, stepped a few times:
//! `Ok` or a `SimError`, never a panic, and consistent records. The decoding
//! and the properties are the property test's (`crates/sim/tests/properties/`).
#![no_main]

#[path = "../../crates/sim/tests/properties/mod.rs"]
mod properties;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = properties::check(data) {
        panic!("{e}");
    }
});
