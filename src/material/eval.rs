//! Evaluation of `E(w)`, `J*(w)`, `E1`, `E2` and the loss tangent over arrays
//! of angular frequencies (physics.md section 2). Large arrays are split over
//! the rayon pool.

use num_complex::Complex64;
use rayon::prelude::*;

use super::{CreepSpectrum, PronySeries};

/// Arrays at least this long are evaluated in parallel.
const PARALLEL_MIN: usize = 4096;

/// A linear viscoelastic response in the frequency domain
/// (`exp(+i w t)` convention, physics.md section 1-2).
pub trait ComplexModulus: Sync {
    /// `E(w) = E1 + i E2` at angular frequency `w` [rad/s].
    fn modulus(&self, omega: f64) -> Complex64;

    /// `J*(w) = 1/E(w)` [1/Pa].
    fn compliance(&self, omega: f64) -> Complex64 {
        1.0 / self.modulus(omega)
    }
}

impl ComplexModulus for CreepSpectrum {
    fn modulus(&self, omega: f64) -> Complex64 {
        CreepSpectrum::modulus(self, omega)
    }
    fn compliance(&self, omega: f64) -> Complex64 {
        CreepSpectrum::compliance(self, omega)
    }
}

impl ComplexModulus for PronySeries {
    fn modulus(&self, omega: f64) -> Complex64 {
        PronySeries::modulus(self, omega)
    }
}

fn map<F: Fn(f64) -> Complex64 + Sync>(omegas: &[f64], f: F) -> Vec<Complex64> {
    if omegas.len() >= PARALLEL_MIN {
        omegas.par_iter().map(|&w| f(w)).collect()
    } else {
        omegas.iter().map(|&w| f(w)).collect()
    }
}

/// `E(w)` at every frequency of `omegas` [rad/s].
pub fn modulus_at<M: ComplexModulus + ?Sized>(m: &M, omegas: &[f64]) -> Vec<Complex64> {
    map(omegas, |w| m.modulus(w))
}

/// Storage modulus, loss modulus and loss tangent over a frequency array.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DynamicModuli {
    /// Angular frequency `w` [rad/s].
    pub omega: Vec<f64>,
    /// Storage modulus `E1 = Re E(w)` \[Pa\].
    pub storage: Vec<f64>,
    /// Loss modulus `E2 = Im E(w)` \[Pa\].
    pub loss: Vec<f64>,
    /// Loss tangent `tan delta = E2 / E1`.
    pub tan_delta: Vec<f64>,
}

impl DynamicModuli {
    /// Evaluate `m` at `omegas`.
    pub fn evaluate<M: ComplexModulus + ?Sized>(m: &M, omegas: &[f64]) -> Self {
        let e = modulus_at(m, omegas);
        Self {
            omega: omegas.to_vec(),
            storage: e.iter().map(|z| z.re).collect(),
            loss: e.iter().map(|z| z.im).collect(),
            tan_delta: e.iter().map(|z| z.im / z.re).collect(),
        }
    }
}

/// `n` frequencies evenly spaced in `log w` from `from` to `to` inclusive.
pub fn log_space(from: f64, to: f64, n: usize) -> Vec<f64> {
    match n {
        0 => Vec::new(),
        1 => vec![from],
        _ => {
            let (a, b) = (from.ln(), to.ln());
            (0..n)
                .map(|i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_and_serial_paths_agree_with_pointwise() {
        let s = CreepSpectrum::standard_linear_solid(1e6, 1e8, 1e-3).unwrap();
        let w = log_space(1e-3, 1e9, PARALLEL_MIN + 10);
        let e = modulus_at(&s, &w);
        for (wi, ei) in w.iter().zip(&e) {
            assert_eq!(*ei, s.modulus(*wi));
        }
        let d = DynamicModuli::evaluate(&s, &w[..10]);
        assert_eq!(d.storage[3], s.modulus(w[3]).re);
        assert!(d.tan_delta.iter().all(|t| *t > 0.0));
        let j = s.compliance(w[2]);
        assert!((j * e[2] - 1.0).norm() < 1e-15);
    }
}
