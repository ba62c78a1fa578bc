//! `[layer]`: a viscoelastic layer of finite thickness on a rigid base
//! (paper Eq. 5); built by `LayerConfig::build` in [`crate::kernel`].

use serde::{Deserialize, Serialize};

/// How the layer is supported at its base.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerBase {
    /// Bonded (no slip, no normal displacement) to a rigid base.
    Bonded,
    /// Resting on a rigid base without friction (no shear traction).
    Frictionless,
}

/// `[layer]` section of a config: `thickness` (m) and `base`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerConfig {
    /// Thickness `h` \[m\].
    pub thickness: f64,
    /// `"bonded"` or `"frictionless"`.
    pub base: LayerBase,
}
