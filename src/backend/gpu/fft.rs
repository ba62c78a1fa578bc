//! The Toeplitz matvec on the device: the exact linear (non-periodic) 2-D
//! convolution of paper Eq. 7, `u_i = sum_k L(i - k) p_k`, by a zero-padded
//! FFT (physics.md section 3, "Discretisation"; CPU twin:
//! [`crate::operator::ToeplitzFft`]). The padded sizes are powers of two
//! `mx >= 2 nx - 1`, `my >= 2 ny - 1`, so circular and linear convolution
//! agree on the `nx x ny` output block. The dispatches are those of a
//! [`MatvecPlan`]: by default workgroup-memory Stockham passes over real
//! rows with the spectral product fused into the column passes
//! ([`Path::Shared`]), else radix-2 passes (`shaders/fft_pass.wgsl`); both
//! ping-pong between two work buffers. The kernel spectrum is computed once
//! on the host in f64 (a real-to-complex transform, rows and columns in
//! parallel: [`path_spectrum`]) and stored in f32 (or f16,
//! [`SpectrumPrecision::F16`], radix-2 path only); the preconditioner's
//! inverse spectrum comes from the same transform, and near full contact
//! the inverse of T. Chan's circulant, as on the host, from its table.

use num_complex::Complex64;
use rayon::prelude::*;

use super::context::{check_binding_count, GpuError};
use super::engine::{Buf, Engine, Kernel};
pub use super::fft_plan::padded;
use super::fft_plan::{grid, work_elements, MatvecPlan, Path, Role, MIN_WORKGROUPS};
use crate::operator::half_spectrum as real_half_spectrum;
use crate::operator::{
    chan_inverse_table, chan_kernel, inverse_multiplier, OffsetTable, CHAN_FRACTION,
};

/// Storage precision of the kernel spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpectrumPrecision {
    /// Two f32 per entry.
    #[default]
    F32,
    /// Two f16 per entry (half the memory of the spectrum), scaled by the
    /// largest component; about three decimal digits.
    F16,
}

/// Which FFT a [`FftMatvec`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FftChoice {
    /// The workgroup-memory FFT sized from the adapter's limits
    /// ([`Path::for_device`]); the radix-2 passes where those forbid it or
    /// with the f16 spectrum.
    #[default]
    Auto,
    /// The radix-2 passes, one dispatch each.
    Radix2,
    /// The workgroup-memory FFT with radices at most `max_radix` (a power
    /// of two, at least 2): more passes than needed, for tests.
    SharedMaxRadix(usize),
}

/// Plan and device buffers of the padded-FFT matvec.
pub struct FftMatvec {
    pub nx: usize,
    pub ny: usize,
    pub mx: usize,
    pub my: usize,
    plan: MatvecPlan,
    a: Buf,
    b: Buf,
    kernel: Buf,
    /// The inverse spectrum of the preconditioner, same layout as `kernel`.
    inverse: Option<Buf>,
    /// The inverse of T. Chan's circulant, with the preconditioner only
    /// ([`Self::set_contact_fraction`]).
    chan: Option<ChanInverse>,
    /// Whether [`Self::record_inverse`] applies `chan`.
    use_chan: bool,
    twiddle_x: Buf,
    twiddle_y: Buf,
}

/// T. Chan's circulant for the preconditioner of near-full contact sets:
/// its first row until first needed, then its inverse's spectrum.
enum ChanInverse {
    Kernel(Vec<f64>),
    Spectrum(Buf),
}

/// A device buffer holding `spectrum` as f32 pairs (rounded from f64).
fn storage_f32(engine: &mut Engine, label: &str, spectrum: &[Complex64]) -> Buf {
    let host: Vec<f32> = spectrum
        .iter()
        .flat_map(|z| [z.re as f32, z.im as f32])
        .collect();
    engine.storage_with(label, bytemuck::cast_slice(&host))
}

/// `exp(-2 pi i t / n)` for `t < n / 2`, in f32 pairs from f64.
fn twiddles(n: usize) -> Vec<f32> {
    let mut w = Vec::with_capacity(n.max(2));
    for t in 0..(n / 2).max(1) {
        let ang = -std::f64::consts::TAU * t as f64 / n as f64;
        w.push(ang.cos() as f32);
        w.push(ang.sin() as f32);
    }
    w
}

/// `exp(-2 pi i t / n)` for `t < n`, in f32 pairs from f64 (the tables of
/// the workgroup-memory passes).
fn full_twiddles(n: usize) -> Vec<f32> {
    (0..n.max(1))
        .flat_map(|t| {
            let ang = -std::f64::consts::TAU * t as f64 / n as f64;
            [ang.cos() as f32, ang.sin() as f32]
        })
        .collect()
}

