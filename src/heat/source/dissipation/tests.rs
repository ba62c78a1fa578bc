//! The planned dissipation density against the direct evaluation it
//! replaced, and its grid sum against the friction's mode sum.

use super::nyquist::{NyquistParts, Parts};
use super::*;
use crate::heat::source::stress::dissipation_form;
use crate::material::{CreepSpectrum, CreepTerm, Material};

impl Dissipation {
    /// `D` \[W/m^3\] at the grid points (C order, axis 0 = x) at depth
    /// `z` \[m\].
    pub fn density_at(&self, z: f64) -> Result<Vec<f64>, HeatError> {
        self.layer_densities(&[vec![(z, 1.0)]])
    }

    /// [`Dissipation::layer_densities_until`] to the end.
    /// (its band-limited parts brought onto the grid).
    pub fn layer_densities(&self, nodes: &[Vec<(f64, f64)>]) -> Result<Vec<f64>, HeatError> {
        self.layer_densities_until(nodes, &mut || false)?.maps()
    }
}

/// The cells' side along x \[m\] (along y 1.3 times it).
const CELL: f64 = 1e-5;

/// 24 overlapping creep elements, 1e-7 to 1e4 s: their rates combine to
/// fewer than 24 (`rank.rs`).
fn overlapping_elements() -> CreepSpectrum {
    CreepSpectrum::new(
        1e7,
        (0..24)
            .map(|k| CreepTerm {
                compliance: 1e-8 * (1.0 + (k % 5) as f64),
                time: 1e-7 * 10f64.powf(k as f64 / 2.0),
            })
            .collect(),
    )
    .unwrap()
}

/// The dissipation of a rough pressure on a periodic `nx x ny` grid of
/// `CELL x 1.3 CELL` cells, sliding at 0.02 m/s at `deg` rad from +x.
fn rough_plan(
    spectrum: &CreepSpectrum,
    nu: f64,
    (nx, ny): (usize, usize),
    deg: f64,
) -> Dissipation {
    let material = Material::new(spectrum.clone(), nu).unwrap();
    let grid = Grid::new(nx, ny, (CELL, 1.3 * CELL)).unwrap().periodic();
    let response = SlidingResponse::new(&material, 0.02, deg, None).unwrap();
    let p: Vec<f64> = (0..nx * ny)
        .map(|k| ((k * 7919) % 13) as f64 * 1e4 + ((k % 3) as f64) * 3e3)
        .collect();
    Dissipation::new(&p, &grid, &response).unwrap()
}

/// `got` equals `want` to 1e-12 of `want`'s largest value (a density,
/// non-negative), which must be positive; `what` names the case.
fn assert_density_close(got: &[f64], want: &[f64], what: &str) {
    let scale = want.iter().copied().fold(0.0, f64::max);
    let worst = got
        .iter()
        .zip(want)
        .map(|(g, d)| (g - d).abs())
        .fold(0.0, f64::max);
    assert!(
        scale > 0.0 && worst <= 1e-12 * scale,
        "{what}: {worst} of {scale}"
    );
}

/// Every layer of `n` cells of `got` equals `want`'s
/// ([`assert_density_close`]).
fn assert_layers_close(got: &[f64], want: &[f64], n: usize, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (l, (g, w)) in got.chunks(n).zip(want.chunks(n)).enumerate() {
        assert_density_close(g, w, &format!("{what} layer {l}"));
    }
}

/// The direct evaluation the planned one replaced: per element, every
/// mode's parts by the general rule ([`Dissipation::parts`]: the
/// stresses of `mode_stress`, the Nyquist signs), six inverse transforms
/// by `height_fft`, the form of `dissipation_form` at every point.
fn direct_density(plan: &Dissipation, z: f64) -> Vec<f64> {
    let (nx, ny) = (plan.nx, plan.ny);
    let mut density = vec![0.0; nx * ny];
    for rate in &plan.element_rates() {
        let parts: Vec<Parts> = (0..(ny / 2 + 1) * nx)
            .map(|k| plan.parts(k % nx, k / nx, rate, z).unwrap_or_default())
            .collect();
        let fields: Vec<Vec<f64>> = (0..6)
            .map(|c| {
                let spec = parts.iter().map(|p| component(&p.mean, c)).collect();
                height_fft::inverse(spec, nx, ny).unwrap()
            })
            .collect();
        for (n, d) in density.iter_mut().enumerate() {
            let dev = [0, 1, 2, 3, 4].map(|c| fields[c][n]);
            *d += dissipation_form(&dev, fields[5][n], plan.nu);
        }
        let nyquist = NyquistParts {
            row: if nx % 2 == 0 {
                (0..=ny / 2).map(|j| parts[j * nx + nx / 2]).collect()
            } else {
                Vec::new()
            },
            column: if ny % 2 == 0 {
                parts[(ny / 2) * nx..(ny / 2 + 1) * nx].to_vec()
            } else {
                Vec::new()
            },
        };
        plan.add_nyquist(&nyquist, 1.0, &mut density);
    }
    density
}

