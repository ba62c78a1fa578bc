//! A volume source on depth layers (periodic cell) against the Fourier
//! formula of physics.md section 14 on a single mode, its depth integral
//! done here by Gauss-Legendre quadrature; a thin layer at the surface
//! against the surface flux; the block's background of a volume source;
//! what a pad refuses.

use num_complex::Complex64;
use viscoslide::heat::{
    Conduction, DepthLayers, HeatDomain, HeatError, HeatSetup, HeatSolver, HeatSource, LayerDensity,
};
use viscoslide::internals::gauss::gauss_legendre;
use viscoslide::response::Grid;

const LAMBDA: f64 = 0.25;
const KAPPA: f64 = 1e-7;

fn periodic(nx: usize, ny: usize, d: f64, speed: f64, deg: f64, block: Option<f64>) -> HeatSetup {
    HeatSetup {
        grid: Grid::new(nx, ny, (d, d)).unwrap(),
        conduction: Conduction {
            conductivity: LAMBDA,
            diffusivity: KAPPA,
        },
        speed,
        direction_rad: deg.to_radians(),
        domain: HeatDomain::Periodic {
            block_length: block,
        },
    }
}

/// `Int_a^b [exp(-m |z - z'|) + exp(-m (z + z'))] dz'` by 40-point
/// Gauss-Legendre on each side of `z`.
fn depth_integral(m: Complex64, (a, b): (f64, f64), z: f64) -> Complex64 {
    let (x, w) = gauss_legendre(40);
    let mut cuts = vec![a, b];
    if a < z && z < b {
        cuts.insert(1, z);
    }
    let mut sum = Complex64::default();
    for p in cuts.windows(2) {
        let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
        for (xi, wi) in x.iter().zip(&w) {
            let zp = c + h * xi;
            sum += h * wi * ((-m * (z - zp).abs()).exp() + (-m * (z + zp)).exp());
        }
    }
    sum
}

/// Layers with different amplitudes of one mode `cos(k.x + 0.3)`, sliding
/// at 20 degrees, the rise at depths above, inside and below the layers:
/// `theta(k, z) = 1/(2 lam m) Int [...] Q(k, z') dz'` to 1e-9 relative
/// (the quadrature here is exact to ~1e-15 on these smooth pieces).
#[test]
fn layers_of_one_mode_match_the_fourier_formula() {
    let (nx, ny, d) = (40, 24, 2e-6);
    let layers = DepthLayers::new(vec![0.0, 1e-6, 3e-6, 8e-6, 2e-5]).unwrap();
    let amps = [4e10, -1e10, 2.5e10, 5e9];
    let depths = [0.0, 5e-7, 2e-6, 8e-6, 1.3e-5, 4e-5];
    let tau = std::f64::consts::TAU;
    let mut worst: f64 = 0.0;
    for (kx, ky) in [(2, 1), (-5, 3), (0, 7)] {
        let k = (
            tau * kx as f64 / (nx as f64 * d),
            tau * ky as f64 / (ny as f64 * d),
        );
        let phase =
            |i: usize, j: usize| k.0 * (i as f64 + 0.5) * d + k.1 * (j as f64 + 0.5) * d + 0.3;
        let mut source = Vec::new();
        for a in amps {
            for i in 0..nx {
                for j in 0..ny {
                    source.push(a * phase(i, j).cos());
                }
            }
        }
        let density = LayerDensity::from_maps(source, nx, ny);
        for speed in [1e-3, 0.5, 20.0] {
            let t = 20f64.to_radians();
            let ke = k.0 * t.cos() + k.1 * t.sin();
            let m = Complex64::new(k.0 * k.0 + k.1 * k.1, -speed * ke / KAPPA).sqrt();
            let mut solver = HeatSolver::new(periodic(nx, ny, d, speed, 20.0, None)).unwrap();
            let maps = solver.volume(&layers, &density, &depths).unwrap();
            // Measured against the largest rise over all depths: deep below
            // the layers the mode has decayed to ~1e-35 at the highest
            // speed, below the round-off of the transforms (~1e-16 of the
            // largest rise).
            let mut scale: f64 = 0.0;
            let mut diff: f64 = 0.0;
            for (map, &z) in maps.iter().zip(&depths) {
                let amp: Complex64 = layers
                    .iter()
                    .zip(amps)
                    .map(|(l, a)| a * depth_integral(m, l, z))
                    .sum::<Complex64>()
                    / (2.0 * LAMBDA * m);
                for i in 0..nx {
                    for j in 0..ny {
                        let want = (amp * Complex64::from_polar(1.0, phase(i, j))).re;
                        scale = scale.max(want.abs());
                        diff = diff.max((map.rise[i * ny + j] - want).abs());
                    }
                }
            }
            let err = diff / scale;
            assert!(err < 1e-9, "mode ({kx}, {ky}), v {speed}: {err:e}");
            worst = worst.max(err);
        }
    }
    eprintln!("volume layers, single modes: largest relative error {worst:.2e}");
}

