//! Layer coefficients as cell integrals of Eq. 5's Green's function
//! `Theta(r/h) / r` (physics.md section 3, "Finite thickness"), against an
//! independent quadrature in polar coordinates around the target:
//!
//! `M(d) = int_cell Theta(|d - x'|/h) / |d - x'| d2x' = int dphi [T(r_out) - T(r_in)]`,
//! `T(R) = int_0^R Theta(r/h) dr`,
//!
//! with `r_in, r_out` where the ray from `d` enters and leaves the cell
//! (no singularity left: `Theta` is smooth), adaptive Gauss-Kronrod in `phi`
//! between the corner directions and Gauss-Legendre panels for `T`.

use viscoslide::internals::kernel::quad::{adaptive, gauss_legendre_unit};
use viscoslide::internals::kernel::{Axis, SlidingKernel, ThetaRule, ThetaTable};
use viscoslide::material::{CreepSpectrum, Material};
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

const A: f64 = 3.125e-4;

fn sls() -> Material {
    Material::new(
        CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap(),
        0.5,
    )
    .unwrap()
}

/// `T(R) = int_0^R Theta(r/h) dr` by 16-point Gauss-Legendre on panels of
/// at most `h/4`.
fn t_of(theta: &ThetaTable, r: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let h = theta.layer.thickness;
    let (gx, gw) = gauss_legendre_unit(16);
    let n = (r / (0.25 * h)).ceil().max(1.0) as usize;
    let b = r / n as f64;
    let mut s = 0.0;
    for p in 0..n {
        for (t, w) in gx.iter().zip(&gw) {
            s += b * w * theta.at_distance((p as f64 + t) * b);
        }
    }
    s
}