/// The scaled kernel spectrum `FFT(wrapped table) / (mx my)` of an offset
/// table (`(2nx-1) x (2ny-1)`, layout of [`crate::operator::OffsetTable`]),
/// row-major, in the layout of `path`: the bins `0 ..= my / 2` of each of
/// the `mx` rows on the workgroup-memory path (the real-row transforms need
/// no more), the full `mx x my` spectrum on the radix-2 path (the other
/// bins by Hermitian symmetry, `S(r, c) = conj S(-r, -c)`: the table is
/// real). One real-to-complex transform of the wrapped table on the host's
/// threads ([`crate::operator`]'s, the CPU operator's own), in f64.
pub fn path_spectrum(
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    table: &[f64],
    path: Path,
) -> Vec<Complex64> {
    assert_eq!(
        table.len(),
        (2 * nx - 1) * (2 * ny - 1),
        "offset table size"
    );
    let w = 2 * ny - 1;
    let mut wrapped = vec![0.0; mx * my];
    wrapped.par_chunks_mut(my).enumerate().for_each(|(r, row)| {
        // The offset di whose wrap is row r, if any.
        let di = if r < nx {
            r as isize
        } else if r + nx > mx {
            r as isize - mx as isize
        } else {
            return;
        };
        let src = (di + nx as isize - 1) as usize * w;
        for dj in -(ny as isize - 1)..=(ny as isize - 1) {
            let c = dj.rem_euclid(my as isize) as usize;
            row[c] = table[src + (dj + ny as isize - 1) as usize];
        }
    });
    // Column-major: `my / 2 + 1` columns of `mx` modes, unnormalised.
    let columns = real_half_spectrum(&wrapped, mx, my);
    drop(wrapped);
    let myh = my / 2 + 1;
    let scale = 1.0 / (mx * my) as f64;
    let half = |r: usize, c: usize| columns[c * mx + r] * scale;
    let width = if path == Path::Radix2 { my } else { myh };
    let mut out = vec![Complex64::default(); mx * width];
    out.par_chunks_mut(width).enumerate().for_each(|(r, row)| {
        for (c, v) in row.iter_mut().enumerate() {
            *v = if c < myh {
                half(r, c)
            } else {
                half((mx - r) % mx, my - c).conj()
            };
        }
    });
    out
}

/// The path a [`FftMatvec`] takes on a device that allows `device` (its
/// [`Path::for_device`]) with `shared` elements in its FFT block.
pub fn choose_path(
    choice: FftChoice,
    precision: SpectrumPrecision,
    device: Path,
    shared: usize,
) -> Path {
    match (choice, device) {
        (FftChoice::Radix2, _) | (_, Path::Radix2) => Path::Radix2,
        _ if precision == SpectrumPrecision::F16 => Path::Radix2,
        (FftChoice::Auto, path) => path,
        (FftChoice::SharedMaxRadix(r), _) => Path::Shared {
            shared,
            max_radix: r.clamp(2, shared),
            min_workgroups: MIN_WORKGROUPS,
        },
    }
}

