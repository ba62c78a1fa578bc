//! The crate-wide error type. Each layer has its own typed error (config,
//! material, surface, kernel, file formats and output, solver, GPU, mesh,
//! analysis, plots, heat); this enum sits above them all and wraps each by `From`,
//! so the library API and the command line report any of them in one line.
//! No lower layer imports it.

use std::path::PathBuf;

/// Any error the engine reports to a user.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Config(#[from] crate::config::ConfigError),
    #[error(transparent)]
    Material(#[from] crate::material::MaterialError),
    #[error(transparent)]
    Surface(#[from] crate::surface::SurfaceError),
    #[error(transparent)]
    Kernel(#[from] crate::kernel::KernelError),
    #[error(transparent)]
    Response(#[from] crate::response::ResponseError),
    #[error(transparent)]
    Npy(#[from] crate::io::npy::NpyError),
    #[error(transparent)]
    Output(#[from] crate::io::OutputError),
    #[error(transparent)]
    Solver(#[from] crate::solver::SolverError),
    #[error(transparent)]
    Gpu(#[from] crate::backend::gpu::GpuError),
    #[error(transparent)]
    Analysis(crate::analysis::AnalysisError),
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    #[error(transparent)]
    Persson(#[from] crate::persson::PerssonError),
    #[error(transparent)]
    Heat(crate::heat::HeatError),
    #[error("{context}: {source}")]
    Io {
        context: String,
        #[source]
        source: std::io::Error,
    },
    #[error("invalid argument: {0}")]
    Invalid(String),
}

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// This error prefixed with `context` (`"{context}: ..."`), an invalid
    /// argument staying one without its prefix said twice.
    pub fn within(self, context: &str) -> Self {
        match self {
            Error::Invalid(m) => Error::Invalid(format!("{context}: {m}")),
            other => Error::Invalid(format!("{context}: {other}")),
        }
    }

    /// This error's one line as a user reads it: a number that f64's
    /// `Display` writes out in full (`1e300` as 301 digits, `1e-300` as
    /// 300 zeros after the point; counts up to `u64::MAX` stay whole),
    /// because a message formatted a value
    /// given with `{}`, is shown in scientific notation
    /// ([`Error::compact_numbers`]).
    pub fn message(&self) -> String {
        compact_numbers(&self.to_string())
    }

    /// Any message (a lower layer's error, a warning) with its numbers
    /// written out in full shown as [`Error::message`] shows them.
    pub fn compact_numbers(text: &str) -> String {
        compact_numbers(text)
    }

    /// An I/O error with the path that caused it.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            context: path.into().display().to_string(),
            source,
        }
    }
}

/// Digits an integer may have and still be a count or an index (`u64`
/// holds up to 20): a longer one is an f64 written out in full.
const WHOLE_DIGITS: usize = 20;

/// Zeros after `0.` a plain decimal may have: f64 carries 17 significant
/// digits, so more zeros than that is a tiny f64 written out in full.
const LEADING_ZEROS: usize = 17;

/// `text` with each number written out in full (an integer part of more
/// than [`WHOLE_DIGITS`] digits, or more than [`LEADING_ZEROS`] zeros
/// after `0.`) replaced by its shortest scientific form (`{:e}`). A number is a
/// run of digits with at most one inner point that no letter, digit,
/// `_`, `/` or `\` touches (so paths and names keep their digits).
fn compact_numbers(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let (mut i, mut copied) = (0, 0);
    let word = |c: u8| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'/' | b'\\' | b'.');
    while i < b.len() {
        if !b[i].is_ascii_digit() || (i > 0 && word(b[i - 1])) {
            i += 1;
            continue;
        }
        let start = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        let whole = i - start;
        let mut end = i;
        if i + 1 < b.len() && b[i] == b'.' && b[i + 1].is_ascii_digit() {
            end = i + 1;
            while end < b.len() && b[end].is_ascii_digit() {
                end += 1;
            }
        }
        // A sentence's full stop may follow; a letter, digit or path may not.
        let free = end == b.len() || b[end] == b'.' || !word(b[end]);
        let number = &text[start..end];
        let zeros = number
            .strip_prefix("0.")
            .map_or(0, |f| f.bytes().take_while(|&c| c == b'0').count());
        let long = whole > WHOLE_DIGITS || zeros > LEADING_ZEROS;
        if free && long {
            if let Ok(v) = number.parse::<f64>() {
                out.push_str(&text[copied..start]);
                out.push_str(&format!("{v:e}"));
                copied = end;
            }
        }
        i = end;
    }
    out.push_str(&text[copied..]);
    out
}

impl From<crate::heat::HeatError> for Error {
    /// A heat source given up on request is the solve's cancellation, as
    /// the caller that asked for it sees every other stop.
    fn from(e: crate::heat::HeatError) -> Self {
        match e {
            crate::heat::HeatError::Cancelled => {
                Error::Solver(crate::solver::SolverError::Cancelled)
            }
            other => Error::Heat(other),
        }
    }
}

impl From<crate::analysis::AnalysisError> for Error {
    /// The analysis wraps lower errors; unwrap them so each keeps its own
    /// variant here.
    fn from(e: crate::analysis::AnalysisError) -> Self {
        use crate::analysis::AnalysisError as A;
        match e {
            A::Surface(e) => Error::Surface(e),
            A::Npy(e) => Error::Npy(e),
            A::Plot(e) => Error::Plot(e),
            A::Output(e) => Error::Output(e),
            other => Error::Analysis(other),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level's error says "invalid argument" once.
    #[test]
    fn context_keeps_one_prefix() {
        let e = Error::Invalid("no scales".into()).within("level 1");
        assert_eq!(e.to_string(), "invalid argument: level 1: no scales");
        let io = Error::io("a.npy", std::io::Error::other("gone")).within("level 2");
        assert_eq!(io.to_string(), "invalid argument: level 2: a.npy: gone");
    }

    /// Numbers written out in full become scientific, with their sign and
    /// unit; plain ones, paths and names keep their digits.
    #[test]
    fn numbers_written_out_in_full_read_as_scientific() {
        let huge = format!("{}", 1e300);
        let tiny = format!("{}", -1e-300);
        let big = format!("{}", 1.0000000000000002e296);
        assert_eq!(
            compact_numbers(&format!("[loading] temperature = {huge} C, got {tiny}.")),
            "[loading] temperature = 1e300 C, got -1e-300."
        );
        assert_eq!(
            compact_numbers(&format!("({big} N)")),
            "(1.0000000000000002e296 N)"
        );
        for plain in [
            "speed = 0.25 m/s at 123456789012 cells, 1e-300 and 0.000001",
            "/tmp/123456789012345678901234/out: exists",
            "run_123456789012345678901234 and x123456789012345678901234",
            "12345678901234567.5 has 17 digits",
            "a seed of 99999999999999999999, a side of 18446744073709551615 cells",
            "0.000000000000000001 is 1e-18 (17 zeros)",
        ] {
            assert_eq!(compact_numbers(plain), plain);
        }
        assert_eq!(
            compact_numbers(
                "100000000000000000000 is 1e20 (21 digits), 1000000000000000000000 1e21"
            ),
            "1e20 is 1e20 (21 digits), 1e21 1e21"
        );
        assert_eq!(
            compact_numbers("0.0000000000000000001 is 1e-19 (18 zeros)"),
            "1e-19 is 1e-19 (18 zeros)"
        );
    }
}
