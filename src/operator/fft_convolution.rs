//! The 2-D real-FFT convolution both FFT operators are built on: an
//! `nx x ny` block, embedded in an `mx x my` transform (zero-padded when
//! larger: [`super::ToeplitzFft`]; the same size: [`super::SpectralPeriodic`]),
//! multiplied mode by mode by a fixed spectrum.
//!
//! Layout: row r2c transforms of the block's `nx` rows (`my / 2 + 1` bins
//! per row) into the spectrum buffer; then, a few columns at a time, complex
//! column FFTs of length `mx` (the padding rows are zero and never stored),
//! the pointwise product and the inverse column FFTs, written back in place;
//! then c2r of the `nx` rows. The only full-size buffer is the block's
//! spectrum (`nx (my / 2 + 1)` complex values); rows and column blocks are
//! transformed in small per-task buffers. Plans, the multiplier and every
//! buffer are built once; `apply` allocates nothing and runs its transforms
//! with rayon.
//!
//! Precision (physics.md section 13): the multipliers, the transforms and
//! the spectrum are held in the engine's [`Real`] type, f64 or f32; inputs
//! and outputs are f64 either way. An f32 engine halves the bytes stored
//! and moved; its [`SpectralEngine::apply_exact`] repeats the convolution
//! with f64 transforms (in the same buffer, which is sized for f64) and the
//! f32 multiplier, for the residuals of iterative refinement.
//! (The one-shot transforms of height maps are the surface layer's,
//! `surface/height_fft.rs`.)

use std::sync::Arc;

use num_complex::{Complex, Complex64};
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};

use super::field::{set_fields, Field, FieldMut};
pub use super::real::Real;
use super::real_rows::RealRows;

/// Bytes of the run of bins that one task reads from (and writes back to)
/// each spectrum row in the column pass: 8 f64 or 16 f32 columns
/// transformed together. The row-to-column copies are bound by the number
/// of row visits, not by the bytes, so an f32 pass visits each row half as
/// often as an f64 one.
const COLUMN_BLOCK_BYTES: usize = 128;

/// Padding between the columns of a task's column block \[bytes\]. With
/// columns exactly `mx` values apart (a power of two), the copy into the
/// block writes every column at the same cache set and 16 f32 columns
/// overflow its ways; one cache line apart they spread (f32 products at
/// 2048^2 went from 28 to 25 ms, f64 ones were unchanged: BENCHMARKS.md).
const COLUMN_PAD_BYTES: usize = 64;

/// Columns in one block, and the distance between them, in values of `U`.
fn column_layout<U: Real>(mx: usize) -> (usize, usize) {
    let complex = 2 * U::BYTES;
    (
        COLUMN_BLOCK_BYTES / complex,
        mx + COLUMN_PAD_BYTES / complex,
    )
}

/// Complex f64 values of a per-task column block that holds either
/// precision's layout.
fn column_block_len(mx: usize) -> usize {
    let bytes = |(width, stride): (usize, usize), complex: usize| width * stride * complex;
    let most = bytes(column_layout::<f64>(mx), 16).max(bytes(column_layout::<f32>(mx), 8));
    most.div_ceil(16)
}

/// The four transforms of one precision.
struct Plans<U: Real> {
    rows: RealRows<U>,
    fwd: Arc<dyn Fft<U>>,
    inv: Arc<dyn Fft<U>>,
}

impl<U: Real> Plans<U> {
    fn new(mx: usize, my: usize) -> Self {
        let mut cp = FftPlanner::<U>::new();
        Self {
            rows: RealRows::new(my),
            fwd: cp.plan_fft_forward(mx),
            inv: cp.plan_fft_inverse(mx),
        }
    }

    fn scratch_len(&self) -> usize {
        self.rows
            .scratch_len()
            .max(self.fwd.get_inplace_scratch_len())
            .max(self.inv.get_inplace_scratch_len())
            .max(1)
    }
}

/// Per-task work space, sized for f64 (an f32 pass uses the front half).
struct Scratch {
    fft: Vec<Complex64>,
    row: Vec<f64>,
    columns: Vec<Complex64>,
}

/// A raw view of the spectrum buffer for tasks that write disjoint columns.
#[derive(Clone, Copy)]
struct Columns<U>(*mut Complex<U>);
// SAFETY: each task reads and writes only its own columns.
unsafe impl<U> Send for Columns<U> {}
unsafe impl<U> Sync for Columns<U> {}

