//! Faults injected on request, so that tests can show what a crash or a
//! full disk at a given step of an output commit leaves behind.
//!
//! `VISCOSLIDE_TEST_FAULT=STEP` makes the process abort (as `kill -9`
//! would stop it: no destructor, no cleanup) when it reaches the named step
//! of [`super::atomic`] (`staged`, `swapped`, `renaming`; `aside` also
//! takes the rename-aside path, as on a file system without an exchange);
//! `VISCOSLIDE_TEST_FAULT=enospc` makes every output write fail as on a
//! full disk; `VISCOSLIDE_TEST_FAULT=slow-STEP` makes the named step of a
//! study (`point`: after each point is written) take half a second, as on
//! a slow file system, so that a test can start a second writer while the
//! first is at work; `VISCOSLIDE_TEST_FAULT=available-BYTES` makes the
//! memory available to new work read `BYTES`, as on a smaller machine
//! ([`super::memory::check_fits`]). Unset (always, outside tests), nothing
//! happens.

/// The environment variable naming the fault.
pub const FAULT_VAR: &str = "VISCOSLIDE_TEST_FAULT";

fn fault() -> Option<String> {
    std::env::var(FAULT_VAR).ok()
}

/// Abort the process here if the fault names `step`.
pub fn crash_point(step: &str) {
    if fault().is_some_and(|f| f == step) {
        std::process::abort();
    }
}

/// A full disk, if the fault asks for one.
pub fn full_disk() -> Result<(), std::io::Error> {
    if fault().is_some_and(|f| f == "enospc") {
        return Err(std::io::Error::from_raw_os_error(libc::ENOSPC));
    }
    Ok(())
}

/// Whether to act as if the file system could not exchange directories.
pub fn no_exchange() -> bool {
    fault().is_some_and(|f| f == "aside")
}

/// Half a second at `step`, if the fault asks for `slow-STEP`.
pub fn slow_point(step: &str) {
    if fault().is_some_and(|f| f.strip_prefix("slow-") == Some(step)) {
        std::thread::sleep(std::time::Duration::from_millis(500));
    }
}

/// The memory available \[bytes\], if the fault `available-BYTES` states
/// it.
pub fn available_memory() -> Option<u64> {
    fault()?.strip_prefix("available-")?.parse().ok()
}
