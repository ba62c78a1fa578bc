//! A GPU's mixed precision as one iteration (physics.md section 13): the
//! [`GridOperator`] whose working products run on the device in f32 and
//! whose exact products are the host's f64 operator of the same
//! description. Wrapped in [`crate::backend::CpuBackend`] it is the CPU's
//! mixed-precision iteration (f64 vectors on the host, every GMRES
//! restart's residual in f64, [`crate::backend::Backend::refines`]) with
//! the device as its f32 product engine.
//!
//! - [`GridOperator::apply_set`], [`GridOperator::precondition_set`] (the
//!   Krylov products and the preconditioner): the set's values uploaded as
//!   f32, scattered, multiplied and gathered on the device by the kernels
//!   of [`GpuBackend`] (the padded-FFT matvec of paper Eq. 7, the inverse of
//!   the padded circulant or of T. Chan's circulant), and downloaded: one
//!   upload and one download of the short vector per product, the work
//!   between them one submission; the set's positions are uploaded once
//!   per contact set. A periodic cell's preconditioner, the inverse of its
//!   circulant, is a second device operator ([`MixedOperator::with_inverse`]).
//! - [`GridOperator::apply_exact`], [`GridOperator::apply_set_exact`]: the
//!   host's f64 operator (the operator `--backend cpu` builds for the
//!   description), to f64 rounding.
//!
//! Every device round trip is counted and timed in a [`DeviceTraffic`]
//! ledger that the operators of one solve share
//! ([`MixedOperator::recording_into`]): what crosses the bus and how long
//! the host, the device and the readback take, so that a solve says where
//! its products' time goes.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use super::backend::{GpuBackend, GpuIndex, GpuVector};
use crate::backend::Backend;
use crate::operator::{GridOperator, GridWork};

/// The device round trips of mixed-precision products, and where their
/// time went (`summary.json`'s `device_traffic`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct DeviceTraffic {
    /// Products and preconditioner applications on the device (one upload
    /// and one download each).
    pub round_trips: usize,
    /// Uploads of a contact set's positions (once per set).
    pub set_uploads: usize,
    /// Bytes written to the device (values and positions).
    pub bytes_to_device: u64,
    /// Bytes read back from the device.
    pub bytes_from_device: u64,
    /// Host time \[s\] converting the inputs to f32 and writing them (and
    /// the positions) to the device.
    pub to_device_s: f64,
    /// Time \[s\] from the products' submission to their completion on the
    /// device (the uploads' transfer included).
    pub device_s: f64,
    /// Time \[s\] reading the outputs back and converting them to f64.
    pub from_device_s: f64,
}

impl DeviceTraffic {
    /// The traffic since `earlier`, a snapshot of the same ledger.
    pub fn since(&self, earlier: &DeviceTraffic) -> DeviceTraffic {
        DeviceTraffic {
            round_trips: self.round_trips - earlier.round_trips,
            set_uploads: self.set_uploads - earlier.set_uploads,
            bytes_to_device: self.bytes_to_device - earlier.bytes_to_device,
            bytes_from_device: self.bytes_from_device - earlier.bytes_from_device,
            to_device_s: self.to_device_s - earlier.to_device_s,
            device_s: self.device_s - earlier.device_s,
            from_device_s: self.from_device_s - earlier.from_device_s,
        }
    }

    /// Seconds of the round trips in all.
    pub fn total_s(&self) -> f64 {
        self.to_device_s + self.device_s + self.from_device_s
    }
}

/// A ledger shared by the operators of one solve.
pub type TrafficLedger = Arc<Mutex<DeviceTraffic>>;

/// The products of one device operator on host vectors: the set's
/// positions (uploaded when the set changes) and the short input and
/// output vectors on the device.
struct DeviceProducts {
    backend: GpuBackend,
    /// The contact set whose positions are on the device, and its index.
    set: Option<(Vec<usize>, GpuIndex)>,
    /// The short (set) input and output of the products.
    short: Option<(GpuVector, GpuVector)>,
    /// Where the round trips are counted and timed.
    ledger: TrafficLedger,
}

