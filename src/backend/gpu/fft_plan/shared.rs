//! The steps of [`super::Path::Shared`]: workgroup-memory Stockham passes
//! over real rows, the zero rows skipped, the spectral product fused (the
//! module docs of [`super`]).

use super::{
    radices, Builder, Kernel, Layout, Params, Radix, Role, Step, FFT_BATCH_FAST, FFT_INVERSE,
    FFT_MERGE, FFT_SPLIT, MIN_BATCH,
};

/// The shared-memory plan (module docs).
pub(super) fn shared_steps(
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    shared: usize,
    max_radix: usize,
    min_workgroups: u64,
) -> Vec<Step> {
    let mut b = Builder {
        steps: Vec::new(),
        shared,
        min_workgroups,
    };
    let h = my / 2;
    let w = h + 1;
    // Strided and multi-pass transforms keep MIN_BATCH transforms per block.
    let strided = (shared / MIN_BATCH).min(max_radix).max(2);
    let real = Layout {
        bsf: ny,
        esf: 2,
        lim: ny,
    };
    let bins = Layout {
        bsf: 2 * w,
        esf: 2,
        lim: 2 * w,
    };
    let packed = Layout {
        bsf: 2 * h,
        esf: 2,
        lim: 2 * h,
    };
    let column = |rows: usize| Layout {
        bsf: 2,
        esf: 2 * w,
        lim: 2 * rows,
    };
    let row_tw = (Role::RowTwiddle, my);
    let col_tw = (Role::ColTwiddle, mx);
    let mut cur = Role::A;
    let other = |r: Role| if r == Role::A { Role::B } else { Role::A };

    // Forward rows: real x -> nx rows of w bins in A.
    if h <= max_radix {
        b.radix(
            Kernel::FftRadix,
            [Role::Input, Role::A],
            row_tw,
            Radix {
                n: h,
                ns: 1,
                r: h,
                batches: nx,
                flags: FFT_SPLIT,
                input: real,
                output: bins,
                table: 0,
                t: 0,
            },
        );
    } else {
        let rs = radices(h, strided);
        let mut ns = 1;
        let mut src = Role::Input;
        let mut dst = Role::A;
        for (k, &r) in rs.iter().enumerate() {
            b.radix(
                Kernel::FftRadix,
                [src, dst],
                row_tw,
                Radix {
                    n: h,
                    ns,
                    r,
                    batches: nx,
                    flags: 0,
                    input: if k == 0 { real } else { packed },
                    output: packed,
                    table: 0,
                    t: 0,
                },
            );
            ns *= r;
            src = dst;
            dst = other(dst);
        }
        split_merge(&mut b, Kernel::FftSplit, src, dst, nx, h, my);
        cur = dst;
    }

    // Columns: forward passes, the product fused into the last forward and
    // the first inverse pass, inverse passes.
    let rs = radices(mx, strided);
    let last = rs.len() - 1;
    let mut ns = 1;
    for (k, &r) in rs.iter().enumerate() {
        let fused = k == last;
        let next = other(cur);
        b.radix(
            if fused {
                Kernel::FftRadixProduct
            } else {
                Kernel::FftRadix
            },
            [cur, next],
            col_tw,
            Radix {
                n: mx,
                ns,
                r,
                batches: w,
                flags: FFT_BATCH_FAST,
                input: column(if k == 0 { nx } else { mx }),
                output: column(if fused && last == 0 { nx } else { mx }),
                table: 0,
                t: 0,
            },
        );
        ns *= r;
        cur = next;
    }
    // The fused pass did the first inverse pass (radix rs[last]).
    let mut ns = rs[last];
    for k in (0..last).rev() {
        let next = other(cur);
        b.radix(
            Kernel::FftRadix,
            [cur, next],
            col_tw,
            Radix {
                n: mx,
                ns,
                r: rs[k],
                batches: w,
                flags: FFT_BATCH_FAST | FFT_INVERSE,
                input: column(mx),
                output: column(if k == 0 { nx } else { mx }),
                table: 0,
                t: 0,
            },
        );
        ns *= rs[k];
        cur = next;
    }

    // Inverse rows: nx rows of w bins -> real y.
    if h <= max_radix {
        b.radix(
            Kernel::FftRadix,
            [cur, Role::Output],
            row_tw,
            Radix {
                n: h,
                ns: 1,
                r: h,
                batches: nx,
                flags: FFT_MERGE | FFT_INVERSE,
                input: bins,
                output: real,
                table: 0,
                t: 0,
            },
        );
    } else {
        let next = other(cur);
        split_merge(&mut b, Kernel::FftMerge, cur, next, nx, h, my);
        cur = next;
        let rs = radices(h, strided);
        let mut ns = 1;
        for (k, &r) in rs.iter().enumerate() {
            let last = k == rs.len() - 1;
            let next = if last { Role::Output } else { other(cur) };
            b.radix(
                Kernel::FftRadix,
                [cur, next],
                row_tw,
                Radix {
                    n: h,
                    ns,
                    r,
                    batches: nx,
                    flags: FFT_INVERSE,
                    input: packed,
                    output: if last { real } else { packed },
                    table: 0,
                    t: 0,
                },
            );
            ns *= r;
            cur = next;
        }
    }
    b.steps
}

/// The split (rows of `h` complex -> `h + 1` bins) or merge (back) of
/// multi-pass real rows, as a dispatch of its own.
fn split_merge(
    b: &mut Builder,
    kernel: Kernel,
    src: Role,
    dst: Role,
    rows: usize,
    h: usize,
    my: usize,
) {
    let (n_in, n_out) = if kernel == Kernel::FftSplit {
        (h, h + 1)
    } else {
        (h + 1, h)
    };
    b.elementwise(
        kernel,
        vec![src, dst, Role::RowTwiddle],
        Params {
            i: [rows as u32, h as u32, 0, 0],
            ..Default::default()
        },
        (rows * n_out) as u64,
    );
    let s = b.last();
    s.read = 8 * (rows * n_in + my) as u64;
    s.written = 8 * (rows * n_out) as u64;
}
