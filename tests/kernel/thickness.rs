//! Finite thickness (paper Eq. 5; physics.md section 3): `S(qh)` limits,
//! `Theta(r/h)` tabulation, and coefficients for layers.

use viscoslide::internals::kernel::thickness::theta_direct;
use viscoslide::internals::kernel::SlidingKernel;
use viscoslide::internals::kernel::ThetaTable;
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::layer::compliance_ratio;
use viscoslide::response::{Grid, Layer, LayerBase, LayerConfig, SlidingResponse};

const A: f64 = 1e-3;

fn sls(nu: f64) -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        nu,
    )
    .unwrap()
}

#[test]
fn thin_layer_limits_of_s() {
    let nu: f64 = 0.3;
    for u in [1e-6, 1e-5] {
        // Bonded: oedometric, S ~ u (1-2nu) / (2 (1-nu)^2).
        let sb = compliance_ratio(LayerBase::Bonded, nu, u) / u;
        let want = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu).powi(2));
        assert!((sb - want).abs() < 1e-9 * want, "{sb} {want}");
        // Frictionless: S ~ u / 2, i.e. w = p h (1 - nu^2) / E.
        let sf = compliance_ratio(LayerBase::Frictionless, nu, u) / u;
        assert!((sf - 0.5).abs() < 1e-9, "{sf}");
    }
    // Thick limit, up to layers whose `|q| h` squared leaves f64.
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        assert!((compliance_ratio(base, nu, 25.0) - 1.0).abs() < 1e-15);
        for u in [400.0, 800.0, 1e154, 1e200, f64::MAX] {
            assert_eq!(compliance_ratio(base, nu, u), 1.0, "{base:?}, u = {u}");
        }
    }
    // Incompressible bonded layer: no O(u) compliance.
    let s = compliance_ratio(LayerBase::Bonded, 0.5, 1e-3);
    assert!(s.abs() < 1e-8, "{s}");
    // Bonded is stiffer than frictionless at every wavelength.
    for k in 1..200 {
        let u = k as f64 * 0.05;
        assert!(
            compliance_ratio(LayerBase::Bonded, nu, u)
                < compliance_ratio(LayerBase::Frictionless, nu, u)
        );
    }
}

#[test]
fn theta_is_one_near_the_load_and_decays_far() {
    let mut worst_interp = 0.0f64;
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        let layer = Layer {
            thickness: 1.0,
            base,
        };
        let t = ThetaTable::new(layer, 0.3).unwrap();
        for rho in [1e-8, 1e-6, 1e-4] {
            assert!((t.eval(rho) - 1.0).abs() < 2.0 * rho, "{base:?} {rho}");
        }
        assert!(t.eval(50.0).abs() < 1e-12, "{}", t.eval(50.0));
        // Interpolation against direct quadrature between nodes.
        for k in 0..60 {
            let rho = 1e-2 * 10f64.powf(k as f64 * 0.0537);
            let d = theta_direct(base, 0.3, rho);
            worst_interp = worst_interp.max((t.eval(rho) - d).abs());
        }
        // Continuity at the series/table seam.
        let s = t.eval(1e-2 * (1.0 - 1e-12)) - t.eval(1e-2 * (1.0 + 1e-12));
        assert!(s.abs() < 1e-10, "{s}");
    }
    println!("Theta interpolation: max abs error {worst_interp:e}");
    // Cubic interpolation in ln(rho) at 256 nodes per decade: ~1e-9.
    assert!(worst_interp < 2e-9, "{worst_interp:e}");
}