impl DeviceProducts {
    fn new(backend: GpuBackend) -> Self {
        Self {
            backend,
            set: None,
            short: None,
            ledger: TrafficLedger::default(),
        }
    }

    /// Count and time one round trip of `values` values each way:
    /// `to_device`, then the device's work until `done`, then
    /// `from_device`.
    fn record(&self, values: usize, positions: Option<usize>, times: [Instant; 4]) {
        let [start, uploaded, done, read] = times;
        let mut t = self.ledger.lock().unwrap_or_else(|e| e.into_inner());
        t.round_trips += 1;
        t.bytes_to_device += 4 * values as u64;
        t.bytes_from_device += 4 * values as u64;
        if let Some(p) = positions {
            t.set_uploads += 1;
            t.bytes_to_device += 4 * p as u64;
        }
        t.to_device_s += (uploaded - start).as_secs_f64();
        t.device_s += (done - uploaded).as_secs_f64();
        t.from_device_s += (read - done).as_secs_f64();
    }

    /// `out = (P x)[cells]` on the device for `x` on `cells`, `P` the
    /// backend's operator (`precondition` false) or its preconditioner:
    /// one upload of `x`, one submission, one download of `out`.
    fn on_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], precondition: bool) {
        let start = Instant::now();
        let mut positions = None;
        if !matches!(&self.set, Some((host, _)) if same_cells(host, cells)) {
            // The old index back to the pool before the new one is taken.
            self.set = None;
            let index = self.backend.index_from(cells);
            self.set = Some((cells.to_vec(), index));
            positions = Some(cells.len());
        }
        let (_, index) = self.set.as_ref().expect("uploaded above");
        let (mut xs, mut ys) = match self.short.take() {
            Some(v) => v,
            None => (self.backend.zeros(0), self.backend.zeros(0)),
        };
        self.backend.resize(&mut xs, cells.len());
        self.backend.resize(&mut ys, cells.len());
        self.backend.upload(x, &mut xs);
        let uploaded = Instant::now();
        if precondition {
            self.backend.precondition_set(index, &xs, &mut ys);
        } else {
            self.backend.apply_set(index, &xs, &mut ys);
        }
        self.backend.synchronize();
        let done = Instant::now();
        self.backend.download(&ys, out);
        self.short = Some((xs, ys));
        self.record(
            cells.len(),
            positions,
            [start, uploaded, done, Instant::now()],
        );
    }

    /// `y = P x` on the whole grid on the device.
    fn on_grid(&mut self, x: &[f64], y: &mut [f64], precondition: bool) {
        let start = Instant::now();
        let n = x.len();
        let mut xd = self.backend.zeros(n);
        let mut yd = self.backend.zeros(n);
        self.backend.upload(x, &mut xd);
        let uploaded = Instant::now();
        if precondition {
            self.backend.precondition(&xd, &mut yd);
        } else {
            self.backend.apply(&xd, &mut yd);
        }
        self.backend.synchronize();
        let done = Instant::now();
        self.backend.download(&yd, y);
        self.record(n, None, [start, uploaded, done, Instant::now()]);
    }
}

/// Whether two contact sets are the same cells (compared in parallel: a
/// near-full set at 2048^2 is 32 MB, compared before every product).
fn same_cells(a: &[usize], b: &[usize]) -> bool {
    const CHUNK: usize = 1 << 16;
    a.len() == b.len()
        && a.par_chunks(CHUNK)
            .zip(b.par_chunks(CHUNK))
            .all(|(x, y)| x == y)
}

/// Device f32 products beside the host's f64 operator of one grid.
pub struct MixedOperator {
    device: DeviceProducts,
    /// The preconditioner as a device operator of its own (a periodic
    /// cell's inverse circulant, [`MixedOperator::with_inverse`]); `None`:
    /// the device backend's own preconditioner.
    inverse: Option<DeviceProducts>,
    exact: Box<dyn GridOperator>,
    shape: (usize, usize),
}

impl MixedOperator {
    /// The operator of `device` (f32 products of an `nx x ny` grid, its
    /// preconditioner the backend's) and `exact` (the host's f64 operator
    /// of the same grid).
    pub fn new(device: GpuBackend, exact: Box<dyn GridOperator>) -> Self {
        let shape = exact.shape();
        assert_eq!(
            device.grid_len(),
            shape.0 * shape.1,
            "device and host operators of different grids"
        );
        Self {
            device: DeviceProducts::new(device),
            inverse: None,
            exact,
            shape,
        }
    }

