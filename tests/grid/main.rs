//! Integration tests of grids: periodic domains, adaptive meshes, rectangular cells and refinement studies.
//!
//! One test binary per area (docs/ARCHITECTURE.md, "Tests"): each file
//! here is a module; run one with `cargo test --release --test grid FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod mesh_adaptive;
mod periodic_domain_study;
mod periodic_full_contact;
mod periodic_layer;
mod rect_cells;
mod rect_cells_aspect;
mod rect_cells_refinement;
mod refine;
