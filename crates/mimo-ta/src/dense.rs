//! Small dense matrices of a size known at run time (row-major `Vec<f64>`), for the registration
//! estimator (docs/model.md §6.9): products, a Cholesky factor, solves and the inverse of a
//! symmetric positive-definite matrix.

/// An `rows × cols` matrix, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Dense {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// The values, row-major.
    pub a: Vec<f64>,
}

impl Dense {
    /// The zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Dense {
        Dense { rows, cols, a: vec![0.0; rows * cols] }
    }

    /// A diagonal matrix.
    pub fn diag(d: &[f64]) -> Dense {
        let mut m = Dense::zeros(d.len(), d.len());
        for (i, &x) in d.iter().enumerate() {
            m.set(i, i, x);
        }
        m
    }

    /// Element (i, j).
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.cols + j]
    }

    /// Set element (i, j).
    pub fn set(&mut self, i: usize, j: usize, x: f64) {
        self.a[i * self.cols + j] = x;
    }

    /// Add to element (i, j).
    pub fn add_at(&mut self, i: usize, j: usize, x: f64) {
        self.a[i * self.cols + j] += x;
    }

    /// `self · b`.
    pub fn mul(&self, b: &Dense) -> Dense {
        let mut out = Dense::zeros(self.rows, b.cols);
        for i in 0..self.rows {
            for k in 0..self.cols {
                let x = self.at(i, k);
                if x != 0.0 {
                    for j in 0..b.cols {
                        out.a[i * b.cols + j] += x * b.at(k, j);
                    }
                }
            }
        }
        out
    }

    /// `selfᵀ`.
    pub fn t(&self) -> Dense {
        let mut out = Dense::zeros(self.cols, self.rows);
        for i in 0..self.rows {
            for j in 0..self.cols {
                out.set(j, i, self.at(i, j));
            }
        }
        out
    }

    /// `self · x`.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        (0..self.rows).map(|i| (0..self.cols).map(|j| self.at(i, j) * x[j]).sum()).collect()
    }

    /// `self + b`.
    pub fn plus(&self, b: &Dense) -> Dense {
        Dense { rows: self.rows, cols: self.cols, a: self.a.iter().zip(&b.a).map(|(x, y)| x + y).collect() }
    }

    /// `self − b`.
    pub fn minus(&self, b: &Dense) -> Dense {
        Dense { rows: self.rows, cols: self.cols, a: self.a.iter().zip(&b.a).map(|(x, y)| x - y).collect() }
    }

    /// The lower Cholesky factor of a symmetric positive-definite matrix; `None` otherwise.
    pub fn cholesky(&self) -> Option<Dense> {
        let n = self.rows;
        let mut l = Dense::zeros(n, n);
        for j in 0..n {
            let d = self.at(j, j) - (0..j).map(|k| l.at(j, k).powi(2)).sum::<f64>();
            if !(d > 0.0 && d.is_finite()) {
                return None;
            }
            let dj = d.sqrt();
            l.set(j, j, dj);
            for i in j + 1..n {
                let s = self.at(i, j) - (0..j).map(|k| l.at(i, k) * l.at(j, k)).sum::<f64>();
                l.set(i, j, s / dj);
            }
        }
        Some(l)
    }

    /// Solve `L Lᵀ x = b` with `self` the Cholesky factor `L`.
    pub fn chol_solve(&self, b: &[f64]) -> Vec<f64> {
        let n = self.rows;
        let mut y = vec![0.0; n];
        for i in 0..n {
            y[i] = (b[i] - (0..i).map(|k| self.at(i, k) * y[k]).sum::<f64>()) / self.at(i, i);
        }
        let mut x = vec![0.0; n];
        for i in (0..n).rev() {
            x[i] = (y[i] - (i + 1..n).map(|k| self.at(k, i) * x[k]).sum::<f64>()) / self.at(i, i);
        }
        x
    }

    /// The inverse of a symmetric positive-definite matrix; `None` if it is not one.
    pub fn spd_inverse(&self) -> Option<Dense> {
        let l = self.cholesky()?;
        let n = self.rows;
        let mut inv = Dense::zeros(n, n);
        for j in 0..n {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            for (i, x) in l.chol_solve(&e).into_iter().enumerate() {
                inv.set(i, j, x);
            }
        }
        Some(inv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_a_known_matrix() {
        let m = Dense { rows: 2, cols: 2, a: vec![4.0, 2.0, 2.0, 3.0] };
        let inv = m.spd_inverse().expect("spd");
        let id = m.mul(&inv);
        for (k, want) in [1.0, 0.0, 0.0, 1.0].into_iter().enumerate() {
            assert!((id.a[k] - want).abs() < 1e-14, "{id:?}");
        }
        assert!(Dense { rows: 2, cols: 2, a: vec![1.0, 2.0, 2.0, 1.0] }.cholesky().is_none());
    }
}
