//! Integration tests of the contact solver: dense references, physics, friction, floors, cascades, layers, mixed precision and the library API.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test solver FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod cascade;
mod dense_reference;
mod floor;
mod friction;
mod layer;
mod mixed_precision;
mod near_full_contact;
mod physics;
mod problem_api;
mod random_cases;
mod stalled_cases;
mod thin_direction;
mod thin_step;
