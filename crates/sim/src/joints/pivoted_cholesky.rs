//! A rank-revealing Cholesky of a symmetric positive semidefinite matrix
//! (diagonal pivoting): `Πᵀ S Π = L Lᵀ` with `L` of the numerical rank `r`.
//! It stops when the largest remaining pivot is below `tol · top` (`top` the
//! caller's scale, `max diag S` of the rigid rows), so
//! rows that depend on earlier ones (a closed loop, a joint given twice) are
//! dropped rather than inverted. `solve` then answers `S x = b` with `x` zero
//! on the dropped rows: for a consistent `b` an exact solution, and `Gᵀx`
//! (what the joints use) is the same for every solution.
//!
//! (faer's `llt_pivoting` fixes its stop at `n·ε·max diag`; rows of joints
//! built from a moving geometry are dependent only to their round-off, which
//! that bound can miss, so the tolerance here is the caller's.)

/// The factor and its permutation; buffers kept between factorizations.
#[derive(Clone, Debug, Default)]
pub struct PivotedCholesky {
    m: usize,
    rank: usize,
    /// Row-major working copy; `L` in its lower triangle (pivoted order).
    a: Vec<f64>,
    /// `perm[i]`: the original row at pivoted position `i`.
    perm: Vec<usize>,
    y: Vec<f64>,
}

impl PivotedCholesky {
    /// Factors the `m × m` row-major `s`, stopping below `tol · top`.
    pub fn factor(&mut self, s: &[f64], m: usize, tol: f64, top: f64) {
        self.m = m;
        self.a.clear();
        self.a.extend_from_slice(s);
        self.perm.clear();
        self.perm.extend(0..m);
        let a = &mut self.a;
        let stop = tol * top;
        self.rank = 0;
        for j in 0..m {
            // The largest remaining pivot.
            let (p, d) =
                (j..m).map(|i| (i, a[i * m + i])).fold((j, f64::NEG_INFINITY), |b, x| if x.1 > b.1 { x } else { b });
            if !(d > stop && d > 0.0) {
                break;
            }
            if p != j {
                for k in 0..m {
                    a.swap(j * m + k, p * m + k);
                }
                for k in 0..m {
                    a.swap(k * m + j, k * m + p);
                }
                self.perm.swap(j, p);
            }
            let l = d.sqrt();
            a[j * m + j] = l;
            for i in j + 1..m {
                a[i * m + j] /= l;
            }
            // The trailing block, both triangles (kept symmetric for the swaps).
            for i in j + 1..m {
                let lij = a[i * m + j];
                if lij == 0.0 {
                    continue;
                }
                for k in j + 1..m {
                    a[i * m + k] -= lij * a[k * m + j];
                }
            }
            self.rank += 1;
        }
    }

    /// The numerical rank found.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// `x` with `S x = b` on the independent rows, zero on the dropped ones.
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) {
        let mut y = std::mem::take(&mut self.y);
        self.forward(b, 1, &mut y);
        self.backward(&y, x);
        self.y = y;
    }

    /// `Y = L⁻¹ Πᵀ B` for the `m × cols` row-major `B`: `rank × cols`,
    /// row-major (so that `Bᵀ S⁺ B = Yᵀ Y`).
    pub fn forward(&self, b: &[f64], cols: usize, y: &mut Vec<f64>) {
        let (m, r, a) = (self.m, self.rank, &self.a);
        y.clear();
        if cols == 1 {
            // One column (a projection, a contact's normal mobility): the
            // same subtractions in the same order, without a slice per term.
            for (i, &p) in self.perm[..r].iter().enumerate() {
                let mut v = b[p];
                for (k, &u) in y.iter().enumerate() {
                    v -= a[i * m + k] * u;
                }
                y.push(v / a[i * m + i]);
            }
            return;
        }
        for &p in &self.perm[..r] {
            y.extend_from_slice(&b[p * cols..(p + 1) * cols]);
        }
        for i in 0..r {
            let (done, rest) = y.split_at_mut(i * cols);
            let yi = &mut rest[..cols];
            for k in 0..i {
                let l = a[i * m + k];
                if l != 0.0 {
                    for (v, &u) in yi.iter_mut().zip(&done[k * cols..(k + 1) * cols]) {
                        *v -= l * u;
                    }
                }
            }
            let d = a[i * m + i];
            yi.iter_mut().for_each(|v| *v /= d);
        }
    }

    /// `x = Π L⁻ᵀ y` (length `m`, zero on the dropped rows) for a `y` of length `rank`.
    pub fn backward(&self, y: &[f64], x: &mut [f64]) {
        let (m, r, a, perm) = (self.m, self.rank, &self.a, &self.perm);
        // In place in x, pivot i at x[perm[i]] (no buffer: a step calls this twice).
        x.iter_mut().for_each(|v| *v = 0.0);
        for (&p, &v) in perm[..r].iter().zip(y) {
            x[p] = v;
        }
        for i in (0..r).rev() {
            let s: f64 = (i + 1..r).map(|k| a[k * m + i] * x[perm[k]]).sum();
            x[perm[i]] = (x[perm[i]] - s) / a[i * m + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One column is forward-substituted as a block of columns is: the same bits.
    #[test]
    fn one_column_is_one_column_of_a_block() {
        let g = [[1.0, 2.0, 0.5, 0.0], [0.0, 1.0, 3.0, -1.0], [2.0, -1.0, 0.0, 1.0], [0.3, 0.7, -0.2, 2.0]];
        let s: Vec<f64> = (0..16).map(|k| (0..4).map(|t| g[k / 4][t] * g[k % 4][t]).sum()).collect();
        let mut f = PivotedCholesky::default();
        f.factor(&s, 4, 1e-9, 10.0);
        let block = [0.1, -2.0, 3.5, 0.25, 1e-3, 7.0, -0.5, 2.0];
        let (mut both, mut first) = (Vec::new(), Vec::new());
        f.forward(&block, 2, &mut both);
        let column: Vec<f64> = block.iter().step_by(2).copied().collect();
        f.forward(&column, 1, &mut first);
        assert_eq!(first, both.iter().step_by(2).copied().collect::<Vec<_>>());
    }

    #[test]
    fn a_repeated_row_is_dropped_and_the_consistent_system_solved() {
        // S = G Gᵀ with G's third row a copy of its first: rank 2.
        let g = [[1.0, 2.0, 0.0], [0.0, 1.0, 3.0], [1.0, 2.0, 0.0]];
        let s: Vec<f64> = (0..9).map(|k| (0..3).map(|t| g[k / 3][t] * g[k % 3][t]).sum()).collect();
        let mut f = PivotedCholesky::default();
        let top = (0..3).map(|i| s[i * 4]).fold(0.0, f64::max);
        f.factor(&s, 3, 1e-9, top);
        assert_eq!(f.rank(), 2);
        // b = S x₀ is consistent; the answer solves S x = b.
        let x0 = [0.5, -1.0, 2.0];
        let b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| s[i * 3 + j] * x0[j]).sum()).collect();
        let mut x = [0.0; 3];
        f.solve(&b, &mut x);
        for i in 0..3 {
            let sx: f64 = (0..3).map(|j| s[i * 3 + j] * x[j]).sum();
            assert!((sx - b[i]).abs() < 1e-12, "row {i}: {sx} vs {}", b[i]);
        }
    }
}
