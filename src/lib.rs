//! viscoslide: steady sliding contact of a rigid, randomly rough surface on a
//! linear viscoelastic solid, after Carbone & Putignano, "Rough viscoelastic
//! sliding contact: Theory and experiments", Phys. Rev. E 89, 032408 (2014).
//!
//! Data flows one way: `config` -> `material` and `surface` -> `kernel`
//! (influence coefficients) -> operator and solver -> analysis -> report.
//! Every module owns one job; see `../shared/DESIGN.md` for the map.

pub mod backend;
pub mod cli;
pub mod config;
pub mod error;
pub mod io;
pub mod kernel;
pub mod material;
pub mod mesh;
pub mod plot;
pub mod surface;

pub use error::{Error, Result};

/// Crate version recorded in every report.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
pub mod analysis;
pub mod operator;
pub mod persson;
pub mod report;
pub mod run;
pub mod solver;
pub mod sweep;
