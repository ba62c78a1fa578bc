//! `viscoslide magnification CONFIG --q1 Q1,Q2,... | --scales N1,N2,...
//! [--cells-per-wavelength K] [--speed V | --speeds V1,V2,...] [--backend B]
//! [--shard K/N] --out DIR`

use std::path::PathBuf;

use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::magnification::{
    self, LevelPlan, LevelResult, MagnificationParams, StudyObserver, StudyPoint,
};
use crate::problem::{Executor, Problem};
use crate::solver::Observer;
use crate::sweep::Shard;

use super::spinner::Spinner;

#[derive(Debug, clap::Args)]
pub struct MagnificationArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Upper cut-offs q1 of the levels [1/m], increasing, each at most the
    /// configuration's q1, e.g. 2.51e5,1.26e6,6.31e6.
    #[arg(long, value_name = "Q1,Q2,...", conflicts_with = "scales")]
    pub q1: Option<String>,
    /// Numbers of scales N of the levels (q1 = N q_L), increasing.
    #[arg(long, value_name = "N1,N2,...")]
    pub scales: Option<String>,
    /// Cells per shortest wavelength 2 pi / q1 of every level (at least 2).
    #[arg(long, value_name = "K", default_value_t = magnification::plan::DEFAULT_CELLS_PER_WAVELENGTH)]
    pub cells_per_wavelength: f64,
    /// Sliding speed [m/s] (default: the configuration's).
    #[arg(long, conflicts_with = "speeds")]
    pub speed: Option<f64>,
    /// Several sliding speeds [m/s], comma-separated: one curve each.
    #[arg(long, value_name = "V1,V2,...")]
    pub speeds: Option<String>,
    /// Executor: auto (GPU when available), gpu or cpu; default from
    /// VISCOSLIDE_BACKEND, else auto.
    #[arg(long, value_name = "auto|gpu|cpu")]
    pub backend: Option<BackendChoice>,
    /// Run only the points (a level at a speed) with index = K mod N.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Study directory: points go to DIR/points/ (rerunning resumes);
    /// magnification.json, .csv and .png appear when every point is done.
    #[arg(long)]
    pub out: PathBuf,
}

impl MagnificationArgs {
    /// The study's controls from the flags.
    pub fn params(&self) -> Result<MagnificationParams> {
        let list = |flag: &str, text: &Option<String>| {
            text.as_deref()
                .map(|t| magnification::parse_list(flag, t))
                .transpose()
        };
        let speeds = match self.speed {
            Some(v) => Some(vec![v]),
            None => list("--speeds", &self.speeds)?,
        };
        MagnificationParams::from_options(
            list("--q1", &self.q1)?,
            list("--scales", &self.scales)?,
            self.cells_per_wavelength,
            speeds,
        )
    }
}

/// A line per point on stderr and a spinner while a level solves.
impl StudyObserver for Spinner {
    fn point_started(&mut self, done: usize, count: usize, point: &StudyPoint, level: &LevelPlan) {
        let line = format!(
            "point {}/{count} ({}): q1 = {:.4e} 1/m, {} x {} cells ({:.2} per shortest wavelength), rms slope {:.4}, v = {:.4e} m/s",
            done + 1,
            point.id,
            level.q1,
            level.n,
            level.ny,
            level.cells_per_shortest_wavelength,
            level.rms_slope,
            point.speed
        );
        self.bar.suspend(|| eprintln!("{line}"));
        self.bar
            .set_message("generating the surface, influence coefficients");
    }

    fn point_finished(&mut self, done: usize, count: usize, l: &LevelResult) {
        let line = format!(
            "point {}/{count}: friction {:.6e} (dissipation {:.6e}, Persson {:.6e}), contact area fraction {:.5} (Persson {:.5}), {} matvecs, {:.2} s",
            done + 1,
            l.friction_coefficient,
            l.friction_coefficient_dissipation,
            l.persson_friction_coefficient,
            l.contact_area_fraction,
            l.persson_contact_area_fraction,
            l.matvecs,
            l.wall_time_s
        );
        self.finished(&line, &l.warnings);
    }

    fn solver(&mut self) -> &mut dyn Observer {
        self
    }
}

pub fn run(args: MagnificationArgs) -> Result<()> {
    let params = args.params()?;
    let cfg = args.config.load()?;
    let study = magnification::Study::new(&cfg, params)?;
    let choice = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let coarse = Problem::from_config(&study.point_config(&study.points[0])?)?;
    let (executor, line) = Executor::select(choice, &coarse)?;
    eprintln!("{line}");
    let mut progress = Spinner::start("");
    let shard = args.shard.unwrap_or(Shard::ALL);
    let r = magnification::run(&study, &executor, Some(&args.out), shard, &mut progress);
    progress.bar.finish_and_clear();
    let r = r?;
    println!(
        "{} points in the study ({} levels x {} speeds), {} in this shard: {} already done, {} solved now",
        r.total,
        study.levels.len(),
        study.speeds.len(),
        r.in_shard,
        r.skipped,
        r.solved
    );
    match &r.report {
        Some(report) => {
            for w in &report.warnings {
                eprintln!("warning: {w}");
            }
            if let Some(t) = report.temperature_shift {
                println!(
                    "material at {} C: WLF shift factor a_T = {:.6e} (T_ref = {} C)",
                    t.temperature, t.shift_factor, t.reference_temperature
                );
            }
            println!(
                "{:>12} {:>6} {:>10} {:>12} {:>12} {:>10} {:>10}",
                "q1 [1/m]", "n", "rms slope", "mu", "mu Persson", "A/A0", "A Persson"
            );
            for l in &report.levels {
                println!(
                    "{:>12.4e} {:>6} {:>10.4} {:>12.5e} {:>12.5e} {:>10.5} {:>10.5}",
                    l.q1,
                    l.n,
                    l.rms_slope,
                    l.friction_coefficient,
                    l.persson_friction_coefficient,
                    l.contact_area_fraction,
                    l.persson_contact_area_fraction
                );
            }
            println!("wrote {} files to {}", r.written.len(), args.out.display());
        }
        None => println!(
            "the report is written when every point is done (rerun without --shard, or after the other shards)"
        ),
    }
    Ok(())
}
