//! Integration tests of surfaces: generation, formats and readers, preprocessing, resampling, measured scans.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test surface FILE::`.

mod cli;
mod formats;
mod generate;
mod io;
mod measured;
mod npy_format;
mod preprocess;
mod resample;
