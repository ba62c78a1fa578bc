//! The sliding response: one (material at its temperature, speed, sliding
//! direction, layer), built and checked once ([`SlidingResponse::new`]),
//! and the [`Grid`] it is evaluated on.
//!
//! Every consumer of the response takes it from here: the real-space
//! coefficient tables of the Toeplitz formulation
//! ([`crate::kernel::SlidingKernel`], paper Eq. 4-6), the periodic
//! multiplier (Appendix Eq. A2, physics.md section 6), the GPU coefficient
//! and level kernels (their creep-term plan), the dissipation route of the
//! friction (Appendix A3-A4) and the problem's Persson comparison. What
//! they share (the checks of speed and direction, the unit vector `e_v`
//! snapped onto the axes, the prefactor `(1 - nu^2)/pi`, the creep lengths
//! `v tau_k`, the complex compliance `J*(-q.v)` a mode sees and the layer's
//! Fourier ratio `S(|q| h)`) is computed here and nowhere else.

mod grid;
pub mod layer;

pub use grid::Grid;
pub(crate) use grid::{gcd, CELL_SIDE_RANGE};
pub use layer::{Layer, LayerBase, LayerConfig};

use num_complex::Complex64;

use crate::material::Material;

/// A sliding direction given in degrees from `+x`, in radians: whole turns
/// are taken off first (exactly, `degrees % 360`), so that `90 + 360 k`
/// degrees is the direction of 90 degrees for every `k` (multiplying a
/// large angle by `pi / 180` first rounds away its place in the turn).
/// Not finite stays not finite.
pub fn direction_rad(degrees: f64) -> f64 {
    (degrees % 360.0).to_radians()
}

/// The unit vector `e_v` of a sliding direction `direction_rad` from `+x`,
/// components below 1e-15 snapped to zero so that 90 degrees is exactly
/// `+y` and the tables of a direction along an axis are exactly
/// mirror-symmetric (the one such rule: the response and the heat problem
/// take it).
pub(crate) fn unit_direction(direction_rad: f64) -> (f64, f64) {
    let (s, c) = direction_rad.sin_cos();
    let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
    (snap(c), snap(s))
}

/// A sliding response that cannot be built; each names the offending value.
#[derive(Debug, thiserror::Error)]
pub enum ResponseError {
    #[error("{0}")]
    Invalid(String),
}

/// One steady-sliding response: the material (already at its temperature,
/// [`Material::at_temperature`]), the sliding speed `v`, the direction
/// `e_v` and an optional layer of finite thickness (Eq. 5).
#[derive(Debug, Clone, PartialEq)]
pub struct SlidingResponse {
    material: Material,
    speed: f64,
    direction_rad: f64,
    /// `e_v`, components below 1e-15 snapped to zero so that 90 degrees is
    /// exactly `+y`.
    e: (f64, f64),
    layer: Option<Layer>,
}

impl SlidingResponse {
    /// The response of `material` sliding at `speed` [m/s] (`>= 0`; `0` is
    /// fully relaxed, `f64::INFINITY` fully glassy) along `direction_rad`
    /// from `+x` (finite), on a half-space or on `layer` (thickness
    /// positive and finite).
    pub fn new(
        material: &Material,
        speed: f64,
        direction_rad: f64,
        layer: Option<Layer>,
    ) -> Result<Self, ResponseError> {
        if speed.is_nan() || speed < 0.0 {
            return Err(ResponseError::Invalid(format!(
                "speed = {speed} m/s must be >= 0 (may be infinite)"
            )));
        }
        if !direction_rad.is_finite() {
            return Err(ResponseError::Invalid(format!(
                "direction = {direction_rad} rad must be finite"
            )));
        }
        if let Some(l) = &layer {
            l.validate()?;
        }
        Ok(Self {
            material: material.clone(),
            speed,
            direction_rad,
            e: unit_direction(direction_rad),
            layer,
        })
    }

    /// The material, at the temperature of this response.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// Poisson ratio `nu`.
    pub fn poisson(&self) -> f64 {
        self.material.poisson
    }

    /// Sliding speed `v` [m/s].
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// In-plane angle of `e_v` from `+x` \[rad\].
    pub fn direction_rad(&self) -> f64 {
        self.direction_rad
    }

    /// Unit sliding direction `e_v`.
    pub fn direction(&self) -> (f64, f64) {
        self.e
    }

    /// The layer, if any (Eq. 5).
    pub fn layer(&self) -> Option<Layer> {
        self.layer
    }

    /// `(1 - nu^2) / pi`, the prefactor of Eq. 4.
    pub fn prefactor(&self) -> f64 {
        self.material.composite_factor() / std::f64::consts::PI
    }

    /// `1/E_inf` [1/Pa].
    pub fn glassy_compliance(&self) -> f64 {
        self.material.spectrum.glassy_compliance()
    }

