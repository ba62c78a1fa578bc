//! `viscoslide gpu`: list adapters with their limits and features;
//! `viscoslide gpu plan`: the dispatch plan and memory traffic of the GPU
//! matvec for a grid (no device needed); `viscoslide gpu bench`: the
//! coefficient table and the matvec timed on the device
//! ([`super::gpu_bench`]).

use crate::backend::gpu;
use crate::backend::gpu::fft_plan::{shared_elements, MatvecPlan, Path, Traffic};
use crate::error::{Error, Result};

#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct GpuArgs {
    #[command(subcommand)]
    pub command: Option<GpuCommand>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, clap::Subcommand)]
pub enum GpuCommand {
    /// Dispatches and bytes moved per matvec (the padded-FFT convolution of
    /// paper Eq. 7) on the default and the radix-2 path, the floor, and the
    /// time they predict at a given memory bandwidth.
    Plan(PlanArgs),
    /// Time the coefficient table and the matvec of an n x n grid of a
    /// config's material on the device (medians), check them against the
    /// host's f64 answers, and compare the bytes moved with the plan.
    Bench(super::gpu_bench::BenchArgs),
}

#[derive(Debug, clap::Args)]
pub struct PlanArgs {
    /// Grid side (nx).
    #[arg(long)]
    pub n: usize,
    /// Grid side along y (default: n).
    #[arg(long)]
    pub ny: Option<usize>,
    /// Workgroup storage of the adapter [KiB] (WebGPU guarantees 16; an
    /// H100 under Vulkan allows 48, lavapipe 32).
    #[arg(long, default_value_t = 48)]
    pub shared_kib: u64,
    /// Largest storage binding of the adapter [MiB] (lavapipe: 128): arrays
    /// above it are bound in windows.
    #[arg(long, default_value_t = 128)]
    pub binding_mib: u64,
    /// Largest buffer of the adapter [MiB] (lavapipe: 2048).
    #[arg(long, default_value_t = 2048)]
    pub buffer_mib: u64,
    /// Memory bandwidth of the prediction [TB/s] (H100 SXM: about 3).
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub bandwidth: f64,
    /// List every dispatch of the default path.
    #[arg(long)]
    pub steps: bool,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: GpuArgs) -> Result<()> {
    match args.command {
        Some(GpuCommand::Plan(p)) => return plan(p),
        Some(GpuCommand::Bench(b)) => return super::gpu_bench::run(b),
        None => {}
    }
    let adapters = gpu::adapter_details();
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&adapters).expect("serialisable")
        );
        return Ok(());
    }
    if adapters.is_empty() {
        println!(
            "no GPU adapter found (install a Vulkan driver; on CPU-only Linux: apt-get install mesa-vulkan-drivers libvulkan1)"
        );
    }
    for (k, a) in adapters.iter().enumerate() {
        let l = &a.limits;
        println!("[{k}] {}", a.summary);
        println!(
            "    workgroup storage {} KiB, {} invocations per workgroup, {} storage buffers per stage, largest buffer {} MiB, {} workgroups per dimension",
            l.max_compute_workgroup_storage_size >> 10,
            l.max_compute_invocations_per_workgroup,
            l.max_storage_buffers_per_shader_stage,
            l.max_buffer_size >> 20,
            l.max_compute_workgroups_per_dimension
        );
        println!("    features: {}", a.features.join(" "));
    }
    Ok(())
}

