//! Rectangular cells (physics.md section 11): Love's closed form is for an
//! `a_x x a_y` rectangle, the sliding line integral shifts the along
//! coordinate only and the periodic multiplier uses `q = 2 pi (i / L_x,
//! j / L_y)`. Checked here against references written in the test: the
//! coefficient tables against Johnson's Eq. 3.25 and the per-offset
//! evaluation, the FFT operators and the contact solves against dense
//! matrices assembled pairwise, and the full-contact sinusoid of physics.md
//! section 9.2 along either axis.

use crate::common;
use viscoslide::response::{Grid, SlidingResponse};

use std::f64::consts::{PI, TAU};

use faer::Mat;
use num_complex::Complex64;
use viscoslide::config::Formulation;
use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::internals::operator::{GridOperator, PeriodicResponse, SpectralPeriodic};
use viscoslide::internals::solver::{reference, Control, Silent, SolverParams};
use viscoslide::material::Material;
use viscoslide::problem::{Executor, Problem};
use viscoslide::surface::HeightMap;

/// Creep time of the paper material \[s\].
const TAU_C: f64 = 0.01;

fn kernel(m: &Material, speed: f64, direction_rad: f64) -> SlidingKernel {
    SlidingKernel::new(&SlidingResponse::new(m, speed, direction_rad, None).unwrap()).unwrap()
}

/// Johnson, Contact Mechanics, Eq. 3.25 (Love 1929): the integral of `1/r`
/// over the rectangle `[-a, a] x [-b, b]` at `(x, y)`, written with the four
/// logarithms as printed (independent of the library's asinh form).
fn love_johnson(x: f64, y: f64, a: f64, b: f64) -> f64 {
    let r = |u: f64, v: f64| u.hypot(v);
    (x + a) * (((y + b) + r(y + b, x + a)) / ((y - b) + r(y - b, x + a))).ln()
        + (y + b) * (((x + a) + r(y + b, x + a)) / ((x - a) + r(y + b, x - a))).ln()
        + (x - a) * (((y - b) + r(y - b, x - a)) / ((y + b) + r(y + b, x - a))).ln()
        + (y - b) * (((x - a) + r(y - b, x - a)) / ((x + a) + r(y - b, x + a))).ln()
}

/// At `v = 0` the table is the relaxed elastic one:
/// `K = (1 - nu^2) / (pi E0) L(d)`. Against Johnson's form on the offsets
/// within five cells, for cells twice as long along x and 2.5 times as long
/// along y. Tolerance 1e-12 relative: both closed forms are exact and
/// cancel at most like `eps (r / a_min)^2 ~ 1e-13` at these offsets.
#[test]
fn relaxed_table_is_loves_rectangle() {
    let m = common::paper_material();
    let k = kernel(&m, 0.0, 0.0);
    let e0 = m.spectrum.relaxed_modulus();
    let pref = m.composite_factor() / (PI * e0);
    for (ax, ay) in [(2e-4, 1e-4), (1e-4, 2.5e-4)] {
        let (nx, ny) = (9, 7);
        let t = k.table(&Grid::new(nx, ny, (ax, ay)).unwrap()).unwrap();
        assert_eq!((t.cell_size, t.cell_size_y), (ax, ay));
        let mut worst = 0.0f64;
        for di in -5isize..=5 {
            for dj in -5isize..=5 {
                if di.unsigned_abs() >= nx || dj.unsigned_abs() >= ny {
                    continue;
                }
                let want = pref * love_johnson(di as f64 * ax, dj as f64 * ay, 0.5 * ax, 0.5 * ay);
                worst = worst.max((t.get(di, dj) - want).abs() / want);
            }
        }
        println!("{ax:e} x {ay:e}: relaxed table vs Johnson 3.25, max rel {worst:.2e}");
        assert!(worst < 1e-12, "{ax:e} x {ay:e}: {worst:e}");
    }
}

