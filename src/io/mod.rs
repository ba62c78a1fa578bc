//! File formats and atomic output.

pub mod atomic;
pub mod npy;

pub use atomic::{write_atomic, OutputError, StagedOutput};
