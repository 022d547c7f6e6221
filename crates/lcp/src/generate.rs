//! Seeded LCP generators (placeholder being written).