/// The planned density (one exponential per mode and depth, the
/// stresses component by component, planned transforms, the layers
/// side by side, the elements combined by `rank.rs`) equals the direct
/// evaluation element by element at every point, on even and odd grids,
/// `nu = 0.5` and `0.3`, sliding obliquely and along x, at depths from a
/// hundredth of a cell to a period: 1e-12 of the largest value (the same
/// sums in another order, and the combination's `2 RANK_CUT` per mode:
/// round-off). Three well separated elements, and 24 overlapping ones
/// (two per decade, as a fitted rubber's) that combine into fewer; both
/// sets along x (the separable path) and obliquely.
#[test]
fn planned_density_is_the_direct_one() {
    let three = CreepSpectrum::new(
        1e7,
        vec![
            CreepTerm {
                compliance: 1e-7,
                time: 1e-3,
            },
            CreepTerm {
                compliance: 5e-8,
                time: 3e-2,
            },
            CreepTerm {
                compliance: 2e-8,
                time: 4.0,
            },
        ],
    )
    .unwrap();
    let many = overlapping_elements();
    for (spectrum, deg) in [(&three, 0.4), (&three, 0.0), (&many, 0.4), (&many, 0.0)] {
        for (nx, ny) in [(8, 6), (7, 5), (8, 5), (16, 12)] {
            for nu in [0.5, 0.3] {
                let a = CELL;
                let plan = rough_plan(spectrum, nu, (nx, ny), deg);
                if spectrum.terms.len() == 24 {
                    assert!(plan.rates.len() < 24, "{}", plan.rates.len());
                }
                let depths = [0.01 * a, 0.3 * a, a, 4.0 * a, nx as f64 * a];
                let nodes: Vec<Vec<(f64, f64)>> = depths.iter().map(|&z| vec![(z, 1.0)]).collect();
                let planned = plan.layer_densities(&nodes).unwrap();
                for (l, &z) in depths.iter().enumerate() {
                    let direct = direct_density(&plan, z);
                    let got = &planned[l * nx * ny..(l + 1) * nx * ny];
                    assert_density_close(got, &direct, &format!("{nx}x{ny} nu {nu} z {z}"));
                }
            }
        }
    }
}

/// On grids with Nyquist modes along x, y and both (even sizes) and
/// without (odd), for `nu = 0.5` and `0.3` and an oblique sliding
/// direction, the grid sum of `D` integrated over depth by 64-point
/// Gauss-Legendre on geometric panels equals the closed-form mode sum
/// (discrete Parseval with the Nyquist odd parts): 1e-10, the depth
/// rule's error (panels of ratio 1.5, far below 1e-12) and round-off.
#[test]
fn grid_sum_is_the_mode_sum() {
    let spectrum = CreepSpectrum::new(
        1e7,
        vec![
            CreepTerm {
                compliance: 1e-7,
                time: 1e-3,
            },
            CreepTerm {
                compliance: 5e-8,
                time: 3e-2,
            },
        ],
    )
    .unwrap();
    let (x, w) = crate::gauss::gauss_legendre(64);
    for (nx, ny) in [(8, 6), (7, 5), (8, 5)] {
        for nu in [0.5, 0.3] {
            let a = CELL;
            let plan = rough_plan(&spectrum, nu, (nx, ny), 0.4);
            let mut total = 0.0;
            let (mut lo, mut hi) = (0.0, 1e-3 * a);
            while lo < 40.0 * nx as f64 * a {
                let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
                for (xi, wi) in x.iter().zip(&w) {
                    let d = plan.density_at(c + h * xi).unwrap();
                    assert!(d.iter().all(|v| *v >= 0.0));
                    total += h * wi * d.iter().sum::<f64>();
                }
                lo = hi;
                hi *= 1.5;
            }
            let mean = total / (nx * ny) as f64;
            let exact = plan.exact_power_per_area();
            assert!(
                (mean / exact - 1.0).abs() < 1e-10,
                "{nx}x{ny} nu {nu}: {mean} vs {exact}"
            );
        }
    }
}