impl FftMatvec {
    /// Plan the matvec for an `nx x ny` grid from its offset table; with
    /// `inverse_floor` (f32 spectrum only) also the preconditioner `K = R
    /// C^-1 R^T`, `C` the circulant of the padded transform (of which `L`
    /// is the leading block): the same plan with the inverse of the scaled
    /// spectrum in f32, modes below `floor` times the largest multiplier
    /// clamped there (`inverse_multiplier`, shared with the host's
    /// [`crate::operator::ToeplitzFft::with_preconditioner`]), from the same
    /// host transform.
    pub fn new(
        engine: &mut Engine,
        nx: usize,
        ny: usize,
        table: &[f64],
        precision: SpectrumPrecision,
        choice: FftChoice,
        inverse_floor: Option<f64>,
    ) -> Result<Self, GpuError> {
        if nx == 0 || ny == 0 || table.len() != (2 * nx - 1) * (2 * ny - 1) {
            return Err(GpuError::Invalid(format!(
                "an offset table of a {nx} x {ny} grid has {} entries, got {}",
                (2 * nx.max(1) - 1) * (2 * ny.max(1) - 1),
                table.len()
            )));
        }
        let device = Path::for_device(&engine.ctx.device.limits());
        let mut path = choose_path(choice, precision, device, engine.fft_shared);
        if let Path::Shared { min_workgroups, .. } = &mut path {
            if engine.ctx.adapter.device_type == "Cpu" {
                // A CPU adapter runs a workgroup per thread: big blocks, and
                // enough of them for the host's threads.
                let threads = std::thread::available_parallelism().map_or(4, |n| n.get());
                *min_workgroups = 2 * threads as u64;
            }
        }
        let plan = MatvecPlan::new(nx, ny, path);
        let (mx, my) = (plan.mx, plan.my);
        let bytes = 8 * work_elements(nx, ny, path) as u64;
        check_device(
            &engine.ctx.device.limits(),
            &engine.ctx.adapter.name,
            nx,
            ny,
            path,
        )?;
        let spectrum = path_spectrum(nx, ny, mx, my, table, path);
        // The inverse is taken mode by mode against the largest modulus,
        // which the half spectrum holds as the full one does.
        let inverse = match (inverse_floor, precision) {
            (Some(floor), SpectrumPrecision::F32) => {
                let inverse = inverse_multiplier::<f64, f64>(&spectrum, mx * my, floor);
                Some(storage_f32(
                    engine,
                    "viscoslide inverse spectrum f32",
                    &inverse,
                ))
            }
            _ => None,
        };
        let chan = inverse.is_some().then(|| {
            ChanInverse::Kernel(chan_kernel(OffsetTable {
                nx,
                ny,
                values: table,
            }))
        });
        let kernel = match precision {
            SpectrumPrecision::F32 => {
                storage_f32(engine, "viscoslide kernel spectrum f32", &spectrum)
            }
            SpectrumPrecision::F16 => {
                let scale = f16_scale(&spectrum);
                let host: Vec<u32> = spectrum
                    .iter()
                    .map(|z| {
                        let re = half::f16::from_f64(z.re / scale).to_bits() as u32;
                        let im = half::f16::from_f64(z.im / scale).to_bits() as u32;
                        re | (im << 16)
                    })
                    .collect();
                engine.storage_with(
                    "viscoslide kernel spectrum f16",
                    bytemuck::cast_slice(&host),
                )
            }
        };
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let a = engine.create_buffer("viscoslide fft buffer a", bytes, usage);
        let b = engine.create_buffer("viscoslide fft buffer b", bytes, usage);
        let table_of = |n: usize| match path {
            Path::Radix2 => twiddles(n),
            Path::Shared { .. } => full_twiddles(n),
        };
        let twiddle_x = engine.storage_with(
            "viscoslide fft twiddles x",
            bytemuck::cast_slice(&table_of(mx)),
        );
        let twiddle_y = engine.storage_with(
            "viscoslide fft twiddles y",
            bytemuck::cast_slice(&table_of(my)),
        );
        let mut plan = plan;
        if precision == SpectrumPrecision::F16 {
            let scale = f16_scale(&spectrum) as f32;
            for s in &mut plan.steps {
                if s.kernel == Kernel::SpectralProduct {
                    s.kernel = Kernel::SpectralProductF16;
                    s.params.f[0] = scale;
                }
            }
        }
        Ok(Self {
            nx,
            ny,
            mx,
            my,
            plan,
            a,
            b,
            kernel,
            inverse,
            chan,
            use_chan: false,
            twiddle_x,
            twiddle_y,
        })
    }

    /// Whether the matvec has the preconditioner's inverse spectrum.
    pub fn has_inverse(&self) -> bool {
        self.inverse.is_some()
    }

    /// Record `y = K x` with the inverse spectrum of the preconditioner
    /// that [`Self::set_contact_fraction`] picked (the matvec's plan).
    pub fn record_inverse(&self, engine: &mut Engine, x: &Buf, y: &Buf) {
        let inverse = match (&self.chan, self.use_chan) {
            (Some(ChanInverse::Spectrum(chan)), true) => chan,
            _ => self
                .inverse
                .as_ref()
                .expect("a matvec planned with inverse_floor"),
        };
        self.record_with(engine, x, y, inverse);
    }