/// A layer of thickness `h` at the surface carrying `Q h = q` gives the
/// surface flux's rise times `(1 - exp(-m h)) / (m h) = 1 - m h / 2 +
/// ...`: the difference falls linearly with `h`, below `|m| h / 2` of the
/// rise for the largest `|m|` of the grid, at the surface and at depth.
#[test]
fn a_thin_surface_layer_approaches_the_surface_flux() {
    let (nx, ny, d, speed) = (32, 32, 1e-6, 0.2);
    let mut flux = vec![0.0; nx * ny];
    for (k, q) in flux.iter_mut().enumerate() {
        let (i, j) = (k / ny, k % ny);
        *q = if (10..18).contains(&i) && (12..16).contains(&j) {
            1e6
        } else {
            0.0
        };
    }
    let mut solver = HeatSolver::new(periodic(nx, ny, d, speed, 0.0, None)).unwrap();
    let depths = [0.0, 2e-6];
    let surface = solver.surface_at(&flux, &depths).unwrap();
    // The largest |m| on the grid: |k| at the corner, |m|^2 <= |k|^2 + v |k| / kappa.
    let kmax = std::f64::consts::PI / d * 2f64.sqrt();
    let mmax = (kmax.powi(4) + (speed * kmax / KAPPA).powi(2)).powf(0.25);
    let mut last = f64::INFINITY;
    for h in [1e-8, 1e-9, 1e-10] {
        let layers = DepthLayers::new(vec![0.0, h]).unwrap();
        let source = LayerDensity::from_maps(flux.iter().map(|q| q / h).collect(), nx, ny);
        let vol = solver.volume(&layers, &source, &depths).unwrap();
        let mut err: f64 = 0.0;
        for (v, s) in vol.iter().zip(&surface) {
            let scale = s.rise.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            for (a, b) in v.rise.iter().zip(&s.rise) {
                err = err.max((a - b).abs() / scale);
            }
        }
        eprintln!(
            "thin layer h = {h:e}: relative difference {err:.2e} (|m|max h / 2 = {:.2e})",
            0.5 * mmax * h
        );
        assert!(err <= 0.5 * mmax * h, "h {h}: {err}");
        assert!(err < 0.2 * last, "h {h}: {err} after {last}");
        last = err;
    }
}

/// The background of a volume source: a thin surface layer gives the
/// surface flux's `(4/3) qbar sqrt(kappa t_c / pi) / lam` (to `O(h /
/// sqrt(kappa t_c))`); a deeper source warms the surface less.
#[test]
fn the_background_of_a_volume_source() {
    let (nx, ny, d, speed, block) = (8, 8, 1e-6, 0.1, 0.02);
    let conduction = Conduction {
        conductivity: LAMBDA,
        diffusivity: KAPPA,
    };
    let tc = block / speed;
    let reach = (KAPPA * tc).sqrt();
    let mut solver = HeatSolver::new(periodic(nx, ny, d, speed, 0.0, Some(block))).unwrap();
    let qbar = 2e4;
    let h = 1e-4 * reach;
    let thin = DepthLayers::new(vec![0.0, h]).unwrap();
    let t = solver
        .volume(
            &thin,
            &LayerDensity::from_maps(vec![qbar / h; nx * ny], nx, ny),
            &[0.0],
        )
        .unwrap();
    let want = conduction.surface_background(qbar, tc);
    let got = t[0].background.unwrap();
    assert!((got / want - 1.0).abs() < 2e-4, "{got} vs {want}");
    assert!((t[0].mean() / want - 1.0).abs() < 2e-4);
    let deep = DepthLayers::new(vec![0.0, 0.5 * reach, reach]).unwrap();
    let mut source = vec![0.0; nx * ny];
    source.extend(vec![qbar / (0.5 * reach); nx * ny]);
    let t = solver
        .volume(
            &deep,
            &LayerDensity::from_maps(source, nx, ny),
            &[0.0, reach],
        )
        .unwrap();
    let (top, below) = (t[0].background.unwrap(), t[1].background.unwrap());
    assert!(
        top < want && below < want && top > 0.0 && below > 0.0,
        "{top} {below} {want}"
    );
}