/// The row-marched tables on rectangles equal the per-offset evaluation of
/// `Kernel::coefficient(d, a_x, a_y)` and `Kernel::derivative` at every
/// offset: aspect ratios 2 and 1/2.5, sliding along +x, +y and -x, memory
/// lengths of 0.3, 3 and 30 cells (the march's shared, mid and peaked
/// groups). Tolerance 1e-9 relative, as for square cells
/// (tests/kernel/accuracy.rs: the per-offset path is converged to ~1e-13).
#[test]
fn marched_tables_match_per_offset_on_rectangles() {
    let m = common::paper_material();
    let mut worst = 0.0f64;
    for (ax, ay) in [(2e-4, 1e-4), (1e-4, 2.5e-4)] {
        for (dir, lambda) in [(0.0, 0.3), (0.5 * PI, 3.0), (PI, 30.0), (0.0, 3.0)] {
            // lambda = v tau / a_x.
            let speed = lambda * ax / TAU_C;
            let k = kernel(&m, speed, dir);
            let (nx, ny) = (11, 9);
            let fast = k.table(&Grid::new(nx, ny, (ax, ay)).unwrap()).unwrap();
            let slow = k.table_per_offset(&Grid::new(nx, ny, (ax, ay)).unwrap(), None);
            for di in 1 - nx as isize..nx as isize {
                for dj in 1 - ny as isize..ny as isize {
                    let direct = k
                        .coefficient(di as f64 * ax, dj as f64 * ay, ax, ay)
                        .total();
                    assert_eq!(slow.get(di, dj), direct);
                    let e = (fast.get(di, dj) - direct).abs() / direct.abs();
                    worst = worst.max(e);
                    assert!(
                        e < 1e-9,
                        "{ax:e} x {ay:e} dir {dir} lambda {lambda} ({di},{dj}): {} vs {direct}",
                        fast.get(di, dj)
                    );
                }
            }
            let axis = if dir == 0.5 * PI { Axis::Y } else { Axis::X };
            let fast = k
                .derivative_table(&Grid::new(nx, ny, (ax, ay)).unwrap(), axis)
                .unwrap();
            let scale = fast.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for di in 1 - nx as isize..nx as isize {
                for dj in 1 - ny as isize..ny as isize {
                    let direct = k.derivative(di as f64 * ax, dj as f64 * ay, ax, ay, axis);
                    let e = (fast.get(di, dj) - direct).abs() / direct.abs().max(1e-6 * scale);
                    worst = worst.max(e);
                    assert!(
                        e < 1e-9,
                        "D {ax:e} x {ay:e} dir {dir} lambda {lambda} ({di},{dj}): {} vs {direct}",
                        fast.get(di, dj)
                    );
                }
            }
        }
    }
    println!("rectangular tables: march vs per-offset, max rel {worst:.2e}");
}

/// A smooth band-limited surface on the square `L x L` (integer wave
/// numbers in `2 pi / L` up to `kmax`), evaluated at the centres of an
/// `nx x ny` grid of `L/nx x L/ny` cells: the same continuous surface on
/// any cell shape.
fn smooth_surface(nx: usize, ny: usize, length: f64, kmax: i32, slope: f64, seed: u64) -> Vec<f64> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut modes = Vec::new();
    for kx in -kmax..=kmax {
        for ky in 0..=kmax {
            let k2 = (kx * kx + ky * ky) as f64;
            if (ky == 0 && kx <= 0) || k2 > (kmax * kmax) as f64 {
                continue;
            }
            let amp = k2.powf(-0.9);
            modes.push((kx as f64, ky as f64, amp, rng.random_range(0.0..TAU)));
        }
    }
    let q = TAU / length;
    let s2: f64 = modes
        .iter()
        .map(|m| m.2 * m.2 * q * q * (m.0 * m.0 + m.1 * m.1) / 2.0)
        .sum();
    let scale = slope / s2.sqrt();
    let (ax, ay) = (length / nx as f64, length / ny as f64);
    let mut z = vec![0.0; nx * ny];
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = ((i as f64 + 0.5) * ax, (j as f64 + 0.5) * ay);
            z[i * ny + j] = scale
                * modes
                    .iter()
                    .map(|m| m.2 * (q * (m.0 * x + m.1 * y) + m.3).cos())
                    .sum::<f64>();
        }
    }
    z
}

