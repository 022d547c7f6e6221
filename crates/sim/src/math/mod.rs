//! Small fixed-size linear algebra: just what rigid bodies and contacts need.
//!
//! `Vec3`, `Mat3` (row-major) and unit quaternions `Quat` stored as
//! (w, x, y, z), the crate's convention. Everything is `Copy` and allocation-free;
//! no external dependency is worth pulling in for ~300 lines of arithmetic.

mod mat3;
mod quat;
mod vec3;

pub use mat3::Mat3;
pub use quat::Quat;
pub use vec3::Vec3;
