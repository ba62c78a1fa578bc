//! Resampling against analytic surfaces: spline accuracy and its order,
//! Fourier exactness on band-limited maps, identity, orientation, rms, bad
//! input.

use std::f64::consts::PI;

use super::*;

/// `f` sampled at the pixel centres of an `nx x ny` grid of `dx x dy`.
fn sample(nx: usize, ny: usize, dx: f64, dy: f64, f: impl Fn(f64, f64) -> f64) -> Topography {
    let h = (0..nx * ny)
        .map(|k| {
            f(
                (k / ny) as f64 * dx + 0.5 * dx,
                (k % ny) as f64 * dy + 0.5 * dy,
            )
        })
        .collect();
    Topography::new(nx, ny, dx, dy, h, "test").unwrap()
}

/// Largest deviation of `t` from `f` at its pixel centres, shifted by the
/// grid's offset.
fn max_error(t: &Topography, g: &ResampleGrid, f: impl Fn(f64, f64) -> f64) -> f64 {
    (0..t.nx * t.ny)
        .map(|k| {
            let x = g.offset_x + ((k / t.ny) as f64 + 0.5) * t.dx;
            let y = g.offset_y + ((k % t.ny) as f64 + 0.5) * t.dy;
            (t.heights[k] - f(x, y)).abs()
        })
        .fold(0.0, f64::max)
}

/// Smooth, non-periodic and asymmetric in x and y (unit amplitude).
fn smooth(x: f64, y: f64) -> f64 {
    (0.21 * x + 0.4).sin() * (0.09 * y - 0.3).cos() + 0.002 * x * y - 0.01 * y
}

#[test]
fn spline_matches_a_smooth_surface_with_fourth_order_error() {
    // 60 x 24 pixels of 1 x 2.5 (a 60 x 60 map) onto square pixels of 1.25.
    let errors: Vec<f64> = [1.0, 0.5]
        .iter()
        .map(|&s| {
            let n = (60.0 / s) as usize;
            let t = sample(n, (24.0 / s) as usize, s, 2.5 * s, smooth);
            let g = resample_grid(
                &t,
                ResampleTarget::Pixel(1.25 * s, 1.25 * s),
                ResampleMethod::Spline,
            )
            .unwrap();
            assert_eq!((g.nx, g.ny), ((48.0 / s) as usize, (48.0 / s) as usize));
            assert_eq!((g.dx, g.dy), (1.25 * s, 1.25 * s));
            let r = resample(&t, &g, ResampleMethod::Spline).unwrap();
            max_error(&r, &g, smooth)
        })
        .collect();
    // The interpolation error of a cubic spline is at most
    // (5/384) h^4 max|f''''| in the interior, per pass: along x h = 1 and
    // |d^4 f / dx^4| <= 0.21^4, along y h = 2.5 and |d^4 f / dy^4| <= 0.09^4,
    // 6e-5 in all. The not-a-knot end pieces have a larger constant (the
    // measured maximum, 1.8e-4, sits at the edges); five times the interior
    // bound allows for them.
    let interior = 5.0 / 384.0 * (0.21f64.powi(4) + (0.09f64 * 2.5).powi(4));
    assert!(errors[0] < 5.0 * interior, "{errors:?} {interior:e}");
    // Fourth order: halving both pixel sides divides the error by 16 (12
    // allows for the end pieces).
    assert!(errors[0] / errors[1] > 12.0, "{errors:?}");
}

#[test]
fn spline_reproduces_cubics_exactly() {
    // A not-a-knot spline reproduces any cubic; the grid is rectangular and
    // the polynomial asymmetric, so x stays along axis 0.
    let cubic = |x: f64, y: f64| 0.3 * x - 0.05 * x * x * x / 100.0 + 2.0 * y * y / 50.0 - y;
    let t = sample(17, 9, 0.5, 1.5, cubic);
    for target in [
        ResampleTarget::Pixel(0.4, 0.4),
        ResampleTarget::Shape(5, 30),
        ResampleTarget::Pixel(1.1, 0.7),
    ] {
        let g = resample_grid(&t, target, ResampleMethod::Spline).unwrap();
        let r = resample(&t, &g, ResampleMethod::Spline).unwrap();
        // Round-off of values of order 10.
        assert!(max_error(&r, &g, cubic) < 1e-11, "{target:?}");
    }
}

#[test]
fn fourier_is_exact_on_band_limited_periodic_surfaces() {
    // Modes up to 5 along x and 3 along y; both grids resolve them.
    let (lx, ly) = (40.0, 36.0);
    let f = |x: f64, y: f64| {
        let (u, v) = (2.0 * PI * x / lx, 2.0 * PI * y / ly);
        (u + 0.3).cos() + 0.5 * (5.0 * u - 2.0 * v).sin() + 0.25 * (3.0 * v + 1.0).cos()
            - 0.7 * (2.0 * u + v).cos()
    };
    for (nx, ny) in [(40, 12), (41, 13)] {
        let t = sample(nx, ny, lx / nx as f64, ly / ny as f64, f);
        for target in [
            ResampleTarget::Pixel(1.0, 1.0),
            ResampleTarget::Shape(12, 7),
            ResampleTarget::Shape(64, 9),
            ResampleTarget::Shape(11, 8),
        ] {
            let g = resample_grid(&t, target, ResampleMethod::Fourier).unwrap();
            assert_eq!((g.offset_x, g.offset_y), (0.0, 0.0));
            let r = resample(&t, &g, ResampleMethod::Fourier).unwrap();
            // Round-off of FFTs of length <= 64 on values of order 1.
            let e = max_error(&r, &g, f);
            assert!(e < 1e-12, "{nx}x{ny} -> {target:?}: {e:e}");
        }
    }
}

