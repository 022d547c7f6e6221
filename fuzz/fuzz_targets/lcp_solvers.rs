//! `Lcp::new` and every solver on small arbitrary problems: no panic, sizes and
//! budgets kept, `Solved` only within the documented rule. The decoding and the
//! properties are the property test's (`crates/lcp/tests/properties/`).
#![no_main]

#[path = "../../crates/lcp/tests/properties/mod.rs"]
mod properties;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = properties::check(&properties::decode(data)) {
        panic!("{e}");
    }
});
