//! `viscoslide surface generate`: a self-affine random surface, or one
//! following a tabulated PSD, from flags and/or a `[surface.generate]` table.

use std::path::{Path, PathBuf};

use crate::config::LoadedConfig;
use crate::error::Result;
use crate::io::StagedOutput;
use crate::plot::Series;
use crate::surface::{
    self, AnisotropyConfig, BelowTable, GenerateConfig, NpyPrecision, RadialPsd, SelfAffinePsd,
    SurfaceError, SynthParams, TabulatedPsd, Window,
};

use super::{json_bytes, log_plot, pairs, parse_pair, psd_plot};

/// Flags override the keys of `[surface.generate]` in `--config`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct GenerateArgs {
    /// TOML config with a [surface.generate] table.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Override a config key, e.g. `--set surface.generate.seed=3` (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE", requires = "config")]
    pub set: Vec<String>,
    /// Cells along x (and y unless --ny).
    #[arg(long)]
    pub n: Option<usize>,
    /// Cells along y.
    #[arg(long)]
    pub ny: Option<usize>,
    /// Side along x in m.
    #[arg(long)]
    pub length: Option<f64>,
    /// Hurst exponent H (0 < H <= 1).
    #[arg(long)]
    pub hurst: Option<f64>,
    /// Number of scales N: q1 = N q_L.
    #[arg(long, conflicts_with = "q1")]
    pub scales: Option<f64>,
    /// Upper cut-off q1 [1/m] (with --psd: the table is cut there).
    #[arg(long)]
    pub q1: Option<f64>,
    /// Lower cut-off q_L [1/m] (default 2 pi / length).
    #[arg(long)]
    pub ql: Option<f64>,
    /// Roll-off wavenumber q0 [1/m] (default q_L: no roll-off).
    #[arg(long)]
    pub rolloff_q0: Option<f64>,
    /// rms height in m.
    #[arg(long, conflicts_with = "rms_slope")]
    pub rms_height: Option<f64>,
    /// rms slope.
    #[arg(long)]
    pub rms_slope: Option<f64>,
    /// Seed of the random phases (default 0).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Stretch RATIO along the direction ANGLE_DEG from +x.
    #[arg(long, value_name = "RATIO,ANGLE_DEG", value_parser = parse_anisotropy)]
    pub anisotropy: Option<AnisotropyConfig>,
    /// Follow a tabulated PSD (CSV: q [1/m], C [m^4]) instead of the
    /// self-affine formula; needs --n, --length, optionally --ny, --seed,
    /// --q1. With --q1 the table is cut at q1 without changing the lower modes.
    #[arg(long, conflicts_with_all = ["hurst", "scales", "ql", "rolloff_q0", "rms_height", "rms_slope", "anisotropy"])]
    pub psd: Option<PathBuf>,
    /// With --psd: what the grid's modes below the table's first row get:
    /// first_bin (default: the first row's value down to the lower edge of
    /// its bin, half a row spacing below it), extrapolate (the first two
    /// rows' power law further down) or none.
    #[arg(long, value_name = "RULE")]
    pub below_table: Option<String>,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_anisotropy(s: &str) -> std::result::Result<AnisotropyConfig, String> {
    let (ratio, angle_deg) = parse_pair(s)?;
    Ok(AnisotropyConfig { ratio, angle_deg })
}

impl GenerateArgs {
    fn flags(&self) -> GenerateConfig {
        GenerateConfig {
            n: self.n,
            ny: self.ny,
            length: self.length,
            hurst: self.hurst,
            scales: self.scales,
            q1: self.q1,
            ql: self.ql,
            rolloff_q0: self.rolloff_q0,
            rms_height: self.rms_height,
            rms_slope: self.rms_slope,
            seed: self.seed,
            anisotropy: self.anisotropy,
            psd: self.psd.clone(),
            below_table: self.below_table.clone(),
        }
    }
}

