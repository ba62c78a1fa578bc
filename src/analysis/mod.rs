//! Quantities computed from a solved contact: friction (paper Eq. 8-9 and the
//! dissipated power of Appendix A3-A4), real contact area and pressure
//! statistics, and the anisotropy of the deformed surface and of the contact
//! area (paper Section IV, Eq. 11-13, Fig. 8-10). Nothing here depends on how
//! the solve was done.

pub mod anisotropy;
pub mod chi;
pub mod contact;
pub mod ellipse;
pub mod fields;
pub mod figures;
pub mod files;
pub mod friction;
pub mod report;
pub mod spots;

pub use anisotropy::{deformed_anisotropy, AnisotropyTensor, DeformedAnisotropy, ZetaBand};
pub use chi::{chi_spectrum, contour_level, ChiLevel, ChiSpectrum};
pub use contact::{contact_statistics, ContactStatistics};
pub use ellipse::{fit_centred_ellipse, EllipseFit};
pub use fields::analyze;
pub use files::{
    analyze_dir, read_summary, scales_from_config, write_analysis, AnalysisOverrides, SolveSummary,
};
pub use friction::{
    friction_force_dissipation, friction_force_periodic, friction_force_stencil,
    full_contact_friction_stress,
};
pub use report::{
    AnalysisError, AnalysisInputs, AnalysisParams, AnalysisReport, ChiReport, ANALYSIS_FILES,
};
pub use spots::{find_spots, spot_statistics, Connectivity, Spot, SpotStatistics};
