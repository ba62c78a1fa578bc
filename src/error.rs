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
    Heat(#[from] crate::heat::HeatError),
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

    /// An I/O error with the path that caused it.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            context: path.into().display().to_string(),
            source,
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
}
