//! Executors: the CPU reference path and the GPU (wgpu) path.

pub mod gpu;

use serde::{Deserialize, Serialize};

/// Which executor runs a computation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum, Default)]
#[serde(rename_all = "snake_case")]
pub enum BackendChoice {
    /// The GPU when an adapter exists, otherwise the CPU (with a notice).
    #[default]
    Auto,
    /// The GPU; an error when no adapter exists.
    Gpu,
    /// The CPU reference path.
    Cpu,
}

/// Environment variable that selects the backend when no flag is given.
pub const BACKEND_ENV: &str = "VISCOSLIDE_BACKEND";

impl BackendChoice {
    /// The flag if given, else `VISCOSLIDE_BACKEND`, else `auto`.
    pub fn resolve(flag: Option<BackendChoice>) -> Result<BackendChoice, String> {
        if let Some(f) = flag {
            return Ok(f);
        }
        match std::env::var(BACKEND_ENV) {
            Ok(v) => match v.trim().to_ascii_lowercase().as_str() {
                "auto" | "" => Ok(BackendChoice::Auto),
                "gpu" => Ok(BackendChoice::Gpu),
                "cpu" => Ok(BackendChoice::Cpu),
                other => Err(format!("{BACKEND_ENV}={other}: expected auto, gpu or cpu")),
            },
            Err(_) => Ok(BackendChoice::Auto),
        }
    }
}
