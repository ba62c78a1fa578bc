//! Inputs and outputs of the grid operators: a field on every cell of the
//! grid, or its values on a set of cells (the contact set of the iteration,
//! the cells' positions sorted, C order).
//!
//! A product between values on a set ([`GridOperator::apply_set`]) needs no
//! grid-size vector when the operator reads its input and writes its output
//! row by row, as the FFT engine does: the set's values are put into each
//! row as it is transformed and picked from each row as it comes back.
//! The iteration then holds no scattered copy of its short vectors and no
//! full product (two grid vectors: 16 bytes per cell).
//!
//! [`GridOperator::apply_set`]: super::GridOperator::apply_set

use super::real::Real;

/// A field read by an operator.
#[derive(Clone, Copy)]
pub(crate) enum Field<'a> {
    /// Every cell, C order.
    Grid(&'a [f64]),
    /// `values[k]` on cell `cells[k]`, zero on the cells not listed
    /// (`cells` strictly increasing).
    Set {
        cells: &'a [usize],
        values: &'a [f64],
    },
}

/// A field written by an operator.
pub(crate) enum FieldMut<'a> {
    /// Every cell, C order.
    Grid(&'a mut [f64]),
    /// Only the listed cells: `values[k]` for cell `cells[k]`.
    Set {
        cells: &'a [usize],
        values: &'a mut [f64],
    },
}

/// The input and output fields of a product between values on `cells`.
pub(crate) fn set_fields<'a>(
    cells: &'a [usize],
    x: &'a [f64],
    out: &'a mut [f64],
) -> (Field<'a>, FieldMut<'a>) {
    (
        Field::Set { cells, values: x },
        FieldMut::Set { cells, values: out },
    )
}

/// The part of a [`Field`] on a run of whole rows.
#[derive(Clone, Copy)]
pub(crate) enum Rows<'a> {
    Grid(&'a [f64]),
    /// The run's cells (absolute positions) and values.
    Set(&'a [usize], &'a [f64]),
}

/// The part of a [`FieldMut`] on a run of whole rows.
pub(crate) enum RowsMut<'a> {
    Grid(&'a mut [f64]),
    Set(&'a [usize], &'a mut [f64]),
}

/// Where each run of `rows_per` rows (of `ny` cells) starts in a sorted
/// list of cells: `runs + 1` positions, the last `cells.len()`.
fn run_starts(cells: &[usize], rows_per: usize, ny: usize, runs: usize) -> Vec<usize> {
    (0..=runs)
        .map(|r| cells.partition_point(|&c| c < r * rows_per * ny))
        .collect()
}

impl<'a> Field<'a> {
    /// Split into `runs` runs of `rows_per` rows (the last may be shorter)
    /// of a grid of `nx x ny` cells.
    pub(crate) fn runs(self, nx: usize, ny: usize, rows_per: usize) -> Vec<Rows<'a>> {
        let runs = nx.div_ceil(rows_per);
        match self {
            Field::Grid(x) => {
                assert_eq!(x.len(), nx * ny, "a grid field holds every cell");
                x.chunks(rows_per * ny).map(Rows::Grid).collect()
            }
            Field::Set { cells, values } => {
                assert_eq!(cells.len(), values.len(), "one value per cell");
                let at = run_starts(cells, rows_per, ny, runs);
                at.windows(2)
                    .map(|w| Rows::Set(&cells[w[0]..w[1]], &values[w[0]..w[1]]))
                    .collect()
            }
        }
    }
}

impl<'a> FieldMut<'a> {
    /// [`Field::runs`] for an output.
    pub(crate) fn runs(self, nx: usize, ny: usize, rows_per: usize) -> Vec<RowsMut<'a>> {
        let runs = nx.div_ceil(rows_per);
        match self {
            FieldMut::Grid(y) => {
                assert_eq!(y.len(), nx * ny, "a grid field holds every cell");
                y.chunks_mut(rows_per * ny).map(RowsMut::Grid).collect()
            }
            FieldMut::Set { cells, values } => {
                assert_eq!(cells.len(), values.len(), "one value per cell");
                let at = run_starts(cells, rows_per, ny, runs);
                let mut rest = values;
                let mut out = Vec::with_capacity(runs);
                for w in at.windows(2) {
                    let (head, tail) = std::mem::take(&mut rest).split_at_mut(w[1] - w[0]);
                    out.push(RowsMut::Set(&cells[w[0]..w[1]], head));
                    rest = tail;
                }
                out
            }
        }
    }
}

