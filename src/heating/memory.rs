//! The heated solve's memory, checked before its first isothermal solve:
//! a grid whose heat problem cannot be held is refused in one line, not
//! stopped by an allocation failure after minutes of solving (measured
//! peaks: BENCHMARKS.md "The heated solve's memory").

use crate::error::{Error, Result};
use crate::heat::memory::{plan_bytes_per_cell, volume_bytes};
use crate::heat::{DepthRule, SourceKind};
use crate::io::memory::{check_fits, size};
use crate::problem::{memory_estimate, Problem};

/// Bytes per cell the heated solve holds beside one isothermal solve and
/// its heat problem while the next evaluation runs: the warm start's four
/// fields (pressure, displacement, gap, contact: 32) and each root kept,
/// its fields and surface rise (40), for up to three roots (a cold, an
/// unstable and a hot branch; measured: 987 MiB at 1024^2 with three,
/// 867 MiB with one, BENCHMARKS.md "The heated solve's memory").
const KEPT_BYTES_PER_CELL: u64 = 32 + 3 * 40;

/// The bytes of one grid's part of a heated solve of `problem` with the
/// heat source `kind`: its isothermal solve, its planned heat problem,
/// what the fixed point keeps and, for the volume source, the source's
/// density and layer spectra (the last also returned apart).
fn grid_bytes(problem: &Problem, kind: SourceKind, rule: &DepthRule) -> Result<(u64, u64)> {
    let s = &problem.surface;
    let cells = (s.nx as u64).saturating_mul(s.ny as u64);
    let grid = problem.grid()?;
    let solve = memory_estimate(
        s.nx,
        s.ny,
        problem.params.restart,
        problem.formulation,
        problem.precision.unwrap_or_default(),
    );
    let kept = cells.saturating_mul(plan_bytes_per_cell(grid.is_periodic()) + KEPT_BYTES_PER_CELL);
    let volume = match kind {
        SourceKind::Volume => {
            volume_bytes(&grid, rule)
                .map_err(|e| Error::Invalid(e.to_string()))?
                .0
        }
        SourceKind::Surface => 0,
    };
    Ok((solve.saturating_add(kept).saturating_add(volume), volume))
}

/// Refuse the heated solve of `problem` (and of its `coarse` scan grid)
/// with the heat source `kind` where it needs more memory than is
/// available, naming the volume source's share and what the surface
/// source would need.
pub(crate) fn check_heated_memory(
    problem: &Problem,
    coarse: Option<&Problem>,
    kind: SourceKind,
    rule: &DepthRule,
) -> Result<()> {
    let total = |kind: SourceKind| -> Result<(u64, u64)> {
        let (mut need, mut volume) = grid_bytes(problem, kind, rule)?;
        if let Some(c) = coarse {
            let (n, v) = grid_bytes(c, kind, rule)?;
            need = need.saturating_add(n);
            volume = volume.saturating_add(v);
        }
        Ok((need, volume))
    };
    let (need, volume) = total(kind)?;
    let s = &problem.surface;
    check_fits(
        || {
            let part = if kind == SourceKind::Volume {
                format!(
                    " (the volume source's density and layer spectra {})",
                    size(volume)
                )
            } else {
                String::new()
            };
            format!("heated solve of {} x {} cells{part}", s.nx, s.ny)
        },
        need,
    )
    .map_err(|e| {
        let hint = match kind {
            SourceKind::Volume => match total(SourceKind::Surface) {
                Ok((surface, _)) => format!(
                    "; [heating] source = \"surface\" needs {}, or take fewer cells",
                    size(surface)
                ),
                Err(_) => String::new(),
            },
            SourceKind::Surface => "; take fewer cells".to_string(),
        };
        Error::Invalid(format!("[heating] {e}{hint}"))
    })
}
