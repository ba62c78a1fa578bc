//! The Toeplitz matvec on the device: the exact linear (non-periodic) 2-D
//! convolution of paper Eq. 7, `u_i = sum_k L(i - k) p_k`, by a zero-padded
//! FFT (physics.md section 3, "Discretisation"; CPU twin:
//! [`crate::operator::ToeplitzFft`]). The padded sizes are powers of two
//! `mx >= 2 nx - 1`, `my >= 2 ny - 1`, so circular and linear convolution
//! agree on the `nx x ny` output block. Transforms are radix-2 Stockham
//! passes (`shaders/fft_pass.wgsl`), rows then columns, ping-ponging between
//! two complex buffers; the kernel spectrum is computed once on the host in
//! f64 and stored in f32 (or f16, [`SpectrumPrecision::F16`]).

use num_complex::Complex64;
use rustfft::FftPlanner;

use super::context::GpuError;
use super::engine::{groups_for, Buf, Engine, Kernel, Params};

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

/// Plan and device buffers of the padded-FFT matvec.
pub struct FftMatvec {
    pub nx: usize,
    pub ny: usize,
    pub mx: usize,
    pub my: usize,
    a: Buf,
    b: Buf,
    kernel: Buf,
    twiddle_x: Buf,
    twiddle_y: Buf,
    precision: SpectrumPrecision,
    f16_scale: f32,
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

/// 2-D forward FFT of a row-major `mx x my` complex array, in place, f64.
fn fft2(data: &mut [Complex64], mx: usize, my: usize) {
    let mut planner = FftPlanner::<f64>::new();
    planner.plan_fft_forward(my).process(data);
    let mut t = vec![Complex64::default(); mx * my];
    for r in 0..mx {
        for c in 0..my {
            t[c * mx + r] = data[r * my + c];
        }
    }
    planner.plan_fft_forward(mx).process(&mut t);
    for r in 0..mx {
        for c in 0..my {
            data[r * my + c] = t[c * mx + r];
        }
    }
}

/// The scaled kernel spectrum `FFT(wrapped table) / (mx my)` of an offset
/// table (`(2nx-1) x (2ny-1)`, layout of [`crate::operator::OffsetTable`]).
pub fn kernel_spectrum(
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    table: &[f64],
) -> Vec<Complex64> {
    let w = 2 * ny - 1;
    let mut data = vec![Complex64::default(); mx * my];
    for di in -(nx as isize - 1)..=(nx as isize - 1) {
        let r = di.rem_euclid(mx as isize) as usize;
        for dj in -(ny as isize - 1)..=(ny as isize - 1) {
            let c = dj.rem_euclid(my as isize) as usize;
            let v = table[(di + nx as isize - 1) as usize * w + (dj + ny as isize - 1) as usize];
            data[r * my + c] = Complex64::new(v, 0.0);
        }
    }
    fft2(&mut data, mx, my);
    let s = 1.0 / (mx * my) as f64;
    data.iter_mut().for_each(|z| *z *= s);
    data
}

/// Padded power-of-two size for a grid side `n`.
pub fn padded(n: usize) -> usize {
    (2 * n - 1).next_power_of_two()
}

impl FftMatvec {
    /// Plan the matvec for an `nx x ny` grid from its offset table.
    pub fn new(
        engine: &mut Engine,
        nx: usize,
        ny: usize,
        table: &[f64],
        precision: SpectrumPrecision,
    ) -> Result<Self, GpuError> {
        if nx == 0 || ny == 0 || table.len() != (2 * nx - 1) * (2 * ny - 1) {
            return Err(GpuError::Invalid(format!(
                "an offset table of a {nx} x {ny} grid has {} entries, got {}",
                (2 * nx.max(1) - 1) * (2 * ny.max(1) - 1),
                table.len()
            )));
        }
        let (mx, my) = (padded(nx), padded(ny));
        let bytes = (mx * my * 8) as u64;
        engine.check_binding(
            &format!("the padded {mx} x {my} complex FFT of a {nx} x {ny} grid"),
            bytes,
        )?;
        let spectrum = kernel_spectrum(nx, ny, mx, my, table);
        let (kernel, f16_scale) = match precision {
            SpectrumPrecision::F32 => {
                let host: Vec<f32> = spectrum
                    .iter()
                    .flat_map(|z| [z.re as f32, z.im as f32])
                    .collect();
                (
                    engine.storage_with(
                        "viscoslide kernel spectrum f32",
                        bytemuck::cast_slice(&host),
                    ),
                    1.0,
                )
            }
            SpectrumPrecision::F16 => {
                let scale = spectrum
                    .iter()
                    .map(|z| z.re.abs().max(z.im.abs()))
                    .fold(0.0f64, f64::max)
                    .max(f64::MIN_POSITIVE);
                let host: Vec<u32> = spectrum
                    .iter()
                    .map(|z| {
                        let re = half::f16::from_f64(z.re / scale).to_bits() as u32;
                        let im = half::f16::from_f64(z.im / scale).to_bits() as u32;
                        re | (im << 16)
                    })
                    .collect();
                (
                    engine.storage_with(
                        "viscoslide kernel spectrum f16",
                        bytemuck::cast_slice(&host),
                    ),
                    scale as f32,
                )
            }
        };
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let a = engine.create_buffer("viscoslide fft buffer a", bytes, usage);
        let b = engine.create_buffer("viscoslide fft buffer b", bytes, usage);
        let twiddle_x = engine.storage_with(
            "viscoslide fft twiddles x",
            bytemuck::cast_slice(&twiddles(mx)),
        );
        let twiddle_y = engine.storage_with(
            "viscoslide fft twiddles y",
            bytemuck::cast_slice(&twiddles(my)),
        );
        Ok(Self {
            nx,
            ny,
            mx,
            my,
            a,
            b,
            kernel,
            twiddle_x,
            twiddle_y,
            precision,
            f16_scale,
        })
    }

