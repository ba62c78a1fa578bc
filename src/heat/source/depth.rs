//! The depth layers a volume heat source is given on, and the Gauss nodes
//! inside each layer at which the dissipation density is evaluated
//! (physics.md section 14: each surface mode `q` dissipates within a depth
//! of about `1 / |q|`, so the layers must reach from a fraction of the
//! smallest contact spot, the cell, down to the period).

use super::super::error::{positive, HeatError};
use super::super::layers::DepthLayers;
use crate::gauss::gauss_legendre;
use crate::response::Grid;

/// Geometric depth layers and the Gauss rule within each.
///
/// The boundaries are `0, z_1, z_1 r, z_1 r^2, ...` down to the first at or
/// below `bottom`, with `z_1 = first_fraction * min(a_x, a_y)` and `bottom
/// = depth_periods * max(L_x, L_y)`; each layer's dissipation is its
/// average by `points`-point Gauss-Legendre. The default (`first_fraction`
/// 1/8, `ratio` 2, `points` 3, `depth_periods` 2) integrates the
/// dissipation of every mode of the grid over depth to about 5e-5 (the
/// mode `q` integrand `(qz)^2 exp(-2qz)` on geometric panels; the deepest
/// mode, `2 pi / L`, is cut at `exp(-8 pi)`); [`DepthRule::refined`]
/// (`ratio` `sqrt 2`, `points` 4) to about 5e-9.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthRule {
    /// The first boundary below the surface in units of the smaller cell
    /// side.
    pub first_fraction: f64,
    /// Ratio of consecutive boundaries (> 1).
    pub ratio: f64,
    /// Gauss-Legendre points per layer (1 to 16).
    pub points: usize,
    /// The depth reached, in units of the longer period.
    pub depth_periods: f64,
}

impl Default for DepthRule {
    fn default() -> Self {
        Self {
            first_fraction: 0.125,
            ratio: 2.0,
            points: 3,
            depth_periods: 2.0,
        }
    }
}

impl DepthRule {
    /// Finer layers and more points: depth integrals to about 5e-9.
    pub fn refined() -> Self {
        Self {
            ratio: std::f64::consts::SQRT_2,
            points: 4,
            ..Self::default()
        }
    }

    fn check(&self) -> Result<(), HeatError> {
        positive(
            "the first layer's fraction of a cell",
            self.first_fraction,
            "",
        )?;
        positive("the depth in periods", self.depth_periods, "")?;
        if !(self.ratio > 1.0 && self.ratio.is_finite()) {
            return Err(HeatError::Layers(format!(
                "the ratio of consecutive boundaries must be > 1 and finite, got {}",
                self.ratio
            )));
        }
        if !(1..=16).contains(&self.points) {
            return Err(HeatError::Layers(format!(
                "give 1 to 16 Gauss points per layer, got {}",
                self.points
            )));
        }
        Ok(())
    }

    /// The layers of `grid`.
    pub fn layers(&self, grid: &Grid) -> Result<DepthLayers, HeatError> {
        self.check()?;
        let (ax, ay) = grid.cell();
        let (lx, ly) = grid.lengths();
        let bottom = self.depth_periods * lx.max(ly);
        let mut z = self.first_fraction * ax.min(ay);
        let mut bounds = vec![0.0];
        loop {
            bounds.push(z);
            if z >= bottom || bounds.len() > 10_000 {
                break;
            }
            z *= self.ratio;
        }
        DepthLayers::new(bounds)
    }

    /// The Gauss nodes \[m\] of every layer and their weights (summing to
    /// 1 within a layer: the layer average).
    pub(crate) fn nodes(&self, layers: &DepthLayers) -> Vec<Vec<(f64, f64)>> {
        let (x, w) = gauss_legendre(self.points);
        layers
            .iter()
            .map(|(a, b)| {
                let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
                x.iter()
                    .zip(&w)
                    .map(|(xi, wi)| (c + h * xi, 0.5 * wi))
                    .collect()
            })
            .collect()
    }
}