    /// The preconditioner `K` applied as the operator of `inverse` (a
    /// device backend of the same grid whose matvec is `K`: the periodic
    /// cell's inverse multiplier as the offset table of its circulant,
    /// [`wrapped_table`], the host's preconditioner in f32).
    pub fn with_inverse(mut self, inverse: GpuBackend) -> Self {
        assert_eq!(inverse.grid_len(), self.shape.0 * self.shape.1);
        let mut inverse = DeviceProducts::new(inverse);
        inverse.ledger = self.device.ledger.clone();
        self.inverse = Some(inverse);
        self
    }

    /// Count and time the device round trips in `ledger` (shared with the
    /// other operators of a solve) instead of a ledger of its own.
    pub fn recording_into(mut self, ledger: TrafficLedger) -> Self {
        if let Some(inverse) = &mut self.inverse {
            inverse.ledger = ledger.clone();
        }
        self.device.ledger = ledger;
        self
    }

    /// The round trips counted so far in this operator's ledger.
    pub fn traffic(&self) -> DeviceTraffic {
        *self.device.ledger.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl GridOperator for MixedOperator {
    fn shape(&self) -> (usize, usize) {
        self.shape
    }

    fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.device.on_grid(x, y, false);
    }

    fn apply_exact(&mut self, x: &[f64], y: &mut [f64]) {
        self.exact.apply_exact(x, y);
    }

    fn epsilon(&self) -> f64 {
        f32::EPSILON as f64
    }

    fn apply_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64], _work: &mut GridWork) {
        self.device.on_set(cells, x, out, false);
    }

    fn apply_set_exact(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        work: &mut GridWork,
    ) {
        self.exact.apply_set_exact(cells, x, out, work);
    }

    fn precondition_set(
        &mut self,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
        _work: &mut GridWork,
    ) {
        match &mut self.inverse {
            Some(inverse) => inverse.on_set(cells, x, out, false),
            None => self.device.on_set(cells, x, out, true),
        }
    }

    fn has_preconditioner(&self) -> bool {
        self.inverse.is_some() || self.device.backend.has_preconditioner()
    }

    fn set_contact_fraction(&mut self, fraction: f64) {
        self.device.backend.set_contact_fraction(fraction);
    }

    fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        match &mut self.inverse {
            Some(inverse) => inverse.on_grid(x, y, false),
            None if self.device.backend.has_preconditioner() => self.device.on_grid(x, y, true),
            None => y.copy_from_slice(x),
        }
    }
}

/// The offset table (layout of [`crate::operator::OffsetTable`]) whose
/// block-Toeplitz operator on an `nx x ny` grid is the circulant `y_i =
/// sum_k c(i - k mod n) x_k` of the periodic response `c` (`c = L e_0`, the
/// response to a unit input at cell 0): `table(di, dj) = c(di mod nx, dj
/// mod ny)`. The device's padded (linear) convolution of this table is
/// then the periodic product, exactly.
pub fn wrapped_table(nx: usize, ny: usize, c: &[f64]) -> Vec<f64> {
    assert_eq!(c.len(), nx * ny, "a response of the grid's cells");
    let w = 2 * ny - 1;
    let mut table = vec![0.0; (2 * nx - 1) * w];
    for (a, row) in table.chunks_exact_mut(w).enumerate() {
        let i = (a + 1) % nx; // (a - (nx - 1)) mod nx
        for (b, t) in row.iter_mut().enumerate() {
            let j = (b + 1) % ny;
            *t = c[i * ny + j];
        }
    }
    table
}

/// The response `f(e_0)` of a grid map to a unit input at cell 0 (`n`
/// cells), for [`wrapped_table`].
pub fn impulse_response(n: usize, f: impl FnOnce(&[f64], &mut [f64])) -> Vec<f64> {
    let mut unit = vec![0.0; n];
    unit[0] = 1.0;
    let mut c = vec![0.0; n];
    f(&unit, &mut c);
    c
}
