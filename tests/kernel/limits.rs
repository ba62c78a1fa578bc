//! Limits and symmetries of the steady-sliding kernel (paper Eq. 4;
//! physics.md section 3): relaxed and glassy limits, y-mirror symmetry, the
//! direction of the memory shift (the trailing, -v, neighbour gets the larger
//! coefficient), rotation of the sliding direction, input validation.

use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::{Grid, SlidingResponse};

const A: f64 = 1e-3;
const TAU: f64 = 0.01;

fn sls() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, TAU).unwrap(),
        0.5,
    )
    .unwrap()
}

fn kernel(speed: f64, theta: f64) -> SlidingKernel {
    SlidingKernel::new(&SlidingResponse::new(&sls(), speed, theta, None).unwrap()).unwrap()
}

const OFFSETS: [(f64, f64); 7] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (-1.0, 0.0),
    (2.0, -3.0),
    (-7.0, 1.0),
    (40.0, 40.0),
    (-300.0, 0.0),
];

#[test]
fn slow_and_fast_limits_are_elastic() {
    let m = sls();
    let e0 = m.spectrum.relaxed_modulus();
    let einf = m.spectrum.glassy_modulus;
    // Elastic kernel with modulus E: (1-nu^2)/(pi E) L = K(v=0) scaled.
    let relaxed = kernel(0.0, 0.0);
    let glassy = kernel(f64::INFINITY, 0.0);
    let slow = kernel(1e-11 * A / TAU, 0.0);
    let fast = kernel(1e14 * A / TAU, 0.0);
    let mut worst = 0.0f64;
    for (i, j) in OFFSETS {
        let (dx, dy) = (i * A, j * A);
        let k0 = relaxed.coefficient(dx, dy, A, A);
        let kinf = glassy.coefficient(dx, dy, A, A);
        // Exact limits: v = 0 is E0-elastic, v = inf is E_inf-elastic.
        assert!((k0.total() * e0 - kinf.total() * einf).abs() < 1e-14 * k0.total() * e0);
        assert_eq!(kinf.viscoelastic, 0.0);
        assert_eq!(k0.elastic, kinf.elastic);
        let ks = slow.coefficient(dx, dy, A, A).total();
        let kf = fast.coefficient(dx, dy, A, A).total();
        let es = (ks - k0.total()).abs() / k0.total();
        let ef = (kf - kinf.total()).abs() / kinf.total();
        worst = worst.max(es).max(ef);
        println!("({i},{j}) slow {es:e} fast {ef:e}");
        assert!(es < 1e-9, "v->0 ({i},{j}): {es:e}");
        assert!(ef < 1e-9, "v->inf ({i},{j}): {ef:e}");
    }
    println!("speed limits: max rel deviation {worst:e}");
    // Tables too.
    let t0 = relaxed.table(&Grid::square(6, 6, A).unwrap()).unwrap();
    let ts = slow.table(&Grid::square(6, 6, A).unwrap()).unwrap();
    for (a, b) in t0.values.iter().zip(&ts.values) {
        assert!((a - b).abs() < 1e-9 * a);
    }
}

#[test]
fn mirror_symmetry_in_y() {
    let k = kernel(3.0 * A / TAU, 0.0);
    for (i, j) in OFFSETS {
        let a = k.coefficient(i * A, j * A, A, A).total();
        let b = k.coefficient(i * A, -j * A, A, A).total();
        assert!((a - b).abs() <= 1e-15 * a, "({i},{j}) {a} {b}");
    }
    let t = k.table(&Grid::square(9, 7, A).unwrap()).unwrap();
    for di in -8..=8 {
        for dj in 0..=6 {
            assert_eq!(t.get(di, dj).to_bits(), t.get(di, -dj).to_bits());
        }
    }
}

#[test]
fn trailing_neighbour_gets_the_larger_coefficient() {
    // The material remembers the pressure it met ahead (+v): the displacement
    // behind the load (-x) is larger than in front of it.
    for xi in [0.01, 0.3, 3.0, 30.0] {
        let k = kernel(xi * A / TAU, 0.0);
        for d in [1.0, 2.0, 5.0] {
            let behind = k.coefficient(-d * A, 0.0, A, A).total();
            let ahead = k.coefficient(d * A, 0.0, A, A).total();
            assert!(behind > ahead, "xi={xi} d={d}: {behind} <= {ahead}");
        }
        let t = k.table(&Grid::square(8, 8, A).unwrap()).unwrap();
        assert!(t.get(-1, 0) > t.get(1, 0));
        assert!(t.get(-6, 2) > t.get(6, 2));
        // Friction stencil: sum_i p_i sum_k D_x(i-k) p_k < 0 for a uniform
        // block of pressure (the solid pushes the indenter back).
        let d = k
            .derivative_table(&Grid::square(5, 5, A).unwrap(), Axis::X)
            .unwrap();
        let mut work = 0.0;
        for i in 0..5isize {
            for j in 0..5isize {
                for k2 in 0..5isize {
                    for l in 0..5isize {
                        work += d.get(i - k2, j - l);
                    }
                }
            }
        }
        assert!(work < 0.0, "xi={xi}: {work}");
    }
    // And in the relaxed limit the friction stencil is antisymmetric.
    let k = kernel(0.0, 0.0);
    let d = k
        .derivative_table(&Grid::square(4, 4, A).unwrap(), Axis::X)
        .unwrap();
    for di in -3..=3 {
        for dj in -3..=3 {
            let s = d.get(di, dj) + d.get(-di, dj);
            assert!(s.abs() < 1e-13 * d.get(1, 0).abs(), "({di},{dj}) {s}");
        }
    }
}

