//! NNLS spectrum fit (physics.md section 2): recovery of a known 34-term
//! spectrum from synthetic E1/E2 data, and the WLF time-temperature shift.

use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::material::{fit_spectrum, FitParams, PronySeries, PronyTerm, Wlf};

const N: usize = 34;
const THETA0: f64 = 1e-10;

/// Known relaxation spectrum on the fit grid (34 times, ratio e): a broad
/// positive profile like a rubber's glass transition, E0 = 5 MPa.
fn truth() -> PronySeries {
    let terms = (0..N)
        .map(|j| {
            let x = j as f64 - 15.0;
            PronyTerm {
                modulus: 8e7 * (-(x * x) / 50.0).exp() * (1.0 + 0.2 * (0.9 * j as f64).cos()),
                time: THETA0 * (j as f64).exp(),
            }
        })
        .collect();
    PronySeries::new(5e6, terms).unwrap()
}

/// 10 points per decade across the grid's frequency range (14.3 decades).
fn frequencies() -> Vec<f64> {
    let lo = 1.0 / (THETA0 * ((N - 1) as f64).exp());
    let hi = 1.0 / THETA0;
    let n = 144;
    (0..n)
        .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
        .collect()
}

fn params() -> FitParams {
    FitParams {
        terms: N,
        ratio: std::f64::consts::E,
        shortest_time: Some(THETA0),
    }
}

/// Largest `|E_fit - E_true| / |E_true|` over `omegas`.
fn max_rel_error(fit: &viscoslide::material::SpectrumFit, t: &PronySeries, omegas: &[f64]) -> f64 {
    omegas
        .iter()
        .map(|&w| (fit.creep.modulus(w) - t.modulus(w)).norm() / t.modulus(w).norm())
        .fold(0.0, f64::max)
}

#[test]
fn recovers_known_spectrum_noise_free() {
    let t = truth();
    let w = frequencies();
    let data: Vec<Complex64> = w.iter().map(|&x| t.modulus(x)).collect();
    let fit = fit_spectrum(&w, &data, &params()).unwrap();
    let err = max_rel_error(&fit, &t, &w);
    println!(
        "noise-free: max rel error of E(w) = {err:.3e}, rms E1 {:.3e}, rms E2 {:.3e}, {} terms > 0",
        fit.info.rms_relative_storage, fit.info.rms_relative_loss, fit.info.nonzero_terms
    );
    // The model contains the truth exactly, so only round-off amplified by
    // the conditioning of 34 strongly overlapping basis functions remains
    // (observed: about 1e-15); 1e-6 is the required bound and still fails
    // for any error in the basis, the weighting or the conversion.
    assert!(err < 1e-6, "{err}");
    assert!(fit.info.rms_relative_storage < 1e-6 && fit.info.rms_relative_loss < 1e-6);
}

#[test]
fn recovers_known_spectrum_with_two_percent_noise() {
    let t = truth();
    let w = frequencies();
    let mut rng = ChaCha8Rng::seed_from_u64(2014);
    // Independent 2 % Gaussian noise on E1 and E2 (Box-Muller).
    let mut gauss = || {
        let u1: f64 = rng.random::<f64>().max(1e-300);
        let u2: f64 = rng.random::<f64>();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    };
    let data: Vec<Complex64> = w
        .iter()
        .map(|&x| {
            let e = t.modulus(x);
            Complex64::new(e.re * (1.0 + 0.02 * gauss()), e.im * (1.0 + 0.02 * gauss()))
        })
        .collect();
    let fit = fit_spectrum(&w, &data, &params()).unwrap();
    let err = max_rel_error(&fit, &t, &w);
    println!(
        "2% noise: max rel error of E(w) = {err:.3e}, rms E1 {:.3e}, rms E2 {:.3e}",
        fit.info.rms_relative_storage, fit.info.rms_relative_loss
    );
    // The fit averages the noise over ~10 points per characteristic time, so
    // the fitted curve stays well within one noise standard deviation (2 %);
    // 3 % is the required bound. The residual against the noisy data itself
    // must be close to the noise level (it cannot fit noise with 35 smooth
    // terms): between 1 % and 3 %.
    assert!(err < 0.03, "{err}");
    for r in [fit.info.rms_relative_storage, fit.info.rms_relative_loss] {
        assert!(r > 0.01 && r < 0.03, "{r}");
    }
}

#[test]
fn default_grid_is_centred_on_the_data() {
    let t = truth();
    let w = frequencies();
    let data: Vec<Complex64> = w.iter().map(|&x| t.modulus(x)).collect();
    let p = FitParams::default();
    let fit = fit_spectrum(&w, &data, &p).unwrap();
    let (hi, lo) = fit.info.margin_decades;
    // The data span exactly the grid here, so both margins vanish (1e-9:
    // round-off in the logarithms).
    assert!(hi.abs() < 1e-9 && lo.abs() < 1e-9, "{hi} {lo}");
    assert!((fit.info.shortest_time / THETA0 - 1.0).abs() < 1e-9);
}

#[test]
fn wlf_shift_round_trip() {
    let wlf = Wlf::new(8.86, 101.6, 17.0).unwrap();
    // Universal WLF: at T_ref - 20 K, log10 a_T = 8.86*20/81.6.
    let expect = 8.86 * 20.0 / 81.6;
    assert!((wlf.log10_shift(-3.0).unwrap() - expect).abs() < 1e-14);
    for &(t1, t2) in &[(-20.0, 60.0), (0.0, 17.0), (40.0, -10.0), (25.0, 25.0)] {
        let w = 123.4;
        let there = wlf.shift_frequency(w, t1, t2).unwrap();
        let back = wlf.shift_frequency(there, t2, t1).unwrap();
        // Two powers of ten and two products: a few ulps.
        assert!((back / w - 1.0).abs() < 1e-14, "{t1} -> {t2}: {back}");
        // Composition through the reference temperature.
        let via = wlf
            .shift_frequency(wlf.shift_frequency(w, t1, 17.0).unwrap(), 17.0, t2)
            .unwrap();
        assert!((via / there - 1.0).abs() < 1e-14);
    }
    // E(w, T) = E(w a_T, T_ref): a material at T_ref evaluated at the shifted
    // frequency is the material at T.
    let t = truth();
    let a = wlf.shift_factor(0.0).unwrap();
    let w = 10.0;
    let at_ref = t.modulus(w * a);
    let shifted = t.modulus(wlf.shift_frequency(w, 0.0, 17.0).unwrap());
    assert!((at_ref - shifted).norm() / at_ref.norm() < 1e-14);
    assert!(a > 1.0, "colder material responds as at a higher frequency");
}
