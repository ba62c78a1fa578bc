//! Deformed-surface anisotropy (paper Eq. 11-13, physics.md section 5) on
//! synthetic surfaces whose exact tensor is known.
//!
//! `crate::surface::generate` with `Anisotropy { ratio: s, angle }` gives
//! `<(dh/de)^2> / <(dh/de_perp)^2> = 1/s^2` for the continuous PSD, and its
//! Fourier amplitudes are deterministic (random phases only), so the lattice
//! sums of Eq. 11 differ from the continuum only by the discretisation of the
//! cut-off ellipses. The band is chosen to contain the whole support, so the
//! exact `gamma = min(s^2, 1/s^2)` and `theta_P = angle + 90 deg` for `s > 1`
//! (the stretched direction has the smaller slopes), `theta_P = angle` for
//! `s < 1`. Tolerances: 2 % on `gamma` (lattice discretisation of the
//! elliptical support with 64 scales on 256^2: measured well below 1 %) and
//! 1 degree on `theta_P`.

use viscoslide::internals::analysis::anisotropy::wrap_axis_deg;
use viscoslide::internals::analysis::{analyze, AnalysisInputs, AnalysisParams, AnalysisReport};
use viscoslide::surface::{generate, Anisotropy, GenerateParams, UpperCutoff, Window};

const N: usize = 256;
const L: f64 = 0.01;
/// Roll-off `q_r / q_L` of the test surfaces (see the module doc).
const ROLLOFF: f64 = 8.0;

fn surface(seed: u64, scales: f64, anisotropy: Option<Anisotropy>) -> Vec<f64> {
    surface_rolloff(seed, scales, anisotropy, Some(ROLLOFF))
}

fn surface_rolloff(
    seed: u64,
    scales: f64,
    anisotropy: Option<Anisotropy>,
    rolloff: Option<f64>,
) -> Vec<f64> {
    generate(&GenerateParams {
        nx: N,
        ny: N,
        length: L,
        upper: UpperCutoff::Scales(scales),
        rolloff_q0: rolloff.map(|r| r * 2.0 * std::f64::consts::PI / L),
        seed,
        anisotropy,
        ..GenerateParams::default()
    })
    .unwrap()
    .heights
}

fn analyse(u: &[f64], n: usize, scales: Option<f64>, params: &AnalysisParams) -> AnalysisReport {
    let zeros = vec![0.0; n * n];
    analyze(
        &AnalysisInputs {
            nx: n,
            ny: n,
            cell_size: L / N as f64,
            cell_size_y: L / N as f64,
            displacement: u,
            contact: &zeros,
            pressure: &zeros,
            scales,
            xi: None,
        },
        params,
    )
    .unwrap()
}

fn periodic() -> AnalysisParams {
    AnalysisParams {
        window: Window::None,
        ..AnalysisParams::default()
    }
}

fn axial_diff(a: f64, b: f64) -> f64 {
    wrap_axis_deg(a - b).abs()
}

#[test]
fn stretched_surfaces_give_exact_gamma_and_direction() {
    let s = 1.5;
    let exact = 1.0 / (s * s);
    let mut thetas = Vec::new();
    for angle in [0.0, 30.0, 60.0] {
        let u = surface(
            3,
            64.0,
            Some(Anisotropy {
                ratio: s,
                angle_deg: angle,
            }),
        );
        let r = analyse(&u, N, Some(64.0), &periodic());
        let want_theta = wrap_axis_deg(angle + 90.0);
        eprintln!(
            "s = {s}, angle = {angle}: gamma = {:.5} (exact {exact:.5}, rel err {:.2e}), theta_P = {:.4} (exact {want_theta}), band modes {}",
            r.gamma,
            r.gamma / exact - 1.0,
            r.theta_p_deg,
            r.band.modes
        );
        assert_eq!((r.band.zeta1, r.band.zeta2), (1.0, 64.0));
        assert!((r.gamma / exact - 1.0).abs() < 0.02, "gamma {}", r.gamma);
        assert!(
            axial_diff(r.theta_p_deg, want_theta) < 1.0,
            "theta_P {}",
            r.theta_p_deg
        );
        // Eq. 13 at theta_P is the largest eigenvalue.
        let m2 = r.tensor.m2(r.theta_p_deg.to_radians());
        assert!((m2 / r.tensor.m2_max - 1.0).abs() < 1e-12);
        thetas.push(r.theta_p_deg);
    }
    // Rotating the input rotates theta_P by the same angle.
    assert!((axial_diff(thetas[1], thetas[0]) - 30.0).abs() < 1.0);
    assert!((axial_diff(thetas[2], thetas[0]) - 60.0).abs() < 1.0);
}

