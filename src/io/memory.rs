//! What the machine can hold: the memory available now, and a one-line
//! refusal of work that would not fit (instead of an allocation abort).

/// Work that needs more memory than is available.
#[derive(Debug, thiserror::Error)]
#[error("a {what} needs about {:.1} GiB of memory, but only {:.1} GiB is available", gib(*.need), gib(*.available))]
pub struct MemoryError {
    /// What was to be made, e.g. `512 x 512 grid`.
    pub what: String,
    /// Bytes it needs.
    pub need: u64,
    /// Bytes available.
    pub available: u64,
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 30) as f64
}

/// Memory available to a new allocation \[bytes\] (`MemAvailable` of
/// `/proc/meminfo`); `None` where the system does not say.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Refuse `need` bytes for `what` when more than is available.
pub fn check_fits(what: impl FnOnce() -> String, need: u64) -> Result<(), MemoryError> {
    match available_memory() {
        Some(available) if need > available => Err(MemoryError {
            what: what(),
            need,
            available,
        }),
        _ => Ok(()),
    }
}
