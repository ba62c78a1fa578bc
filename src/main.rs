//! The `viscoslide` command line; all logic lives in the library.

fn main() -> std::process::ExitCode {
    quiet_headless_vulkan();
    match viscoslide::cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
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
