//! `viscoslide gpu bench`: how fast this machine's GPU computes the
//! influence-coefficient table (paper Eq. 4 and 6, `shaders/coefficients.wgsl`)
//! and the matvec of the contact iteration (the padded FFT convolution of
//! paper Eq. 7) on an `n x n` grid of a config's material and speed, how far
//! both are from the host's f64 answers, and how many bytes the matvec moves
//! against the traffic model ([`crate::backend::gpu::fft_plan`]).
//!
//! Times are medians over `--rounds` rounds after one warm-up round; a
//! table round ends with the table read back and scaled on the host (as a
//! solve uses it), a matvec round submits `--batch` matvecs and waits for
//! the device, so the per-matvec time excludes the readback.

use std::time::Instant;

use crate::backend::gpu::engine::Engine;
use crate::backend::gpu::{coefficients, GpuBackend, GpuContext, GpuOptions};
use crate::backend::Backend;
use crate::error::{Error, Result};
use crate::operator::{GridOperator, OffsetTable, ToeplitzFft};
use crate::problem::Problem;
use crate::response::Grid;

#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Grid side: the table is `(2n-1)^2` offsets, the matvec's FFT is
    /// padded to `2n x 2n`. The cell is the config's length over n.
    #[arg(long)]
    pub n: usize,
    /// Timed rounds (after one warm-up round); medians are reported.
    #[arg(long, default_value_t = 5)]
    pub rounds: usize,
    /// Matvecs submitted per timed matvec round.
    #[arg(long, default_value_t = 10)]
    pub batch: usize,
    /// Skip the comparisons with the host (sampled table entries, and the
    /// CPU's f64 matvec, which needs about 40 bytes per padded cell).
    #[arg(long)]
    pub no_check: bool,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Offsets of the table compared with the host's f64 coefficients.
const SAMPLED_OFFSETS: usize = 4096;

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

/// A deterministic stream of indices below `m` (64-bit LCG, high bits).
fn indices(m: usize, count: usize) -> impl Iterator<Item = usize> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..count).map(move |_| {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((s >> 33) as usize) % m
    })
}