impl Rows<'_> {
    /// Write row `r` (absolute; `ny` cells) into `row[..ny]`, converted by
    /// [`Real::of`]; returns whether it holds any value (a set's row may be empty,
    /// then `row` is left as it was). `cursor` walks a set's run in order.
    #[inline]
    pub(crate) fn fill<U: Real>(
        &self,
        r: usize,
        ny: usize,
        first_row: usize,
        cursor: &mut usize,
        row: &mut [U],
    ) -> bool {
        match *self {
            Rows::Grid(x) => {
                let src = &x[(r - first_row) * ny..(r - first_row + 1) * ny];
                for (d, &v) in row.iter_mut().zip(src) {
                    *d = U::of(v);
                }
                true
            }
            Rows::Set(cells, values) => {
                let (start, end) = (r * ny, (r + 1) * ny);
                let k0 = *cursor;
                while *cursor < cells.len() && cells[*cursor] < end {
                    *cursor += 1;
                }
                if k0 == *cursor {
                    return false;
                }
                row[..ny].fill(U::zero());
                for k in k0..*cursor {
                    row[cells[k] - start] = U::of(values[k]);
                }
                true
            }
        }
    }
}

impl RowsMut<'_> {
    /// Whether row `r` is wanted (a set's run may hold no cell of it).
    #[inline]
    pub(crate) fn wants(&self, r: usize, ny: usize, cursor: usize) -> bool {
        match self {
            RowsMut::Grid(_) => true,
            RowsMut::Set(cells, _) => cursor < cells.len() && cells[cursor] < (r + 1) * ny,
        }
    }

    /// Store row `r` (absolute; `row[..ny]`) in f64.
    #[inline]
    pub(crate) fn store<U: Real>(
        &mut self,
        r: usize,
        ny: usize,
        first_row: usize,
        cursor: &mut usize,
        row: &[U],
    ) {
        match self {
            RowsMut::Grid(y) => {
                let dst = &mut y[(r - first_row) * ny..(r - first_row + 1) * ny];
                for (d, &v) in dst.iter_mut().zip(row) {
                    *d = v.wide();
                }
            }
            RowsMut::Set(cells, values) => {
                let (start, end) = (r * ny, (r + 1) * ny);
                while *cursor < cells.len() && cells[*cursor] < end {
                    values[*cursor] = row[cells[*cursor] - start].wide();
                    *cursor += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_split_a_set_by_rows() {
        // 5 rows of 3 cells; runs of 2 rows.
        let cells = [0, 4, 5, 9, 14];
        let values = [1.0, 2.0, 3.0, 4.0, 5.0];
        let runs = Field::Set {
            cells: &cells,
            values: &values,
        }
        .runs(5, 3, 2);
        assert_eq!(runs.len(), 3);
        let lens: Vec<usize> = runs
            .iter()
            .map(|r| match r {
                Rows::Set(c, _) => c.len(),
                Rows::Grid(_) => unreachable!(),
            })
            .collect();
        assert_eq!(lens, vec![3, 1, 1]);
        // Row 1 of the first run: cells 4, 5 -> positions 1, 2.
        let mut cursor = 0;
        let mut row = [9.0; 4];
        assert!(runs[0].fill(0, 3, 0, &mut cursor, &mut row));
        assert_eq!(&row[..3], &[1.0, 0.0, 0.0]);
        assert!(runs[0].fill(1, 3, 0, &mut cursor, &mut row));
        assert_eq!(&row[..3], &[0.0, 2.0, 3.0]);
        // Row 2 (second run, cell 9 is row 3): empty.
        let mut cursor = 0;
        assert!(!runs[1].fill(2, 3, 2, &mut cursor, &mut row));
        assert!(runs[1].fill(3, 3, 2, &mut cursor, &mut row));
        assert_eq!(&row[..3], &[4.0, 0.0, 0.0]);

        let mut out = [0.0; 5];
        let mut runs = FieldMut::Set {
            cells: &cells,
            values: &mut out,
        }
        .runs(5, 3, 2);
        let mut cursor = 0;
        assert!(runs[0].wants(1, 3, 1));
        runs[0].store(0, 3, 0, &mut cursor, &[10.0, 11.0, 12.0]);
        runs[0].store(1, 3, 0, &mut cursor, &[13.0, 14.0, 15.0]);
        assert_eq!(cursor, 3);
        drop(runs);
        assert_eq!(&out[..3], &[10.0, 14.0, 15.0]);
    }
}