/// The `config` entry of surface.json: the file and its merged document.
fn config_json(config: Option<&(PathBuf, LoadedConfig)>) -> Option<serde_json::Value> {
    config.map(|(p, loaded)| {
        serde_json::json!({
            "path": p.display().to_string(),
            "document": loaded.document,
        })
    })
}

pub(super) fn run(args: GenerateArgs) -> Result<()> {
    let flags = args.flags();
    let config = match &args.config {
        None => None,
        Some(path) => Some((path.clone(), crate::config::load(path, &args.set)?)),
    };
    let (merged, base_dir) = match &config {
        None => (flags.clone(), PathBuf::from(".")),
        Some((_, loaded)) => {
            let sc = loaded.surface()?;
            // The keys of a surface file are refused beside
            // [surface.generate] here as in a solve.
            sc.check()?;
            let base = sc.generate.clone().unwrap_or_default();
            let mut m = base.merged(&flags);
            if m.length.is_none() {
                m.length = sc.length;
            }
            (m, loaded.base_dir.clone())
        }
    };
    if let Some((table_path, sp)) = merged.synth_params(None)? {
        // A --psd flag is relative to the working directory, a config key to the config.
        let table_path = if args.psd.is_some() {
            table_path
        } else {
            base_dir.join(table_path)
        };
        return run_from_table(&args.out, &table_path, sp, config.as_ref());
    }
    let params = match &config {
        None => flags.params(None)?,
        Some((path, loaded)) => {
            let sc = loaded.surface()?;
            let mut base = sc.generate.clone().ok_or_else(|| {
                SurfaceError::Invalid(format!(
                    "{}: no [surface.generate] table to generate from",
                    path.display()
                ))
            })?;
            // A flag for one of two exclusive keys replaces both.
            if flags.scales.is_some() || flags.q1.is_some() {
                base.scales = None;
                base.q1 = None;
            }
            if flags.rms_height.is_some() || flags.rms_slope.is_some() {
                base.rms_height = None;
                base.rms_slope = None;
            }
            base.merged(&flags).params(sc.length)?
        }
    };
    let (map, target) = surface::generate_with_target(&params)?;
    let stats = surface::stats(&map)?;
    let psd = surface::psd_2d(&map, Window::None)?;
    let radial = surface::radial_average(&psd);
    // Fit over the self-affine band, away from the cut-offs.
    let fit = surface::fit_hurst(&radial, 2.0 * target.q0, 0.5 * target.q1).ok();
    // The stretch's realised slope ratio, summed once for the record and
    // its warning.
    let slope_ratio = surface::lattice_slope_ratio(&params)?;
    let warnings: Vec<String> = match slope_ratio {
        Some(got) => surface::slope_ratio_warning(&params, got)?,
        None => None,
    }
    .into_iter()
    .collect();

    let json = serde_json::json!({
        "version": crate::version::VERSION,
        "seed": params.seed,
        "params": params,
        "target_psd": target,
        "stats": stats,
        "hurst_fit": fit,
        "slope_ratio": slope_ratio,
        "warnings": warnings,
        "config": config_json(config.as_ref()),
        "files": ["heights.npy", "psd.csv", "psd.png", "surface.json"],
    });
    let mut out = StagedOutput::new(&args.out)?;
    out.write("heights.npy", &surface::encode_npy(&map, NpyPrecision::F64))?;
    out.write("psd.csv", psd_csv(&radial, Some(&target)).as_bytes())?;
    let png = out.path("psd.png");
    psd_plot(&png, &radial, Some(&target), "PSD of the generated surface")?;
    out.write("surface.json", json_bytes(&json)?.as_slice())?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "{} x {} surface, seed {}, rms height {:.4e} m, rms slope {:.4e}: {}",
        map.nx,
        map.ny,
        params.seed,
        stats.rms_height,
        stats.rms_slope,
        dir.display()
    );
    Ok(())
}