    /// `1/E_inf + sum_k C_k` = `1/E_0` [1/Pa].
    pub fn relaxed_compliance(&self) -> f64 {
        self.glassy_compliance()
            + self
                .material
                .spectrum
                .terms
                .iter()
                .map(|t| t.compliance)
                .sum::<f64>()
    }

    /// The creep elements as `(C_k, l_k)`: compliance [1/Pa] and the length
    /// `l_k = v tau_k / unit` the sliding solid travels in one creep time,
    /// in units of `unit` \[m\] (`1.0` for metres); `0` at `v = 0`, `inf`
    /// at `v = inf` (the memory integral of Eq. 4).
    pub fn creep_lengths(&self, unit: f64) -> Vec<(f64, f64)> {
        let v = self.speed;
        self.material
            .spectrum
            .terms
            .iter()
            .map(|t| {
                let l = if v.is_infinite() {
                    f64::INFINITY
                } else {
                    v * t.time / unit
                };
                (t.compliance, l)
            })
            .collect()
    }

    /// `q.e_v` for the wavevector `q = (qx, qy)` [1/m].
    pub fn along(&self, (qx, qy): (f64, f64)) -> f64 {
        qx * self.e.0 + qy * self.e.1
    }

    /// `J*(-q.v)` [1/Pa] for `qv = q.e_v` [1/m]: the complex compliance at
    /// the frequency `omega = -q.v` a mode `exp(i q.x)` is met with
    /// (physics.md section 6; time factor `exp(+i w t)`).
    pub fn compliance_along(&self, qv: f64) -> Complex64 {
        self.material.spectrum.compliance(-qv * self.speed)
    }

    /// The layer's compliance ratio `S(|q| h)` to the half-space at `|q|`
    /// [1/m]; `1` on a half-space.
    pub fn layer_ratio(&self, q: f64) -> f64 {
        self.layer.map_or(1.0, |l| {
            layer::compliance_ratio(l.base, self.material.poisson, q * l.thickness)
        })
    }

    /// The surface multiplier `u(q) / p(q) = 2 (1 - nu^2) S(|q| h) J*(-q.v) / |q|`
    /// [m/Pa] of the mode of wavevector `q` (Appendix Eq. A2 with the
    /// layer's exact ratio); zero at `q = 0`. `compliance` is `J*(-q.v)`
    /// for `qv = q.e_v`, given so that a caller may share it among modes.
    pub fn surface_multiplier_with(
        &self,
        q: (f64, f64),
        compliance: impl Fn(f64) -> Complex64,
    ) -> Complex64 {
        let qn = q.0.hypot(q.1);
        if qn == 0.0 {
            return Complex64::default();
        }
        compliance(self.along(q))
            * (2.0 * self.material.composite_factor() * self.layer_ratio(qn) / qn)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::CreepSpectrum;

    fn sls() -> Material {
        Material::new(
            CreepSpectrum::standard_linear_solid(3.3e6, 1e7, 0.01).unwrap(),
            0.5,
        )
        .unwrap()
    }

    #[test]
    fn refuses_bad_speed_direction_and_layer_naming_them() {
        let m = sls();
        let e = SlidingResponse::new(&m, f64::NAN, 0.0, None).unwrap_err();
        assert!(e.to_string().contains("speed = NaN"), "{e}");
        let e = SlidingResponse::new(&m, -1.0, 0.0, None).unwrap_err();
        assert!(e.to_string().contains("speed = -1"), "{e}");
        let e = SlidingResponse::new(&m, 1.0, f64::INFINITY, None).unwrap_err();
        assert!(e.to_string().contains("direction = inf"), "{e}");
        let thin = Layer {
            thickness: 0.0,
            base: LayerBase::Bonded,
        };
        let e = SlidingResponse::new(&m, 1.0, 0.0, Some(thin)).unwrap_err();
        assert!(e.to_string().contains("thickness = 0"), "{e}");
        assert!(SlidingResponse::new(&m, f64::INFINITY, 0.0, None).is_ok());
    }

    #[test]
    fn snaps_axis_directions_and_matches_the_relaxed_limit() {
        let r = SlidingResponse::new(&sls(), 0.0, std::f64::consts::FRAC_PI_2, None).unwrap();
        assert_eq!(r.direction(), (0.0, 1.0));
        // At v = 0 every mode sees the relaxed compliance 1/E_0.
        let j = r.compliance_along(123.0);
        assert!((j.re * 3.3e6 - 1.0).abs() < 1e-12 && j.im == 0.0);
        assert!((r.relaxed_compliance() * 3.3e6 - 1.0).abs() < 1e-12);
        let m = r.surface_multiplier_with((3.0, 4.0), |qv| r.compliance_along(qv));
        assert!((m.re - 2.0 * 0.75 / 5.0 / 3.3e6).abs() < 1e-20);
    }
}