/// A pad solves surface fluxes at its surface only: a volume source or a
/// depth below it is refused in one line.
#[test]
fn a_pad_refuses_volume_sources_and_depths() {
    let mut s = periodic(4, 4, 1e-6, 0.1, 0.0, None);
    s.domain = HeatDomain::Pad;
    let mut solver = HeatSolver::new(s).unwrap();
    let layers = DepthLayers::uniform(1e-5, 2).unwrap();
    let e = solver
        .volume(
            &layers,
            &LayerDensity::from_maps(vec![1.0; 32], 4, 4),
            &[0.0],
        )
        .unwrap_err();
    assert!(matches!(e, HeatError::Unsupported(_)), "{e}");
    let e = solver.surface_at(&[1.0; 16], &[0.0, 1e-6]).unwrap_err();
    assert!(matches!(e, HeatError::Unsupported(_)), "{e}");
    let at0 = solver.surface_at(&[1.0; 16], &[0.0]).unwrap();
    assert_eq!(at0[0], solver.surface(&[1.0; 16]).unwrap());
    assert!(DepthLayers::new(vec![1e-6, 2e-6]).is_err());
    assert!(DepthLayers::new(vec![0.0, 2e-6, 1e-6]).is_err());
    assert!(matches!(
        solver.surface_at(&[1.0; 16], &[-1e-6]),
        Err(HeatError::Depth(_))
    ));
}

/// `HeatSolver::under` sums `Int theta Q dV` mode by mode (one sweep down
/// and one up the layers per mode, no depth maps); it must equal the sum
/// over the depth maps of `HeatSolver::volume` at the layers' middles
/// weighted by the layers' sources, and its surface map the surface map:
/// on even and odd grids (Nyquist modes averaged over their signs),
/// sliding at 0 and 35 degrees, from slow to fast (Peclet numbers of a
/// cell 1e-2 to 2e2), with and without the block's background, on
/// geometric layers reaching far below the period (modes decayed to
/// underflow). 1e-12 relative: the same closed forms summed in another
/// order (round-off of the transforms, ~1e-15).
#[test]
fn the_weighted_rise_is_the_depth_maps_sum() {
    let d = 1e-6;
    let mut bounds = vec![0.0, d / 8.0];
    while *bounds.last().unwrap() < 80.0 * d {
        bounds.push(2.0 * bounds.last().unwrap());
    }
    let layers = DepthLayers::new(bounds).unwrap();
    let middles: Vec<f64> = layers.iter().map(|(a, b)| 0.5 * (a + b)).collect();
    for (nx, ny) in [(16, 12), (15, 9), (20, 7)] {
        let n = nx * ny;
        // A positive source, rough in x, y and depth.
        let source: Vec<f64> = (0..layers.count() * n)
            .map(|k| 1e9 * (1.0 + ((k * 7919) % 17) as f64 / 4.0) / (1.0 + (k / n) as f64))
            .collect();
        for (speed, deg, block) in [
            (1e-3, 0.0, None),
            (0.3, 35.0, Some(1e-3)),
            (20.0, 35.0, None),
            (20.0, 0.0, Some(1e-2)),
        ] {
            let mut solver = HeatSolver::new(periodic(nx, ny, d, speed, deg, block)).unwrap();
            let density = LayerDensity::from_maps(source.clone(), nx, ny);
            let volume = HeatSource::Volume {
                layers: layers.clone(),
                density: density.clone(),
            };
            let (surface, theta) = solver.under(&volume).unwrap();
            let mut depths = vec![0.0];
            depths.extend(&middles);
            let maps = solver.volume(&layers, &density, &depths).unwrap();
            let (mut weighted, mut total) = (0.0, 0.0);
            for (l, (a, b)) in layers.iter().enumerate() {
                let q = &source[l * n..(l + 1) * n];
                total += (b - a) * q.iter().sum::<f64>();
                weighted += (b - a)
                    * maps[l + 1]
                        .rise
                        .iter()
                        .zip(q)
                        .map(|(r, q)| r * q)
                        .sum::<f64>();
            }
            let want = weighted / total;
            assert!(
                (theta / want - 1.0).abs() < 1e-12,
                "{nx}x{ny} v {speed} {deg} deg: {theta} vs {want}"
            );
            let scale = maps[0].rise.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let worst = surface
                .rise
                .iter()
                .zip(&maps[0].rise)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst < 1e-12 * scale,
                "{nx}x{ny} v {speed}: map {worst} of {scale}"
            );
            assert_eq!(surface.background, maps[0].background);
        }
    }
}

