//! Brute-force enumeration (placeholder being written).
