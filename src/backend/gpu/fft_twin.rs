//! The CPU twin of the shared-memory FFT kernels (`shaders/fft_radix.wgsl`,
//! `shaders/fft_radix_product.wgsl`, `shaders/fft_split.wgsl`,
//! `shaders/fft_merge.wgsl` and their blocks in `shared/fft_block.wgsl`):
//! it runs a [`MatvecPlan`] step by step on host arrays in f64 with the
//! shaders' index arithmetic (group and element mapping, zero limits,
//! twiddle indices, bit reversal, split and merge; the radix-2 stages one
//! by one where the shaders run them two per barrier, the same arithmetic),
//! one group at a time instead of one workgroup at a time (the groups of a
//! pass are independent). Its tests hold every plan shape against the CPU
//! Toeplitz FFT without a device; `tests/gpu/conformance.rs` holds the
//! shaders against the same reference on a device.

use std::collections::HashMap;

use num_complex::Complex64;

use super::engine::{Kernel, Params};
use super::fft_plan::{MatvecPlan, Role, Step, FFT_BATCH_FAST, FFT_INVERSE, FFT_MERGE, FFT_SPLIT};

/// `exp(-2 pi i num / den)` read from a table of length `len` as the shader
/// does (`w[num len / den]`), conjugated when `inverse`.
fn twiddle(num: usize, den: usize, len: usize, inverse: bool) -> Complex64 {
    let t = num * (len / den);
    let w = Complex64::from_polar(1.0, -std::f64::consts::TAU * t as f64 / len as f64);
    if inverse {
        w.conj()
    } else {
        w
    }
}

fn bitrev(s: usize, log2r: u32) -> usize {
    if log2r == 0 {
        0
    } else {
        (s as u32).reverse_bits() as usize >> (32 - log2r)
    }
}

#[derive(Clone, Copy)]
struct Layout {
    bsf: usize,
    esf: usize,
    lim: usize,
}

impl Layout {
    fn read(&self, a: &[f64], b: usize, pos: usize) -> Complex64 {
        let at = b * self.bsf + pos * self.esf;
        let re = if 2 * pos < self.lim { a[at] } else { 0.0 };
        let im = if 2 * pos + 1 < self.lim {
            a[at + 1]
        } else {
            0.0
        };
        Complex64::new(re, im)
    }

    fn write(&self, a: &mut [f64], b: usize, pos: usize, v: Complex64) {
        let at = b * self.bsf + pos * self.esf;
        if 2 * pos < self.lim {
            a[at] = v.re;
        }
        if 2 * pos + 1 < self.lim {
            a[at + 1] = v.im;
        }
    }
}

/// Radix-2 DIF stages (natural in, bit-reversed out), as `fft_dif`.
fn dif(v: &mut [Complex64], len: usize, inverse: bool) {
    let mut h = v.len() / 2;
    while h >= 1 {
        for u in 0..v.len() / 2 {
            let i = u & (h - 1);
            let at = 2 * (u - i) + i;
            let (a, b) = (v[at], v[at + h]);
            v[at] = a + b;
            v[at + h] = (a - b) * twiddle(i, 2 * h, len, inverse);
        }
        h /= 2;
    }
}

/// Radix-2 DIT stages (bit-reversed in, natural out), as `fft_dit`.
fn dit(v: &mut [Complex64], len: usize, inverse: bool) {
    let mut h = 1;
    while h < v.len() {
        for u in 0..v.len() / 2 {
            let i = u & (h - 1);
            let at = 2 * (u - i) + i;
            let (a, b) = (v[at], v[at + h] * twiddle(i, 2 * h, len, inverse));
            v[at] = a + b;
            v[at + h] = a - b;
        }
        h *= 2;
    }
}

