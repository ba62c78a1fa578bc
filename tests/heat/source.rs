//! The heat source of a solved contact (physics.md section 14): the creep
//! elements' dissipation density on depth layers against the friction
//! power (the energy balance, default and refined layers), a single
//! pressure mode against the closed-form stresses and element rates
//! written out here, `D >= 0`, the surface work flux's exact identity, and
//! what is refused.

use viscoslide::config;
use viscoslide::heat::{Conduction, DepthRule, HeatSource, SourceKind};
use viscoslide::internals::solver::Silent;
use viscoslide::material::{CreepSpectrum, CreepTerm, Material};
use viscoslide::problem::{Executor, Problem, Solution};
use viscoslide::response::{Grid, SlidingResponse};

const RUBBER: Conduction = Conduction {
    conductivity: 0.25,
    diffusivity: 1e-7,
};

const SLS: &str = r#"
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5
"#;

/// Three Maxwell arms, converted to creep elements when read (section 2).
const PRONY: &str = r#"
model = "prony"
relaxed_modulus = 2.0e6
prony = [[3.0e6, 1.0e-3], [4.0e6, 1.0e-2], [2.0e6, 1.0e-1]]
poisson = 0.5
"#;

/// A rough periodic cell, 32^2, partial contact, solved at `speed` m/s
/// along `deg`.
fn solve(material: &str, formulation: &str, deg: f64) -> (Problem, Solution) {
    let text = format!(
        r#"
[material]
{material}

[surface.generate]
n = 32
length = 1e-3
hurst = 0.8
scales = 4
rms_slope = 0.05
seed = 5

[loading]
mean_pressure = 2e4
speed = 1e-3
direction_deg = {deg}

[solver]
tolerance = 1e-10
formulation = "{formulation}"
"#
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(&path, text).unwrap();
    let problem = Problem::from_config(&config::load(&path, &[]).unwrap()).unwrap();
    let solution = problem.solve(&Executor::Cpu, &mut Silent).unwrap();
    (problem, solution)
}

/// `Int D dV = mu F_N v` (the dissipation route, Appendix A3-A4) on a
/// periodic cell, for an SLS and a Prony material along two directions:
/// 1e-3 with the default layers (their depth rule integrates each mode to
/// about 5e-5), 1e-6 with the refined ones (about 5e-9). `D >= 0` on
/// every layer and cell. The surface work flux on the same cells carries
/// the stencil route's `mu F_N v` (the same products summed: 1e-10).
#[test]
fn energy_balance_on_periodic_cells() {
    for (material, deg) in [(SLS, 0.0), (SLS, 35.0), (PRONY, 0.0), (PRONY, 90.0)] {
        let (problem, solution) = solve(material, "periodic", deg);
        assert!(solution.stats.contact_area_fraction < 0.5);
        for (rule, tol) in [(DepthRule::default(), 1e-3), (DepthRule::refined(), 1e-6)] {
            let heat = problem
                .contact_heating(&solution, RUBBER, Some(0.01), SourceKind::Volume, &rule)
                .unwrap();
            let HeatSource::Volume { density, .. } = &heat.source else {
                panic!("a volume source")
            };
            assert!(density.maps().unwrap().iter().all(|d| *d >= 0.0));
            assert!(heat.friction_power_w > 0.0);
            assert!(
                heat.balance().abs() < tol,
                "{deg} deg, {rule:?}: {} vs {} W ({:.3e})",
                heat.heat_power_w,
                heat.friction_power_w,
                heat.balance()
            );
            assert!(heat.effective_rise > 0.0 && heat.temperature.max() > 0.0);
        }
        let surface = problem
            .contact_heating(
                &solution,
                RUBBER,
                Some(0.01),
                SourceKind::Surface,
                &DepthRule::default(),
            )
            .unwrap();
        assert!(surface.balance().abs() < 1e-10, "{:.3e}", surface.balance());
    }
}

/// The surface work flux on a pad: its total is the stencil route's
/// `mu F_N v` (1e-10: the same products, summed in another order); a
/// volume source and a block length are refused there in one line.
#[test]
fn surface_flux_on_a_pad_and_refusals() {
    let (problem, solution) = solve(SLS, "non_periodic", 20.0);
    let rule = DepthRule::default();
    let heat = problem
        .contact_heating(&solution, RUBBER, None, SourceKind::Surface, &rule)
        .unwrap();
    assert!(heat.balance().abs() < 1e-10, "{:.3e}", heat.balance());
    assert!(heat.temperature.max() > 0.0 && heat.effective_rise > 0.0);
    let e = problem
        .contact_heating(&solution, RUBBER, None, SourceKind::Volume, &rule)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("periodic cells only") && !e.contains('\n'),
        "{e}"
    );
    let e = problem
        .contact_heating(&solution, RUBBER, Some(0.01), SourceKind::Surface, &rule)
        .unwrap_err()
        .to_string();
    assert!(e.contains("block length"), "{e}");
}

