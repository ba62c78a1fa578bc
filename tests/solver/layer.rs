//! A layer of finite thickness (paper Eq. 5) in the contact solve: it is
//! stiffer than the half-space, and the two friction routes still agree.

use crate::common;
use viscoslide::response::{Grid, Layer, LayerBase, SlidingResponse};

use common::*;
use viscoslide::internals::analysis;
use viscoslide::internals::backend::CpuBackend;
use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::internals::operator::{OffsetTable, ToeplitzFft};
use viscoslide::internals::solver::{self, ContactProblem, Control, SolverParams};

#[test]
fn bonded_layer_is_stiffer_and_friction_routes_agree() {
    let m = paper_material();
    let (n, length) = (64, 0.01);
    let a = length / n as f64;
    let z = trig_surface(n, length, 8, 0.8, 0.02, 21);
    let g = gap_of(&z);
    let load = 3e3 * length * length;
    let speed = 1.17e-2 * length / 0.01;
    let mut areas = Vec::new();
    for layer in [
        None,
        Some(Layer {
            thickness: 0.25 * length,
            base: LayerBase::Bonded,
        }),
    ] {
        let kernel =
            SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, layer).unwrap()).unwrap();
        let table = kernel.table(&Grid::square(n, n, a).unwrap()).unwrap();
        let tab = OffsetTable {
            nx: n,
            ny: n,
            values: &table.values,
        };
        let mut be = CpuBackend::new(ToeplitzFft::new(tab));
        let (sol, _) = solver::solve(
            &mut be,
            ContactProblem::new(&g, a * a, tab.get(0, 0), Control::Load(load)),
            &SolverParams::default(),
            None,
            &mut solver::Silent,
        )
        .unwrap();
        let d = kernel
            .derivative_table(&Grid::square(n, n, a).unwrap(), Axis::X)
            .unwrap();
        let mut op = ToeplitzFft::new(OffsetTable {
            nx: n,
            ny: n,
            values: &d.values,
        });
        let fs = analysis::friction_force_stencil(&mut op, &sol.pressure, a * a);
        let fd = analysis::friction::friction_force_dissipation(
            &sol.pressure,
            &Grid::square(n, n, a).unwrap(),
            &SlidingResponse::new(&m, speed, 0.0, layer.as_ref().copied()).unwrap(),
        );
        let frac = sol.contact.iter().filter(|&&c| c > 0.5).count() as f64 / (n * n) as f64;
        let rel = (fs - fd).abs() / fs.abs();
        eprintln!("layer {layer:?}: A/A0 = {frac:.4}, mu = {:.5e}, dissipation {:.5e}, rel diff {rel:.2e}", -fs / load, -fd / load);
        // The coefficients are cell integrals of Eq. 4-5's Green's function,
        // whose Fourier transform is the layer response the Fourier route
        // uses: they agree to the latter's quadrature error (well under 2 %).
        assert!(rel < 0.02, "{rel}");
        areas.push(frac);
    }
    assert!(
        areas[1] < areas[0],
        "a bonded incompressible layer is stiffer: {areas:?}"
    );
}

/// `configs/default.toml`'s pad at 64^2 under 1 MPa on a bonded
/// incompressible layer (contact on 2 cells), solved on either side of the
/// local limit's switch `R h = a/2` (`h = 1.8806e-6` and `1.8844e-6` m, the
/// thicknesses of issue #41): the friction jumped 225 times there (7.3e-4
/// to 0.164: the resolved cell integral above the switch misses the
/// layer's response at the cell centres, tests/kernel/thin_switch.rs).
/// The law below and its grid continuation above differ by at most 0.13 %
/// of the self coefficient (the kernel tests), so friction and contact,
/// which on a few cells move by whole cells, must agree to a few percent:
/// asserted 5 %, measured 0.19 % on the same 2 cells. The periodic
/// formulation (no switch) is printed beside them: 3.6e-3 on 4 cells,
/// against the non-periodic dissipation route's 5.6e-3 and Eq. 9's 3.6e-3
/// (the friction stencil as the work on the cell edges; 7.3e-4 with the
/// centred difference); on 2-4 cells neither is a sharper reference. The
/// upper switch (`h = a`) is printed here (1.02e-3 and 8.6e-4) and
/// asserted against refined solves in tests/solver/thin_step.rs.
#[test]
fn friction_is_continuous_across_the_thin_layer_switches() {
    use viscoslide::problem::Executor;
    let a = 0.01 / 64.0;
    let solve = |h: f64, formulation: &str| {
        let problem = crate::thin_step::bonded_pad(64, h, 1.17e-2, formulation);
        let s = problem.solve(&Executor::Cpu, &mut solver::Silent).unwrap();
        let cells = s.fields.contact.iter().filter(|&&c| c > 0.5).count();
        eprintln!(
            "h = {h:.5e} {formulation}: mu = {:.4e} (dissipation {:.4e}), {cells} cells",
            s.friction_coefficient, s.friction_coefficient_dissipation
        );
        (s.friction_coefficient, cells)
    };
    solve(0.999 * a, "non_periodic");
    solve(1.001 * a, "non_periodic");
    {
        let (lo, hi) = (1.8806e-6, 1.8844e-6);
        let (mu_lo, c_lo) = solve(lo, "non_periodic");
        let (mu_hi, c_hi) = solve(hi, "non_periodic");
        assert!(
            (mu_hi / mu_lo - 1.0).abs() < 0.05,
            "h = {lo:e}: mu {mu_lo:e}, h = {hi:e}: mu {mu_hi:e}"
        );
        assert_eq!(c_lo, c_hi, "contact cells");
        // The periodic formulation beside them (no switch there): on 2-4
        // contact cells it is no sharper reference than either side.
        solve(hi, "periodic");
    }
}
