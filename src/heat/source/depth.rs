//! The depth layers a volume heat source is given on, and the Gauss nodes
//! inside each layer at which the dissipation density is evaluated
//! (physics.md section 14: each surface mode `q` dissipates within a depth
//! of about `1 / |q|`, so the layers must reach from a fraction of the
//! smallest contact spot, the cell, down to the period).

use super::super::error::{positive, HeatError};
use super::super::layers::DepthLayers;
use crate::gauss::gauss_legendre;
use crate::response::Grid;

/// Geometric depth layers, the Gauss rule within each, and the layers the
/// source is given on.
///
/// The boundaries are `0, z_1, z_1 r, z_1 r^2, ...` down to the first at or
/// below `bottom`, with `z_1 = first_fraction * min(a_x, a_y)` and `bottom
/// = depth_periods * max(L_x, L_y)`; the dissipation is evaluated at the
/// `points` Gauss-Legendre nodes of each layer, and each node's value holds
/// on its share of the layer (between the cumulative Gauss weights around
/// it): the source's layers ([`DepthRule::layers`]) are these shares, and
/// its total power is the Gauss rule's. The default (`first_fraction`
/// 1/8, `ratio` 2, `points` 3, `depth_periods` 2) integrates the
/// dissipation of every mode of the grid over depth to about 5e-5 (the
/// mode `q` integrand `(qz)^2 exp(-2qz)` on geometric panels; the deepest
/// mode, `2 pi / L`, is cut at `exp(-8 pi)`); [`DepthRule::refined`]
/// (`ratio` `sqrt 2`, `points` 4) to about 5e-9. The weighted rise `Theta`
/// (physics.md section 14) also depends on how the source varies within a
/// layer: holding each node's value on its share, it is within about
/// 2e-3 (default) and 3e-4 (refined) of a converged rule on the paper's
/// rubber, where each layer's average held on the whole layer was 2 %
/// (default) and 0.6 % (refined) low (BENCHMARKS.md, "The heated solve").
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

    /// The geometric layers of `grid` (module docs), before the Gauss
    /// nodes split them.
    fn panels(&self, grid: &Grid) -> Result<DepthLayers, HeatError> {
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

    /// The layers the source of `grid` is given on: each geometric layer
    /// split into its Gauss nodes' shares (type docs).
    pub fn layers(&self, grid: &Grid) -> Result<DepthLayers, HeatError> {
        Ok(self.source_layers(grid)?.0)
    }

    /// The source's layers ([`DepthRule::layers`]) and the depth \[m\] of
    /// the Gauss node each one holds the value of.
    pub(crate) fn source_layers(&self, grid: &Grid) -> Result<(DepthLayers, Vec<f64>), HeatError> {
        let panels = self.panels(grid)?;
        let (x, w) = gauss_legendre(self.points);
        let mut bounds = vec![0.0];
        let mut nodes = Vec::with_capacity(panels.count() * self.points);
        for (a, b) in panels.iter() {
            let h = b - a;
            let mut share = 0.0;
            for (k, (xi, wi)) in x.iter().zip(&w).enumerate() {
                nodes.push(a + 0.5 * h * (1.0 + xi));
                share += 0.5 * wi;
                // The last share ends on the layer's own boundary.
                bounds.push(if k + 1 == self.points {
                    b
                } else {
                    a + h * share
                });
            }
        }
        Ok((DepthLayers::new(bounds)?, nodes))
    }
}