/// A surface synthesised from the PSD table at `table_path`.
fn run_from_table(
    out_dir: &Path,
    table_path: &Path,
    sp: SynthParams,
    config: Option<&(PathBuf, LoadedConfig)>,
) -> Result<()> {
    let table = TabulatedPsd::from_csv(table_path)?;
    let map = surface::generate_from_table(&table, &sp)?;
    let stats = surface::stats(&map)?;
    let radial = surface::radial_average(&surface::psd_2d(&map, Window::None)?);
    let qn = std::f64::consts::PI / map.cell_size;
    let (below_modes, below_ms) = surface::below_table_modes(&table, &sp);
    let grid_q_min = 2.0 * std::f64::consts::PI / map.length_x().max(map.length_y());
    let band_lo = match (sp.below, below_modes) {
        (_, 0) => table.q_min().max(grid_q_min),
        (BelowTable::FirstBin, _) => table.first_bin_edge().max(grid_q_min),
        _ => grid_q_min,
    };
    let band_hi = sp.highest_q(&table).min(qn);
    let json = serde_json::json!({
        "version": crate::version::VERSION,
        "seed": sp.seed,
        "psd_table": table_path.display().to_string(),
        "synth_params": sp,
        "table_rms_height": table.moment(0).sqrt(),
        "table_rms_height_first_bin": table.moment_first_bin(0).sqrt(),
        "below_table": {
            "rule": sp.below,
            "table_q_min_per_m": table.q_min(),
            "first_bin_edge_per_m": table.first_bin_edge(),
            "grid_q_min_per_m": grid_q_min,
            "modes": below_modes,
            "rms_height": below_ms.sqrt(),
            "note": match sp.below {
                BelowTable::FirstBin => "modes between the lower edge of the table's first bin and its first row take the first row's C",
                BelowTable::Extrapolate => "modes below the table's first row take the power law of its first two rows, down to the grid's longest mode: power the table does not hold",
                BelowTable::None => "no power below the table's first row",
            },
        },
        "table_rms_slope": table.moment(2).sqrt(),
        "grid_band_per_m": [band_lo, band_hi],
        "stats": stats,
        "config": config_json(config),
        "files": ["heights.npy", "psd.csv", "psd.png", "surface.json"],
    });
    let mut csv = String::from("q_per_m,c_radial_m4,c_target_m4,modes\n");
    for i in 0..radial.q.len() {
        csv.push_str(&format!(
            "{:.10e},{:.10e},{:.10e},{}\n",
            radial.q[i],
            radial.c[i],
            table.eval(radial.q[i]),
            radial.count[i]
        ));
    }
    let mut out = StagedOutput::new(out_dir)?;
    out.write("heights.npy", &surface::encode_npy(&map, NpyPrecision::F64))?;
    out.write("psd.csv", csv.as_bytes())?;
    let png = out.path("psd.png");
    log_plot(
        &png,
        "PSD of the surface generated from a table",
        "m^4",
        vec![
            Series::points("radial average", pairs(&radial.q, &radial.c), 2),
            Series::line("tabulated PSD", pairs(table.q(), table.c()), 0),
        ],
    )?;
    out.write("surface.json", &json_bytes(&json)?)?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    println!(
        "{} x {} surface from {}, seed {}, rms height {:.4e} m, rms slope {:.4e}: {}",
        map.nx,
        map.ny,
        table_path.display(),
        sp.seed,
        stats.rms_height,
        stats.rms_slope,
        dir.display()
    );
    Ok(())
}

/// `q,c_radial,c_target` (1/m, m^4, m^4); the target column is empty
/// without a target.
fn psd_csv(radial: &RadialPsd, target: Option<&SelfAffinePsd>) -> String {
    let mut s = String::from("q_per_m,c_radial_m4,c_target_m4\n");
    for (q, c) in radial.q.iter().zip(&radial.c) {
        let t = target
            .map(|t| format!("{:.10e}", t.eval_radial(*q)))
            .unwrap_or_default();
        s.push_str(&format!("{q:.10e},{c:.10e},{t}\n"));
    }
    s
}