/// `a . b` of two 3x3 tensors.
fn contract(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> f64 {
    (0..3)
        .map(|i| (0..3).map(|j| a[i][j] * b[i][j]).sum::<f64>())
        .sum()
}

/// One pressure mode `p0 + p1 cos(q.x)` on a periodic cell of rectangular
/// cells, sliding obliquely, two creep elements, `nu = 0.5` and `0.3`:
/// every layer's `D` against the closed form written here, the stress of
/// the mode (Johnson sec. 2.9, rotated into x, y) times each element's
/// rate `i w / (1 + i w tau)` at `w = -v q.e_v`, its deviator and trace
/// formed numerically. The default rule's three Gauss nodes per geometric
/// layer split it into three source layers (`0, 5/18, 13/18, 1` of it),
/// each holding `D` at its node `(1 + xi) / 2`, `xi = -sqrt(3/5), 0,
/// sqrt(3/5)`: the source against the closed form at those depths, to
/// round-off (1e-11 of the largest value), and the split itself to 1e-15
/// of the layer.
#[test]
fn a_single_mode_matches_the_closed_form() {
    let (nx, ny, ax, ay) = (16, 12, 2e-6, 3e-6);
    let (kx, ky) = (2.0, 1.0);
    let (speed, deg) = (0.05f64, 25.0f64);
    let elements = [(1e-7, 2e-5), (4e-8, 3e-4)];
    let spectrum = CreepSpectrum::new(
        1e7,
        elements
            .iter()
            .map(|&(c, t)| CreepTerm {
                compliance: c,
                time: t,
            })
            .collect(),
    )
    .unwrap();
    let grid = Grid::new(nx, ny, (ax, ay)).unwrap().periodic();
    let (lx, ly) = grid.lengths();
    let tau2 = std::f64::consts::TAU;
    let q = (tau2 * kx / lx, tau2 * ky / ly);
    let k = q.0.hypot(q.1);
    let (nxv, nyv) = (q.0 / k, q.1 / k);
    let e = (deg.to_radians().cos(), deg.to_radians().sin());
    let w = -speed * (q.0 * e.0 + q.1 * e.1);
    let (p0, p1) = (5e4, 3e4);
    let pressure: Vec<f64> = (0..nx * ny)
        .map(|n| {
            let (x, y) = ((n / ny) as f64 * ax, (n % ny) as f64 * ay);
            p0 + p1 * (q.0 * x + q.1 * y).cos()
        })
        .collect();
    let rule = DepthRule::default();
    let xi = [-(0.6f64.sqrt()), 0.0, 0.6f64.sqrt()];
    let shares = [0.0, 5.0 / 18.0, 13.0 / 18.0, 1.0];
    for nu in [0.5, 0.3] {
        let material = Material::new(spectrum.clone(), nu).unwrap();
        let response = SlidingResponse::new(&material, speed, deg.to_radians(), None).unwrap();
        let source =
            HeatSource::from_contact(SourceKind::Volume, &pressure, &grid, &response, &rule)
                .unwrap();
        let HeatSource::Volume { layers, density } = source else {
            panic!("a volume source")
        };
        let density = density.maps().unwrap();
        // D at (x, z) in closed form.
        let closed = |x: f64, y: f64, z: f64| -> f64 {
            let t = k * z;
            let f = (-t).exp();
            let phase = q.0 * x + q.1 * y;
            let mut d = 0.0;
            for &(c, tau) in &elements {
                // r = Re[g exp(i phase)] with g = i w / (1 + i w tau).
                let (gr, gi) = {
                    let den = 1.0 + w * w * tau * tau;
                    (w * w * tau / den, w / den)
                };
                let cos = gr * phase.cos() - gi * phase.sin();
                // Re[i g exp(i phase)] for the shear, which is i t f.
                let sin = -gi * phase.cos() - gr * phase.sin();
                let normal = |s: f64| p1 * s * cos;
                let (sxi, szz, seta) = (
                    normal(-(1.0 - t) * f),
                    normal(-(1.0 + t) * f),
                    normal(-2.0 * nu * f),
                );
                let sxz = p1 * t * f * sin;
                let r = [
                    [
                        sxi * nxv * nxv + seta * nyv * nyv,
                        (sxi - seta) * nxv * nyv,
                        sxz * nxv,
                    ],
                    [
                        (sxi - seta) * nxv * nyv,
                        sxi * nyv * nyv + seta * nxv * nxv,
                        sxz * nyv,
                    ],
                    [sxz * nxv, sxz * nyv, szz],
                ];
                let tr = r[0][0] + r[1][1] + r[2][2];
                let mut dev = r;
                for (i, row) in dev.iter_mut().enumerate() {
                    row[i] -= tr / 3.0;
                }
                d += tau
                    * c
                    * ((1.0 + nu) * contract(&dev, &dev) + (1.0 - 2.0 * nu) / 3.0 * tr * tr);
            }
            d
        };
        let n = nx * ny;
        let top = density.iter().copied().fold(0.0, f64::max);
        assert!(top > 0.0);
        let bounds: Vec<(f64, f64)> = layers.iter().collect();
        assert_eq!(bounds.len() % 3, 0);
        for (g, geometric) in bounds.chunks(3).enumerate() {
            let (top_z, bottom_z) = (geometric[0].0, geometric[2].1);
            let h = bottom_z - top_z;
            for (k, &(a, b)) in geometric.iter().enumerate() {
                assert!(
                    (a - (top_z + shares[k] * h)).abs() <= 1e-15 * bottom_z,
                    "{g} {k}"
                );
                assert!(
                    (b - (top_z + shares[k + 1] * h)).abs() <= 1e-15 * bottom_z,
                    "{g} {k}"
                );
                let node = top_z + 0.5 * h * (1.0 + xi[k]);
                let l = 3 * g + k;
                for cell in (0..n).step_by(7) {
                    let (x, y) = ((cell / ny) as f64 * ax, (cell % ny) as f64 * ay);
                    let want = closed(x, y, node);
                    let got = density[l * n + cell];
                    assert!(
                        (got - want).abs() < 1e-11 * top,
                        "nu {nu} layer {l} cell {cell}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// The weighted rise `Theta` converges with the depth rule: each Gauss
/// node's value held on its share of its layer puts the default rule
/// within 5e-3 and the refined one within 1e-3 of a fine rule (ratio
/// `2^(1/4)`, 6 points, the first layer a sixteenth of a cell), with and
/// without the block's background (measured here: 1.6e-3 and 3.7e-3
/// default, 2.1e-4 and 5.0e-4 refined; each layer's average held on the
/// whole layer gave 2.2e-2 and 4.4e-3 with the block).
#[test]
fn the_weighted_rise_converges_with_the_depth_rule() {
    let (problem, solution) = solve(SLS, "periodic", 20.0);
    let fine = DepthRule {
        ratio: 2f64.powf(0.25),
        points: 6,
        first_fraction: 1.0 / 16.0,
        ..DepthRule::default()
    };
    for block in [Some(0.01), None] {
        let rise = |rule: &DepthRule| {
            problem
                .contact_heating(&solution, RUBBER, block, SourceKind::Volume, rule)
                .unwrap()
                .effective_rise
        };
        let reference = rise(&fine);
        let default = rise(&DepthRule::default()) / reference - 1.0;
        let refined = rise(&DepthRule::refined()) / reference - 1.0;
        assert!(default.abs() < 5e-3, "{block:?}: default {default:.3e}");
        assert!(refined.abs() < 1e-3, "{block:?}: refined {refined:.3e}");
    }
}

/// A contact that dissipates nothing (an SLS whose relaxed and glassy
/// moduli are equal: purely elastic) has no heat: zero rise everywhere
/// with a note saying why, as the heated solve's evaluation answers it,
/// not a refusal of "the total heat source = 0".
#[test]
fn an_elastic_contact_has_no_heat() {
    let elastic = SLS.replace("3.3333333333333335e6", "1.0e7");
    let (problem, solution) = solve(&elastic, "periodic", 0.0);
    let heat = problem
        .contact_heating(
            &solution,
            RUBBER,
            Some(0.01),
            SourceKind::Volume,
            &DepthRule::default(),
        )
        .unwrap();
    assert_eq!(heat.heat_power_w, 0.0);
    assert_eq!(heat.effective_rise, 0.0);
    assert!(heat.temperature.rise.iter().all(|r| *r == 0.0));
    assert_eq!(heat.temperature.background, Some(0.0));
    assert_eq!(heat.balance(), 0.0);
    assert!(
        heat.notes.len() == 1 && heat.notes[0].starts_with("the contact dissipates nothing"),
        "{:?}",
        heat.notes
    );
}