#[test]
fn transposing_the_map_mirrors_theta_p() {
    let u = surface(
        5,
        64.0,
        Some(Anisotropy {
            ratio: 1.5,
            angle_deg: 30.0,
        }),
    );
    let mut t = vec![0.0; N * N];
    for i in 0..N {
        for j in 0..N {
            t[j * N + i] = u[i * N + j];
        }
    }
    let a = analyse(&u, N, Some(64.0), &periodic());
    let b = analyse(&t, N, Some(64.0), &periodic());
    eprintln!(
        "transpose: theta_P {:.4} -> {:.4}, gamma {:.5} -> {:.5}",
        a.theta_p_deg, b.theta_p_deg, a.gamma, b.gamma
    );
    // (x, y) -> (y, x) maps the direction theta to 90 - theta.
    assert!(axial_diff(b.theta_p_deg, 90.0 - a.theta_p_deg) < 1e-6);
    assert!((a.gamma - b.gamma).abs() < 1e-9);
    assert!((a.m20 - b.m02).abs() < 1e-9 * a.m20 && (a.m11 - b.m11).abs() < 1e-9 * a.m20);
}

#[test]
fn compressed_surface_default_band() {
    // s < 1: larger slopes along e, support reaching q1 / s = 80 q0; the
    // default band without a known number of scales is n/2 = 128.
    let s = 0.8;
    let u = surface(
        7,
        64.0,
        Some(Anisotropy {
            ratio: s,
            angle_deg: 45.0,
        }),
    );
    let r = analyse(&u, N, None, &periodic());
    eprintln!(
        "s = {s}, angle 45: gamma = {:.5} (exact {:.5}), theta_P = {:.4}, zeta2 = {}",
        r.gamma,
        s * s,
        r.theta_p_deg,
        r.band.zeta2
    );
    assert_eq!(r.band.zeta2, 128.0);
    assert!((r.gamma / (s * s) - 1.0).abs() < 0.02);
    assert!(axial_diff(r.theta_p_deg, 45.0) < 1.0);
}

#[test]
fn isotropic_surfaces_are_isotropic_also_when_cropped() {
    // Non-periodic crops (as the displacement of a non-periodic solve), with
    // the default Hann taper.
    let m = 192;
    let mut sum = 0.0;
    let mut sum_none = 0.0;
    let seeds = [1u64, 2, 3, 4, 5, 6, 7, 8];
    for seed in seeds {
        let u = surface(seed, 64.0, None);
        let crop: Vec<f64> = (0..m)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .map(|(i, j)| u[i * N + j])
            .collect();
        let r = analyse(&crop, m, Some(48.0), &AnalysisParams::default());
        let rn = analyse(&crop, m, Some(48.0), &periodic());
        eprintln!(
            "seed {seed}: gamma = {:.4} (Hann), {:.4} (no taper)",
            r.gamma, rn.gamma
        );
        sum += r.gamma;
        sum_none += rn.gamma;
    }
    let mean = sum / seeds.len() as f64;
    eprintln!(
        "mean gamma {mean:.4} (Hann), {:.4} (no taper)",
        sum_none / seeds.len() as f64
    );
    assert!(mean > 0.9, "mean gamma {mean}");
}

