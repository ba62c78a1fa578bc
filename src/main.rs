//! The `viscoslide` command line; all logic lives in the library.

fn main() -> std::process::ExitCode {
    quiet_headless_vulkan();
    return_large_arrays_when_freed();
    match viscoslide::cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", e.message());
            std::process::ExitCode::FAILURE
        }
    }
}

/// On a machine without a desktop session (no usable `XDG_RUNTIME_DIR`),
/// Mesa's implicit Vulkan device-select layer tries to reach a Wayland
/// compositor and prints `error: XDG_RUNTIME_DIR is invalid or not set`
/// once per Vulkan instance. The layer only reorders adapters, which
/// viscoslide ranks itself (`viscoslide gpu`), so it is switched off
/// there (`NODEVICE_SELECT=1`) unless the user set that variable. Runs first
/// in `main`, before any thread exists.
fn quiet_headless_vulkan() {
    let session = std::env::var_os("XDG_RUNTIME_DIR")
        .map(|d| std::path::Path::new(&d).is_dir())
        .unwrap_or(false);
    if !session && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// Arrays of 1 MiB and more come from the kernel (mmap) and go back to it
/// when freed. glibc's default raises that threshold, up to 32 MiB, each
/// time such an array is freed; later arrays below it then come from the
/// heap, whose freed memory stays with the process while it is
/// fragmented. On the 2048^2 paper experiment in mixed precision (f32
/// arrays of 17 MB) that held on to freed arrays long enough to put the
/// peak RSS after the iteration 27 MB higher (334 against 307 MB; f64,
/// whose arrays are above 32 MiB, was unchanged: BENCHMARKS.md, "Where an
/// f32 product's time goes"). A fixed threshold turns the adjustment off;
/// its cost, page faults on each new large array, is within the run-to-run
/// spread (1024^2 f64 iteration: 2.41 against 2.34 s, medians of five;
/// peak RSS 92 -> 88 MB, mixed 102 -> 85 MB). Runs first in `main`, before
/// any thread exists.
fn return_large_arrays_when_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; no other thread
    // exists yet.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20);
    }
}
