//! The dispatch plan of the padded-FFT matvec (paper Eq. 7 by a zero-padded
//! convolution; physics.md section 3) and the memory-traffic model computed
//! from it. [`super::fft::FftMatvec`] records exactly these steps, so the
//! bytes reported here are those of the dispatches that run.
//!
//! Two paths:
//!
//! - [`Path::Shared`] (the default): a Stockham FFT whose every dispatch
//!   loads a block into workgroup memory, runs several radix-2 stages there
//!   and writes once (`shaders/fft_radix.wgsl`). The rows are real: each
//!   row of `my` reals is a complex row of `my / 2` (even and odd entries),
//!   transformed whole in one workgroup and split into its `my / 2 + 1`
//!   bins in the same dispatch (`FFT_SPLIT`); the inverse merges the bins
//!   on load (`FFT_MERGE`). Only the `nx` data rows are transformed, and
//!   the column passes skip the zero rows on their first load and write
//!   only the `nx` rows the output needs on their last store. The kernel
//!   spectrum is applied between the last forward and the first inverse
//!   column pass inside one dispatch (`shaders/fft_radix_product.wgsl`).
//! - [`Path::Radix2`]: the previous complex-to-complex radix-2 passes, one
//!   dispatch per pass (kept as the fallback where the workgroup limits
//!   forbid blocks, for the f16 spectrum, and as the reference of the
//!   traffic comparison).
//!
//! Bytes count every element a dispatch reads or writes in global memory
//! once, plus the twiddle table it binds; reads the shader skips (zero
//! padding) and writes it drops (discarded rows) are not counted.

mod radix2;
mod shared;

use super::engine::{Kernel, Params, WORKGROUP};
pub use super::shaders::{shared_elements, MAX_SHARED};
use radix2::radix2_steps;
use shared::shared_steps;

/// Smallest block worth a shared-memory pass; below it the plan falls back
/// to [`Path::Radix2`].
pub const MIN_SHARED: usize = 2 * WORKGROUP as usize;
/// Strided passes keep at least this many transforms per workgroup, so each
/// load and store touches runs of at least 32 bytes.
pub const MIN_BATCH: usize = 4;

/// A pass whose full blocks would give fewer workgroups than this takes
/// fewer groups per block (down to one), so that small grids still spread
/// over a GPU (twice the 132 SMs of an H100). CPU adapters (lavapipe run
/// each workgroup on one thread, and pay per workgroup) use twice their
/// threads instead ([`Path::Shared::min_workgroups`]).
pub const MIN_WORKGROUPS: u64 = 256;

/// `flags` bit: transforms of consecutive batches are adjacent (columns).
pub const FFT_BATCH_FAST: u32 = 1;
/// `flags` bit: conjugate twiddles (unscaled inverse transform).
pub const FFT_INVERSE: u32 = 2;
/// `flags` bit: split a whole complex row into the bins of a real row.
pub const FFT_SPLIT: u32 = 4;
/// `flags` bit: merge the bins of a real row into a complex row on load.
pub const FFT_MERGE: u32 = 8;

/// The buffers a step binds, by role.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    /// The grid vector `x` (`nx ny` f32).
    Input,
    /// The grid vector `y`.
    Output,
    /// Work buffers, ping-ponged.
    A,
    B,
    /// The kernel spectrum.
    Spectrum,
    /// Twiddles of the row axis and of the column axis.
    RowTwiddle,
    ColTwiddle,
}

/// Which FFT the matvec runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    /// Complex radix-2 passes, one dispatch each.
    Radix2,
    /// Workgroup-memory Stockham passes: `shared` complex elements per
    /// workgroup (the shader's array), radices at most `max_radix`, blocks
    /// shrunk until a pass has `min_workgroups` workgroups (or one group
    /// each).
    Shared {
        shared: usize,
        max_radix: usize,
        min_workgroups: u64,
    },
}

impl Path {
    /// The path a device allows: [`Path::for_limits`] of its workgroup
    /// storage, or [`Path::Radix2`] when it runs fewer than [`WORKGROUP`]
    /// invocations per workgroup (the block kernels' workgroup size).
    pub fn for_device(limits: &wgpu::Limits) -> Path {
        if limits.max_compute_invocations_per_workgroup < WORKGROUP
            || limits.max_compute_workgroup_size_x < WORKGROUP
        {
            return Path::Radix2;
        }
        Path::for_limits(limits.max_compute_workgroup_storage_size as u64)
    }

