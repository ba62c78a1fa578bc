//! The crate version recorded in every report and output file; a module of
//! the bottom layer so that every layer may name it without importing the
//! crate root.

/// Crate version recorded in every report.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
