//! File formats, atomic output (one writer per directory, injected faults
//! for its tests) and what memory the machine has.

pub mod atomic;
pub(crate) mod digest;
pub mod dirlock;
pub(crate) mod fault;
pub(crate) mod memory;
pub mod npy;
pub mod study_lock;

pub(crate) use atomic::check_output_dir;
pub use atomic::{write_atomic, OutputError, StagedOutput};
pub use dirlock::LockMode;
pub use memory::MemoryError;
pub use study_lock::StudyLock;
