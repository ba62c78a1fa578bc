//! Integration tests of materials: configs, conversions, DMA data and fits, temperature.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test material FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod config;
mod conversion;
mod data_range;
mod dma_data;
mod fit;
mod temperature;