pub fn run(args: BenchArgs) -> Result<()> {
    let n = args.n;
    if n == 0 || args.rounds == 0 || args.batch == 0 {
        return Err(Error::Invalid(format!(
            "--n {n}, --rounds {}, --batch {}: each must be at least 1",
            args.rounds, args.batch
        )));
    }
    crate::backend::gpu::fft_plan::check_plan_size(n, n).map_err(Error::Invalid)?;
    let cfg = args.config.load()?;
    let problem = Problem::from_config(&cfg)?;
    if problem.layer.is_some() {
        return Err(Error::Invalid(
            "gpu bench times the half-space table computed on the device; a [layer]'s table is computed on the host: remove [layer]".into(),
        ));
    }
    let (ax, _) = problem.surface.cell();
    let length = ax * problem.surface.nx as f64;
    let cell = length / n as f64;
    let kernel = problem.sliding_kernel()?;

    let ctx = GpuContext::open()?;
    let adapter = ctx.adapter.clone();
    let progress = |what: &str| {
        if !args.json {
            eprintln!("{what}");
        }
    };

    progress(&format!(
        "{adapter}\ncoefficient table of {n} x {n} cells ({} creep terms), {} rounds",
        problem.material.spectrum.terms.len(),
        args.rounds
    ));
    let mut engine = Engine::new(ctx);
    let mut table_s = Vec::with_capacity(args.rounds);
    let mut table = Vec::new();
    for round in 0..=args.rounds {
        let t = Instant::now();
        table = coefficients::coefficient_table(
            &mut engine,
            kernel.response(),
            &Grid::square(n, n, cell)?,
        )?;
        if round > 0 {
            table_s.push(t.elapsed().as_secs_f64());
        }
    }
    let offsets = OffsetTable {
        nx: n,
        ny: n,
        values: &table,
    };
    let table_error = (!args.no_check).then(|| {
        let self_coefficient = offsets.get(0, 0).abs();
        let side = 2 * n - 1;
        let mut worst = 0.0f64;
        for k in indices(side * side, SAMPLED_OFFSETS).chain([(n - 1) * side + n - 1]) {
            let (i, j) = (
                (k / side) as isize - (n as isize - 1),
                (k % side) as isize - (n as isize - 1),
            );
            let host = kernel
                .coefficient(i as f64 * cell, j as f64 * cell, cell, cell)
                .total();
            worst = worst.max((offsets.get(i, j) - host).abs() / self_coefficient);
        }
        worst
    });

    progress(&format!(
        "matvec, {} rounds of {} matvecs",
        args.rounds, args.batch
    ));
    let mut backend = GpuBackend::with_engine(engine, n, n, &table, GpuOptions::default())?;
    let plan = backend.fft_plan().cloned();
    let host_x: Vec<f64> = indices(1009, n * n).map(|k| k as f64 / 1009.0).collect();
    let mut x = backend.zeros(n * n);
    backend.upload(&host_x, &mut x);
    let mut y = backend.zeros(n * n);
    let mut matvec_s = Vec::with_capacity(args.rounds);
    for round in 0..=args.rounds {
        backend.synchronize();
        let t = Instant::now();
        for _ in 0..args.batch {
            backend.apply(&x, &mut y);
        }
        backend.synchronize();
        if round > 0 {
            matvec_s.push(t.elapsed().as_secs_f64() / args.batch as f64);
        }
    }
    let (matvec_error, cpu_matvec_s) = if args.no_check {
        (None, None)
    } else {
        progress("the host's f64 matvec of the same table");
        let mut device_y = vec![0.0; n * n];
        backend.download(&y, &mut device_y);
        drop(backend);
        let mut op = ToeplitzFft::new(offsets);
        let mut host_y = vec![0.0; n * n];
        let mut times = Vec::new();
        for _ in 0..3 {
            let t = Instant::now();
            op.apply(&host_x, &mut host_y);
            times.push(t.elapsed().as_secs_f64());
        }
        let num: f64 = device_y
            .iter()
            .zip(&host_y)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        let den: f64 = host_y.iter().map(|b| b * b).sum();
        (Some((num / den).sqrt()), Some(median(&times)))
    };

    let table_median = median(&table_s);
    let matvec_median = median(&matvec_s);
    let traffic = plan.as_ref().map(|p| (p.traffic(), p.floor(), p.mx, p.my));
    let gbs = |bytes: u64| bytes as f64 / matvec_median / 1e9;
    let v = serde_json::json!({
        "adapter": adapter,
        "n": n,
        "cell_m": cell,
        "speed_m_s": problem.speed,
        "creep_terms": problem.material.spectrum.terms.len(),
        "rounds": args.rounds,
        "batch": args.batch,
        "table_seconds": table_median,
        "table_seconds_all": table_s,
        "table_max_error_vs_host": table_error,
        "table_sampled_offsets": (!args.no_check).then_some(SAMPLED_OFFSETS + 1),
        "matvec_seconds": matvec_median,
        "matvec_seconds_all": matvec_s,
        "matvec_relative_l2_vs_host": matvec_error,
        "host_matvec_seconds": cpu_matvec_s,
        "host_threads": rayon::current_num_threads(),
        "padded": traffic.map(|t| [t.2, t.3]),
        "path": plan.as_ref().map(|p| format!("{:?}", p.path)),
        "dispatches": traffic.map(|t| t.0.dispatches),
        "bytes": traffic.map(|t| t.0.bytes()),
        "floor_bytes": traffic.map(|t| t.1.bytes()),
        "achieved_gb_s": traffic.map(|t| gbs(t.0.bytes())),
    });
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    println!("{adapter}");
    println!(
        "coefficient table {n} x {n} ({} offsets): median {:.3} ms{}",
        offsets.values.len(),
        table_median * 1e3,
        table_error.map_or(String::new(), |e| format!(
            "; worst of {} sampled offsets against the host: {e:.2e} of the self coefficient",
            SAMPLED_OFFSETS + 1
        ))
    );
    println!(
        "matvec {n} x {n}: median {:.3} ms{}",
        matvec_median * 1e3,
        matvec_error.map_or(String::new(), |e| format!(
            "; relative L2 {e:.2e} against the host's f64 matvec ({:.1} ms on {} threads)",
            cpu_matvec_s.unwrap_or(f64::NAN) * 1e3,
            rayon::current_num_threads()
        ))
    );
    if let Some((t, floor, mx, my)) = traffic {
        println!(
            "  padded {mx} x {my}, {} dispatches, {:.1} MB per matvec ({:.2}x the floor's {:.1} MB): {:.1} GB/s achieved",
            t.dispatches,
            t.bytes() as f64 / 1e6,
            t.bytes() as f64 / floor.bytes() as f64,
            floor.bytes() as f64 / 1e6,
            gbs(t.bytes())
        );
    }
    Ok(())
}