    /// The contact set of the next preconditioner applications covers
    /// `fraction` of the grid: above [`CHAN_FRACTION`] the preconditioner is
    /// the inverse of T. Chan's optimal circulant (as the host operator's,
    /// [`crate::operator::ToeplitzFft`]'s; the padded circulant's
    /// restriction serves small sets, near-full ones badly), its spectrum
    /// built at first use from the offset table of that inverse
    /// (`operator::chan_inverse_table`), whose padded convolution is the inverse on
    /// the grid exactly.
    pub fn set_contact_fraction(&mut self, engine: &mut Engine, fraction: f64) {
        self.use_chan = fraction > CHAN_FRACTION && self.chan.is_some();
        if !self.use_chan {
            return;
        }
        if let Some(ChanInverse::Kernel(kernel)) = &self.chan {
            let plan = &self.plan;
            let table = chan_inverse_table(kernel, plan.nx, plan.ny);
            let spectrum = path_spectrum(plan.nx, plan.ny, plan.mx, plan.my, &table, plan.path);
            drop(table);
            self.chan = Some(ChanInverse::Spectrum(storage_f32(
                engine,
                "viscoslide chan inverse spectrum f32",
                &spectrum,
            )));
        }
    }

    /// The dispatch plan this matvec records.
    pub fn plan(&self) -> &MatvecPlan {
        &self.plan
    }

    /// Device memory of the plan \[bytes\].
    pub fn device_bytes(&self) -> u64 {
        let chan = match &self.chan {
            Some(ChanInverse::Spectrum(b)) => Some(b),
            _ => None,
        };
        [
            Some(&self.a),
            Some(&self.b),
            Some(&self.kernel),
            self.inverse.as_ref(),
            chan,
        ]
        .into_iter()
        .flatten()
        .map(|b| b.buffer.size())
        .sum()
    }

    /// Record `y = L x` (grid vectors of `nx ny` f32): the steps of the plan.
    pub fn record_apply(&self, engine: &mut Engine, x: &Buf, y: &Buf) {
        self.record_with(engine, x, y, &self.kernel);
    }

    /// The plan's steps with `spectrum` as the multiplier.
    fn record_with(&self, engine: &mut Engine, x: &Buf, y: &Buf, spectrum: &Buf) {
        for step in &self.plan.steps {
            let bufs: Vec<&Buf> = step
                .bufs
                .iter()
                .map(|role| match role {
                    Role::Input => x,
                    Role::Output => y,
                    Role::A => &self.a,
                    Role::B => &self.b,
                    Role::Spectrum => spectrum,
                    Role::RowTwiddle => &self.twiddle_y,
                    Role::ColTwiddle => &self.twiddle_x,
                })
                .collect();
            engine.dispatch(step.kernel, &bufs, step.params, grid(step.groups));
        }
    }
}

/// How the work buffers and the spectrum of an `nx x ny` grid's matvec on
/// `path` fit a device with `limits`: every array in one buffer, bound in
/// windows where larger than one storage binding ([`super::split`]; every
/// kernel of both paths reaches its work buffers, spectrum and grid
/// vectors through accessors): `(bytes of each, windows of each)`, or the
/// limit they break (one buffer, or the storage bindings of the kernel
/// that binds the most windows).
pub fn check_device(
    limits: &wgpu::Limits,
    adapter: &str,
    nx: usize,
    ny: usize,
    path: Path,
) -> Result<(u64, u64), GpuError> {
    let (mx, my) = super::fft_plan::padded_shape(nx.max(1), ny.max(1), path);
    let what = format!("the padded {mx} x {my} FFT of a {nx} x {ny} grid");
    let bytes = 8 * work_elements(nx.max(1), ny.max(1), path) as u64;
    let binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    if bytes <= binding {
        return Ok((bytes, 1));
    }
    if bytes > limits.max_buffer_size {
        return Err(GpuError::TooLarge {
            what,
            need: bytes,
            limit: limits.max_buffer_size,
            per: "per buffer",
            adapter: adapter.to_string(),
        });
    }
    let window =
        super::split::window_bytes(binding, limits.min_storage_buffer_offset_alignment.into());
    let windows = super::split::windows(bytes, window);
    let bindings = match path {
        // The load binds the input vector and both work buffers (the
        // passes two work buffers and the twiddles, the product a work
        // buffer and the spectrum, at most as many).
        Path::Radix2 => {
            let vector = 4 * (nx.max(1) * ny.max(1)) as u64;
            let vector_windows = if vector <= binding {
                1
            } else {
                super::split::windows(vector, window)
            };
            2 * windows + vector_windows
        }
        // The product pass binds two work buffers, the spectrum and the
        // twiddles.
        Path::Shared { .. } => 3 * windows + 1,
    };
    check_binding_count(&what, bindings, limits, adapter)?;
    Ok((bytes, windows))
}

/// The scale of the f16 spectrum: its largest component.
fn f16_scale(spectrum: &[Complex64]) -> f64 {
    spectrum
        .iter()
        .map(|z| z.re.abs().max(z.im.abs()))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE)
}
