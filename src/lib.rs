//! viscoslide: steady sliding contact of a rigid, randomly rough surface on a
//! linear viscoelastic solid, after Carbone & Putignano, "Rough viscoelastic
//! sliding contact: Theory and experiments", Phys. Rev. E 89, 032408 (2014).
//!
//! # The library API
//!
//! A [`problem::Problem`] (material, surface, loading, layer, solver
//! options) is built from a configuration file
//! ([`problem::Problem::from_config`]) or from values; `solve` runs it on an
//! [`problem::Executor`] and returns a [`problem::Solution`] that analyses,
//! summarises and writes itself. Every front end (the command line, sweeps)
//! uses only this:
//!
//! ```
//! use viscoslide::material::{CreepSpectrum, Material};
//! use viscoslide::problem::{Executor, Problem};
//! use viscoslide::problem::{Control, Silent};
//! use viscoslide::surface::{GenerateParams, UpperCutoff};
//!
//! # fn main() -> viscoslide::Result<()> {
//! // A standard linear solid (E0 = 3.3 MPa, E_inf = 10 MPa, tau = 10 ms) ...
//! let spectrum = CreepSpectrum::standard_linear_solid(3.3e6, 1e7, 0.01)?;
//! let material = Material::new(spectrum, 0.5)?;
//! // ... under a self-affine surface of 32 x 32 cells on 1 cm ...
//! let surface = GenerateParams {
//!     nx: 32,
//!     ny: 32,
//!     upper: UpperCutoff::Scales(8.0),
//!     seed: 7,
//!     ..Default::default()
//! };
//! // ... pressed with 0.1 N and sliding at 1 cm/s.
//! let problem = Problem::generated(material, surface, Control::Load(0.1), 0.01)?;
//! let solution = problem.solve(&Executor::Cpu, &mut Silent)?;
//! assert!(solution.friction_coefficient > 0.0);
//! assert!(solution.stats.contact_area_fraction < 1.0);
//! let summary = solution.summary();
//! assert_eq!(summary["grid"], serde_json::json!([32, 32]));
//!
//! // The same physical problem on a finer grid, started from nothing.
//! let fine = problem.with_grid(64)?.solve(&Executor::Cpu, &mut Silent)?;
//! assert_eq!(fine.grid(), (64, 64));
//! // `solution.write(dir)` writes summary.json, the maps and the figures.
//! # Ok(())
//! # }
//! ```
//!
//! # Layers
//!
//! Data flows one way: `config` -> `material` and `surface` -> `mesh` ->
//! `response` (one sliding response on one grid) -> `kernel` (influence
//! coefficients) -> `operator` -> `backend` -> `solver` -> `analysis` ->
//! `problem` (the API) -> `sweep` and `refine` -> `magnification` -> `cli`;
//! `io` and `plot` serve every layer. `persson` (Persson's theory, the
//! analytic reference) needs only `material` and `surface`. The engine
//! (`kernel`, `operator`, `backend`, `solver`, `mesh`, `analysis`, `gauss`,
//! `plot`) is public only under [`internals`], for tests and benches;
//! [`problem`] re-exports the engine types the API takes and returns.
//! `heat` (frictional heating's heat problem) sits beside `operator`,
//! whose FFT embedding it uses, and knows nothing of contact.
//! `docs/ARCHITECTURE.md` says what each layer owns and may import;
//! `tests/architecture.rs` keeps the imports pointing down.

pub mod config;
pub mod error;
pub mod heat;
pub mod heating;
pub mod io;
pub mod magnification;
pub mod material;
pub mod persson;
pub mod problem;
pub mod refine;
pub mod response;
pub mod surface;
pub mod sweep;
pub mod version;

pub use error::{Error, Result};
pub use version::VERSION;

/// The `viscoslide` command line (clap): the binary's front end, not a
/// library API.
#[doc(hidden)]
pub mod cli;

pub mod internals;
pub(crate) use internals::{analysis, backend, gauss, kernel, mesh, operator, plot, solver};