impl<U> Columns<U> {
    /// `width` values from `offset`.
    ///
    /// # Safety
    /// In bounds, and no other task touches them while the slice lives.
    #[allow(clippy::mut_from_ref)]
    unsafe fn run(&self, offset: usize, width: usize) -> &mut [Complex<U>] {
        std::slice::from_raw_parts_mut(self.0.add(offset), width)
    }
}

/// Which of a [`SpectralEngine`]'s products.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Product {
    /// The multiplier, transforms in the engine's precision.
    Working,
    /// The inverse multiplier ([`SpectralEngine::set_inverse_multiplier`]).
    Inverse,
    /// The multiplier, transforms in f64 ([`SpectralEngine::with_exact`]).
    Exact,
}

/// `y = F^-1 [m F [x padded]]` restricted to the input block, the
/// transforms in precision `T`.
pub(crate) struct SpectralEngine<T: Real = f64> {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    /// `my / 2 + 1` complex bins per row after the real transform.
    myh: usize,
    plans: Plans<T>,
    /// f64 transforms for [`SpectralEngine::apply_exact`] (f32 engines).
    exact: Option<Plans<f64>>,
    /// Multiplier, column-major (`myh` columns of length `mx`), scaled by
    /// `1 / (mx my)` (the unnormalised inverse transforms).
    multiplier_t: Vec<Complex<T>>,
    /// Optional second multiplier with the same layout and scaling:
    /// the approximate inverse applied by [`SpectralEngine::apply_inverse`].
    inverse_t: Option<Vec<Complex<T>>>,
    /// The block's spectrum, `nx` rows of `myh` bins, sized for f64.
    spec: Vec<Complex64>,
    pool: Vec<Scratch>,
}

/// The first `len` values of `buf` viewed as `Complex<U>` (`buf` holds at
/// least `len` of them).
fn view<U: Real>(buf: &mut [Complex64], len: usize) -> &mut [Complex<U>] {
    let all: &mut [Complex<U>] = bytemuck::cast_slice_mut(buf);
    &mut all[..len]
}

/// A whole per-task FFT scratch viewed as `Complex<U>`.
fn scratch_of<U: Real>(buf: &mut [Complex64]) -> &mut [Complex<U>] {
    bytemuck::cast_slice_mut(buf)
}

/// The first `len` reals of `buf` viewed as `U`.
fn view_real<U: Real>(buf: &mut [f64], len: usize) -> &mut [U] {
    let all: &mut [U] = bytemuck::cast_slice_mut(buf);
    &mut all[..len]
}

impl<T: Real> SpectralEngine<T> {
    /// Plans and buffers for an `nx x ny` block in an `mx x my` transform;
    /// the multiplier starts at zero ([`Self::set_multiplier`]).
    pub(crate) fn new(nx: usize, ny: usize, mx: usize, my: usize) -> Self {
        assert!(nx > 0 && ny > 0, "grid must be non-empty");
        assert!(mx >= nx && my >= ny, "the transform must hold the block");
        let myh = my / 2 + 1;
        let plans = Plans::<T>::new(mx, my);
        let mut engine = Self {
            nx,
            ny,
            mx,
            my,
            myh,
            plans,
            exact: None,
            multiplier_t: vec![Complex::<T>::default(); myh * mx],
            inverse_t: None,
            spec: vec![Complex64::default(); (nx * myh * T::BYTES).div_ceil(8)],
            pool: Vec::new(),
        };
        engine.size_pool();
        engine
    }

    /// Also plan f64 transforms for [`Self::apply_exact`] (the spectrum
    /// buffer grows to f64 size; an f64 engine has them already).
    pub(crate) fn with_exact(mut self) -> Self {
        if T::BYTES < 8 {
            self.exact = Some(Plans::<f64>::new(self.mx, self.my));
            self.spec.resize(self.nx * self.myh, Complex64::default());
            self.size_pool();
        }
        self
    }

    fn size_pool(&mut self) {
        let groups = 4 * rayon::current_num_threads().max(1);
        let mut fft = self.plans.scratch_len();
        if let Some(e) = &self.exact {
            fft = fft.max(e.scratch_len());
        }
        let (mx, my) = (self.mx, self.my);
        self.pool = (0..groups)
            .map(|_| Scratch {
                fft: vec![Complex64::default(); fft],
                row: vec![0.0; my],
                columns: vec![Complex64::default(); column_block_len(mx)],
            })
            .collect();
    }

