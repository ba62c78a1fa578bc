//! Integration tests of the command line as a user meets it: solves, layers, messages, refusals, output faults and size guards.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test cli FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod input_refusals;
mod layer;
mod messages;
mod new_user;
mod output_faults;
mod size_guards;
mod solve;
mod surface_files;