#[test]
fn ninety_degrees_is_the_transpose() {
    let v = 3.0 * A / TAU;
    let k0 = kernel(v, 0.0);
    let k90 = kernel(v, std::f64::consts::FRAC_PI_2);
    for (i, j) in OFFSETS {
        let a = k0.coefficient(i * A, j * A, A, A).total();
        let b = k90.coefficient(j * A, i * A, A, A).total();
        assert!((a - b).abs() <= 1e-14 * a, "({i},{j}) {a} {b}");
        let da = k0.derivative(i * A, j * A, A, A, Axis::X);
        let db = k90.derivative(j * A, i * A, A, A, Axis::Y);
        assert!(
            (da - db).abs() <= 1e-12 * da.abs().max(1e-3),
            "D ({i},{j}) {da} {db}"
        );
    }
    let t0 = k0.table(&Grid::square(7, 5, A).unwrap()).unwrap();
    let t90 = k90.table(&Grid::square(5, 7, A).unwrap()).unwrap();
    for di in -6..=6 {
        for dj in -4..=4 {
            let (a, b) = (t0.get(di, dj), t90.get(dj, di));
            assert!((a - b).abs() <= 1e-14 * a, "({di},{dj}) {a} {b}");
        }
    }
    // Derivative tables rotate with the direction.
    let d0 = k0
        .derivative_table(&Grid::square(7, 5, A).unwrap(), Axis::X)
        .unwrap();
    let d90 = k90
        .derivative_table(&Grid::square(5, 7, A).unwrap(), Axis::Y)
        .unwrap();
    let peak = d0.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for di in -6..=6 {
        for dj in -4..=4 {
            let (a, b) = (d0.get(di, dj), d90.get(dj, di));
            assert!((a - b).abs() <= 1e-13 * peak, "D90 ({di},{dj}) {a} {b}");
        }
    }
    let d180 = kernel(v, std::f64::consts::PI)
        .derivative_table(&Grid::square(7, 5, A).unwrap(), Axis::X)
        .unwrap();
    for di in -6..=6 {
        for dj in -4..=4 {
            let (a, b) = (d0.get(di, dj), -d180.get(-di, dj));
            assert!((a - b).abs() <= 1e-13 * peak, "D180 ({di},{dj}) {a} {b}");
        }
    }
    // Sliding along -x mirrors x.
    let k180 = kernel(v, std::f64::consts::PI);
    let t180 = k180.table(&Grid::square(7, 5, A).unwrap()).unwrap();
    for di in -6..=6 {
        for dj in -4..=4 {
            let (a, b) = (t0.get(di, dj), t180.get(-di, dj));
            assert!((a - b).abs() <= 1e-14 * a);
        }
    }
}

#[test]
fn invalid_inputs_are_rejected() {
    let m = sls();
    for speed in [-1.0, f64::NAN] {
        assert!(SlidingResponse::new(&m, speed, 0.0, None).is_err());
    }
    let k = kernel(1.0, 0.0);
    assert!(k.try_coefficient(0.0, 0.0, 0.0, A).is_err());
    assert!(k.try_coefficient(0.0, 0.0, A, f64::NAN).is_err());
    assert!(Grid::square(4, 4, -1.0).is_err());
    assert!(Grid::square(0, 4, A).is_err());
    assert!(k.coefficient(0.0, 0.0, -A, A).total().is_nan());
}

/// The kernel holds at any scale whose squares f64 represents: with the
/// speed scaled with the cell (the same `v tau / a`), `K / a` and `dK/dx`
/// are the same at 1e-150 m and 1e150 m as at 1 mm (the far field's
/// multipoles are formed in units of the cell: powers of the cell itself
/// left f64's range beyond 1e+-19 m, giving NaN). Beyond that range cells
/// are refused in one line naming the cell size, as is a table whose
/// distances' squares overflow within it (huge cells, far offsets), not
/// returned with NaN in it.
#[test]
fn the_kernel_holds_at_every_scale_f64_squares_and_refuses_beyond() {
    let table = |a: f64, derivative: bool| {
        let k = kernel(0.3 * a / A, 0.0);
        let grid = Grid::square(6, 6, a).unwrap();
        if derivative {
            k.derivative_table(&grid, Axis::X)
        } else {
            k.table(&grid)
        }
    };
    for derivative in [false, true] {
        let unit = if derivative { 1.0 } else { A };
        let reference = table(A, derivative).unwrap().values;
        let peak = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for a in [1e-150, 1e-40, 1e-20, 1e20, 1e40, 1e150] {
            let scale = if derivative { 1.0 } else { a };
            let t = table(a, derivative).unwrap().values;
            for (got, want) in t.iter().zip(&reference) {
                let (got, want) = (got / scale, want / unit);
                assert!(
                    (got - want).abs() <= 1e-13 * peak / unit,
                    "a = {a:e}, derivative {derivative}: {got} against {want}"
                );
            }
        }
    }
    let k = kernel(0.01, 0.0);
    for a in [1e-300, 1e-155, 1e155, 1e200] {
        let grid = Grid::square(4, 4, a).unwrap();
        for e in [
            k.table(&grid).unwrap_err().to_string(),
            k.derivative_table(&grid, Axis::X).unwrap_err().to_string(),
            k.check_cells(a, a).unwrap_err().to_string(),
        ] {
            assert!(
                e.contains(&format!("the cell size {a:e} m is beyond the range"))
                    && !e.contains('\n'),
                "{e}"
            );
        }
    }
    // Within the range, a distance of 3e154 m squares beyond f64::MAX.
    let e = k
        .table(&Grid::square(4, 4, 1e154).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the cell size 1e154 m is beyond the range") && e.contains("at offset ("),
        "{e}"
    );
}
