//! The steps of [`super::Path::Radix2`]: the complex-to-complex radix-2
//! passes, one dispatch each (the fallback and the traffic comparison's
//! reference).

use super::{Builder, Kernel, Params, Role, Step};

/// The previous plan: complex load, radix-2 passes, product, extract.
pub(super) fn radix2_steps(nx: usize, ny: usize, mx: usize, my: usize) -> Vec<Step> {
    let mut b = Builder {
        steps: Vec::new(),
        shared: 0,
        min_workgroups: 1,
    };
    let shape = [nx as u32, ny as u32, mx as u32, my as u32];
    let (nx64, ny64, mx64, my64) = (nx as u64, ny as u64, mx as u64, my as u64);
    let full = Params {
        i: shape,
        ..Default::default()
    };
    b.elementwise(
        Kernel::FftLoad,
        vec![Role::Input, Role::A, Role::B],
        full,
        mx64 * my64,
    );
    b.last().read = 4 * nx64 * ny64;
    b.last().written = 8 * mx64 * my64 + 8 * (mx64 - nx64) * my64;
    let mut in_b = false;
    let mut axis = |b: &mut Builder, n: usize, es: usize, bs: usize, batches: usize, sign: f32| {
        let tw = if n == mx {
            Role::ColTwiddle
        } else {
            Role::RowTwiddle
        };
        let mut ns = 1;
        while ns < n {
            let (src, dst) = if in_b {
                (Role::B, Role::A)
            } else {
                (Role::A, Role::B)
            };
            b.elementwise(
                Kernel::FftPass,
                vec![src, dst, tw],
                Params {
                    i: [n as u32, ns as u32, es as u32, bs as u32],
                    j: [batches as u32, 0, 0, 0],
                    f: [sign, 0.0, 0.0, 0.0],
                },
                (batches * n / 2) as u64,
            );
            let bytes = 8 * (batches * n) as u64;
            let s = b.last();
            s.read = bytes + 4 * n as u64;
            s.written = bytes;
            s.label = format!("fft_pass n {n} span {ns} x {batches}");
            in_b = !in_b;
            ns *= 2;
        }
        if in_b {
            Role::B
        } else {
            Role::A
        }
    };
    // Rows r >= nx are zero in both buffers: transform the first nx only.
    axis(&mut b, my, 1, my, nx, 1.0);
    let spec = axis(&mut b, mx, my, 1, my, 1.0);
    b.elementwise(
        Kernel::SpectralProduct,
        vec![spec, Role::Spectrum],
        Params {
            i: [(mx * my) as u32, 0, 0, 0],
            ..Default::default()
        },
        mx64 * my64,
    );
    b.last().read = 16 * mx64 * my64;
    b.last().written = 8 * mx64 * my64;
    axis(&mut b, mx, my, 1, my, -1.0);
    // Only the first nx rows of the result are needed.
    let out = axis(&mut b, my, 1, my, nx, -1.0);
    b.elementwise(
        Kernel::FftExtract,
        vec![out, Role::Output],
        full,
        nx64 * ny64,
    );
    b.last().read = 8 * nx64 * ny64;
    b.last().written = 4 * nx64 * ny64;
    b.steps
}
