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
