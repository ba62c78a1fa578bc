//! Integration tests of studies: sweeps, magnification and Persson's theory.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test studies FILE::`.

mod magnification;
mod one_writer;
mod persson_cli;
mod persson_inputs;
mod persson_theory;
mod pinned_files;
mod refusals;
mod study_faults;
mod support;
mod sweep;
mod sweep_vary;
mod vary_keys;
