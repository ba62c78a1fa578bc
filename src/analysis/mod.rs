//! Quantities computed from a solved contact: friction (paper Eq. 8-9 and the
//! dissipated power of Appendix A3-A4), real contact area and pressure
//! statistics. Nothing here depends on how the solve was done.

pub mod contact;
pub mod friction;
pub mod periodic;

pub use contact::{contact_statistics, ContactStatistics};
pub use friction::{friction_force_dissipation, friction_force_stencil};
pub use periodic::{friction_force_periodic, full_contact_friction_stress};