    /// The shared-memory path for an adapter allowing `storage_bytes` of
    /// workgroup memory, or [`Path::Radix2`] when that is below
    /// [`MIN_SHARED`] elements.
    pub fn for_limits(storage_bytes: u64) -> Path {
        let shared = shared_elements(storage_bytes);
        if shared < MIN_SHARED {
            Path::Radix2
        } else {
            Path::Shared {
                shared,
                max_radix: shared,
                min_workgroups: MIN_WORKGROUPS,
            }
        }
    }
}

/// One dispatch.
#[derive(Debug, Clone)]
pub struct Step {
    pub kernel: Kernel,
    pub bufs: Vec<Role>,
    pub params: Params,
    /// Workgroups.
    pub groups: u64,
    /// Bytes read and written in global memory.
    pub read: u64,
    pub written: u64,
    pub label: String,
}

/// Totals of a plan.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Traffic {
    pub dispatches: usize,
    pub read: u64,
    pub written: u64,
}

impl Traffic {
    /// Bytes moved.
    pub fn bytes(&self) -> u64 {
        self.read + self.written
    }
}

/// The steps of one matvec `y = L x` on an `nx x ny` grid.
#[derive(Debug, Clone)]
pub struct MatvecPlan {
    pub nx: usize,
    pub ny: usize,
    pub mx: usize,
    pub my: usize,
    pub path: Path,
    pub steps: Vec<Step>,
}

/// Padded power-of-two size for a grid side `n` (at least `2 n - 1`).
pub fn padded(n: usize) -> usize {
    (2 * n.max(1) - 1).next_power_of_two()
}

/// Padded shape `(mx, my)` of a path: the real rows of the shared path need
/// an even row length.
pub fn padded_shape(nx: usize, ny: usize, path: Path) -> (usize, usize) {
    match path {
        Path::Radix2 => (padded(nx), padded(ny)),
        Path::Shared { .. } => (padded(nx), padded(ny).max(2)),
    }
}

/// Refuse a grid whose padded transform the shaders cannot index: every
/// size and offset of a pass is a `u32`, so the padded `mx x my` elements
/// (sides `2 n - 1` rounded up to a power of two, with checked arithmetic)
/// must number at most `u32::MAX`.
pub fn check_plan_size(nx: usize, ny: usize) -> Result<(), String> {
    let side = |n: usize| {
        n.max(1)
            .checked_mul(2)
            .and_then(|m| (m - 1).checked_next_power_of_two())
    };
    let elements = side(nx)
        .zip(side(ny))
        .and_then(|(mx, my)| mx.checked_mul(my.max(2)))
        .filter(|&e| e <= u32::MAX as usize);
    match elements {
        Some(_) => Ok(()),
        None => Err(format!(
            "a {nx} x {ny} grid pads to more than 2^32 transform elements, beyond what the GPU shaders index (u32)"
        )),
    }
}

/// Complex elements of each work buffer and of the spectrum.
pub fn work_elements(nx: usize, ny: usize, path: Path) -> usize {
    let (mx, my) = padded_shape(nx, ny, path);
    match path {
        Path::Radix2 => mx * my,
        Path::Shared { .. } => mx * (my / 2 + 1),
    }
}

/// Radices (powers of two, product `n`, each at most `max_radix`), as equal
/// as possible, largest first.
pub fn radices(n: usize, max_radix: usize) -> Vec<usize> {
    assert!(n.is_power_of_two() && max_radix >= 2);
    let bits = n.trailing_zeros() as usize;
    let max_bits = (max_radix.ilog2() as usize).max(1);
    let passes = bits.div_ceil(max_bits).max(1);
    (0..passes)
        .map(|p| 1usize << (bits / passes + usize::from(p < bits % passes)))
        .collect()
}

/// Memory layout of one operand of a radix pass, in f32 units: element
/// `pos` of transform `b` is at `b bsf + pos esf` (real part, imaginary
/// part next); component `c` exists when `2 pos + c < lim` (zero on load,
/// dropped on store otherwise).
#[derive(Debug, Clone, Copy)]
struct Layout {
    bsf: usize,
    esf: usize,
    lim: usize,
}

/// One workgroup-memory Stockham pass.
#[derive(Debug, Clone, Copy)]
struct Radix {
    n: usize,
    ns: usize,
    r: usize,
    batches: usize,
    flags: u32,
    input: Layout,
    output: Layout,
    /// Length of the twiddle table (a power of two).
    table: usize,
    /// Groups per workgroup (a power of two).
    t: usize,
}

