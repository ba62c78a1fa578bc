//! Friction-stencil tables on elongated rectangular cells (physics.md
//! section 11): cells much narrower across the sliding direction than
//! along it. The closed-form width average of Love's integral loses
//! digits with the square of the aspect ratio, and an adaptive rule asked
//! for more than that spent its whole budget on every offset: a 32^2 pad
//! of 10:1 cells spent 28 s on its `D_x` table, one of 100:1 hours.

use crate::common;
use viscoslide::internals::kernel::{Axis, SlidingKernel};
use viscoslide::response::{Grid, SlidingResponse};

/// The `D_x` table of 10:1 and 30:1 cells (sliding along `+x`, memory
/// length a third of a cell) in well under a second each (asserted 5 s;
/// the first took 13 s before), and equal to the per-offset
/// evaluation at offsets near the source, across many rows and along the
/// trail to 1e-9 (measured against the tables at the old tolerance:
/// 1.5e-11).
#[test]
fn elongated_cells_give_their_friction_stencil_quickly() {
    let m = common::paper_material();
    for (ratio, nx, ny) in [(10.0, 6usize, 24usize), (30.0, 4, 12)] {
        let (ax, ay) = (3.125e-4, 3.125e-4 / ratio);
        let speed = 0.01;
        let k = SlidingKernel::new(&SlidingResponse::new(&m, speed, 0.0, None).unwrap()).unwrap();
        let t = std::time::Instant::now();
        let table = k
            .derivative_table(&Grid::new(nx, ny, (ax, ay)).unwrap(), Axis::X)
            .unwrap();
        let took = t.elapsed().as_secs_f64();
        eprintln!("{ratio}:1 cells, {nx} x {ny}: D_x table in {took:.2} s");
        assert!(took < 5.0, "{ratio}:1 cells: {took} s");
        let scale = table.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let last = ny as isize - 1;
        for (di, dj) in [(0, 0), (1, 0), (-1, 3), (0, last), (2, last / 2), (-3, 1)] {
            let direct = k.derivative(di as f64 * ax, dj as f64 * ay, ax, ay, Axis::X);
            let e = (table.get(di, dj) - direct).abs() / direct.abs().max(1e-6 * scale);
            assert!(
                e < 1e-9,
                "{ratio}:1 ({di}, {dj}): {} vs {direct}",
                table.get(di, dj)
            );
        }
    }
}
