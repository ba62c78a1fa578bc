//! Viscoelastic friction of a solved contact: one home for both routes and
//! both formulations (physics.md sections 5-6).
//!
//! | route | non-periodic grid | periodic cell |
//! |---|---|---|
//! | stencil (paper Eq. 9), [`stencil`] | [`friction_force_stencil`] with the cell-averaged derivative tables of [`crate::kernel`] | [`friction_force_stencil`] with [`crate::operator::SpectralPeriodic`]'s sliding slope |
//! | dissipation (Appendix A3-A4), [`dissipation`] | [`friction_force_dissipation`]: the integral over the plane | [`friction_force_periodic`]: the sum over the cell's modes |
//!
//! [`full_contact`] holds the exact friction of a periodic surface held in
//! full contact, the reference both periodic routes are checked against.
//!
//! All give the x-force of the solid on the indenter, which opposes the
//! motion: `F_T < 0` and the reported friction coefficient is
//! `mu = -F_T / F_N` (physics.md section 5).

pub mod dissipation;
pub mod full_contact;
pub mod stencil;

pub use dissipation::{
    friction_force_dissipation, friction_force_dissipation_thin_law, friction_force_periodic,
};
pub use full_contact::full_contact_friction_stress;
pub use stencil::friction_force_stencil;
