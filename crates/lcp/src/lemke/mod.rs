//! Lemke's complementary pivoting method (being written).
mod options;
pub use options::{LemkeOptions, Pivoting};
use crate::{Lcp, Solution, Status};

pub fn solve(lcp: &Lcp, _o: &LemkeOptions) -> Solution {
    Solution::from_z(lcp, vec![0.0; lcp.n()], Status::Numerical, 0)
}
