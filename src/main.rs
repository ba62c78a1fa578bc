//! The `viscoslide` command line; all logic lives in the library.

fn main() -> std::process::ExitCode {
    match viscoslide::cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
