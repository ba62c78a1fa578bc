//! What the machine can hold: the memory available now, and a one-line
//! refusal of work that would not fit (instead of an allocation abort).

/// Work that needs more memory than is available.
#[derive(Debug, thiserror::Error)]
#[error("a {what} needs {} of memory, but only {} is available", size(*.need), size(*.available))]
pub struct MemoryError {
    /// What was to be made, e.g. `512 x 512 grid`.
    pub what: String,
    /// Bytes it needs.
    pub need: u64,
    /// Bytes available.
    pub available: u64,
}

/// A byte count for a message: GiB to one decimal from 0.1 GiB on, else
/// bytes; a count that overflowed (saturated at `u64::MAX`) is said so.
pub(crate) fn size(bytes: u64) -> String {
    const GIB: f64 = (1u64 << 30) as f64;
    if bytes == u64::MAX {
        "more than 2^64 bytes".into()
    } else if bytes as f64 >= 0.1 * GIB {
        format!("about {:.1} GiB", bytes as f64 / GIB)
    } else {
        format!("{bytes} bytes")
    }
}

/// Memory available to a new allocation \[bytes\] (`MemAvailable` of
/// `/proc/meminfo`, or what a test's fault states,
/// [`super::fault::available_memory`]); `None` where the system does not
/// say.
pub(crate) fn available_memory() -> Option<u64> {
    if let Some(stated) = super::fault::available_memory() {
        return Some(stated);
    }
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The peak resident memory of this process so far \[bytes\] (`VmHWM` of
/// `/proc/self/status`); `None` where the system does not say.
pub fn peak_resident() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Refuse `need` bytes for `what` when more than is available; where the
/// system does not say, only what no address space can hold
/// (`isize::MAX` bytes) is refused.
pub fn check_fits(what: impl FnOnce() -> String, need: u64) -> Result<(), MemoryError> {
    let available = available_memory().unwrap_or(isize::MAX as u64);
    if need > available {
        return Err(MemoryError {
            what: what(),
            need,
            available,
        });
    }
    Ok(())
}

/// Refuse `count` items of `item_bytes` bytes each (a count given by a user
/// or read from a file) before anything is allocated for them: the product
/// is taken with checked arithmetic (an overflow needs "more than 2^64
/// bytes") and compared with the memory available ([`check_fits`]).
pub fn check_count(
    what: impl FnOnce() -> String,
    count: u64,
    item_bytes: u64,
) -> Result<(), MemoryError> {
    check_fits(what, count.saturating_mul(item_bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_name_the_count_and_both_sizes() {
        let e = check_count(
            || "curve of 10000000000 points".into(),
            10_000_000_000,
            1 << 40,
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.starts_with("a curve of 10000000000 points needs"),
            "{msg}"
        );
        assert!(msg.contains("GiB is available"), "{msg}");
        let e = check_count(|| "x".into(), u64::MAX, 2).unwrap_err();
        assert!(e.to_string().contains("more than 2^64 bytes"), "{e}");
        assert!(check_count(|| "x".into(), 1000, 8).is_ok());
    }
}
