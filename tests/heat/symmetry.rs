//! Orientation, symmetry and limits: sliding at 90 degrees is the
//! transposed problem; heat trails behind; the rise scales as `1 /
//! lam` exactly; the FFT embedding against the dense product of the same
//! table (the naive control); the high-speed limit of a wide patch (1-D
//! conduction into the depth, which carries the whole power); refusals.

use viscoslide::heat::{
    surface_temperature, Conduction, HeatDomain, HeatError, HeatSetup, HeatSolver,
};
use viscoslide::internals::operator::{DenseOperator, GridOperator, OffsetTable};
use viscoslide::response::Grid;

const KAPPA: f64 = 1e-7;

fn setup(
    grid: (usize, usize),
    cell: (f64, f64),
    speed: f64,
    deg: f64,
    domain: HeatDomain,
) -> HeatSetup {
    HeatSetup {
        grid: Grid::new(grid.0, grid.1, (cell.0, cell.1)).unwrap(),
        conduction: Conduction {
            conductivity: 0.25,
            diffusivity: KAPPA,
        },
        speed,
        direction_rad: deg.to_radians(),
        domain,
    }
}

/// A seeded pseudo-random value in [0, 1).
fn noise(k: usize) -> f64 {
    let x = (k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    (x >> 11) as f64 / (1u64 << 53) as f64
}

/// A random flux on part of the grid.
fn spots(nx: usize, ny: usize) -> Vec<f64> {
    (0..nx * ny)
        .map(|k| {
            if noise(3 * k) < 0.3 {
                1e5 * noise(k)
            } else {
                0.0
            }
        })
        .collect()
}

fn transpose(a: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    let mut t = vec![0.0; a.len()];
    for i in 0..nx {
        for j in 0..ny {
            t[j * nx + i] = a[i * ny + j];
        }
    }
    t
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Sliding along +y on `nx x ny` cells of `dx x dy` is sliding along +x
/// on the transposed map (`ny x nx` cells of `dy x dx`), for pads and
/// periodic cells: to 1e-12 of the largest rise (the two tables are
/// mirror images computed in mirrored order, equal to rounding).
#[test]
fn sliding_along_y_is_the_transposed_problem() {
    let (nx, ny, dx, dy) = (23, 14, 2e-6, 3e-6);
    let flux = spots(nx, ny);
    for domain in [HeatDomain::Pad, HeatDomain::Periodic { block_length: None }] {
        for speed in [1e-3, 0.3] {
            let a = surface_temperature(setup((nx, ny), (dx, dy), speed, 90.0, domain), &flux)
                .unwrap()
                .rise;
            let b = surface_temperature(
                setup((ny, nx), (dy, dx), speed, 0.0, domain),
                &transpose(&flux, nx, ny),
            )
            .unwrap()
            .rise;
            let bt = transpose(&b, ny, nx);
            let diff = a
                .iter()
                .zip(&bt)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                diff <= 1e-12 * max_abs(&a),
                "{domain:?}, v {speed}: {diff:e}"
            );
        }
    }
}

/// One hot cell: the rise behind it (against `e_v`) exceeds the rise the
/// same distance ahead, for +x, -x, +y and an oblique direction, on a pad
/// and on a periodic cell; and the pad's rise is largest on the cell.
#[test]
fn heat_trails_behind() {
    let (n, d) = (33, 1e-6);
    let mut flux = vec![0.0; n * n];
    flux[16 * n + 16] = 1e6;
    for domain in [HeatDomain::Pad, HeatDomain::Periodic { block_length: None }] {
        for (deg, step) in [
            (0.0, (1, 0)),
            (180.0, (-1, 0)),
            (90.0, (0, 1)),
            (45.0, (1, 1)),
        ] {
            let rise = surface_temperature(setup((n, n), (d, d), 0.5, deg, domain), &flux)
                .unwrap()
                .rise;
            let at = |k: i32| {
                let (i, j) = (16 + k * step.0, 16 + k * step.1);
                rise[i as usize * n + j as usize]
            };
            for k in 1..8 {
                assert!(
                    at(-k) > at(k),
                    "{domain:?} {deg} deg, {k} cells: {} vs {}",
                    at(-k),
                    at(k)
                );
            }
            if domain == HeatDomain::Pad {
                assert_eq!(rise.iter().copied().fold(f64::MIN, f64::max), at(0));
            }
        }
    }
}

/// The rise is linear in the flux and scales as `1 / lam` (to rounding);
/// a conductivity of 1e6 W/(m K) leaves a 1e5 W/m^2 spot below 1e-5 K.
#[test]
fn the_rise_scales_with_one_over_the_conductivity() {
    let (nx, ny) = (20, 17);
    let flux = spots(nx, ny);
    for domain in [
        HeatDomain::Pad,
        HeatDomain::Periodic {
            block_length: Some(0.01),
        },
    ] {
        let base = setup((nx, ny), (1e-6, 1e-6), 0.2, 10.0, domain);
        let a = surface_temperature(base, &flux).unwrap();
        let mut doubled = base;
        doubled.conduction.conductivity *= 2.0;
        let b = surface_temperature(doubled, &flux).unwrap();
        for (x, y) in a.rise.iter().zip(&b.rise) {
            assert!(
                (x - 2.0 * y).abs() <= 1e-13 * max_abs(&a.rise),
                "{x} vs {y}"
            );
        }
        let mut high = base;
        high.conduction.conductivity = 1e6;
        let c = surface_temperature(high, &flux).unwrap();
        assert!(max_abs(&c.rise) < 1e-5, "{}", max_abs(&c.rise));
        // Exactly so at conductivities near f64's range, whose rises it
        // holds (before, the periodic cell's `1 / (lam m)` squared `lam m`:
        // NaN at 1e-200 W/(m K), zero at 1e200).
        for lam in [1e-200, 1e-160, 1e160, 1e200] {
            let mut s = base;
            s.conduction.conductivity = lam;
            let t = surface_temperature(s, &flux).unwrap();
            let scale = lam / base.conduction.conductivity;
            for (x, y) in a.rise.iter().zip(&t.rise) {
                assert!(
                    (x - scale * y).abs() <= 1e-13 * max_abs(&a.rise),
                    "{lam}: {x} vs {y}"
                );
            }
        }
    }
}

/// Fast against naive: the pad's rise equals the dense product of its own
/// table of cell integrals, to 1e-12 of the largest, on several shapes
/// (one row and one column included).
#[test]
fn the_fft_embedding_matches_the_dense_product() {
    for (nx, ny, deg) in [(1, 9, 0.0), (7, 1, 30.0), (12, 9, 90.0), (15, 20, 137.0)] {
        let s = setup((nx, ny), (2e-6, 1e-6), 0.4, deg, HeatDomain::Pad);
        let table = s.moving_source_table();
        let mut dense = DenseOperator::new(OffsetTable {
            nx,
            ny,
            values: &table,
        });
        let flux = spots(nx, ny);
        let mut want = vec![0.0; nx * ny];
        dense.apply(&flux, &mut want);
        let got = surface_temperature(s, &flux).unwrap().rise;
        let diff = got
            .iter()
            .zip(&want)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-12 * max_abs(&want), "{nx} x {ny}: {diff:e}");
    }
}