    /// Block shape `(nx, ny)`.
    pub(crate) fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Transform sizes `(mx, my)`.
    pub(crate) fn padded_shape(&self) -> (usize, usize) {
        (self.mx, self.my)
    }

    /// Bytes held by the multipliers and the spectrum buffer (the per-task
    /// buffers are a few rows and columns).
    pub(crate) fn bytes(&self) -> usize {
        let mult = 2 * T::BYTES * self.multiplier_t.len();
        mult * (1 + usize::from(self.inverse_t.is_some())) + 16 * self.spec.len()
    }

    /// Set the multiplier from its column-major half spectrum (`myh`
    /// columns of `mx` modes, [`half_spectrum`]), unnormalised: the engine
    /// divides by `mx my`, then rounds to its precision.
    pub(crate) fn set_multiplier(&mut self, multiplier_t: Vec<Complex64>) {
        assert_eq!(multiplier_t.len(), self.myh * self.mx, "one value per mode");
        let scale = 1.0 / (self.mx * self.my) as f64;
        self.multiplier_t = multiplier_t
            .par_iter()
            .map(|m| Complex::new(T::of(m.re * scale), T::of(m.im * scale)))
            .collect();
    }

    /// Set the second multiplier to the regularised inverse of the first:
    /// `1 / m` where `|m| > floor max |m|`; `1 / max |m|` where `m = 0` (a
    /// mode the operator does not see, e.g. `q = 0` of the periodic cell:
    /// the stiffness of the longest wave, so that the inverse stays
    /// positive definite); `1 / (floor max |m|)` in the direction of `m` in
    /// between ([`inverse_multiplier`], in f64 from the stored multiplier).
    pub(crate) fn set_inverse_multiplier(&mut self, floor: f64) {
        let points = self.mx * self.my;
        self.inverse_t = Some(inverse_multiplier(&self.multiplier_t, points, floor));
    }

    /// Whether [`SpectralEngine::set_inverse_multiplier`] was called.
    pub(crate) fn has_inverse(&self) -> bool {
        self.inverse_t.is_some()
    }

    /// `y = F^-1 [m F [x]]` on the `nx x ny` block (C order).
    pub(crate) fn apply(&mut self, x: &[f64], y: &mut [f64]) {
        self.product(Product::Working, Field::Grid(x), FieldMut::Grid(y));
    }

    /// `y = F^-1 [m^-1 F [x padded]]` with the inverse multiplier (panics
    /// when none was set).
    pub(crate) fn apply_inverse(&mut self, x: &[f64], y: &mut [f64]) {
        self.product(Product::Inverse, Field::Grid(x), FieldMut::Grid(y));
    }

    /// [`Self::apply`] with f64 transforms and the stored multiplier: the
    /// product of the operator this engine holds, to f64 rounding (needs
    /// [`Self::with_exact`] on an f32 engine).
    pub(crate) fn apply_exact(&mut self, x: &[f64], y: &mut [f64]) {
        self.product(Product::Exact, Field::Grid(x), FieldMut::Grid(y));
    }

    /// One of the engine's products between values on a set of the
    /// block's cells (`cells` sorted; `x[k]`, `out[k]` on `cells[k]`).
    pub(crate) fn set_product(
        &mut self,
        which: Product,
        cells: &[usize],
        x: &[f64],
        out: &mut [f64],
    ) {
        let (x, y) = set_fields(cells, x, out);
        self.product(which, x, y);
    }

    /// `y = K x` with `K` the inverse multiplier where one was set, the
    /// identity otherwise: the preconditioner of an operator that holds
    /// this engine ([`crate::operator::GridOperator::precondition`]).
    pub(crate) fn precondition(&mut self, x: &[f64], y: &mut [f64]) {
        if self.has_inverse() {
            self.apply_inverse(x, y);
        } else {
            y.copy_from_slice(x);
        }
    }

    /// [`Self::precondition`] between values on a set of the block's cells
    /// (as [`Self::set_product`]).
    pub(crate) fn precondition_set(&mut self, cells: &[usize], x: &[f64], out: &mut [f64]) {
        if self.has_inverse() {
            self.set_product(Product::Inverse, cells, x, out);
        } else {
            out.copy_from_slice(x);
        }
    }