impl Radix {
    /// Workgroups of the pass: batch-fast passes give each workgroup `t`
    /// transforms of one group index, the others `t` consecutive groups.
    fn workgroups(&self) -> u64 {
        let per = self.t as u64;
        let groups = (self.n / self.r) as u64;
        if self.flags & FFT_BATCH_FAST != 0 {
            groups * (self.batches as u64).div_ceil(per)
        } else {
            (groups * self.batches as u64).div_ceil(per)
        }
    }

    fn params(&self) -> Params {
        let u = |v: usize| u32::try_from(v).expect("FFT plan sizes fit in u32");
        Params {
            i: [
                u(self.n),
                u(self.ns),
                self.r.trailing_zeros(),
                u(self.batches),
            ],
            j: [
                self.flags | (self.t.trailing_zeros() << 8),
                u(self.input.bsf),
                u(self.input.esf),
                u(self.input.lim),
            ],
            f: [
                f32::from_bits(u(self.output.bsf)),
                f32::from_bits(u(self.output.esf)),
                f32::from_bits(u(self.output.lim)),
                f32::from_bits(self.table.trailing_zeros()),
            ],
        }
    }
}

/// Workgroup grid `(x, y)` of `groups` workgroups.
pub fn grid(groups: u64) -> (u32, u32) {
    super::plan::grid(groups)
}

struct Builder {
    steps: Vec<Step>,
    shared: usize,
    min_workgroups: u64,
}

impl Builder {
    fn radix(&mut self, kernel: Kernel, bufs: [Role; 2], twiddle: (Role, usize), mut p: Radix) {
        p.table = twiddle.1;
        p.t = self.shared / p.r;
        while p.t > 1 && p.workgroups() < self.min_workgroups {
            p.t /= 2;
        }
        let per = |l: Layout, n: usize| l.lim.min(2 * n) as u64;
        let read_n = p.n + usize::from(p.flags & FFT_MERGE != 0);
        let write_n = p.n + usize::from(p.flags & FFT_SPLIT != 0);
        let mut read = 4 * p.batches as u64 * per(p.input, read_n) + 8 * twiddle.1 as u64;
        let mut roles = vec![bufs[0], bufs[1], twiddle.0];
        if kernel == Kernel::FftRadixProduct {
            read += 8 * (p.batches * p.n) as u64;
            roles.push(Role::Spectrum);
        }
        let kind = if p.flags & FFT_INVERSE != 0 {
            "inverse"
        } else {
            "forward"
        };
        self.steps.push(Step {
            kernel,
            bufs: roles,
            params: p.params(),
            groups: p.workgroups(),
            read,
            written: 4 * p.batches as u64 * per(p.output, write_n),
            label: format!(
                "{} {kind} n {} radix {} span {} x {}",
                kernel.file().trim_end_matches(".wgsl"),
                p.n,
                p.r,
                p.ns,
                p.batches
            ),
        });
    }

    fn elementwise(&mut self, kernel: Kernel, bufs: Vec<Role>, params: Params, threads: u64) {
        self.steps.push(Step {
            kernel,
            bufs,
            params,
            groups: threads.div_ceil(WORKGROUP as u64).max(1),
            read: 0,
            written: 0,
            label: kernel.file().trim_end_matches(".wgsl").to_string(),
        });
    }

    fn last(&mut self) -> &mut Step {
        self.steps.last_mut().expect("a step was added")
    }
}

impl MatvecPlan {
    /// The plan of an `nx x ny` grid on `path`.
    pub fn new(nx: usize, ny: usize, path: Path) -> Self {
        assert!(nx > 0 && ny > 0, "grid must be non-empty");
        let (mx, my) = padded_shape(nx, ny, path);
        let steps = match path {
            Path::Radix2 => radix2_steps(nx, ny, mx, my),
            Path::Shared {
                shared,
                max_radix,
                min_workgroups,
            } => shared_steps(
                nx,
                ny,
                mx,
                my,
                shared,
                max_radix.min(shared),
                min_workgroups,
            ),
        };
        Self {
            nx,
            ny,
            mx,
            my,
            path,
            steps,
        }
    }

    /// Dispatches and bytes of one matvec.
    pub fn traffic(&self) -> Traffic {
        Traffic {
            dispatches: self.steps.len(),
            read: self.steps.iter().map(|s| s.read).sum(),
            written: self.steps.iter().map(|s| s.written).sum(),
        }
    }