/// At high Peclet numbers each rubber element under a wide patch is heated
/// as a 1-D half-space for the time `L / v` it has spent under it: the
/// rise `L` behind the leading edge tends to `2 q sqrt(kappa L / (pi v)) /
/// lam` (Jaeger's high-speed limit), the whole power conducted into the
/// depth. At Peclet `v a / kappa = 1e4`, on the centre line, halfway and at
/// the trailing edge: the leading corrections (conduction along the
/// sliding direction, `O(kappa / (v L)) = 2e-4` at the centre, and from
/// the sides, exponentially small here) stay within 2e-4 (measured: 5e-5
/// and 3e-5).
#[test]
fn the_high_speed_limit_is_one_dimensional() {
    let (n, side) = (41, 1e-3);
    let d = side / n as f64;
    let speed = 1e4 * KAPPA / side;
    let (lam, q) = (0.25, 1e5);
    let flux = vec![q; n * n];
    let rise = surface_temperature(setup((n, n), (d, d), speed, 0.0, HeatDomain::Pad), &flux)
        .unwrap()
        .rise;
    // Sliding along +x the rubber enters at the leading edge x = a and
    // leaves at x = 0: cell i is (n - i - 1/2) cells behind the leading edge.
    for i in [20, 0] {
        let behind = (n as f64 - i as f64 - 0.5) * d;
        let want = 2.0 * q * (KAPPA * behind / (std::f64::consts::PI * speed)).sqrt() / lam;
        let got = rise[i * n + 20];
        let err = (got / want - 1.0).abs();
        eprintln!("high-speed limit, {behind:.3e} m behind the leading edge: relative difference {err:.2e}");
        assert!(err < 2e-4, "{got} vs {want}");
    }
}