#[test]
fn fourier_keeps_the_period() {
    let t = sample(30, 20, 1.0, 1.5, |x, _| x);
    let g = resample_grid(&t, ResampleTarget::Pixel(0.7, 0.7), ResampleMethod::Fourier).unwrap();
    // round(30 / 0.7) = 43, round(30 / 0.7) = 43.
    assert_eq!((g.nx, g.ny), (43, 43));
    assert!((g.nx as f64 * g.dx - 30.0).abs() < 1e-12);
    assert!((g.ny as f64 * g.dy - 30.0).abs() < 1e-12);
}

#[test]
fn identity_reproduces_the_input() {
    let t = sample(23, 14, 0.8, 1.9, |x, y| (x * 1.7).sin() + (y * y).cos());
    for m in [ResampleMethod::Spline, ResampleMethod::Fourier] {
        let g = resample_grid(&t, ResampleTarget::Pixel(t.dx, t.dy), m).unwrap();
        assert_eq!((g.nx, g.ny), (t.nx, t.ny));
        let r = resample(&t, &g, m).unwrap();
        let e = r
            .heights
            .iter()
            .zip(&t.heights)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // The spline passes through its knots exactly; the FFT round trip
        // costs a few ulps.
        assert!(e < 1e-13, "{m:?}: {e:e}");
        assert_eq!((r.dx, r.dy), (t.dx, t.dy));
    }
}

#[test]
fn rms_height_is_kept_and_x_stays_along_axis_0() {
    // A periodic random surface, band-limited well below the Nyquist
    // wavenumber, on 2:1 pixels, rougher along x than along y.
    let (nx, ny, lx) = (64usize, 32usize, 64.0);
    let mut state = 12345u64;
    let mut rnd = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let modes: Vec<(f64, f64, f64, f64)> = (0..20)
        .map(|_| {
            let kx = (rnd() * 12.0).floor() + 1.0;
            let ky = (rnd() * 4.0).floor() - 2.0;
            (kx, ky, rnd() * 2.0 * PI, 1.0 / kx)
        })
        .collect();
    let f = |x: f64, y: f64| {
        modes
            .iter()
            .map(|&(kx, ky, p, a)| a * (2.0 * PI * (kx * x + ky * y) / lx + p).cos())
            .sum::<f64>()
    };
    let t = sample(nx, ny, 1.0, 2.0, f);
    let rms = |h: &[f64]| {
        let m = h.iter().sum::<f64>() / h.len() as f64;
        (h.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / h.len() as f64).sqrt()
    };
    for m in [ResampleMethod::Spline, ResampleMethod::Fourier] {
        let g = resample_grid(&t, ResampleTarget::Pixel(1.0, 1.0), m).unwrap();
        assert_eq!((g.nx, g.ny), (64, 64));
        let r = resample(&t, &g, m).unwrap();
        // Band-limited: the rms of the samples is the continuous rms on
        // both grids (Parseval), so only the spline's interpolation error
        // (below 1 % at 4+ pixels per wavelength) remains.
        let (a, b) = (rms(&t.heights), rms(&r.heights));
        assert!((b / a - 1.0).abs() < 0.01, "{m:?}: {a} {b}");
        // Orientation: mean square differences along axis 0 (x, rough)
        // exceed those along axis 1 (y) as in the input.
        let d = |h: &[f64], n0: usize, n1: usize, axis0: bool| {
            let mut s = 0.0;
            for i in 0..n0 - 1 {
                for j in 0..n1 - 1 {
                    let o = if axis0 {
                        (i + 1) * n1 + j
                    } else {
                        i * n1 + j + 1
                    };
                    s += (h[o] - h[i * n1 + j]).powi(2);
                }
            }
            s
        };
        assert!(d(&r.heights, 64, 64, true) > 3.0 * d(&r.heights, 64, 64, false));
    }
}

#[test]
fn bad_targets_are_one_line_errors() {
    let t = sample(10, 8, 1.0, 2.0, |x, y| x + y);
    let cases = [
        (ResampleTarget::Pixel(0.0, 1.0), "pixel size along x"),
        (ResampleTarget::Pixel(1.0, -1.0), "pixel size along y"),
        (ResampleTarget::Pixel(f64::NAN, 1.0), "pixel size along x"),
        (ResampleTarget::Pixel(1e-9, 1e-9), "more than 2^28"),
        (ResampleTarget::Pixel(20.0, 1.0), "at least 2"),
        (ResampleTarget::Shape(1, 5), "at least 2"),
        (ResampleTarget::Shape(1 << 15, 1 << 14), "more than 2^28"),
        (ResampleTarget::Pixel(5.0, 16.0 / 5e7), "intermediate"),
    ];
    for (target, want) in cases {
        for m in [ResampleMethod::Spline, ResampleMethod::Fourier] {
            let e = resample_grid(&t, target, m).unwrap_err().to_string();
            assert!(e.contains(want) && !e.contains('\n'), "{target:?}: {e}");
        }
    }
    let mut holes = t.clone();
    holes.heights[3] = f64::NAN;
    let g = resample_grid(&holes, ResampleTarget::Shape(5, 5), ResampleMethod::Spline).unwrap();
    let e = resample(&holes, &g, ResampleMethod::Spline).unwrap_err();
    assert!(e.to_string().contains("missing"), "{e}");
}
