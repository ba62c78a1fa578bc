//! Integration tests of the sliding kernel: accuracy, limits, Love's solution, layers and the `kernel` command.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test kernel FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod accuracy;
mod cli;
mod layer_cells;
mod limits;
mod love;
mod thickness;
mod thin_direction;
mod thin_layer;
mod thin_switch;