fn plan(args: PlanArgs) -> Result<()> {
    if args.n == 0 || args.ny == Some(0) {
        return Err(Error::Invalid(format!(
            "--n {} / --ny {}: a grid needs at least one cell per side",
            args.n,
            args.ny.unwrap_or(args.n)
        )));
    }
    for (flag, value) in [
        ("--shared-kib", args.shared_kib),
        ("--binding-mib", args.binding_mib),
        ("--buffer-mib", args.buffer_mib),
    ] {
        if value == 0 {
            return Err(Error::Invalid(format!(
                "{flag} 0: an adapter's limit is at least 1 (WebGPU guarantees 16 KiB of workgroup storage, 128 MiB per binding, 256 MiB per buffer)"
            )));
        }
    }
    if !(args.bandwidth.is_finite() && args.bandwidth > 0.0) {
        return Err(Error::Invalid(format!(
            "--bandwidth {} TB/s must be positive and finite",
            args.bandwidth
        )));
    }
    let (nx, ny) = (args.n, args.ny.unwrap_or(args.n));
    crate::backend::gpu::fft_plan::check_plan_size(nx, ny).map_err(Error::Invalid)?;
    let path = Path::for_limits(args.shared_kib.saturating_mul(1024));
    let new = MatvecPlan::new(nx, ny, path);
    let old = MatvecPlan::new(nx, ny, Path::Radix2);
    let floor = new.floor();
    let arrays = arrays(&args, nx, ny, path);
    let ms = |t: Traffic| t.bytes() as f64 / (args.bandwidth * 1e12) * 1e3;
    if args.json {
        let row = |t: Traffic| {
            serde_json::json!({
                "dispatches": t.dispatches, "read": t.read, "written": t.written,
                "bytes": t.bytes(), "predicted_ms": ms(t),
            })
        };
        let v = serde_json::json!({
            "nx": nx, "ny": ny, "padded": [new.mx, new.my],
            "shared_elements": shared_elements(args.shared_kib.saturating_mul(1024)),
            "path": format!("{:?}", new.path),
            "bandwidth_tb_s": args.bandwidth,
            "default": row(new.traffic()),
            "radix2": row(old.traffic()),
            "floor": row(floor),
            "arrays": arrays,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    println!(
        "matvec of a {nx} x {ny} grid, padded {} x {}; {} KiB of workgroup memory: {:?}",
        new.mx, new.my, args.shared_kib, new.path
    );
    println!(
        "{:<22} {:>10} {:>12} {:>12} {:>12} {:>14}",
        "", "dispatches", "read [MB]", "written [MB]", "total [MB]", "at bandwidth"
    );
    let mb = |b: u64| b as f64 / 1e6;
    for (name, t) in [
        ("radix-2 passes", old.traffic()),
        ("default", new.traffic()),
        ("floor", floor),
    ] {
        println!(
            "{name:<22} {:>10} {:>12.1} {:>12.1} {:>12.1} {:>11.3} ms",
            t.dispatches,
            mb(t.read),
            mb(t.written),
            mb(t.bytes()),
            ms(t)
        );
    }
    let (n, o, f) = (
        new.traffic().bytes() as f64,
        old.traffic().bytes() as f64,
        floor.bytes() as f64,
    );
    println!(
        "default / radix-2: {:.3}; default / floor: {:.2}",
        n / o,
        n / f
    );
    println!("{}", arrays["text"].as_str().unwrap_or_default());
    if args.steps {
        for s in &new.steps {
            println!(
                "  {:<60} {:>9} groups {:>10.1} MB read {:>10.1} MB written",
                s.label,
                s.groups,
                mb(s.read),
                mb(s.written)
            );
        }
    }
    Ok(())
}

/// How the arrays of the default path sit in the adapter's bindings
/// (`--binding-mib`, `--buffer-mib`): the FFT work buffers, the spectrum
/// and the grid vectors, each in one buffer, bound in windows of at most
/// one binding where larger ([`gpu::split`]); `text` says so in one line,
/// or why the grid does not fit.
fn arrays(args: &PlanArgs, nx: usize, ny: usize, path: Path) -> serde_json::Value {
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: args.binding_mib.saturating_mul(1 << 20),
        max_buffer_size: args.buffer_mib.saturating_mul(1 << 20),
        max_storage_buffers_per_shader_stage: u32::MAX,
        ..wgpu::Limits::default()
    };
    let vector = 4 * nx as u64 * ny as u64;
    let binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let window = gpu::split::window_bytes(binding, 256);
    let vector_windows = if vector <= binding {
        1
    } else {
        gpu::split::windows(vector, window)
    };
    let fft = gpu::fft::check_device(&limits, "the adapter", nx, ny, path);
    let mb = |b: u64| b as f64 / 1e6;
    let split = |w: u64| match w {
        1 => "one binding".to_string(),
        w => format!("{w} windows of {} MiB", window >> 20),
    };
    let text = match &fft {
        _ if vector > limits.max_buffer_size => format!(
            "arrays: a grid vector ({:.1} MB) exceeds one buffer ({} MiB): does not fit",
            mb(vector),
            args.buffer_mib
        ),
        Err(e) => format!("arrays: {e}"),
        Ok((bytes, w)) => format!(
            "arrays: FFT work buffers and spectrum {:.1} MB each in {}; grid vectors {:.1} MB each in {} (largest binding {} MiB)",
            mb(*bytes),
            split(*w),
            mb(vector),
            split(vector_windows),
            args.binding_mib
        ),
    };
    let (bytes, windows) = fft
        .as_ref()
        .map_or((None, None), |&(b, w)| (Some(b), Some(w)));
    serde_json::json!({
        "binding_bytes": binding,
        "window_bytes": window,
        "fft_buffer_bytes": bytes,
        "fft_buffer_windows": windows,
        "vector_bytes": vector,
        "vector_windows": vector_windows,
        "text": text,
    })
}
