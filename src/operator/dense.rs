//! Dense operator: every entry of `L` stored (faer). The naive control for the
//! FFT operator, and the matrix of the direct reference solver.

use faer::Mat;

use super::{GridOperator, OffsetTable};

/// `L` as an `N x N` dense matrix, `N = nx ny`.
pub struct DenseOperator {
    nx: usize,
    ny: usize,
    matrix: Mat<f64>,
}

impl DenseOperator {
    /// Assemble `L[i, k] = table(i - k)` for every pair of cells.
    pub fn new(table: OffsetTable<'_>) -> Self {
        table.check();
        let (nx, ny) = (table.nx, table.ny);
        let n = nx * ny;
        let matrix = Mat::from_fn(n, n, |r, c| {
            let (ir, jr) = ((r / ny) as isize, (r % ny) as isize);
            let (ic, jc) = ((c / ny) as isize, (c % ny) as isize);
            table.get(ir - ic, jr - jc)
        });
        Self { nx, ny, matrix }
    }

    /// The assembled matrix.
    pub fn matrix(&self) -> &Mat<f64> {
        &self.matrix
    }
}

impl GridOperator for DenseOperator {
    fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        let n = self.nx * self.ny;
        assert_eq!(x.len(), n);
        assert_eq!(y.len(), n);
        y.iter_mut().enumerate().for_each(|(r, yr)| {
            let row = self.matrix.row(r);
            *yr = (0..n).map(|c| row[c] * x[c]).sum();
        });
    }
}
