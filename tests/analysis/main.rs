//! Integration tests of the analysis of solutions: anisotropy, chi and the `analyze` command.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test analysis FILE::`.

mod anisotropy;
mod chi;
mod cli;
