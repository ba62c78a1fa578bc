//! Adaptive non-uniform mesh for surfaces with many scales (physics.md
//! section 7; Putignano, Afferrante, Carbone & Demelio, J. Mech. Phys.
//! Solids 60, 973, 2012): fine cells where contact is possible or found,
//! coarse cells elsewhere, refined as the contact set moves.
//!
//! - [`quadtree`]: the mesh, its geometry and the height rule.
//!
//! The pairwise operator lives in [`crate::operator::AdaptiveOperator`]; the
//! solve-certify-refine loop beside the other solve paths, in
//! [`crate::problem::adaptive`].

pub mod quadtree;

pub use quadtree::{dilate, Cell, MeshError, QuadMesh};