    /// One of the engine's products between fields on the whole block or
    /// on sets of its cells ([`Field`]).
    pub(crate) fn product(&mut self, which: Product, x: Field<'_>, y: FieldMut<'_>) {
        let dims = self.dims();
        let (spec, pool) = (&mut self.spec, &mut self.pool);
        match which {
            Product::Working => {
                convolve(dims, &self.plans, &self.multiplier_t, spec, pool, x, y);
            }
            Product::Inverse => {
                let m = self
                    .inverse_t
                    .as_deref()
                    .expect("no inverse multiplier was set");
                convolve(dims, &self.plans, m, spec, pool, x, y);
            }
            Product::Exact => match &self.exact {
                Some(plans) => convolve(dims, plans, &self.multiplier_t, spec, pool, x, y),
                None => {
                    assert_eq!(T::BYTES, 8, "an f32 engine needs with_exact");
                    convolve(dims, &self.plans, &self.multiplier_t, spec, pool, x, y);
                }
            },
        }
    }

    fn dims(&self) -> Dims {
        Dims {
            nx: self.nx,
            ny: self.ny,
            mx: self.mx,
            my: self.my,
            myh: self.myh,
        }
    }
}

#[derive(Clone, Copy)]
struct Dims {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    myh: usize,
}

/// `y = F^-1 [m F [x padded]]` with the transforms of precision `U` and a
/// multiplier of precision `T` (widened or rounded to `U` per mode). A
/// set's input rows without a listed cell are zero (their transform is
/// skipped), and only the rows holding an output cell are transformed back.
#[allow(clippy::too_many_arguments)]
fn convolve<U: Real, T: Real>(
    d: Dims,
    plans: &Plans<U>,
    multiplier_t: &[Complex<T>],
    spec_buf: &mut [Complex64],
    pool: &mut [Scratch],
    x: Field<'_>,
    y: FieldMut<'_>,
) {
    let Dims {
        nx,
        ny,
        mx,
        my,
        myh,
    } = d;
    let groups = pool.len();
    let spec = view::<U>(spec_buf, nx * myh);
    // Rows: pad, r2c.
    let rows_per = nx.div_ceil(groups).max(1);
    let inputs = x.runs(nx, ny, rows_per);
    let real_rows = &plans.rows;
    spec.par_chunks_mut(rows_per * myh)
        .zip(inputs.into_par_iter())
        .zip(pool.par_iter_mut())
        .enumerate()
        .for_each(|(run, ((srows, xrows), s))| {
            let row = view_real::<U>(&mut s.row, my);
            let scratch = scratch_of::<U>(&mut s.fft);
            let first = run * rows_per;
            let mut cursor = 0;
            for (k, sr) in srows.chunks_exact_mut(myh).enumerate() {
                if xrows.fill(first + k, ny, first, &mut cursor, row) {
                    row[ny..].fill(U::zero());
                    real_rows.forward(row, sr, scratch);
                } else {
                    sr.fill(Complex::default());
                }
            }
        });
    // Columns: a block at a time, padded to mx, transformed, multiplied,
    // transformed back, and written over the first nx rows.
    let cols_per = myh.div_ceil(groups).max(1);
    let (fwd, inv) = (&plans.fwd, &plans.inv);
    let base = Columns(spec.as_mut_ptr());
    pool.par_iter_mut().enumerate().for_each(|(g, s)| {
        let (c0, c1) = (g * cols_per, ((g + 1) * cols_per).min(myh));
        let (block, stride) = column_layout::<U>(mx);
        let columns = view::<U>(&mut s.columns, block * stride);
        let scratch = scratch_of::<U>(&mut s.fft);
        let mut c = c0;
        while c < c1 {
            let width = block.min(c1 - c);
            for r in 0..nx {
                // SAFETY: columns c..c + width of row r belong to this task.
                let src = unsafe { base.run(r * myh + c, width) };
                for (k, v) in src.iter().enumerate() {
                    columns[k * stride + r] = *v;
                }
            }
            for (k, col) in columns.chunks_exact_mut(stride).take(width).enumerate() {
                let col = &mut col[..mx];
                col[nx..].fill(Complex::default());
                fwd.process_with_scratch(col, scratch);
                let m = &multiplier_t[(c + k) * mx..(c + k + 1) * mx];
                for (v, mv) in col.iter_mut().zip(m) {
                    *v *= Complex::new(U::of(mv.re.wide()), U::of(mv.im.wide()));
                }
                inv.process_with_scratch(col, scratch);
            }
            for r in 0..nx {
                // SAFETY: as above.
                let dst = unsafe { base.run(r * myh + c, width) };
                for (k, v) in dst.iter_mut().enumerate() {
                    *v = columns[k * stride + r];
                }
            }
            c += width;
        }
    });
    // Rows: c2r, the block's columns out.
    let outputs = y.runs(nx, ny, rows_per);
    let real_rows = &plans.rows;
    spec.par_chunks_mut(rows_per * myh)
        .zip(outputs.into_par_iter())
        .zip(pool.par_iter_mut())
        .enumerate()
        .for_each(|(run, ((srows, mut yrows), s))| {
            let row = view_real::<U>(&mut s.row, my);
            let scratch = scratch_of::<U>(&mut s.fft);
            let first = run * rows_per;
            let mut cursor = 0;
            for (k, sr) in srows.chunks_exact_mut(myh).enumerate() {
                let r = first + k;
                if !yrows.wants(r, ny, cursor) {
                    continue;
                }
                real_rows.inverse(sr, row, scratch);
                yrows.store(r, ny, first, &mut cursor, row);
            }
        });
}

