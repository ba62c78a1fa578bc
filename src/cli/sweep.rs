//! `viscoslide sweep CONFIG --out DIR [--shard K/N] [--backend B]` and
//! `viscoslide merge DIR`.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};

use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::sweep::{self, Point, Shard, SweepObserver};

/// A sweep's progress on the terminal: the executor's line, a bar over the
/// points this run solves, warnings and notes on stderr.
#[derive(Default)]
struct SweepBar {
    bar: Option<ProgressBar>,
}

impl SweepBar {
    fn say(&self, line: String) {
        match &self.bar {
            Some(bar) => bar.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }
}

impl SweepObserver for SweepBar {
    fn executor(&mut self, line: &str) {
        self.say(line.to_string());
    }

    fn point_started(&mut self, _done: usize, count: usize, id: &str) {
        let bar = self.bar.get_or_insert_with(|| {
            let bar = ProgressBar::new(count as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:30} {pos}/{len} points, {elapsed_precise} elapsed, ETA {eta_precise} {msg}",
                )
                .expect("valid template"),
            );
            bar
        });
        bar.set_message(id.to_string());
    }

    fn point_finished(&mut self, done: usize, count: usize, _id: &str) {
        if let Some(bar) = &self.bar {
            bar.set_position(done as u64);
            if done == count {
                bar.finish_and_clear();
            }
        }
    }

    fn warning(&mut self, id: &str, message: &str) {
        self.say(format!("warning: point {id}: {message}"));
    }

    fn point_failed(&mut self, point: &Point) {
        if let Some(bar) = self.bar.take() {
            bar.abandon();
        }
        self.say(format!(
            "note: point {} failed (its error follows); the points written before it are kept",
            point.describe()
        ));
    }

    fn note(&mut self, message: &str) {
        self.say(format!("note: {message}"));
    }
}

#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Sweep directory: points go to DIR/points/, one JSON each; rerunning
    /// the same command resumes.
    #[arg(long)]
    pub out: PathBuf,
    /// Run only the points with index = K mod N (0 <= K < N), e.g. a Slurm
    /// array task: `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Stop after solving this many new points.
    #[arg(long)]
    pub limit: Option<usize>,
    /// Do not merge after the run.
    #[arg(long)]
    pub no_merge: bool,
    /// Executor: auto (GPU when available), gpu or cpu; default from
    /// VISCOSLIDE_BACKEND, else auto.
    #[arg(long, value_name = "auto|gpu|cpu")]
    pub backend: Option<BackendChoice>,
}

#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Sweep directory.
    pub dir: PathBuf,
    /// Merge the finished points of a sweep with points still missing (a
    /// shard not run yet, a run stopped early); without it such a sweep is
    /// refused, naming them. merge.json records which are missing.
    #[arg(long)]
    pub partial: bool,
}

pub fn run(args: SweepArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let shard = args.shard.unwrap_or(Shard::ALL);
    let backend = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let mut bar = SweepBar::default();
    let result = sweep::run_and_merge(
        &cfg,
        &args.out,
        shard,
        args.limit,
        backend,
        !args.no_merge,
        &mut bar,
    );
    if let Some(b) = &bar.bar {
        b.finish_and_clear();
    }
    let (r, rows) = result?;
    println!(
        "{} points in the sweep, {} in this shard: {} already done, {} solved now",
        r.total, r.in_shard, r.skipped, r.solved
    );
    if let Some(rows) = rows {
        println!(
            "merged {} rows into {}",
            rows.len(),
            args.out.join("sweep.csv").display()
        );
    }
    Ok(())
}

pub fn merge(args: MergeArgs) -> Result<()> {
    let merged = sweep::merge(&args.dir, args.partial, &mut SweepBar::default())?;
    let gap = match merged.planned {
        _ if merged.missing.is_empty() => String::new(),
        Some(planned) => format!(
            " (partial: {} of the sweep's {planned} points missing: {}; all listed in {})",
            merged.missing.len(),
            merged.missing_text(),
            args.dir.join(sweep::MERGE_FILE).display()
        ),
        None => String::new(),
    };
    println!(
        "merged {} rows into {}{gap}",
        merged.rows.len(),
        args.dir.join("sweep.csv").display()
    );
    Ok(())
}

#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// A merged sweep directory.
    pub dir: PathBuf,
    /// Measured friction: CSV with `speed_m_s`, `mu` and optional `mu_std`.
    pub measured: PathBuf,
    /// Interfacial (Coulomb) friction measured at vanishing speed, subtracted
    /// from the measurements.
    #[arg(long, allow_negative_numbers = true)]
    pub coulomb: f64,
}

pub fn compare(args: CompareArgs) -> Result<()> {
    sweep::compare(
        &args.dir,
        &args.measured,
        args.coulomb,
        &mut SweepBar::default(),
    )?;
    println!(
        "wrote {} and {}",
        args.dir.join("compare.csv").display(),
        args.dir.join("compare.png").display()
    );
    Ok(())
}