/// Total displacement volume under a point load: `int w dA = P lim_{q->0}
/// 2 (1-nu^2) S(qh) / (E q)`, i.e. `int_0^inf Theta(rho) drho = S'(0)`: 1/2 for
/// the frictionless base, `(1-2nu) / (2 (1-nu)^2)` for the bonded one. An
/// independent check of the Hankel-transform normalisation of Eq. 5.
#[test]
fn theta_integral_equals_the_long_wave_compliance() {
    let (g, w) = viscoslide::internals::kernel::quad::gauss_legendre(8);
    let nu: f64 = 0.3;
    for (base, want) in [
        (LayerBase::Frictionless, 0.5),
        (
            LayerBase::Bonded,
            (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu).powi(2)),
        ),
    ] {
        let t = ThetaTable::new(
            Layer {
                thickness: 1.0,
                base,
            },
            nu,
        )
        .unwrap();
        let h = 0.01;
        let mut s = 0.0;
        for p in 0..6000 {
            let a = p as f64 * h;
            for (x, wt) in g.iter().zip(&w) {
                s += 0.5 * h * wt * t.eval(a + 0.5 * h * (x + 1.0));
            }
        }
        println!("{base:?}: int Theta = {s}, S'(0) = {want}");
        assert!((s - want).abs() < 1e-7, "{base:?}: {s} vs {want}");
    }
}

fn kernel(layer: Option<Layer>, nu: f64) -> SlidingKernel {
    SlidingKernel::new(&SlidingResponse::new(&sls(nu), 0.3 * A / 0.01, 0.0, layer).unwrap())
        .unwrap()
}

#[test]
fn thick_layer_reproduces_the_half_space() {
    let half = kernel(None, 0.5);
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        let thick = kernel(
            Some(Layer {
                thickness: 1e12 * A,
                base,
            }),
            0.5,
        );
        for (i, j) in [(0.0, 0.0), (1.0, 0.0), (-3.0, 2.0), (-20.0, 0.0)] {
            let a = half.coefficient(i * A, j * A, A, A).total();
            let b = thick.coefficient(i * A, j * A, A, A).total();
            assert!((a - b).abs() < 1e-9 * a, "{base:?} ({i},{j}) {a} {b}");
        }
    }
}

#[test]
fn bonded_layer_is_stiffer() {
    let nu = 0.3;
    let h = 5.0 * A;
    let kb = kernel(
        Some(Layer {
            thickness: h,
            base: LayerBase::Bonded,
        }),
        nu,
    );
    let kf = kernel(
        Some(Layer {
            thickness: h,
            base: LayerBase::Frictionless,
        }),
        nu,
    );
    let half = kernel(None, nu);
    for (i, j) in [(0.0, 0.0), (1.0, 0.0), (-2.0, 1.0)] {
        let b = kb.coefficient(i * A, j * A, A, A).total();
        let f = kf.coefficient(i * A, j * A, A, A).total();
        let s = half.coefficient(i * A, j * A, A, A).total();
        assert!(b < f && f < s, "({i},{j}) {b} {f} {s}");
    }
    // Fast table with a layer agrees with the per-offset path.
    let t = kb.table(&Grid::square(10, 10, A).unwrap()).unwrap();
    let r = kb.table_per_offset(&Grid::square(10, 10, A).unwrap(), None);
    // Theta changes sign near r ~ 1.3 h, so compare against the largest
    // coefficient (the self-influence) rather than entry by entry.
    let peak = r.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (a, b) in t.values.iter().zip(&r.values) {
        worst = worst.max((a - b).abs() / peak);
    }
    println!("layer table fast vs per-offset: {worst:e}");
    assert!(worst < 1e-9, "{worst:e}");
}

#[test]
fn layer_config_parses_and_validates() {
    let c: LayerConfig = toml::from_str("thickness = 0.0075\nbase = \"bonded\"").unwrap();
    assert_eq!(c.base, LayerBase::Bonded);
    assert!(c.build().is_ok());
    let c: LayerConfig = toml::from_str("thickness = -1.0\nbase = \"frictionless\"").unwrap();
    assert!(c.build().is_err());
    assert!(toml::from_str::<LayerConfig>("thickness = 1.0\nbase = \"glued\"").is_err());
    assert!(toml::from_str::<LayerConfig>("thickness = 1.0\nbase = \"bonded\"\nx = 1").is_err());
}