fn problem(
    m: &Material,
    z: Vec<f64>,
    (nx, ny): (usize, usize),
    length: f64,
    load: f64,
    speed: f64,
) -> Problem {
    let map = HeightMap::with_cells(nx, ny, length / nx as f64, length / ny as f64, z).unwrap();
    Problem::new(m.clone(), map, Control::Load(load), speed).with_solver_params(SolverParams {
        tolerance: 1e-10,
        ..SolverParams::default()
    })
}

fn rel_l2(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

/// Non-periodic formulation on 2:1 and 1:2.5 cells: the solve (coefficient
/// table by the row march, Toeplitz FFT, preconditioned iteration) equals
/// the dense LCP solve (faer LU on the active set) with the matrix assembled
/// pairwise from `Kernel::coefficient(x_s - x_t, a_x, a_y)`, and its Eq. 9
/// friction equals `a_x a_y p . D p` with `D` assembled pairwise from
/// `Kernel::derivative`. Tolerances: pressure 1e-8 relative L2 and friction
/// 1e-7 (both solves are exact up to the iteration's 1e-10 tolerance and
/// the march's 1e-9). The dissipation route differs from Eq. 9 by a few
/// percent on grids this coarse (3.9 % on 8 x 16 with 12 cells in
/// contact); its convergence is checked in tests/grid/rect_cells_refinement.rs.
#[test]
fn non_periodic_solve_matches_dense_pairwise_reference() {
    let m = common::paper_material();
    let length = 0.01;
    for (nx, ny) in [(8usize, 16usize), (20, 8)] {
        let (ax, ay) = (length / nx as f64, length / ny as f64);
        let z = smooth_surface(nx, ny, length, 3, 0.02, 7);
        let g = common::gap_of(&z);
        let load = 3e3 * length * length;
        let speed = 1.17e-2 * length / TAU_C;
        let k = kernel(&m, speed, 0.0);
        let n = nx * ny;
        let pos = |s: usize| ((s / ny) as f64 * ax, (s % ny) as f64 * ay);
        let l = Mat::from_fn(n, n, |s, t| {
            let ((xs, ys), (xt, yt)) = (pos(s), pos(t));
            k.coefficient(xs - xt, ys - yt, ax, ay).total()
        });
        let (p_ref, d_ref) =
            reference::solve_dense(&l, &g, ax * ay, Control::Load(load), 500).unwrap();
        let sol = problem(&m, z, (nx, ny), length, load, speed)
            .solve(&Executor::Cpu, &mut Silent)
            .unwrap();
        let cells = sol.stats.contact_cells;
        assert!(cells > 2 && cells < n / 2, "partial contact: {cells}");
        let e = rel_l2(&sol.fields.pressure, &p_ref);
        assert!(e < 1e-8, "{nx}x{ny}: pressure rel L2 {e:e}");
        assert!((sol.fields.approach - d_ref).abs() <= 1e-8 * d_ref.abs());
        let mut f = 0.0;
        for s in 0..n {
            for t in 0..n {
                let ((xs, ys), (xt, yt)) = (pos(s), pos(t));
                f += p_ref[s] * k.derivative(xs - xt, ys - yt, ax, ay, Axis::X) * p_ref[t];
            }
        }
        let mu_ref = -f * ax * ay / load;
        let mu = sol.friction_coefficient;
        let mu_d = sol.friction_coefficient_dissipation;
        println!(
            "{nx}x{ny} ({ax:.2e} x {ay:.2e} m): {cells} cells, pressure rel L2 {e:.1e}, mu {mu:.8e} vs dense {mu_ref:.8e}, dissipation {mu_d:.6e}"
        );
        assert!((mu - mu_ref).abs() <= 1e-7 * mu_ref, "{mu} vs {mu_ref}");
        assert!(
            (sol.stats.contact_area - cells as f64 * ax * ay).abs() <= 1e-15,
            "contact area counts a_x a_y per cell"
        );
    }
}

/// The periodic multiplier written here from physics.md section 6 with
/// `q = 2 pi (i / L_x, j / L_y)`: `m(q) = 2 (1 - nu^2) J*(-q_x v) / |q|`.
fn multiplier(m: &Material, qx: f64, qy: f64, speed: f64) -> Complex64 {
    let q = qx.hypot(qy);
    if q == 0.0 {
        return Complex64::default();
    }
    m.spectrum.compliance(-qx * speed) * (2.0 * m.composite_factor() / q)
}

/// The periodic operator on odd grids (no Nyquist modes) of 2:1 and 1:2.5
/// cells equals the dense mode sum
/// `L[s, t] = (1/N) sum_q Re[m(q) e^{i q.(x_s - x_t)}]` built here; the
/// periodic solve equals the dense LCP solve with that matrix. Tolerances:
/// operator 1e-12 (round-off), pressure 1e-8 relative L2 (iteration).
#[test]
fn periodic_solve_matches_dense_mode_sum() {
    let m = common::paper_material();
    let length = 0.01;
    for (nx, ny) in [(9usize, 17usize), (21, 9)] {
        let (ax, ay) = (length / nx as f64, length / ny as f64);
        let speed = 1.17e-2 * length / TAU_C;
        let n = nx * ny;
        let mut l = Mat::<f64>::zeros(n, n);
        let signed = |i: usize, n: usize| {
            if i <= n / 2 {
                i as f64
            } else {
                i as f64 - n as f64
            }
        };
        for i in 0..nx {
            for j in 0..ny {
                let (qx, qy) = (TAU * signed(i, nx) / length, TAU * signed(j, ny) / length);
                let mq = multiplier(&m, qx, qy, speed);
                for s in 0..n {
                    for t in 0..n {
                        let dx = ((s / ny) as f64 - (t / ny) as f64) * ax;
                        let dy = ((s % ny) as f64 - (t % ny) as f64) * ay;
                        let ph = Complex64::from_polar(1.0, qx * dx + qy * dy);
                        l[(s, t)] += (mq * ph).re / n as f64;
                    }
                }
            }
        }
        let mut op = SpectralPeriodic::new(
            &Grid::new(nx, ny, (ax, ay)).unwrap(),
            &SlidingResponse::new(&m, speed, 0.0, None).unwrap(),
            PeriodicResponse::Displacement,
        );
        let p: Vec<f64> = (0..n).map(|k| ((k * 37 % 11) as f64) - 4.3).collect();
        let mut u = vec![0.0; n];
        op.apply(&p, &mut u);
        let dense: Vec<f64> = (0..n)
            .map(|s| (0..n).map(|t| l[(s, t)] * p[t]).sum())
            .collect();
        let e = rel_l2(&u, &dense);
        assert!(e < 1e-12, "{nx}x{ny}: operator rel L2 {e:e}");

        let z = smooth_surface(nx, ny, length, 3, 0.02, 5);
        let g = common::gap_of(&z);
        let load = 3e3 * length * length;
        let (p_ref, _) = reference::solve_dense(&l, &g, ax * ay, Control::Load(load), 500).unwrap();
        let sol = problem(&m, z, (nx, ny), length, load, speed)
            .with_formulation(Formulation::Periodic)
            .solve(&Executor::Cpu, &mut Silent)
            .unwrap();
        let e = rel_l2(&sol.fields.pressure, &p_ref);
        println!(
            "periodic {nx}x{ny}: {} cells, pressure rel L2 {e:.1e} against the dense mode sum",
            sol.stats.contact_cells
        );
        assert!(sol.stats.contact_cells > 2 && sol.stats.contact_cells < n / 2);
        assert!(e < 1e-8, "{nx}x{ny}: pressure rel L2 {e:e}");
    }
}

/// physics.md section 9.2 on rectangular cells: a periodic sinusoid
/// `g = h0 (1 - cos k s)` in full contact along the sliding direction,
/// along x on cells 2.5 times longer in y and along y (sliding along +y) on
/// cells twice as long in x, gives
/// `mu = k^2 h0^2 E2(k v) / (4 (1 - nu^2) p0)` by both friction routes.
/// The grid samples the single mode exactly and the multiplier is the
/// continuous one, so only the linear solve errs: 1e-8, as for square cells
/// (tests/grid/periodic_full_contact.rs).
#[test]
fn full_contact_sinusoid_on_rectangular_cells() {
    let m = common::paper_material();
    let length = 0.01;
    let k = TAU / length;
    let h0 = 1e-5;
    let e_inf = m.spectrum.glassy_modulus;
    let p0 = 2.0 * k * h0 * e_inf / (2.0 * m.composite_factor());
    for along_y in [false, true] {
        // 32 cells along the sinusoid; 4 across, of a different side.
        let (nx, ny, lx, ly) = if along_y {
            (4, 32, 4.0 * 2.0 * length / 32.0, length)
        } else {
            (32, 4, length, 4.0 * 2.5 * length / 32.0)
        };
        let (ax, ay) = (lx / nx as f64, ly / ny as f64);
        assert!((ax / ay - if along_y { 2.0 } else { 0.4 }).abs() < 1e-12);
        let z: Vec<f64> = (0..nx * ny)
            .map(|c| {
                let s = if along_y {
                    ((c % ny) as f64 + 0.5) * ay
                } else {
                    ((c / ny) as f64 + 0.5) * ax
                };
                h0 * (k * s).cos()
            })
            .collect();
        for speed in [0.03, 0.3, 3.0] {
            let map = HeightMap::with_cells(nx, ny, ax, ay, z.clone()).unwrap();
            let load = p0 * lx * ly;
            let sol = Problem::new(m.clone(), map, Control::Load(load), speed)
                .with_direction_deg(if along_y { 90.0 } else { 0.0 })
                .with_formulation(Formulation::Periodic)
                .with_solver_params(SolverParams {
                    tolerance: 1e-12,
                    ..SolverParams::default()
                })
                .solve(&Executor::Cpu, &mut Silent)
                .unwrap();
            assert_eq!(sol.stats.contact_cells, nx * ny, "full contact");
            let e2 = m.spectrum.modulus(k * speed).im;
            let exact = k * k * h0 * h0 * e2 / (4.0 * m.composite_factor() * p0);
            for mu in [
                sol.friction_coefficient,
                sol.friction_coefficient_dissipation,
            ] {
                let rel = (mu - exact).abs() / exact;
                println!("sinusoid along {}: v = {speed}: mu {mu:.10e}, exact {exact:.10e}, rel {rel:.1e}", if along_y { "y" } else { "x" });
                assert!(rel < 1e-8, "along_y {along_y} v {speed}: {mu} vs {exact}");
            }
        }
    }
}

/// A `[surface]` file with `length_y` gives rectangular cells (no longer an
/// error); the solve states both sides in `summary.json`, warns beyond an
/// aspect ratio of 4 (summary `warnings`), and the adaptive mesh refuses
/// rectangular cells with a one-line error saying why.
#[test]
fn config_file_with_length_y_solves_on_rectangular_cells() {
    use viscoslide::config;
    let dir = tempfile::tempdir().unwrap();
    let (nx, ny) = (40, 8);
    let z = smooth_surface(nx, ny, 0.01, 3, 0.02, 9);
    viscoslide::surface::save_npy(
        &HeightMap::new(nx, ny, 0.01, z).unwrap(),
        &dir.path().join("scan.npy"),
        viscoslide::surface::NpyPrecision::F64,
    )
    .unwrap();
    let text = |mesh: &str| {
        format!(
            r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface]
file = "scan.npy"
length = 0.01
length_y = 0.01

[loading]
mean_pressure = 3000.0
speed = 0.0117

[solver]
mesh = "{mesh}"
"#
        )
    };
    let path = dir.path().join("c.toml");
    std::fs::write(&path, text("uniform")).unwrap();
    let p = Problem::from_config(&config::load(&path, &[]).unwrap()).unwrap();
    assert_eq!(p.surface.cell(), (0.01 / 40.0, 0.01 / 8.0));
    let s = p.solve(&Executor::Cpu, &mut Silent).unwrap();
    let doc = s.summary();
    assert_eq!(doc["cell_size"].as_f64(), Some(0.01 / 40.0));
    assert_eq!(doc["cell_size_y"].as_f64(), Some(0.01 / 8.0));
    let warnings: Vec<&str> = doc["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .collect();
    assert!(
        warnings.iter().any(|w| w.contains("aspect ratio of 5.00")),
        "{warnings:?}"
    );
    std::fs::write(&path, text("adaptive")).unwrap();
    let e = Problem::from_config(&config::load(&path, &[]).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("needs square cells") && !e.contains('\n'), "{e}");
}
