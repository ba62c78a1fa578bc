//! `viscoslide solve CONFIG --out DIR`

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};

use crate::backend::gpu::{GpuBackend, GpuContext};
use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::run::{self, SolveSetup};
use crate::solver::Observer;

#[derive(Debug, clap::Args)]
pub struct SolveArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Executor: auto (GPU when available), gpu or cpu; default from
    /// VISCOSLIDE_BACKEND, else auto.
    #[arg(long, value_enum)]
    pub backend: Option<BackendChoice>,
    /// Output directory (created; files appear only when the solve succeeds).
    #[arg(long)]
    pub out: PathBuf,
}

struct Spinner(ProgressBar);

impl Observer for Spinner {
    fn iteration(&mut self, iteration: usize, matvecs: usize, residual: f64, contact_cells: usize) {
        self.0.set_message(format!(
            "active-set iteration {iteration}: {contact_cells} cells in contact, residual {residual:.2e}, {matvecs} matvecs"
        ));
        self.0.tick();
    }
}

pub fn run(args: SolveArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let setup = SolveSetup::from_config(&cfg)?;
    let choice = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let gpu = match choice {
        BackendChoice::Cpu => {
            eprintln!("backend: cpu");
            None
        }
        BackendChoice::Gpu => {
            let ctx = GpuContext::open().map_err(|e| Error::Invalid(e.to_string()))?;
            eprintln!("backend: gpu, adapter {}", ctx.adapter);
            Some(ctx)
        }
        BackendChoice::Auto => match GpuContext::open().and_then(|ctx| {
            GpuBackend::check_fits(&ctx, setup.surface.nx, setup.surface.ny).map(|()| ctx)
        }) {
            Ok(ctx) if ctx.adapter.device_type == "Cpu" => {
                eprintln!(
                    "backend: cpu (auto: the only adapter, {}, is emulated on the CPU and slower than the CPU backend; --backend gpu forces it)",
                    ctx.adapter
                );
                None
            }
            Ok(ctx) => {
                eprintln!("backend: gpu (auto), adapter {}", ctx.adapter);
                Some(ctx)
            }
            Err(e) => {
                eprintln!("backend: cpu (auto: {e})");
                None
            }
        },
    };
    eprintln!(
        "solving {} x {} cells, v = {:.4e} m/s{}",
        setup.surface.nx,
        setup.surface.ny,
        setup.speed,
        setup
            .xi()
            .map(|x| format!(" (xi = {x:.4e})"))
            .unwrap_or_default()
    );
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
            .expect("valid template"),
    );
    bar.set_message("computing influence coefficients");
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    let mut spinner = Spinner(bar);
    let outcome = match gpu {
        Some(ctx) => run::solve_gpu(&setup, ctx, &mut spinner),
        None => run::solve_cpu(&setup, &mut spinner),
    };
    spinner.0.finish_and_clear();
    let outcome = outcome?;
    let written = crate::report::write_solve(&args.out, &setup, &outcome)?;
    println!(
        "friction coefficient {:.6e} (dissipation: {:.6e}), contact area fraction {:.5}, {} iterations, {} matvecs, residual {:.2e}, {:.2} s",
        outcome.friction_coefficient,
        outcome.friction_coefficient_dissipation,
        outcome.stats.contact_area_fraction,
        outcome.info.iterations,
        outcome.info.matvecs,
        outcome.info.residual,
        outcome.timings.total_s
    );
    println!("wrote {} files to {}", written.len(), args.out.display());
    Ok(())
}