#[test]
fn m20_is_the_mean_square_x_slope() {
    // Few scales (q a <= 8 q0 a = 0.2): centred differences are accurate to
    // (q a)^2 / 6 < 0.7 %; tolerance 1 %.
    let u = surface_rolloff(
        11,
        8.0,
        Some(Anisotropy {
            ratio: 1.3,
            angle_deg: 20.0,
        }),
        None,
    );
    let r = analyse(&u, N, Some(8.0), &periodic());
    let a = L / N as f64;
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for i in 0..N {
        for j in 0..N {
            let ux = (u[((i + 1) % N) * N + j] - u[((i + N - 1) % N) * N + j]) / (2.0 * a);
            let uy = (u[i * N + (j + 1) % N] - u[i * N + (j + N - 1) % N]) / (2.0 * a);
            sxx += ux * ux;
            syy += uy * uy;
            sxy += ux * uy;
        }
    }
    let n2 = (N * N) as f64;
    let (sxx, syy, sxy) = (sxx / n2, syy / n2, sxy / n2);
    eprintln!(
        "m20 {:.5e} vs <u_x^2> {sxx:.5e}; m02 {:.5e} vs {syy:.5e}; m11 {:.5e} vs {sxy:.5e}",
        r.m20, r.m02, r.m11
    );
    assert!((r.m20 / sxx - 1.0).abs() < 0.01);
    assert!((r.m02 / syy - 1.0).abs() < 0.01);
    assert!((r.m11 - sxy).abs() < 0.01 * sxx.max(syy));
}

/// `analyze` on an `nx x ny` isotropic surface with square cells and the
/// band `1 <= |q|/q0 <= 8`.
fn analyse_rectangle(nx: usize, ny: usize, seed: u64) -> AnalysisReport {
    let u = generate(&GenerateParams {
        nx,
        ny,
        length: L,
        upper: UpperCutoff::Scales(8.0),
        seed,
        ..GenerateParams::default()
    })
    .unwrap()
    .heights;
    let zeros = vec![0.0; nx * ny];
    let a = L / nx as f64;
    analyze(
        &AnalysisInputs {
            nx,
            ny,
            cell_size: a,
            cell_size_y: a,
            displacement: &u,
            contact: &zeros,
            pressure: &zeros,
            scales: Some(8.0),
            xi: None,
        },
        &periodic(),
    )
    .unwrap()
}

#[test]
fn an_elongated_map_warns_that_its_band_samples_directions_unevenly() {
    // 64 x 8: along y the mode spacing is 8 q0, so the band holds modes
    // along q_x only (and q_y = +-8 q0 on its edge): gamma is the map's.
    for seed in 1..=3 {
        let r = analyse_rectangle(64, 8, seed);
        assert!(r.band.grid_gamma < 0.1, "{}", r.band.grid_gamma);
        let w: Vec<&String> = r
            .warnings
            .iter()
            .filter(|w| w.contains("samples directions unevenly"))
            .collect();
        assert_eq!(w.len(), 1, "seed {seed}: {:?}", r.warnings);
        assert!(
            w[0].contains("64 x 8") && w[0].contains("8.000 q0 along y"),
            "{}",
            w[0]
        );
    }
    // Square maps: the band's tensor is isotropic whatever the band, and
    // nothing is said; a mildly rectangular map stays above the threshold.
    for (nx, ny) in [(64, 64), (16, 16), (64, 56)] {
        let r = analyse_rectangle(nx, ny, 1);
        if nx == ny {
            assert!(
                (r.band.grid_gamma - 1.0).abs() < 1e-12,
                "{}",
                r.band.grid_gamma
            );
        }
        assert!(r.warnings.is_empty(), "{nx} x {ny}: {:?}", r.warnings);
    }
}