/// Every bad input is refused in one line that names it, before anything
/// is planned; the crate's `Error` carries the same message.
#[test]
fn bad_inputs_are_refused_in_one_line() {
    let good = setup((4, 3), (1e-6, 1e-6), 0.1, 0.0, HeatDomain::Pad);
    let flux = vec![1.0; 12];
    let refuse = |s: HeatSetup, f: &[f64], words: &[&str]| {
        let e = surface_temperature(s, f).unwrap_err();
        let msg = e.to_string();
        assert!(!msg.contains('\n'), "{msg}");
        for w in words {
            assert!(msg.contains(w), "'{msg}' lacks '{w}'");
        }
        let top: viscoslide::Error = e.into();
        assert_eq!(top.to_string(), msg);
    };
    for v in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut s = good;
        s.speed = v;
        refuse(s, &flux, &["speed", "positive"]);
    }
    let mut s = good;
    s.conduction.conductivity = -0.2;
    refuse(s, &flux, &["conductivity", "W/(m K)"]);
    let mut s = good;
    s.conduction.diffusivity = 0.0;
    refuse(s, &flux, &["diffusivity", "m^2/s"]);
    // The grid refuses its own bad cells and sizes, where it is built.
    let e = Grid::new(4, 3, (1e-5, f64::NAN)).unwrap_err().to_string();
    assert!(e.contains("cell size ay = NaN"), "{e}");
    let mut s = good;
    s.direction_rad = f64::INFINITY;
    refuse(s, &flux, &["direction"]);
    let mut s = good;
    s.domain = HeatDomain::Periodic {
        block_length: Some(-1.0),
    };
    refuse(s, &flux, &["block length"]);
    // The block holds the 4 x 3 um cell: at least 4 um long sliding along
    // x, 3 um along y, and the chord through the cell's centre, 3 um /
    // sin 45 deg = 4.243 um, at 45 deg.
    for (deg, cell, text) in [
        (0.0, 4e-6, "4.0000e-6 m"),
        (90.0, 3e-6, "3.0000e-6 m"),
        (45.0, 3e-6 * 2f64.sqrt(), "4.2426e-6 m"),
        (180.0, 4e-6, "4.0000e-6 m"),
    ] {
        let mut s = good;
        s.direction_rad = f64::to_radians(deg);
        s.domain = HeatDomain::Periodic {
            block_length: Some(0.99 * cell),
        };
        refuse(s, &flux, &["shorter than the periodic cell", text]);
        s.domain = HeatDomain::Periodic {
            block_length: Some(1.001 * cell),
        };
        assert!(surface_temperature(s, &flux).is_ok(), "{deg} deg");
    }
    let mut bad = flux.clone();
    bad[7] = f64::NAN;
    refuse(good, &bad, &["heat flux", "NaN", "(2, 1)"]);
    refuse(good, &flux[..5], &["holds 5 values", "4 x 3"]);
    // A finite flux whose rise is beyond f64 (before: an inf/NaN map, and
    // the command failed drawing it, naming its staging directory).
    for domain in [
        HeatDomain::Pad,
        HeatDomain::Periodic {
            block_length: Some(0.01),
        },
    ] {
        let mut s = good;
        s.domain = domain;
        refuse(
            s,
            &[1e308; 12],
            &["temperature rise overflows", "cell (0, 0)"],
        );
    }
    let e = Grid::new(0, 3, (1e-5, 1e-5)).unwrap_err().to_string();
    assert!(e.contains("0 x 3"), "{e}");
    assert!(matches!(
        HeatSolver::new(good).unwrap().surface(&[]),
        Err(HeatError::Empty(_))
    ));
}
