//! The heated contact (physics.md section 14): the isothermal solve, its
//! dissipation as a heat source, the temperature rise it causes, and the
//! effective temperature at which the three agree.
//!
//! - `params.rs`: `[heating]` typed and checked ([`HeatingParams`]).
//! - `branches.rs`: every root of `T0 + Theta(T) - T` in a bracket
//!   (`Branches`).
//! - `two_level.rs`: the same bracket scanned on a coarse grid, its roots
//!   closed on the full grid; `coarse.rs`: that coarse grid.
//! - `solve.rs`: the fixed point over isothermal solves ([`solve_heated`]);
//!   `no_heat.rs`: its answer where nothing is dissipated at any
//!   temperature (at rest, an elastic rubber).
//! - `memory.rs`: its memory, checked before the first solve.
//! - `report.rs`: what it reports ([`HeatingReport`]) and writes
//!   ([`HeatedSolution`]).

mod branches;
mod coarse;
mod memory;
mod no_heat;
mod params;
mod report;
mod solve;
mod two_level;

pub use branches::{Branch, Evaluation};
pub use params::{BranchChoice, HeatingParams};
pub(crate) use report::{scale_extremes, scale_text};
pub use report::{DepthRow, HeatedSolution, HeatingReport, Rises};
pub use solve::solve_heated;