/// Nodes deep enough for a coarser grid (`band.rs`) give the direct
/// evaluation on the full grid at every point: 1e-12 of each layer's
/// largest value (the modes left out carry below `3e-20` of their surface
/// amplitude, the padding is exact, the rest is round-off). Even (Nyquist
/// modes along both axes) and odd grids, along x and obliquely, `nu = 0.5`
/// and `0.3`, 24 overlapping elements; layers of one coarse node, of one
/// full node, and mixed (a full and two coarse nodes, Gauss-like weights).
#[test]
fn coarse_nodes_are_the_direct_density() {
    let many = overlapping_elements();
    for (nx, ny) in [(128, 96), (127, 95)] {
        for deg in [0.0, 0.4] {
            for nu in [0.5, 0.3] {
                let a = CELL;
                let lx = nx as f64 * a;
                let plan = rough_plan(&many, nu, (nx, ny), deg);
                let nodes: Vec<Vec<(f64, f64)>> = vec![
                    vec![(0.3 * a, 1.0)],
                    vec![(0.5 * lx, 1.0)],
                    vec![(lx, 1.0)],
                    vec![(2.0 * lx, 1.0)],
                    vec![(3.0 * a, 0.3), (0.6 * lx, 0.5), (1.5 * lx, 0.2)],
                ];
                let (_, plans) = plan.coarse_plans(&nodes, true);
                let coarse: Vec<Vec<bool>> = plans
                    .iter()
                    .map(|l| l.iter().map(Option::is_some).collect())
                    .collect();
                assert_eq!(
                    coarse,
                    [
                        vec![false],
                        vec![true],
                        vec![true],
                        vec![true],
                        vec![false, true, true]
                    ],
                    "{nx}x{ny}"
                );
                let planned = plan.layer_densities(&nodes).unwrap();
                for (l, layer) in nodes.iter().enumerate() {
                    let mut direct = vec![0.0; nx * ny];
                    for &(z, w) in layer {
                        for (d, v) in direct.iter_mut().zip(direct_density(&plan, z)) {
                            *d += w * v;
                        }
                    }
                    let got = &planned[l * nx * ny..(l + 1) * nx * ny];
                    assert_density_close(
                        got,
                        &direct,
                        &format!("{nx}x{ny} deg {deg} nu {nu} layer {l}"),
                    );
                }
            }
        }
    }
}

/// The heat problem takes a deep layer's density as its coarse spectrum
/// placed in the grid's (`LayerDensity::spectra`), never as a map: that
/// spectrum is the forward transform of the layer's map
/// (`LayerDensity::maps`, the coarse parts transformed onto the grid) to
/// 1e-13 of the layer's largest coefficient, and the layers' sums are
/// the maps' to 1e-13 (round-off of one transform pair). Layers of full
/// nodes, of coarse nodes only (which hold no map) and mixed; even and
/// odd grids, along x and obliquely.
#[test]
fn coarse_parts_give_their_maps_spectra() {
    let many = overlapping_elements();
    for (nx, ny) in [(128, 96), (127, 95)] {
        for deg in [0.0, 0.4] {
            let a = CELL;
            let lx = nx as f64 * a;
            let plan = rough_plan(&many, 0.5, (nx, ny), deg);
            let nodes: Vec<Vec<(f64, f64)>> = vec![
                vec![(0.3 * a, 1.0)],
                vec![(0.5 * lx, 1.0)],
                vec![(2.0 * lx, 1.0)],
                vec![(3.0 * a, 0.3), (0.6 * lx, 0.5), (1.5 * lx, 0.2)],
            ];
            let density = plan.layer_densities_until(&nodes, &mut || false).unwrap();
            let n = nx * ny;
            // The two layers of coarse nodes only hold no map: less than
            // three maps in all.
            assert!(
                density.bytes() < 8 * 3 * n,
                "{nx}x{ny}: {}",
                density.bytes()
            );
            let maps = density.maps().unwrap();
            let forward = height_fft::Forward::new(nx, ny);
            let spectra = density.spectra(&forward).unwrap();
            let mut rows = Vec::new();
            for (l, (map, got)) in maps.chunks(n).zip(&spectra).enumerate() {
                let mut want = vec![Complex64::default(); got.len()];
                forward.run(map, &mut rows, &mut want).unwrap();
                let top = want.iter().map(|c| c.norm()).fold(0.0, f64::max);
                assert!(top > 0.0);
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).norm() <= 1e-13 * top,
                        "{nx}x{ny} deg {deg} layer {l}: {g} against {w}"
                    );
                }
                let sum: f64 = map.iter().sum();
                let got_sum = density.layer_sums()[l];
                assert!(
                    (got_sum - sum).abs() <= 1e-13 * sum.abs(),
                    "{nx}x{ny} deg {deg} layer {l}: {got_sum} against {sum}"
                );
            }
        }
    }
}

