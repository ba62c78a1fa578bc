//! Persson's theory (physics.md section 10) against closed forms, limits, an
//! independent brute-force quadrature, and across the three PSD sources.

use std::f64::consts::PI;

use num_complex::Complex64;
use viscoslide::material::{load_material_file, CreepSpectrum, Material};
use viscoslide::persson::{self, Persson, PerssonParams, PerssonPoint};
use viscoslide::surface::{self, GenerateParams, Normalisation, TabulatedPsd, UpperCutoff, Window};

fn sls() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

fn elastic(modulus: f64, poisson: f64) -> Material {
    Material::new(CreepSpectrum::new(modulus, vec![]).unwrap(), poisson).unwrap()
}

/// The surface of configs/paper_friction_speed.toml (Fig. 1/7).
fn fig1_params() -> GenerateParams {
    GenerateParams {
        nx: 256,
        ny: 256,
        length: 0.01,
        hurst: 0.8,
        upper: UpperCutoff::Scales(32.0),
        ql: None,
        rolloff_q0: Some(8.0 * 2.0 * PI / 0.01),
        normalisation: Normalisation::RmsSlope(0.02),
        seed: 1,
        anisotropy: None,
    }
}

/// The surface of configs/paper_experiment.toml (Fig. 6).
fn experiment_params() -> GenerateParams {
    GenerateParams {
        nx: 1024,
        ny: 1024,
        length: 2.5032990e-4,
        hurst: 0.82,
        upper: UpperCutoff::Q1(6.31e6),
        ql: None,
        rolloff_q0: None,
        normalisation: Normalisation::RmsSlope(0.5),
        seed: 1,
        anisotropy: None,
    }
}