/// A volume source whose rise, or its source-weighted mean, leaves f64
/// (a conductivity near zero, or a source near f64's range) is refused in
/// one line naming the conductivity, by `under` (the heated solve's and
/// `heat --from-run`'s route) and `volume` alike, as a surface flux is:
/// never an infinite or NaN rise handed on (before: a NaN effective
/// temperature, refused as a `[loading] temperature` outside the WLF
/// range, and `heat --from-run` failing to draw its figure).
#[test]
fn a_volume_source_whose_rise_leaves_f64_is_refused() {
    let layers = DepthLayers::uniform(4e-6, 3).unwrap();
    let (nx, ny) = (8, 6);
    let source = |q: f64| -> Vec<f64> {
        (0..layers.count() * nx * ny)
            .map(|k| q * (1.0 + (k % 5) as f64))
            .collect()
    };
    // The rise itself beyond f64 (about 1e309 K), with and without the
    // block's background; then rises of 1e288 K whose weighted sum
    // `Int theta Q dV` leaves f64 (`under` only: the maps are finite).
    for (q, conductivity, block, maps) in [
        (1e299, 1e-20, None, true),
        (1e299, 1e-20, Some(1e-3), true),
        (1e299, 1.0, None, false),
    ] {
        let density = LayerDensity::from_maps(source(q), nx, ny);
        let mut s = periodic(nx, ny, 1e-6, 0.1, 30.0, block);
        s.conduction.conductivity = conductivity;
        let mut solver = HeatSolver::new(s).unwrap();
        let volume = HeatSource::Volume {
            layers: layers.clone(),
            density: density.clone(),
        };
        let mut errors = vec![solver.under(&volume).map(|_| ()).unwrap_err()];
        let at_depths = solver.volume(&layers, &density, &[0.0, 5e-6]);
        if maps {
            errors.push(at_depths.map(|_| ()).unwrap_err());
        } else {
            assert!(at_depths
                .unwrap()
                .iter()
                .all(|t| t.rise.iter().all(|r| r.is_finite())));
        }
        for e in errors {
            let text = e.to_string();
            assert!(
                text.contains("conductivity") && text.contains("beyond the range of f64"),
                "{q} {conductivity} {block:?}: {text}"
            );
            assert!(!text.contains('\n'), "{text}");
        }
    }
}

/// A volume source's rise scales as `1 / lam` exactly, at conductivities
/// near f64's range too (its modes' `1 / (2 lam m)` once squared `lam m`:
/// NaN at 1e-200 W/(m K), zero at 1e200), at the surface, at depth and
/// source-weighted, with and without the block's background.
#[test]
fn a_volume_sources_rise_scales_as_one_over_the_conductivity() {
    let layers = DepthLayers::new(vec![0.0, 1e-6, 3e-6, 8e-6]).unwrap();
    let (nx, ny) = (10, 7);
    let density: Vec<f64> = (0..layers.count() * nx * ny)
        .map(|k| 1e9 * (1.0 + ((k * 7919) % 13) as f64))
        .collect();
    let depths = [0.0, 2e-6, 5e-6];
    for block in [None, Some(1e-3)] {
        let base = periodic(nx, ny, 1e-6, 0.05, 25.0, block);
        let rise = |lam: f64| {
            let mut s = base;
            s.conduction.conductivity = lam;
            let mut solver = HeatSolver::new(s).unwrap();
            let density = LayerDensity::from_maps(density.clone(), nx, ny);
            let volume = HeatSource::Volume {
                layers: layers.clone(),
                density: density.clone(),
            };
            let (_, theta) = solver.under(&volume).unwrap();
            let maps = solver.volume(&layers, &density, &depths).unwrap();
            (theta, maps)
        };
        let (theta, maps) = rise(LAMBDA);
        for lam in [1e-200, 1e200] {
            let scale = lam / LAMBDA;
            let (t, m) = rise(lam);
            assert!(
                (scale * t / theta - 1.0).abs() < 1e-13,
                "{lam}: {t} vs {theta}"
            );
            for (a, b) in maps.iter().zip(&m) {
                let top = a.rise.iter().fold(0.0f64, |x, v| x.max(v.abs()));
                for (x, y) in a.rise.iter().zip(&b.rise) {
                    assert!((x - scale * y).abs() <= 1e-13 * top, "{lam}: {x} vs {y}");
                }
            }
        }
    }
}
