//! A finite pad on an unbounded half-space: the surface rise of a flux
//! map, piecewise constant on cells, as the exact linear convolution of
//! the flux with the moving point source integrated over each cell
//! (physics.md section 14: "non-periodic pads ... use the real-space
//! kernel integrated over cells, Toeplitz-embedded like the elastic one").
//!
//! The `(2 nx - 1) x (2 ny - 1)` table of cell integrals
//! ([`moving_source_table`], [`super::cell`]) is applied by the elastic
//! kernel's zero-padded FFT embedding ([`ToeplitzFft`]), planned once.

use rayon::prelude::*;

use super::cell::{MovingSource, Rect};
use super::setup::HeatSetup;
use crate::operator::{GridOperator, OffsetTable, ToeplitzFft};

/// The rise \[K\] at the centre of cell `(i, j)` per unit flux \[W/m^2\]
/// on cell `(i - di, j - dj)`, for every offset of the grid of `setup`:
/// `values[(di + nx - 1) * (2 ny - 1) + (dj + ny - 1)]` (the layout of
/// [`OffsetTable`]). `setup` must pass [`HeatSetup::check`]. When the
/// sliding direction is along a grid axis the table is exactly mirror
/// symmetric across it (one half computed, the other copied).
pub(crate) fn moving_source_table(setup: &HeatSetup) -> Vec<f64> {
    let g = setup.grid;
    let (nx, ny) = (g.nx() as isize, g.ny() as isize);
    let e = setup.direction();
    let source = MovingSource::new(setup.speed, setup.conduction.diffusivity, e);
    let scale = 1.0 / (std::f64::consts::TAU * setup.conduction.conductivity);
    let width = (2 * ny - 1) as usize;
    let (mirror_x, mirror_y) = (e.0 == 0.0, e.1 == 0.0);
    let mut values = vec![0.0; (2 * nx - 1) as usize * width];
    values
        .par_chunks_mut(width)
        .enumerate()
        .for_each(|(row, out)| {
            let di = row as isize - (nx - 1);
            if mirror_x && di < 0 {
                return;
            }
            for dj in -(ny - 1)..ny {
                if mirror_y && dj < 0 {
                    continue;
                }
                let r = Rect::centred(
                    di as f64 * g.cell().0,
                    dj as f64 * g.cell().1,
                    g.cell().0,
                    g.cell().1,
                );
                out[(dj + ny - 1) as usize] = scale * source.rect(r);
            }
            if mirror_y {
                for dj in 1..ny {
                    out[(ny - 1 - dj) as usize] = out[(ny - 1 + dj) as usize];
                }
            }
        });
    if mirror_x {
        for di in 1..nx {
            let (from, to) = ((nx - 1 + di) as usize, (nx - 1 - di) as usize);
            let (low, high) = values.split_at_mut(from * width);
            low[to * width..(to + 1) * width].copy_from_slice(&high[..width]);
        }
    }
    values
}

impl HeatSetup {
    /// The rise \[K\] at the centre of cell `(i, j)` per unit flux
    /// \[W/m^2\] on cell `(i - di, j - dj)`, for every offset of the grid:
    /// `values[(di + nx - 1) * (2 ny - 1) + (dj + ny - 1)]`; `self` must
    /// pass [`HeatSetup::check`].
    pub fn moving_source_table(&self) -> Vec<f64> {
        moving_source_table(self)
    }
}

/// The pad's operator: the table's FFT embedding, planned once.
pub(crate) struct PadPlan {
    op: ToeplitzFft,
}

impl PadPlan {
    pub fn new(setup: &HeatSetup) -> Self {
        let table = moving_source_table(setup);
        let op = ToeplitzFft::new(OffsetTable {
            nx: setup.grid.nx(),
            ny: setup.grid.ny(),
            values: &table,
        });
        Self { op }
    }

    /// The surface rise \[K\] at every cell centre under `flux` \[W/m^2\].
    pub fn apply(&mut self, flux: &[f64]) -> Vec<f64> {
        let mut rise = vec![0.0; flux.len()];
        self.op.apply(flux, &mut rise);
        rise
    }
}
