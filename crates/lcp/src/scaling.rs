//! Diagonal scaling (placeholder being written).

/// Row and column scale factors: the scaled problem is `D_r M D_c, D_r q`.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    pub row: Vec<f64>,
    pub col: Vec<f64>,
}