    /// Device memory of the plan \[bytes\].
    pub fn device_bytes(&self) -> u64 {
        self.a.buffer.size() + self.b.buffer.size() + self.kernel.buffer.size()
    }

    /// Record the passes of one FFT along an axis (length `n`, element
    /// stride `es`, `batches` transforms `bs` apart). Returns whether the
    /// result is in buffer `b` (an odd number of passes).
    #[allow(clippy::too_many_arguments)]
    fn record_axis(
        &self,
        engine: &mut Engine,
        in_b: bool,
        n: usize,
        es: usize,
        bs: usize,
        batches: usize,
        sign: f32,
        twiddle: &Buf,
    ) -> bool {
        let mut cur_b = in_b;
        let mut ns = 1usize;
        let groups = groups_for((batches * n / 2) as u64);
        while ns < n {
            let (src, dst) = if cur_b {
                (&self.b, &self.a)
            } else {
                (&self.a, &self.b)
            };
            engine.dispatch(
                Kernel::FftPass,
                &[src, dst, twiddle],
                Params {
                    i: [n as u32, ns as u32, es as u32, bs as u32],
                    j: [batches as u32, 0, 0, 0],
                    f: [sign, 0.0, 0.0, 0.0],
                },
                groups,
            );
            cur_b = !cur_b;
            ns *= 2;
        }
        cur_b
    }

    /// Record `y = L x` (grid vectors of `nx ny` f32).
    pub fn record_apply(&self, engine: &mut Engine, x: &Buf, y: &Buf) {
        let (nx, ny, mx, my) = (self.nx, self.ny, self.mx, self.my);
        let shape = [nx as u32, ny as u32, mx as u32, my as u32];
        let all = groups_for((mx * my) as u64);
        engine.dispatch(
            Kernel::FftLoad,
            &[x, &self.a, &self.b],
            Params {
                i: shape,
                ..Default::default()
            },
            all,
        );
        // Rows r >= nx are zero in both buffers: transform the first nx only.
        let mut in_b = self.record_axis(engine, false, my, 1, my, nx, 1.0, &self.twiddle_y);
        in_b = self.record_axis(engine, in_b, mx, my, 1, my, 1.0, &self.twiddle_x);
        let spec = if in_b { &self.b } else { &self.a };
        let mut p = Params {
            i: [(mx * my) as u32, 0, 0, 0],
            ..Default::default()
        };
        match self.precision {
            SpectrumPrecision::F32 => {
                engine.dispatch(Kernel::SpectralProduct, &[spec, &self.kernel], p, all)
            }
            SpectrumPrecision::F16 => {
                p.f[0] = self.f16_scale;
                engine.dispatch(Kernel::SpectralProductF16, &[spec, &self.kernel], p, all)
            }
        }
        in_b = self.record_axis(engine, in_b, mx, my, 1, my, -1.0, &self.twiddle_x);
        // Only the first nx rows of the result are needed.
        in_b = self.record_axis(engine, in_b, my, 1, my, nx, -1.0, &self.twiddle_y);
        let spec = if in_b { &self.b } else { &self.a };
        engine.dispatch(
            Kernel::FftExtract,
            &[spec, y],
            Params {
                i: shape,
                ..Default::default()
            },
            groups_for((nx * ny) as u64),
        );
    }
}