/// One `fft_radix` or `fft_radix_product` dispatch.
fn radix(p: &Params, src: &[f64], dst: &mut [f64], tw_len: usize, spectrum: Option<&[f64]>) {
    let [n, ns, log2r, batches] = p.i.map(|v| v as usize);
    let log2r = log2r as u32;
    let flags = p.j[0];
    let input = Layout {
        bsf: p.j[1] as usize,
        esf: p.j[2] as usize,
        lim: p.j[3] as usize,
    };
    let output = Layout {
        bsf: p.f[0].to_bits() as usize,
        esf: p.f[1].to_bits() as usize,
        lim: p.f[2].to_bits() as usize,
    };
    let inverse = flags & FFT_INVERSE != 0;
    let r = 1usize << log2r;
    let groups = n / r;
    let _ = flags & FFT_BATCH_FAST; // the order of groups does not change the result
    let mut v = vec![Complex64::default(); r];
    for b in 0..batches {
        for j in 0..groups {
            let k = j & (ns - 1);
            for (rr, slot) in v.iter_mut().enumerate() {
                *slot = if flags & FFT_MERGE != 0 {
                    let x = input.read(src, b, rr);
                    let c = input.read(src, b, n - rr).conj();
                    let d = (x - c) * twiddle(rr, 2 * n, tw_len, true);
                    x + c + Complex64::i() * d
                } else {
                    let x = input.read(src, b, j + rr * groups);
                    if k != 0 {
                        x * twiddle(rr * k, ns * r, tw_len, inverse)
                    } else {
                        x
                    }
                };
            }
            if let Some(s) = spectrum {
                dif(&mut v, tw_len, false);
                let (sb, se) = (input.bsf / 2, input.esf / 2);
                for (slot, z) in v.iter_mut().enumerate() {
                    let pos = (j - k) * r + k + bitrev(slot, log2r) * ns;
                    let at = 2 * (b * sb + pos * se);
                    *z *= Complex64::new(s[at], s[at + 1]);
                }
                dit(&mut v, tw_len, true);
                for (rr, &z) in v.iter().enumerate() {
                    output.write(dst, b, j * r + rr, z);
                }
                continue;
            }
            dif(&mut v, tw_len, inverse);
            if flags & FFT_SPLIT != 0 {
                for kk in 0..=r {
                    let z = v[bitrev(kk & (r - 1), log2r)];
                    let c = v[bitrev((r - kk) & (r - 1), log2r)].conj();
                    let even = 0.5 * (z + c);
                    let odd = -Complex64::i() * 0.5 * (z - c);
                    output.write(dst, b, kk, even + twiddle(kk, 2 * r, tw_len, false) * odd);
                }
            } else {
                for q in 0..r {
                    output.write(dst, b, (j - k) * r + k + q * ns, v[bitrev(q, log2r)]);
                }
            }
        }
    }
}

/// One `fft_split` or `fft_merge` dispatch.
fn split_merge(p: &Params, split: bool, src: &[f64], dst: &mut [f64], tw_len: usize) {
    let (rows, n) = (p.i[0] as usize, p.i[1] as usize);
    let at = |a: &[f64], k: usize| Complex64::new(a[2 * k], a[2 * k + 1]);
    let mut put = |k: usize, v: Complex64| {
        dst[2 * k] = v.re;
        dst[2 * k + 1] = v.im;
    };
    for b in 0..rows {
        if split {
            for k in 0..=n {
                let z = at(src, b * n + (k & (n - 1)));
                let c = at(src, b * n + ((n - k) & (n - 1))).conj();
                let odd = -Complex64::i() * 0.5 * (z - c);
                put(
                    b * (n + 1) + k,
                    0.5 * (z + c) + twiddle(k, 2 * n, tw_len, false) * odd,
                );
            }
        } else {
            for k in 0..n {
                let x = at(src, b * (n + 1) + k);
                let c = at(src, b * (n + 1) + n - k).conj();
                let d = (x - c) * twiddle(k, 2 * n, tw_len, true);
                put(b * n + k, x + c + Complex64::i() * d);
            }
        }
    }
}

