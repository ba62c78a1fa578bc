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
//!   `at_rest.rs`: its answer at `v = 0`, where nothing is dissipated.
//! - `memory.rs`: its memory, checked before the first solve.
//! - `report.rs`: what it reports ([`HeatingReport`]) and writes
//!   ([`HeatedSolution`]).

mod at_rest;
mod branches;
mod coarse;
mod memory;
mod params;
mod report;
mod solve;
mod two_level;

pub use branches::{Branch, Evaluation};
pub use params::{BranchChoice, HeatingParams};
pub(crate) use report::{scale_extremes, scale_text};
pub use report::{DepthRow, HeatedSolution, HeatingReport, Rises};
pub use solve::solve_heated;
