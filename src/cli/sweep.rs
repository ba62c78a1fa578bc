//! `viscoslide sweep CONFIG --out DIR [--shard K/N] [--backend B]` and
//! `viscoslide merge DIR`.

use std::path::PathBuf;

use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::sweep::{self, Shard};

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
    #[arg(long, value_enum)]
    pub backend: Option<BackendChoice>,
}

#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Sweep directory.
    pub dir: PathBuf,
}

pub fn run(args: SweepArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let shard = args.shard.unwrap_or(Shard::ALL);
    let backend = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let (r, rows) =
        sweep::run_and_merge(&cfg, &args.out, shard, args.limit, backend, !args.no_merge)?;
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
    let rows = sweep::merge(&args.dir)?;
    println!(
        "merged {} rows into {}",
        rows.len(),
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
    sweep::compare(&args.dir, &args.measured, args.coulomb)?;
    println!(
        "wrote {} and {}",
        args.dir.join("compare.csv").display(),
        args.dir.join("compare.png").display()
    );
    Ok(())
}
