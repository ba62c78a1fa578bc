//! Integration tests of the heat room (physics.md section 14): the moving
//! heat source against independent quadrature and closed forms, the
//! periodic cell mode by mode, volume sources on depth layers, symmetry,
//! limits, refusals, and `viscoslide heat`.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test heat FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod closed_form;
mod edited_runs;
mod heated;
mod memory;
mod periodic;
mod reference;
mod source;
mod symmetry;
mod volume;
