//! Influence coefficients of the steady-sliding viscoelastic Green's function
//! (paper Eq. 4-6; physics.md section 3).

/// Errors evaluating influence coefficients.
#[derive(Debug, thiserror::Error)]
pub enum KernelError {
    #[error("{0}")]
    Invalid(String),
}
