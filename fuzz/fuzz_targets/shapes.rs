//! Convex hulls, triangle meshes, compounds and height fields on arbitrary points, faces, parts and grids, added to a
//! world and stepped: a shape or a `BadGeometry` naming the field, never a
//! panic, a refused body leaves the world unchanged. The decoding and the
//! properties are the property test's (`crates/sim/tests/shape_properties/`).
#![no_main]

#[path = "../../crates/sim/tests/properties/mod.rs"]
mod properties;
#[path = "../../crates/sim/tests/shape_properties/mod.rs"]
mod shape_properties;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = shape_properties::check(data) {
        panic!("{e}");
    }
});