/// `M(d)` for the `a x a` cell centred at the origin, in polar coordinates
/// around `d = (x, y)`.
fn m_polar(theta: &ThetaTable, x: f64, y: f64, a: f64) -> f64 {
    let h = 0.5 * a;
    let chord = |phi: f64| -> f64 {
        let (c, s) = (phi.cos(), phi.sin());
        let mut t0 = f64::NEG_INFINITY;
        let mut t1 = f64::INFINITY;
        for (p, d) in [(x, c), (y, s)] {
            if d.abs() < 1e-300 {
                if p.abs() > h {
                    return 0.0;
                }
            } else {
                let (ta, tb) = ((-h - p) / d, (h - p) / d);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
        }
        if t1 <= t0.max(0.0) {
            return 0.0;
        }
        t_of(theta, t1) - t_of(theta, t0.max(0.0))
    };
    let mut br: Vec<f64> = [(-h, -h), (-h, h), (h, -h), (h, h)]
        .iter()
        .map(|&(cx, cy)| (cy - y).atan2(cx - x))
        .collect();
    br.extend([-std::f64::consts::PI, std::f64::consts::PI]);
    br.sort_by(f64::total_cmp);
    br.dedup();
    adaptive(chord, &br, 1e-16 * a, 1e-14, 4000)
}

/// The resolved cell integral at every thickness: a bonded incompressible
/// layer below a cell otherwise takes the thin-layer law's continuation
/// (`kernel/thin_band.rs`), which these tests do not define.
fn kernel(h_cells: f64, base: LayerBase, speed: f64) -> SlidingKernel {
    SlidingKernel::new(
        &SlidingResponse::new(
            &sls(),
            speed,
            0.0,
            Some(Layer {
                thickness: h_cells * A,
                base,
            }),
        )
        .unwrap(),
    )
    .unwrap()
    .without_local_limit()
}

/// At `v = 0` every creep term is relaxed: `K = (1-nu^2)/(pi E0) M`.
#[test]
fn relaxed_coefficients_are_cell_integrals() {
    let m = sls();
    let pref = m.composite_factor() / std::f64::consts::PI / m.spectrum.relaxed_modulus();
    let mut worst = 0.0f64;
    for base in [LayerBase::Bonded, LayerBase::Frictionless] {
        for h_cells in [0.5, 1.0, 2.0, 3.8, 9.6] {
            let k = kernel(h_cells, base, 0.0);
            let theta = k.theta().unwrap().clone();
            let self_m = m_polar(&theta, 0.0, 0.0, A);
            for (i, j) in [
                (0.0, 0.0),
                (1.0, 0.0),
                (0.5, 0.5),
                (2.0, 1.0),
                (0.3, -0.2),
                (5.0, 3.0),
            ] {
                let want = pref * m_polar(&theta, i * A, j * A, A);
                let got = k.coefficient(i * A, j * A, A, A).total();
                let err = (got - want).abs() / (pref * self_m);
                worst = worst.max(err);
                assert!(
                    err < 1e-9,
                    "{base:?} h = {h_cells} a, ({i}, {j}): {got:e} vs {want:e} ({err:e})"
                );
            }
            // The paper's collocation keeps the half-space's self coefficient.
            let c = k.clone().with_theta_rule(ThetaRule::Collocation);
            let coll = c.coefficient(0.0, 0.0, A, A).total();
            let cell = k.coefficient(0.0, 0.0, A, A).total();
            eprintln!(
                "{base:?} h = {h_cells} a: K(0,0) collocation / cell integral = {:.4}",
                coll / cell
            );
        }
    }
    eprintln!("worst relative error (of K(0,0)): {worst:e}");
}

/// The memory part too: at `v > 0`, `K = pref [M(d)/E_inf + int phi(s) M(d + s e_v) ds]`,
/// with `M` by polar quadrature and the trail by Gauss-Laguerre-like
/// geometric panels.
#[test]
fn sliding_coefficients_are_cell_integrals() {
    let m = sls();
    let term = m.spectrum.terms[0];
    let pref = m.composite_factor() / std::f64::consts::PI;
    let speed = 2.0 * A / term.time; // memory length two cells
    let l = speed * term.time;
    for (base, h_cells) in [(LayerBase::Bonded, 1.0), (LayerBase::Frictionless, 3.8)] {
        let k = kernel(h_cells, base, speed);
        let theta = k.theta().unwrap().clone();
        let self_k = k.coefficient(0.0, 0.0, A, A).total();
        for (i, j) in [(0.0, 0.0), (-2.0, 1.0), (1.0, 0.0)] {
            let (x, y) = (i * A, j * A);
            let mut br = vec![0.0, 0.5 * A - x, -0.5 * A - x, -x, l, 4.0 * l, 16.0 * l];
            br.retain(|b| *b >= 0.0);
            br.push(46.0 * l);
            br.sort_by(f64::total_cmp);
            br.dedup_by(|p, q| (*p - *q).abs() < 1e-18);
            let mem = adaptive(
                |s| term.compliance / l * (-s / l).exp() * m_polar(&theta, x + s, y, A),
                &br,
                1e-14 * A * term.compliance,
                1e-12,
                400,
            );
            let want = pref * (m.spectrum.glassy_compliance() * m_polar(&theta, x, y, A) + mem);
            let got = k.coefficient(x, y, A, A).total();
            let err = (got - want).abs() / self_k;
            eprintln!("{base:?} h = {h_cells} a ({i}, {j}): rel err {err:e}");
            assert!(err < 1e-8, "{got:e} vs {want:e}");
        }
    }
}

/// The tables (row march) agree with the per-offset evaluation, `K` and
/// `D_x`, for layers from half a cell to five cells, sliding along +x and -y.
#[test]
fn layer_tables_match_per_offset() {
    for (h_cells, dir) in [(0.6, 0.0), (1.0, 0.0), (2.0, -90.0f64), (5.0, 0.0)] {
        let layered = kernel(h_cells, LayerBase::Bonded, 3.0 * A / 0.01);
        let r = layered.response();
        let k = SlidingKernel::new(
            &SlidingResponse::new(&sls(), r.speed(), dir.to_radians(), r.layer()).unwrap(),
        )
        .unwrap();
        let n = 12;
        let axis = if dir == 0.0 { Axis::X } else { Axis::Y };
        for d in [None, Some(axis)] {
            let fast = match d {
                None => k.table(&Grid::square(n, n, A).unwrap()).unwrap(),
                Some(ax) => k
                    .derivative_table(&Grid::square(n, n, A).unwrap(), ax)
                    .unwrap(),
            };
            let slow = k.table_per_offset(&Grid::square(n, n, A).unwrap(), d);
            let peak = slow.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let worst = fast
                .values
                .iter()
                .zip(&slow.values)
                .map(|(a, b)| (a - b).abs() / peak)
                .fold(0.0, f64::max);
            eprintln!("h = {h_cells} a, dir {dir}, {d:?}: march vs per-offset {worst:e}");
            assert!(worst < 1e-9, "{worst:e}");
        }
    }
}

/// Off the grid axes the derivative tables go offset by offset; each `Kbar`
/// at a half-cell point is computed once and shared by the two offsets it
/// lies between. The shared table equals the entry-by-entry one (the same
/// `Kbar`, its points rounded differently: 1e-12 of the peak), for `D_x`
/// and `D_y`, square and rectangular cells, odd and even sides, on a layer
/// and on the half-space.
#[test]
fn off_axis_derivative_tables_share_their_half_cell_values() {
    let layered = kernel(1.5, LayerBase::Bonded, 3.0 * A / 0.01);
    let r = layered.response();
    for (layer, deg) in [(r.layer(), 30.0f64), (None, 120.0)] {
        let k = SlidingKernel::new(
            &SlidingResponse::new(&sls(), r.speed(), deg.to_radians(), layer).unwrap(),
        )
        .unwrap();
        for grid in [
            Grid::square(6, 6, A).unwrap(),
            Grid::new(5, 4, (A, 1.3 * A)).unwrap(),
        ] {
            for axis in [Axis::X, Axis::Y] {
                let shared = k.derivative_table(&grid, axis).unwrap();
                let each = k.table_per_offset(&grid, Some(axis));
                let peak = each.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let worst = shared
                    .values
                    .iter()
                    .zip(&each.values)
                    .map(|(a, b)| (a - b).abs() / peak)
                    .fold(0.0, f64::max);
                eprintln!(
                    "{deg} deg, {:?}, {axis:?}: shared vs per entry {worst:e}",
                    grid.size()
                );
                assert!(peak > 0.0 && worst < 1e-12, "{worst:e}");
            }
        }
    }
}

/// Refinement: the displacement at the centre of a fixed physical patch
/// (side `3 h`) under unit pressure, summed over `n x n` cells (`n` odd, so
/// the centre is a cell centre). The cell integrals add up exactly, so every
/// `n` gives the same value to the accuracy of the cell rules (1e-9; rate:
/// exact at every resolution); collocation converges to it, measured 7x,
/// 14x, 23x per 3x refinement (faster than its O(a/h) self-coefficient
/// error, whose weight in the sum falls like `(a / side)^2`).
#[test]
fn refinement_of_a_fixed_layer() {
    let h = 1e-3;
    let side = 3.0 * h;
    let mut coll_err = vec![];
    let mut exact = None;
    for n in [1usize, 3, 9, 27] {
        let a = side / n as f64;
        let k = SlidingKernel::new(
            &SlidingResponse::new(
                &sls(),
                0.0,
                0.0,
                Some(Layer {
                    thickness: h,
                    base: LayerBase::Bonded,
                }),
            )
            .unwrap(),
        )
        .unwrap()
        .without_local_limit();
        let c = k.clone().with_theta_rule(ThetaRule::Collocation);
        let half = (n / 2) as isize;
        let (mut u, mut uc) = (0.0, 0.0);
        for i in -half..=half {
            for j in -half..=half {
                let (x, y) = (i as f64 * a, j as f64 * a);
                u += k.coefficient(x, y, a, a).total();
                uc += c.coefficient(x, y, a, a).total();
            }
        }
        let e = *exact.get_or_insert(u);
        eprintln!("n = {n}: cell integral {u:.12e}, collocation {uc:.6e}");
        assert!((u - e).abs() < 1e-9 * e, "n = {n}: {u} vs {e}");
        coll_err.push((uc - e).abs() / e);
    }
    for w in coll_err.windows(2) {
        let ratio = w[0] / w[1];
        eprintln!("collocation error ratio per 3x refinement: {ratio:.2}");
        assert!(
            ratio > 2.0,
            "collocation error should fall about 3x: {coll_err:?}"
        );
    }
}

/// The friction-stencil coefficient `D_x` on a layer against its definition
/// (physics.md section 5): `D_x = (1/a) [Kbar(x + a/2) - Kbar(x - a/2)]`,
/// `Kbar` the average of `K` across the target's width, here by adaptive
/// quadrature of `K` itself (split at the source's edges, where `K` has
/// kinks), independent of the triangular-weight rule of the kernel.
#[test]
fn layer_derivative_matches_its_definition() {
    for (h_cells, speed) in [(1.0, 0.0), (3.8, 2.0 * A / 0.01), (0.6, 0.3 * A / 0.01)] {
        let k = kernel(h_cells, LayerBase::Bonded, speed);
        let kbar = |x: f64, y: f64| {
            let mut br = vec![y - 0.5 * A, y + 0.5 * A, -0.5 * A, 0.5 * A];
            br.retain(|b| *b >= y - 0.5 * A && *b <= y + 0.5 * A);
            br.sort_by(f64::total_cmp);
            br.dedup();
            adaptive(
                |t| k.coefficient(x, t, A, A).total(),
                &br,
                1e-24,
                1e-13,
                400,
            ) / A
        };
        let d00 = k.derivative(A, 0.0, A, A, Axis::X).abs();
        for (i, j) in [(1.0, 0.0), (0.0, 1.0), (-2.0, 1.0), (1.0, 2.0), (0.0, 0.0)] {
            let (x, y) = (i * A, j * A);
            let want = (kbar(x + 0.5 * A, y) - kbar(x - 0.5 * A, y)) / A;
            let got = k.derivative(x, y, A, A, Axis::X);
            let err = (got - want).abs() / d00;
            eprintln!("h = {h_cells} a, v = {speed:.2e}, ({i}, {j}): D = {got:.6e} vs {want:.6e} ({err:.1e})");
            assert!(err < 1e-8, "{got:e} vs {want:e}");
        }
    }
}