/// The unnormalised half spectrum of a real `mx x my` array (row-major),
/// in f64, column-major like a multiplier (`my / 2 + 1` columns of `mx`
/// modes): e.g. a wrapped offset table, or a field whose power is summed.
pub(crate) fn half_spectrum(full: &[f64], mx: usize, my: usize) -> Vec<Complex64> {
    assert_eq!(full.len(), mx * my, "array of the transform size");
    let myh = my / 2 + 1;
    let plans = Plans::<f64>::new(mx, my);
    let groups = 4 * rayon::current_num_threads().max(1);
    let scratch_len = plans.scratch_len();
    let mut rows = vec![Complex64::default(); mx * myh];
    let rows_per = mx.div_ceil(groups).max(1);
    rows.par_chunks_mut(rows_per * myh)
        .zip(full.par_chunks(rows_per * my))
        .for_each(|(srows, frows)| {
            let mut row = vec![0.0; my];
            let mut scratch = vec![Complex64::default(); scratch_len];
            for (sr, fr) in srows.chunks_exact_mut(myh).zip(frows.chunks_exact(my)) {
                row.copy_from_slice(fr);
                plans.rows.forward(&mut row, sr, &mut scratch);
            }
        });
    let mut out = vec![Complex64::default(); myh * mx];
    out.par_chunks_mut(mx).enumerate().for_each_init(
        || vec![Complex64::default(); scratch_len],
        |scratch, (c, col)| {
            for (r, v) in col.iter_mut().enumerate() {
                *v = rows[r * myh + c];
            }
            plans.fwd.process_with_scratch(col, scratch);
        },
    );
    out
}

/// The regularised inverse of a multiplier stored times `1 / points` (the
/// unnormalised inverse transform's scale), stored the same way:
/// `conj(m) / |m|^2 / points^2`; modes below `floor` times the largest are
/// raised to it in the direction of `m`, zero modes get the largest's
/// inverse ([`SpectralEngine::set_inverse_multiplier`]; the GPU
/// preconditioner's spectrum too).
pub(crate) fn inverse_multiplier<T: Real, U: Real>(
    multiplier: &[Complex<T>],
    points: usize,
    floor: f64,
) -> Vec<Complex<U>> {
    let wide = |m: &Complex<T>| Complex64::new(m.re.wide(), m.im.wide());
    let scale = 1.0 / points as f64;
    let largest = multiplier
        .iter()
        .map(|m| wide(m).norm())
        .fold(0.0, f64::max);
    let cut = floor * largest;
    // Mode by mode in f64, rounded to `U` as it is stored: no full-size
    // f64 copy of either spectrum (16 bytes per cell at the operator's
    // set-up, its peak in mixed precision).
    multiplier
        .par_iter()
        .map(|m| {
            let m = wide(m);
            let r = m.norm();
            let inverse = if r == 0.0 {
                Complex64::new(scale * scale / largest, 0.0)
            } else {
                let m = if r < cut { m * (cut / r) } else { m };
                m.conj() / m.norm_sqr() * (scale * scale)
            };
            Complex::new(U::of(inverse.re), U::of(inverse.im))
        })
        .collect()
}
