//! Frictional heating's heat problem (physics.md section 14): the steady
//! temperature rise of a rubber half-space (`z >= 0`) moving with velocity
//! `-v e_v` past a given heat source, in the indenter's frame:
//! `-v (e_v . grad) T = kappa lap T + Q / (rho c)`, `-lam dT/dz = q_s` at
//! the surface, `T -> T0` far away.
//!
//! The room knows nothing of contact: it takes a surface flux map `q_s`
//! \[W/m^2\] on a grid of rectangular cells, or a volume source `Q`
//! \[W/m^3\] on depth layers, and returns the rise `T - T0` at the cell
//! centres, in f64, for any sliding direction.
//!
//! - `setup.rs`: the inputs ([`HeatSetup`]: grid, [`Conduction`], speed,
//!   direction, [`HeatDomain`]) and their checks.
//! - `cell.rs`: the moving point source integrated over one cell (polar
//!   rule with the analytic radial integral, Cartesian Gauss far away).
//! - `pad.rs`: a finite pad: the table of cell integrals over every offset,
//!   applied by the elastic kernel's Toeplitz FFT embedding.
//! - `modes.rs`: `m(k)`, the closed-form layer integrals.
//! - `periodic.rs`: one period of a periodic cell: the multiplier
//!   `1 / (lam m)`, depth maps and volume sources mode by mode.
//! - `sweep.rs`: one mode's rises at a volume source's layers, in one
//!   sweep down and one up.
//! - `background.rs`: the block's background heating, the periodic cell's
//!   mean.
//! - `layers.rs`: depth layers of a volume source.
//! - `density.rs`: a volume source's values on its layers ([`LayerDensity`]):
//!   maps, and deep layers' band-limited parts as their coarse spectra.
//! - `solve.rs`: [`HeatSolver`], planned once, applied to many sources.
//! - `source/`: the heat source of a solved contact ([`HeatSource`]): the
//!   creep elements' dissipation density on depth layers, or the surface
//!   work of the contact pressure.
//! - `memory.rs`: what a heat problem holds at once, for refusals before
//!   work starts.
//! - `error.rs`: [`HeatError`].

mod background;
mod cell;
mod density;
mod error;
mod layers;
pub(crate) mod memory;
mod modes;
mod pad;
mod periodic;
mod setup;
mod solve;
mod source;
mod sweep;

pub use density::LayerDensity;
pub use error::HeatError;
pub(crate) use layers::DepthLadder;
pub use layers::DepthLayers;
pub(crate) use setup::AT_REST_NOTE;
pub use setup::{Conduction, HeatDomain, HeatSetup};
pub(crate) use solve::{profile_depths, DepthExtremes};
pub use solve::{surface_temperature, HeatSolver, Temperature};
pub(crate) use source::scale_rises;
pub use source::{DepthRule, HeatSource, ScaleBand, SourceKind};
