//! The command line: clap derive, one file per command group. Each command
//! turns its arguments into library calls; no numerics live here.

mod analyze;
mod gpu;
mod gpu_bench;
mod heat;
mod heat_run;
mod kernel;
mod magnification;
mod material;
pub mod persson;
mod refine;
mod solve;
mod spinner;
mod stage_bar;
mod surface;
mod sweep;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::config::{self, LoadedConfig};
use crate::error::Result;

/// viscoslide: steady sliding contact of rigid rough surfaces on viscoelastic
/// solids (Carbone & Putignano, Phys. Rev. E 89, 032408, 2014).
#[derive(Debug, Parser)]
#[command(name = "viscoslide", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Viscoelastic materials: fit DMA data, show a spectrum.
    #[command(subcommand)]
    Material(material::MaterialCommand),
    /// Rough surfaces: generate self-affine maps, print statistics.
    #[command(subcommand)]
    Surface(surface::SurfaceCommand),
    /// Print influence coefficients for given cell offsets.
    Kernel(kernel::KernelArgs),
    /// Solve one steady sliding contact and write its results.
    Solve(solve::SolveArgs),
    /// Solve one problem on several grids, coarse to fine, and estimate the
    /// grid-converged friction and area (Richardson).
    Refine(refine::RefineArgs),
    /// Run (or resume) a sweep over speed, load and surface realisations.
    Sweep(sweep::SweepArgs),
    /// Aggregate a sweep directory into sweep.csv and plots.
    Merge(sweep::MergeArgs),
    /// Plot measured minus Coulomb friction against a merged sweep (paper Fig. 6).
    Compare(sweep::CompareArgs),
    /// List the GPU adapters wgpu can use; `gpu plan`: the dispatches and
    /// memory traffic of the GPU matvec.
    Gpu(gpu::GpuArgs),
    /// Anisotropy (Eq. 11-13), C_chi contours and contact spots of a solve.
    Analyze(analyze::AnalyzeArgs),
    /// Persson's theory: friction and contact area against speed.
    Persson(persson::PerssonArgs),
    /// Friction and contact area against the cut-off q1 (the PSD held
    /// fixed, cut at each level), boundary elements beside Persson.
    Magnification(magnification::MagnificationArgs),
    /// Steady surface temperature rise of the rubber under a surface heat
    /// flux map, or under the heat source of a solved contact with
    /// --from-run (frictional heating: moving heat source, pad or periodic
    /// cell).
    Heat(heat::HeatArgs),
}

/// A config file plus `--set section.key=value` overrides.
#[derive(Debug, Clone, clap::Args)]
pub struct ConfigArgs {
    /// TOML configuration file (SI units).
    pub config: PathBuf,
    /// Override any key, e.g. `--set material.poisson=0.49` (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
}

impl ConfigArgs {
    pub fn load(&self) -> Result<LoadedConfig> {
        Ok(config::load(&self.config, &self.set)?)
    }
}

/// Parse the process arguments and run the command.
pub fn run() -> Result<()> {
    let cli = Cli::parse();
    crate::kernel::progress::set_stage_observer(Box::new(stage_bar::StageBars));
    match cli.command {
        Command::Material(c) => material::run(c),
        Command::Surface(c) => surface::run(c),
        Command::Kernel(a) => kernel::run(a),
        Command::Solve(a) => solve::run(a),
        Command::Refine(a) => refine::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => sweep::merge(a),
        Command::Compare(a) => sweep::compare(a),
        Command::Gpu(a) => gpu::run(a),
        Command::Analyze(a) => analyze::run(a),
        Command::Persson(a) => persson::run(a),
        Command::Magnification(a) => magnification::run(a),
        Command::Heat(a) => {
            heat::check_numbers(&a)?;
            match a.from_run.clone() {
                Some(dir) => heat_run::run(&a, &dir),
                None => heat::run(a),
            }
        }
    }
}
