//! File formats, atomic output and what memory the machine has.

pub mod atomic;
pub mod memory;
pub mod npy;

pub use atomic::{check_output_dir, write_atomic, OutputError, StagedOutput};
pub use memory::{available_memory, MemoryError};