    /// The floor of any FFT matvec of this grid: read `x` and the real-input
    /// (half) spectrum, write `y`, and one write and one read of the `nx`
    /// transformed rows (`my / 2 + 1` bins each) in each direction: a
    /// padded 2-D transform that does not fit on chip must store its rows
    /// once between the row and the column transforms, forward and back
    /// (three dispatches: rows, columns with the product, rows back).
    pub fn floor(&self) -> Traffic {
        let (nx, ny, mx) = (self.nx as u64, self.ny as u64, self.mx as u64);
        let w = (self.my / 2 + 1) as u64;
        let grid = 4 * nx * ny;
        let rows = 8 * nx * w;
        Traffic {
            dispatches: 3,
            read: grid + 8 * mx * w + 2 * rows,
            written: grid + 2 * rows,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shared(kib: u64) -> Path {
        Path::for_limits(kib * 1024)
    }

    #[test]
    fn radices_multiply_to_the_length_and_respect_the_bound() {
        for bits in 0..=14 {
            let n = 1usize << bits;
            for max in [2, 8, 64, 1024, 4096] {
                let rs = radices(n, max);
                assert_eq!(rs.iter().product::<usize>(), n, "{n} {max}");
                assert!(rs.iter().all(|&r| r <= max.max(1)), "{n} {max}: {rs:?}");
                assert!(rs.windows(2).all(|w| w[0] >= w[1] && w[0] <= 2 * w[1]));
            }
        }
    }

    #[test]
    fn workgroup_storage_sizes_the_block() {
        assert_eq!(shared_elements(16 * 1024), 2048);
        assert_eq!(shared_elements(48 * 1024), 4096);
        assert_eq!(shared_elements(1 << 20), MAX_SHARED);
        assert_eq!(Path::for_limits(2048), Path::Radix2);
    }

    /// A grid whose rows and columns each fit one block: three dispatches
    /// (rows, columns with the product, rows back) that move exactly the
    /// floor.
    #[test]
    fn small_grid_moves_the_floor() {
        let plan = MatvecPlan::new(512, 512, shared(32));
        let t = plan.traffic();
        assert_eq!(t.dispatches, 3);
        let twiddles = 8 * (2 * 1024 + 1024) as u64;
        assert_eq!(t.read, plan.floor().read + twiddles);
        assert_eq!(t.written, plan.floor().written);
    }

    /// Issue #20's targets at 4096^2 on adapters with 32 KiB and more of
    /// workgroup memory: at most 1/4 of the radix-2 bytes and at most 3x
    /// the floor.
    #[test]
    fn traffic_targets_at_4096() {
        for kib in [32, 48, 64] {
            let plan = MatvecPlan::new(4096, 4096, shared(kib));
            let old = MatvecPlan::new(4096, 4096, Path::Radix2).traffic();
            let (b, f) = (plan.traffic().bytes(), plan.floor().bytes());
            assert!(4 * b <= old.bytes(), "{kib} KiB: {b} vs {}", old.bytes());
            assert!(b <= 3 * f, "{kib} KiB: {b} vs floor {f}");
        }
    }

    /// Every radix step reads and writes inside its operands: the largest
    /// element touched lies within the buffer of its role.
    #[test]
    fn steps_stay_inside_their_buffers() {
        for (nx, ny) in [(33, 17), (1, 9), (9, 1), (64, 48)] {
            for path in [
                shared(32),
                Path::Shared {
                    shared: 64,
                    max_radix: 8,
                    min_workgroups: 1,
                },
            ] {
                let plan = MatvecPlan::new(nx, ny, path);
                let work = 2 * work_elements(nx, ny, path);
                let size = |role: Role| match role {
                    Role::Input | Role::Output => nx * ny,
                    _ => work,
                };
                for s in plan.steps.iter().filter(|s| s.kernel == Kernel::FftRadix) {
                    let p = s.params;
                    let (n, batches) = (p.i[0] as usize, p.i[3] as usize);
                    let extra = usize::from(p.j[0] & (FFT_SPLIT | FFT_MERGE) != 0);
                    let reach = |bsf: usize, esf: usize, lim: usize| {
                        let last = (n + extra - 1).min((lim - 1) / 2);
                        (batches - 1) * bsf + last * esf + (lim.min(2 * last + 2) - 2 * last)
                    };
                    let (a, b, c) = (p.j[1] as usize, p.j[2] as usize, p.j[3] as usize);
                    assert!(reach(a, b, c) <= size(s.bufs[0]), "{nx}x{ny} {}", s.label);
                    let (a, b, c) = (
                        p.f[0].to_bits() as usize,
                        p.f[1].to_bits() as usize,
                        p.f[2].to_bits() as usize,
                    );
                    assert!(reach(a, b, c) <= size(s.bufs[1]), "{nx}x{ny} {}", s.label);
                }
            }
        }
    }
}
