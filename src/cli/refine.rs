//! `viscoslide refine CONFIG --levels 512,1024,2048 --out DIR`

use std::path::PathBuf;

use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::io::{LockMode, StudyLock};
use crate::problem::{Executor, Problem};
use crate::refine::{self, Level, RefineObserver, RefineParams, Richardson, Verdict};
use crate::solver::Observer;

use super::spinner::Spinner;

#[derive(Debug, clap::Args)]
pub struct RefineArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Grids (cells along x; y keeps the configured side, so N ny / nx
    /// must be whole), coarse to fine, comma-separated, at least two, e.g.
    /// 512,1024,2048.
    #[arg(long, value_name = "N1,N2,...")]
    pub levels: String,
    /// Executor: auto (GPU when available), gpu or cpu; default from
    /// VISCOSLIDE_BACKEND, else auto.
    #[arg(long, value_name = "auto|gpu|cpu")]
    pub backend: Option<BackendChoice>,
    /// Start every level from the previous level's solution instead of the
    /// solver's own coarse-to-fine cascade (the cascade needs fewer
    /// matvecs: 469 against 911 at 2048^2 on the experiment; BENCHMARKS.md).
    #[arg(long)]
    pub warm_start: bool,
    /// Output directory: refine.json and refine.png appear together when
    /// every level has been solved.
    #[arg(long)]
    pub out: PathBuf,
}

/// Per-level lines on stderr and a spinner while a level solves.
impl RefineObserver for Spinner {
    fn level_started(&mut self, index: usize, count: usize, problem: &Problem, warm: bool) {
        let cells = problem
            .cells_per_shortest_wavelength()
            .map(|c| format!("{c:.2} cells per shortest wavelength"))
            .unwrap_or_else(|| "no roughness wavelength".into());
        let line = format!(
            "level {}/{count}: {} x {} cells, {cells}, {}",
            index + 1,
            problem.surface.nx,
            problem.surface.ny,
            if warm {
                "started from the previous level"
            } else {
                "cold start"
            }
        );
        self.bar.suspend(|| eprintln!("{line}"));
        self.bar.set_message("computing influence coefficients");
    }

    fn level_finished(&mut self, index: usize, count: usize, l: &Level) {
        let line = format!(
            "level {}/{count}: n = {}: friction {:.6e} (dissipation {:.6e}), contact area fraction {:.5}, {} matvecs, {:.2} s",
            index + 1,
            l.n,
            l.friction_coefficient,
            l.friction_coefficient_dissipation,
            l.contact_area_fraction,
            l.matvecs,
            l.wall_time_s
        );
        self.finished(&line, &l.warnings);
    }

    fn solver(&mut self) -> &mut dyn Observer {
        self
    }
}

fn describe(name: &str, r: &Richardson) -> String {
    match r.verdict {
        Verdict::Asymptotic | Verdict::AssumedOrder => format!(
            "{name}: Richardson limit {:.6e} +- {:.2e} ({:.2}%), finest {:.6e}; {}",
            r.extrapolated.unwrap_or(f64::NAN),
            r.error_estimate,
            100.0 * r.relative_error_estimate,
            r.finest,
            r.message
        ),
        Verdict::Converged => format!("{name}: {:.6e}; {}", r.finest, r.message),
        Verdict::NotAsymptotic => format!("{name}: finest {:.6e}; {}", r.finest, r.message),
    }
}

pub fn run(args: RefineArgs) -> Result<()> {
    let levels = refine::parse_levels(&args.levels)?;
    refine::check_levels(&levels)?;
    let cfg = args.config.load()?;
    cfg.refuse_heating("a refinement study")?;
    let problem = Problem::from_config(&cfg)?;
    refine::check_level_memory(&problem, &levels)?;
    let choice = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let (executor, line) = Executor::select(choice, &problem)?;
    eprintln!("{line}");
    let params = RefineParams {
        warm_start: args.warm_start,
        ..RefineParams::new(levels)
    };
    // Every check done: the study takes its directory for the whole run,
    // so a second writer fails now rather than after its solves.
    let _lock = StudyLock::acquire(&args.out, LockMode::Exclusive)?;
    let mut progress = Spinner::start("");
    let report = refine::refine(&problem, &executor, &params, &mut progress);
    progress.bar.finish_and_clear();
    let report = report?;
    let written = report.write(&args.out)?;
    for (name, r) in [
        ("friction coefficient", &report.friction),
        ("contact area fraction", &report.area),
    ] {
        println!("{}", describe(name, r));
    }
    println!(
        "{} matvecs over {} levels ({}), {:.2} s",
        report.levels.iter().map(|l| l.matvecs).sum::<usize>(),
        report.levels.len(),
        if report.warm_start {
            "warm-started"
        } else {
            "cold starts"
        },
        report.total_wall_time_s
    );
    println!("wrote {} files to {}", written.len(), args.out.display());
    Ok(())
}