/// Run the shared-memory `plan` on `x` (`nx ny` values) with the kernel
/// spectrum `spectrum` (the layout [`super::fft::FftMatvec`] uploads:
/// `mx` rows of `my / 2 + 1` bins, scaled by `1 / (mx my)`); returns `y`.
/// Panics on a [`super::fft_plan::Path::Radix2`] plan.
pub fn run(plan: &MatvecPlan, spectrum: &[Complex64], x: &[f64]) -> Vec<f64> {
    let work = 2 * plan.mx * (plan.my / 2 + 1);
    let mut bufs: HashMap<Role, Vec<f64>> = HashMap::new();
    bufs.insert(Role::Input, x.to_vec());
    bufs.insert(Role::Output, vec![0.0; plan.nx * plan.ny]);
    bufs.insert(Role::A, vec![0.0; work]);
    bufs.insert(Role::B, vec![0.0; work]);
    let spec: Vec<f64> = spectrum.iter().flat_map(|z| [z.re, z.im]).collect();
    for step in &plan.steps {
        let Step {
            kernel,
            bufs: roles,
            params,
            ..
        } = step;
        let tw_len = if roles[2] == Role::RowTwiddle {
            plan.my
        } else {
            plan.mx
        };
        let src = bufs[&roles[0]].clone();
        let dst = bufs.get_mut(&roles[1]).expect("a work buffer");
        match kernel {
            Kernel::FftRadix => radix(params, &src, dst, tw_len, None),
            Kernel::FftRadixProduct => radix(params, &src, dst, tw_len, Some(&spec)),
            Kernel::FftSplit => split_merge(params, true, &src, dst, tw_len),
            Kernel::FftMerge => split_merge(params, false, &src, dst, tw_len),
            other => panic!("the CPU twin covers the shared-memory FFT kernels, not {other:?}"),
        }
    }
    bufs.remove(&Role::Output).expect("output buffer")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::gpu::fft::path_spectrum;
    use crate::backend::gpu::fft_plan::Path;
    use crate::operator::{GridOperator, OffsetTable, ToeplitzFft};
    use num_complex::Complex64;
    use rustfft::FftPlanner;

    /// The scaled kernel spectrum written out directly: the wrapped table
    /// in a full complex array, a complex 2-D FFT (rows, then columns
    /// through a transpose), divided by `mx my`. The reference of
    /// [`path_spectrum`].
    fn kernel_spectrum(
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
                let v =
                    table[(di + nx as isize - 1) as usize * w + (dj + ny as isize - 1) as usize];
                data[r * my + c] = Complex64::new(v, 0.0);
            }
        }
        let mut planner = FftPlanner::<f64>::new();
        planner.plan_fft_forward(my).process(&mut data);
        let mut t = vec![Complex64::default(); mx * my];
        for r in 0..mx {
            for c in 0..my {
                t[c * mx + r] = data[r * my + c];
            }
        }
        planner.plan_fft_forward(mx).process(&mut t);
        let s = 1.0 / (mx * my) as f64;
        for r in 0..mx {
            for c in 0..my {
                data[r * my + c] = t[c * mx + r] * s;
            }
        }
        data
    }

    /// The bins `0 ..= my / 2` of each row of a full `mx x my` spectrum:
    /// the spectrum of the real-row path (the others follow by symmetry).
    fn half_spectrum(full: &[Complex64], mx: usize, my: usize) -> Vec<Complex64> {
        let w = my / 2 + 1;
        (0..mx)
            .flat_map(|r| full[r * my..r * my + w].iter().copied())
            .collect()
    }

    /// The host's spectrum of the device matvec (real-to-complex, in
    /// parallel, in the path's layout) equals the complex transform written
    /// out, bin by bin, on both layouts, to f64 rounding of the transform
    /// (a few 1e-16 of the largest bin; bound 1e-13).
    #[test]
    fn path_spectrum_matches_the_complex_transform() {
        for (nx, ny) in [(1, 1), (1, 9), (9, 1), (33, 17), (40, 40), (5, 130)] {
            let table = lcg(11 + nx as u64 + ny as u64, (2 * nx - 1) * (2 * ny - 1));
            for path in [
                Path::Radix2,
                Path::Shared {
                    shared: 4096,
                    max_radix: 4096,
                    min_workgroups: 256,
                },
            ] {
                let plan = MatvecPlan::new(nx, ny, path);
                let (mx, my) = (plan.mx, plan.my);
                let full = kernel_spectrum(nx, ny, mx, my, &table);
                let want = if path == Path::Radix2 {
                    full
                } else {
                    half_spectrum(&full, mx, my)
                };
                let got = path_spectrum(nx, ny, mx, my, &table, path);
                assert_eq!(got.len(), want.len(), "{nx} x {ny} {path:?}");
                let largest = want.iter().map(|z| z.norm()).fold(0.0, f64::max);
                let worst = got
                    .iter()
                    .zip(&want)
                    .map(|(a, b)| (a - b).norm())
                    .fold(0.0, f64::max);
                assert!(
                    worst <= 1e-13 * largest,
                    "{nx} x {ny} {path:?}: {worst:e} of {largest:e}"
                );
            }
        }
    }

    fn lcg(seed: u64, len: usize) -> Vec<f64> {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        (0..len)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect()
    }

    fn error(nx: usize, ny: usize, path: Path) -> f64 {
        let table = lcg(7 + nx as u64, (2 * nx - 1) * (2 * ny - 1));
        let plan = MatvecPlan::new(nx, ny, path);
        let full = kernel_spectrum(nx, ny, plan.mx, plan.my, &table);
        let spectrum = half_spectrum(&full, plan.mx, plan.my);
        let x = lcg(3 + ny as u64, nx * ny);
        let y = run(&plan, &spectrum, &x);
        let mut op = ToeplitzFft::new(OffsetTable {
            nx,
            ny,
            values: &table,
        });
        let mut want = vec![0.0; nx * ny];
        op.apply(&x, &mut want);
        let num: f64 = y.iter().zip(&want).map(|(a, b)| (a - b).powi(2)).sum();
        let den: f64 = want.iter().map(|b| b * b).sum();
        (num / den).sqrt()
    }

    /// Every plan shape (one pass per axis; several passes with separate
    /// split and merge; odd, single-row and single-column grids) reproduces
    /// the CPU Toeplitz FFT to f64 rounding.
    #[test]
    fn twin_matches_the_cpu_toeplitz_fft() {
        for (nx, ny) in [
            (40, 40),
            (33, 17),
            (1, 9),
            (9, 1),
            (1, 1),
            (64, 48),
            (5, 130),
        ] {
            for path in [
                Path::Shared {
                    shared: 4096,
                    max_radix: 4096,
                    min_workgroups: 256,
                },
                Path::Shared {
                    shared: 64,
                    max_radix: 8,
                    min_workgroups: 1,
                },
                Path::Shared {
                    shared: 16,
                    max_radix: 2,
                    min_workgroups: 1,
                },
            ] {
                let e = error(nx, ny, path);
                assert!(e < 1e-12, "{nx} x {ny} {path:?}: {e:.2e}");
            }
        }
    }
}
