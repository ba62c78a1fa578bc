//! Integration tests of the GPU backend (lavapipe without a GPU): context, shaders, conformance with the CPU, memory, adaptive and refined solves.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test gpu FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod adaptive;
mod bench_cli;
mod conformance;
mod context;
mod heated;
mod large_grid;
mod memory;
mod mixed;
mod plan_cli;
mod refine;
mod shaders;
mod split;
