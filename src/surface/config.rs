//! The `[surface]` section of a config.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// `[surface]`: a height map from `file` (with `length`, m), or generated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceConfig {
    /// `.npy` (or plain-text) height map, heights in m at cell centres.
    pub file: Option<PathBuf>,
    /// Side of the map along x [m]; cells are square.
    pub length: Option<f64>,
}
