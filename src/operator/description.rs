//! Operator descriptions: what an executor needs to build the influence
//! operator `u = L p` (paper Eq. 7) of one grid, and nothing of how it is
//! applied. The problem layer produces a description per grid (the fine
//! grid, each grid of a coarse-to-fine cascade, the level tables of the
//! adaptive mesh); each executor turns it into its own
//! [`crate::backend::Backend`] (the CPU: the operators of this module; the
//! GPU: device tables and kernels), so that the iteration, the cascade and
//! the refinement are written once against the backend.

use std::sync::Arc;

use super::LevelTables;
use crate::kernel::{CoefficientTable, KernelError, SlidingKernel};
use crate::response::{Grid, SlidingResponse};

/// The influence operator of one grid or mesh.
#[derive(Debug, Clone, Copy)]
pub enum OperatorDescription<'a> {
    /// Non-periodic uniform grid: the block-Toeplitz operator of the
    /// kernel's coefficient table on `grid` (paper Eq. 6-7, physics.md
    /// section 3), applied by a zero-padded FFT.
    Toeplitz {
        kernel: &'a SlidingKernel,
        grid: Grid,
    },
    /// Periodic cell: the spectral multiplier of the response on `grid`
    /// (paper Appendix, Eq. A1-A2).
    Periodic {
        response: &'a SlidingResponse,
        grid: Grid,
    },
    /// Adaptive quadtree of the fine grid: the pairwise operator read from
    /// per-level coefficient tables (physics.md section 7); each round's
    /// mesh is given to the executor beside it.
    Levels {
        kernel: &'a SlidingKernel,
        tables: &'a Arc<LevelTables>,
    },
}

impl OperatorDescription<'_> {
    /// The `(nx, ny)` cells of the grid (the fine grid of the level tables).
    pub fn shape(&self) -> (usize, usize) {
        match self {
            Self::Toeplitz { grid, .. } | Self::Periodic { grid, .. } => grid.size(),
            Self::Levels { tables, .. } => tables.shape(),
        }
    }

    /// The host f64 coefficient table of a Toeplitz description (`None`
    /// for the others).
    pub fn host_table(&self) -> Option<Result<CoefficientTable, KernelError>> {
        match self {
            Self::Toeplitz { kernel, grid } => Some(kernel.table(grid)),
            _ => None,
        }
    }
}