/// `plan`'s density on the separable path (along y: through
/// `Dissipation::transposed`) equals the general path's at every point of
/// every layer ([`assert_layers_close`]), on three layers of a cell of
/// side `a = CELL` and period `period` along the sliding: one shallow
/// full-grid node, two shallow nodes, and a full-grid node beside deep
/// coarse ones.
fn assert_separable_is_general(plan: &mut Dissipation, period: f64, what: &str) {
    let a = CELL;
    let nodes: Vec<Vec<(f64, f64)>> = vec![
        vec![(0.01 * a, 1.0)],
        vec![(0.3 * a, 0.5), (2.0 * a, 0.5)],
        vec![(a, 0.4), (period, 0.3), (3.0 * period, 0.3)],
    ];
    let separable = plan.layer_densities(&nodes).unwrap();
    plan.separable = false;
    let general = plan.layer_densities(&nodes).unwrap();
    assert_layers_close(&separable, &general, plan.nx * plan.ny, what);
}

/// Sliding along x, the separable path (`separable.rs`) gives the general
/// path's density at every point of every layer: 1e-12 of the largest
/// value (the same sums in another order: round-off). Even and odd sizes
/// along both axes (x-, y- and corner Nyquist modes), `nu = 0.5` and
/// `0.3`, shallow full-grid nodes and deep coarse ones in one layer.
#[test]
fn separable_path_is_the_general_one() {
    let spectrum = overlapping_elements();
    for (nx, ny) in [(16, 12), (15, 11), (16, 11), (15, 12), (64, 48)] {
        for nu in [0.5, 0.3] {
            let a = CELL;
            let mut plan = rough_plan(&spectrum, nu, (nx, ny), 0.0);
            assert!(plan.along_x() && plan.separable);
            let lx = nx as f64 * a;
            assert_separable_is_general(&mut plan, lx, &format!("{nx}x{ny} nu {nu}"));
        }
    }
}

/// Sliding along y, the density is the transposed field's sliding along x
/// (`Dissipation::transposed`, then the separable path) transposed back:
/// the general path's, in this grid's own frame, at every point of every
/// layer, 1e-12 of the largest value. Even and odd sizes along both axes
/// (the Nyquist modes change axes), both senses, `nu = 0.5` and `0.3`,
/// shallow full-grid nodes and deep coarse ones in one layer.
#[test]
fn sliding_along_y_is_the_general_path() {
    let spectrum = overlapping_elements();
    let quarter = std::f64::consts::FRAC_PI_2;
    for (nx, ny) in [(16, 12), (15, 11), (16, 11), (15, 12), (48, 64)] {
        for nu in [0.5, 0.3] {
            for angle in [quarter, -quarter] {
                let a = CELL;
                let mut plan = rough_plan(&spectrum, nu, (nx, ny), angle);
                assert!(plan.along_y() && !plan.along_x() && plan.separable);
                let ly = ny as f64 * 1.3 * a;
                assert_separable_is_general(&mut plan, ly, &format!("{nx}x{ny} nu {nu} {angle}"));
            }
        }
    }
}

/// `stop` is asked before each depth node on the separable path and each
/// multiplier on the general one: asked to stop at its third question,
/// the evaluation gives up there with `Cancelled`; never asked to stop,
/// it is `layer_densities` to the bit.
#[test]
fn a_stop_between_nodes_gives_up_there() {
    let spectrum = overlapping_elements();
    let a = CELL;
    let nodes: Vec<Vec<(f64, f64)>> = vec![
        vec![(0.01 * a, 1.0)],
        vec![(0.3 * a, 0.5), (2.0 * a, 0.5)],
        vec![(a, 1.0)],
    ];
    for separable in [true, false] {
        let mut plan = rough_plan(&spectrum, 0.5, (16, 12), 0.0);
        plan.separable = separable;
        let mut asked = 0;
        let e = plan
            .layer_densities_until(&nodes, &mut || {
                asked += 1;
                asked == 3
            })
            .unwrap_err();
        assert_eq!(e, HeatError::Cancelled, "separable {separable}");
        assert_eq!(asked, 3, "separable {separable}");
        let mut never = 0;
        let whole = plan
            .layer_densities_until(&nodes, &mut || {
                never += 1;
                false
            })
            .unwrap();
        let questions = if separable { 4 } else { plan.rates.len() };
        assert!(questions > 3);
        assert_eq!(never, questions, "separable {separable}");
        assert_eq!(whole.maps().unwrap(), plan.layer_densities(&nodes).unwrap());
    }
}