fn sbr() -> Material {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("configs/data/sbr_like_material.toml");
    load_material_file(&path, Some(0.5)).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn elastic_limit_is_exact() {
    // A real, frequency-independent modulus: mu = 0 exactly, G(q1) in
    // closed form, A/A0 = erf(1 / (2 sqrt G)).
    let (psd_fig1, _) = persson::psd::continuum_self_affine(&fig1_params()).unwrap();
    let table = TabulatedPsd::new(
        vec![1e3, 3e3, 1e4, 2e4, 1e5],
        vec![1e-20, 5e-21, 1e-23, 3e-24, 1e-27],
        "t",
    )
    .unwrap();
    for (psd, sigma0, e, nu) in [
        (&psd_fig1, 3e3, 5e6, 0.5),
        (&psd_fig1, 1e6, 1e7, 0.3),
        (&table, 2e4, 3e6, 0.45),
    ] {
        let m = elastic(e, nu);
        let t = Persson::new(&m, psd, sigma0, PerssonParams::default()).unwrap();
        let e_star = e / (1.0 - nu * nu);
        let g = (e_star / sigma0).powi(2) * psd.moment(2) / 8.0;
        let area = libm::erf(1.0 / (2.0 * g.sqrt()));
        for p in t.curve(&[0.0, 1e-6, 1.0, 1e4]).unwrap() {
            assert_eq!(p.friction_coefficient, 0.0);
            assert!(rel(p.g_q1, g) < 1e-10, "G = {} vs {g}", p.g_q1);
            assert!(
                rel(p.contact_area_fraction, area) < 1e-10,
                "A = {} vs {area}",
                p.contact_area_fraction
            );
        }
    }
}

#[test]
fn slow_and_fast_limits_are_the_relaxed_and_glassy_elastic_solids() {
    let (psd, _) = persson::psd::continuum_self_affine(&fig1_params()).unwrap();
    let sigma0 = 3e3;
    let m = sls();
    let t = Persson::new(&m, &psd, sigma0, PerssonParams::default()).unwrap();
    let relaxed = Persson::new(
        &elastic(1e7 / 3.0, 0.5),
        &psd,
        sigma0,
        PerssonParams::default(),
    )
    .unwrap()
    .point(1.0)
    .unwrap();
    let glassy = Persson::new(&elastic(1e7, 0.5), &psd, sigma0, PerssonParams::default())
        .unwrap()
        .point(1.0)
        .unwrap();
    let speeds = persson::log_speeds(1e-4, 1e1, 61);
    let curve = t.curve(&speeds).unwrap();
    let peak = curve
        .iter()
        .map(|p| p.friction_coefficient)
        .fold(0.0, f64::max);
    assert!(peak > 1e-3, "peak mu = {peak}");
    // Bell-shaped: the peak is inside the range, mu > 0 everywhere.
    assert!(curve.iter().all(|p| p.friction_coefficient > 0.0));
    assert!(curve[0].friction_coefficient < 0.1 * peak);
    assert!(curve[60].friction_coefficient < 0.1 * peak);
    let ends = t.curve(&[0.0, 1e-12, 1e10]).unwrap();
    assert_eq!(ends[0].friction_coefficient, 0.0);
    assert!(ends[1].friction_coefficient < 1e-8 * peak);
    assert!(ends[2].friction_coefficient < 1e-8 * peak);
    assert!(rel(ends[0].contact_area_fraction, relaxed.contact_area_fraction) < 1e-12);
    assert!(rel(ends[1].contact_area_fraction, relaxed.contact_area_fraction) < 1e-9);
    assert!(rel(ends[2].contact_area_fraction, glassy.contact_area_fraction) < 1e-7);
    // The area falls from the relaxed to the glassy value.
    assert!(relaxed.contact_area_fraction > 2.5 * glassy.contact_area_fraction);
    for w in curve.windows(2) {
        assert!(w[1].contact_area_fraction <= w[0].contact_area_fraction * (1.0 + 1e-12));
    }
}

/// Brute-force Persson theory written independently of the module: the SLS
/// modulus in closed form, the trapezoidal rule over the full period in phi
/// (spectrally accurate for a periodic integrand) and over q on a fine
/// uniform grid, cumulative trapezoid for G.
fn brute_force(psd: &TabulatedPsd, sigma0: f64, v: f64) -> (f64, f64) {
    let (e0, einf, tau, nu) = (1e7 / 3.0, 1e7, 0.01, 0.5);
    let modulus = |w: f64| {
        let j = Complex64::new(1.0 / einf, 0.0)
            + (1.0 / e0 - 1.0 / einf) / Complex64::new(1.0, w * tau);
        1.0 / j
    };
    let s = (1.0 - nu * nu) * sigma0;
    let m = 4096;
    let angular = |q: f64| {
        let (mut f, mut k) = (0.0, 0.0);
        for i in 0..m {
            let phi = 2.0 * PI * i as f64 / m as f64;
            let e = modulus(q * v * phi.cos()) / s;
            f += phi.cos() * e.im;
            k += e.norm_sqr();
        }
        let h = 2.0 * PI / m as f64;
        (f * h, k * h)
    };
    let (qa, qb) = (psd.q_min(), psd.q_max());
    let n = 8000;
    let dq = (qb - qa) / n as f64;
    let mut g = 0.0;
    let mut mu = 0.0;
    let mut prev: Option<(f64, f64)> = None; // (dG/dq, dmu/dq) at the previous node
    for i in 0..=n {
        let q = qa + dq * i as f64;
        let c = psd.eval(q.clamp(qa, qb));
        let (f, k) = angular(q);
        let dg = q.powi(3) * c * k / 8.0;
        if let Some((pg, _)) = prev {
            g += 0.5 * dq * (pg + dg);
        }
        let p = if g > 0.0 {
            libm::erf(1.0 / (2.0 * g.sqrt()))
        } else {
            1.0
        };
        let dmu = 0.5 * q.powi(3) * c * p * f;
        if let Some((_, pm)) = prev {
            mu += 0.5 * dq * (pm + dmu);
        }
        prev = Some((dg, dmu));
    }
    (mu, libm::erf(1.0 / (2.0 * g.sqrt())))
}

#[test]
fn sls_narrow_band_matches_brute_force() {
    // A narrow band q in [1e4, 1.25e4] 1/m, C ~ q^-3.6, amplitude chosen so
    // that G(q1) is of order 1 (partial contact) at 10 kPa.
    let psd = TabulatedPsd::new(
        vec![1e4, 1.25e4],
        vec![2e-20, 2e-20 * 1.25f64.powf(-3.6)],
        "band",
    )
    .unwrap();
    let sigma0 = 1e4;
    let t = Persson::new(&sls(), &psd, sigma0, PerssonParams::default()).unwrap();
    // q v tau from about 0.1 to 30 around the loss peak.
    let speeds = [1e-3, 1e-2, 3e-2, 0.3];
    let curve = t.curve(&speeds).unwrap();
    for (v, p) in speeds.iter().zip(&curve) {
        let (mu, area) = brute_force(&psd, sigma0, *v);
        assert!(area > 0.05 && area < 0.95, "partial contact: A = {area}");
        assert!(
            rel(p.friction_coefficient, mu) < 1e-6,
            "v = {v}: mu {} vs brute force {mu} ({:.2e})",
            p.friction_coefficient,
            rel(p.friction_coefficient, mu)
        );
        assert!(
            rel(p.contact_area_fraction, area) < 1e-6,
            "v = {v}: A {} vs brute force {area}",
            p.contact_area_fraction
        );
        eprintln!(
            "v = {v:.1e}: mu {:.10e} (rel. diff {:.1e}), A {:.10e} (rel. diff {:.1e})",
            p.friction_coefficient,
            rel(p.friction_coefficient, mu),
            p.contact_area_fraction,
            rel(p.contact_area_fraction, area)
        );
    }
}

fn finer() -> PerssonParams {
    PerssonParams {
        q_panel_width: 0.2,
        q_nodes: 12,
        grading_ratio: 0.15,
        grading_floor: 1e-3,
        phi_nodes: 14,
        table_width: 0.5,
        table_points: 24,
    }
}

fn max_rel_diff(a: &[PerssonPoint], b: &[PerssonPoint]) -> (f64, f64) {
    a.iter().zip(b).fold((0.0, 0.0), |(dm, da), (x, y)| {
        (
            dm.max(rel(x.friction_coefficient, y.friction_coefficient)),
            da.max(rel(x.contact_area_fraction, y.contact_area_fraction)),
        )
    })
}

#[test]
fn quadrature_converges() {
    // The default rule against one of about twice the resolution in every
    // direction, on the 34-term SBR-like spectrum with the experiment's
    // surface (251 scales, 94 kPa) and on the SLS with the Fig. 1 surface.
    let cases = [
        (
            sbr(),
            persson::psd::continuum_self_affine(&experiment_params())
                .unwrap()
                .0,
            94e3,
            persson::log_speeds(1e-9, 1e2, 23),
        ),
        (
            sls(),
            persson::psd::continuum_self_affine(&fig1_params())
                .unwrap()
                .0,
            3e3,
            persson::log_speeds(1e-5, 1e2, 15),
        ),
        // Low pressure: P(q) drops steeply just above q_L (graded panels).
        (
            sls(),
            persson::psd::continuum_self_affine(&fig1_params())
                .unwrap()
                .0,
            30.0,
            persson::log_speeds(1e-4, 1e1, 6),
        ),
    ];
    for (m, psd, sigma0, speeds) in cases {
        let a = Persson::new(&m, &psd, sigma0, PerssonParams::default())
            .unwrap()
            .curve(&speeds)
            .unwrap();
        let b = Persson::new(&m, &psd, sigma0, finer())
            .unwrap()
            .curve(&speeds)
            .unwrap();
        let (dm, da) = max_rel_diff(&a, &b);
        eprintln!("sigma0 = {sigma0}: max rel. diff mu {dm:.2e}, A {da:.2e}");
        assert!(dm < 1e-7 && da < 1e-7, "mu {dm:.2e}, A {da:.2e}");
    }
}

#[test]
fn three_psd_sources_agree() {
    // One surface (the Fig. 1 surface, 256^2), three PSD sources: the
    // continuum self-affine PSD, the radial average of the height map read
    // back from a .npy file, and a q,C CSV of the self-affine PSD sampled at
    // 40 log-spaced wavenumbers (plus the roll-off).
    let params = fig1_params();
    let (analytic, target) = persson::psd::continuum_self_affine(&params).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let map = surface::generate(&params).unwrap();
    let file = tmp.path().join("heights.npy");
    surface::save_npy(&map, &file, surface::NpyPrecision::F64).unwrap();
    let read = surface::read_height_map(&file, params.length).unwrap();
    let (radial, info) = persson::psd::radial(&read, Window::None).unwrap();
    assert!(info.slope_isotropy > 0.9, "{info:?}");
    let mut qs = persson::log_speeds(target.ql, target.q1, 40);
    qs.push(target.q0);
    qs.sort_by(f64::total_cmp);
    let mut csv = String::from("q_per_m,c_m4\n");
    for q in &qs {
        csv.push_str(&format!("{q:.17e},{:.17e}\n", analytic.eval(*q)));
    }
    let csv_path = tmp.path().join("psd.csv");
    std::fs::write(&csv_path, csv).unwrap();
    let tabulated = TabulatedPsd::from_csv(&csv_path).unwrap();

    let speeds = persson::log_speeds(1e-4, 1.0, 9);
    let run = |psd: &TabulatedPsd| {
        Persson::new(&sls(), psd, 3e3, PerssonParams::default())
            .unwrap()
            .curve(&speeds)
            .unwrap()
    };
    let (a, r, t) = (run(&analytic), run(&radial), run(&tabulated));
    let (dm, da) = max_rel_diff(&t, &a);
    eprintln!("tabulated vs analytic: mu {dm:.2e}, A {da:.2e}");
    assert!(dm < 1e-9 && da < 1e-9);
    let (dm, da) = max_rel_diff(&r, &a);
    eprintln!("radial average of the map vs analytic: mu {dm:.2e}, A {da:.2e}");
    // The map's discrete Fourier modes sample the continuum PSD (bins of
    // width 2 pi / L, normalised by the lattice sum): within 2 % (measured
    // 0.8 % in mu, 0.5 % in A).
    assert!(dm < 0.02 && da < 0.02, "mu {dm:.3e}, A {da:.3e}");
}

#[test]
fn anisotropic_generated_surface_is_refused() {
    let mut p = fig1_params();
    p.anisotropy = Some(surface::Anisotropy {
        ratio: 2.0,
        angle_deg: 0.0,
    });
    let e = persson::psd::continuum_self_affine(&p)
        .unwrap_err()
        .to_string();
    assert!(e.contains("anisotropic") && !e.contains('\n'), "{e}");
}

#[test]
fn bad_inputs_are_refused() {
    let (psd, _) = persson::psd::continuum_self_affine(&fig1_params()).unwrap();
    for s in [0.0, -1.0, f64::NAN] {
        assert!(Persson::new(&sls(), &psd, s, PerssonParams::default()).is_err());
    }
    let t = Persson::new(&sls(), &psd, 3e3, PerssonParams::default()).unwrap();
    assert!(t.curve(&[1.0, -1.0]).is_err());
    assert!(t.curve(&[f64::INFINITY]).is_err());
}

#[test]
fn loss_peak_of_the_sls_is_exact() {
    // E2 of the SLS, E0 + (E_inf - E0) i w theta / (1 + i w theta), peaks
    // at w = 1 / theta, theta = tau E0 / E_inf the relaxation time.
    let tau = 0.01;
    let w = persson::loss_peak(&sls().spectrum).unwrap();
    let exact = 3.0 / tau;
    assert!(rel(w, exact) < 1e-6, "{w} vs {exact}");
    assert!(persson::loss_peak(&elastic(1e6, 0.5).spectrum).is_none());
}

#[test]
fn integrals_beyond_double_precision_are_refused() {
    // A nominal pressure so small, or a PSD so large, that G(q1) ~
    // (E*/sigma0)^2 <|grad h|^2> / 8 overflows: refused in one line naming
    // the pressure, never a NaN G(q1) beside A/A0 = 1.
    let (psd, _) = persson::psd::continuum_self_affine(&fig1_params()).unwrap();
    for sigma0 in [1e-300, 1e-200] {
        let theory = Persson::new(&sls(), &psd, sigma0, PerssonParams::default()).unwrap();
        let err = theory.curve(&[1e-3, 1.0]).unwrap_err().to_string();
        assert!(err.contains("leave double precision"), "{err}");
        assert!(err.contains(&format!("sigma0 = {sigma0:.4e} Pa")), "{err}");
        assert!(!err.contains('\n'), "{err}");
    }
    let huge = TabulatedPsd::new(vec![1e3, 2e3], vec![1e300, 1e300], "t").unwrap();
    let theory = Persson::new(&sls(), &huge, 3e3, PerssonParams::default()).unwrap();
    let err = theory.point(1.0).unwrap_err().to_string();
    assert!(err.contains("mean square slope"), "{err}");
    // Small but representable pressures keep their answer: finite, with
    // the light-load area falling with sigma0.
    let theory = Persson::new(&sls(), &psd, 1e-100, PerssonParams::default()).unwrap();
    for p in theory.curve(&[0.0, 1e-3, 1.0]).unwrap() {
        assert!(p.is_finite(), "{p:?}");
        assert!(
            p.contact_area_fraction > 0.0 && p.contact_area_fraction < 1e-100,
            "{p:?}"
        );
    }
}

#[test]
fn speeds_whose_frequencies_leave_double_precision_are_refused() {
    // q1 v overflows at v = 1e308 m/s: an error naming the speeds, not a
    // panic in the angular table (an assertion, or a capacity overflow
    // for a range reaching it).
    let (psd, _) = persson::psd::continuum_self_affine(&fig1_params()).unwrap();
    let theory = Persson::new(&sls(), &psd, 3e3, PerssonParams::default()).unwrap();
    for speeds in [&[1e308][..], &[1e300, 1e308], &[0.0, 1e308]] {
        let err = theory.curve(speeds).unwrap_err().to_string();
        assert!(
            err.contains("leave double precision") && err.contains("1e308"),
            "{err}"
        );
    }
    // The largest speeds whose frequencies stay finite keep the glassy limit.
    let p = theory.point(1e300).unwrap();
    assert!(p.is_finite() && p.friction_coefficient < 1e-290, "{p:?}");
}
