//! What a heat problem holds at once, so that work too large for the
//! memory available is refused before it starts rather than stopped by an
//! allocation failure in its middle (measured peaks: BENCHMARKS.md "The
//! heated solve's memory").

use crate::response::Grid;

use super::{DepthRule, HeatError};

/// Bytes per cell of a planned heat problem ([`super::HeatSolver::new`]):
/// on a pad the offset table, its wrapped copy and spectrum (four times
/// the grid each) and the block's spectrum; on a periodic cell its
/// multiplier, spectrum and a depth map's transforms (measured peaks at
/// 1024^2: about 190 and 50 bytes per cell).
pub(crate) fn plan_bytes_per_cell(periodic: bool) -> u64 {
    if periodic {
        64
    } else {
        192
    }
}

/// Bytes the volume source of `grid` under `rule` holds at once
/// ([`super::HeatSource::from_contact`], [`super::HeatSolver::under`]):
/// its density, one f64 map per source layer (at most: a deep layer
/// evaluated on a coarser grid holds that grid's spectrum instead,
/// [`super::LayerDensity`]), and, while its rise is summed, each layer's
/// half spectrum (`nx (ny / 2 + 1)` complex values); with the number of
/// source layers.
pub(crate) fn volume_bytes(grid: &Grid, rule: &DepthRule) -> Result<(u64, usize), HeatError> {
    let layers = rule.layers(grid)?.count();
    let (nx, ny) = grid.size();
    let map = (nx as u64).saturating_mul(ny as u64).saturating_mul(8);
    let spectrum = (nx as u64)
        .saturating_mul(ny as u64 / 2 + 1)
        .saturating_mul(16);
    Ok((
        (layers as u64).saturating_mul(map.saturating_add(spectrum)),
        layers,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heat::{HeatSource, SourceKind};
    use crate::material::{CreepSpectrum, Material};
    use crate::response::SlidingResponse;

    #[test]
    fn the_volume_estimate_counts_the_sources_own_layers() {
        let sls = CreepSpectrum::standard_linear_solid(3e6, 1e7, 1e-3).unwrap();
        let material = Material::new(sls, 0.5).unwrap();
        let response = SlidingResponse::new(&material, 0.01, 0.0, None).unwrap();
        for (nx, ny) in [(24, 16), (33, 20)] {
            let grid = Grid::new(nx, ny, (1e-5, 1.3e-5)).unwrap().periodic();
            let pressure: Vec<f64> = (0..nx * ny).map(|k| ((k * 31) % 7) as f64 * 1e4).collect();
            for rule in [DepthRule::default(), DepthRule::refined()] {
                let source = HeatSource::from_contact(
                    SourceKind::Volume,
                    &pressure,
                    &grid,
                    &response,
                    &rule,
                )
                .unwrap();
                let HeatSource::Volume { layers, density } = source else {
                    panic!("a volume source");
                };
                let (bytes, count) = volume_bytes(&grid, &rule).unwrap();
                assert_eq!(count, layers.count());
                // One f64 map and one half spectrum of complex values per
                // layer (a layer of coarse parts only holds less).
                let spectra = count * nx * (ny / 2 + 1) * 16;
                assert!(bytes as usize >= density.bytes() + spectra);
                assert_eq!(density.layer_count(), count);
            }
        }
    }
}
