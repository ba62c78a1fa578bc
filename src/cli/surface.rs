//! `viscoslide surface ...`: generate self-affine height maps and print
//! statistics of existing ones (physics.md section 8).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::plot::{self, Series, XyChart};
use crate::surface::{
    self, AnisotropyConfig, GenerateConfig, NpyPrecision, RadialPsd, SelfAffinePsd, SurfaceError,
    Window,
};

#[derive(Debug, clap::Subcommand)]
pub enum SurfaceCommand {
    /// Generate a self-affine random surface; writes heights.npy, psd.csv,
    /// psd.png and surface.json into --out (all or nothing).
    Generate(Box<GenerateArgs>),
    /// Print statistics of a height map (.npy or text matrix).
    Stats(StatsArgs),
}

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
    /// Side along x \[m\].
    #[arg(long)]
    pub length: Option<f64>,
    /// Hurst exponent H (0 < H <= 1).
    #[arg(long)]
    pub hurst: Option<f64>,
    /// Number of scales N: q1 = N q_L.
    #[arg(long, conflicts_with = "q1")]
    pub scales: Option<f64>,
    /// Upper cut-off q1 [1/m].
    #[arg(long)]
    pub q1: Option<f64>,
    /// Lower cut-off q_L [1/m] (default 2 pi / length).
    #[arg(long)]
    pub ql: Option<f64>,
    /// Roll-off wavenumber q0 [1/m] (default q_L: no roll-off).
    #[arg(long)]
    pub rolloff_q0: Option<f64>,
    /// rms height \[m\].
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
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Debug, clap::Args)]
pub struct StatsArgs {
    /// Height map: .npy (float64/float32) or text matrix (rows = x).
    pub file: PathBuf,
    /// Side along x \[m\].
    #[arg(long, allow_negative_numbers = true)]
    pub length: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Hann window for non-periodic (measured) maps.
    #[arg(long)]
    pub hann: bool,
    /// Fit the Hurst exponent over QMIN,QMAX [1/m].
    #[arg(long, value_name = "QMIN,QMAX", value_parser = parse_pair)]
    pub fit: Option<(f64, f64)>,
    /// Also write stats.json, psd.csv and psd.png into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn parse_pair(s: &str) -> std::result::Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected two numbers A,B, got '{s}'"))?;
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{}' is not a number", t.trim()))
    };
    Ok((num(a)?, num(b)?))
}

fn parse_anisotropy(s: &str) -> std::result::Result<AnisotropyConfig, String> {
    let (ratio, angle_deg) = parse_pair(s)?;
    Ok(AnisotropyConfig { ratio, angle_deg })
}

pub fn run(cmd: SurfaceCommand) -> Result<()> {
    match cmd {
        SurfaceCommand::Generate(a) => run_generate(*a),
        SurfaceCommand::Stats(a) => run_stats(a),
    }
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
        }
    }
}

fn run_generate(args: GenerateArgs) -> Result<()> {
    let flags = args.flags();
    let (params, config_doc) = match &args.config {
        None => (flags.params(None)?, None),
        Some(path) => {
            let loaded = crate::config::load(path, &args.set)?;
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
            let merged = base.merged(&flags);
            (
                merged.params(sc.length)?,
                Some((path.clone(), loaded.document.clone())),
            )
        }
    };
    let (map, target) = surface::generate_with_target(&params)?;
    let stats = surface::stats(&map)?;
    let psd = surface::psd_2d(&map, Window::None)?;
    let radial = surface::radial_average(&psd);
    // Fit over the self-affine band, away from the cut-offs.
    let fit = surface::fit_hurst(&radial, 2.0 * target.q0, 0.5 * target.q1).ok();

    let json = serde_json::json!({
        "version": crate::VERSION,
        "seed": params.seed,
        "params": params,
        "target_psd": target,
        "stats": stats,
        "hurst_fit": fit,
        "config": config_doc.as_ref().map(|(p, d)| serde_json::json!({
            "path": p.display().to_string(),
            "document": d,
        })),
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

fn run_stats(args: StatsArgs) -> Result<()> {
    let map = surface::read_height_map(&args.file, args.length)?;
    let window = if args.hann {
        Window::Hann
    } else {
        Window::None
    };
    let stats = surface::stats_with_window(&map, window)?;
    let radial = surface::radial_average(&surface::psd_2d(&map, window)?);
    let fit = args
        .fit
        .map(|(lo, hi)| surface::fit_hurst(&radial, lo, hi))
        .transpose()?;
    let json = serde_json::json!({
        "version": crate::VERSION,
        "file": args.file.display().to_string(),
        "stats": stats,
        "hurst_fit": fit,
    });
    if let Some(dir) = &args.out {
        write_stats_dir(dir, &json, &radial)?;
    }
    if args.json {
        println!("{}", String::from_utf8_lossy(&json_bytes(&json)?));
    } else {
        print!("{stats}");
        if let Some(f) = fit {
            println!(
                "{:<26} {:>16} (slope {:.4}, {} bins in [{:.3e}, {:.3e}] 1/m)",
                "Hurst exponent (fit)",
                format!("{:.4}", f.hurst),
                f.slope,
                f.points,
                f.q_min,
                f.q_max
            );
        }
    }
    Ok(())
}

fn write_stats_dir(dir: &Path, json: &serde_json::Value, radial: &RadialPsd) -> Result<()> {
    let mut out = StagedOutput::new(dir)?;
    out.write("stats.json", &json_bytes(json)?)?;
    out.write("psd.csv", psd_csv(radial, None).as_bytes())?;
    let png = out.path("psd.png");
    psd_plot(&png, radial, None, "PSD")?;
    out.commit()?;
    Ok(())
}

fn json_bytes(v: &serde_json::Value) -> Result<Vec<u8>> {
    let mut b = serde_json::to_vec_pretty(v)
        .map_err(|e| Error::Invalid(format!("cannot encode JSON: {e}")))?;
    b.push(b'\n');
    Ok(b)
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

fn psd_plot(
    path: &Path,
    radial: &RadialPsd,
    target: Option<&SelfAffinePsd>,
    title: &str,
) -> Result<()> {
    // Modes outside the band hold FFT round-off (~1e-30 of the peak); keep
    // them off the log axis.
    let peak = radial.c.iter().copied().fold(0.0, f64::max);
    let floor = peak * 1e-12;
    // The log axis is drawn in units of 10^k m^4 with the peak in [1, 10):
    // plotters places no ticks on log axes over very small values.
    let k = if peak > 0.0 {
        peak.log10().floor()
    } else {
        0.0
    };
    let unit = 10f64.powf(k);
    let measured: Vec<(f64, f64)> = radial
        .q
        .iter()
        .zip(&radial.c)
        .filter(|(_, c)| **c > floor)
        .map(|(q, c)| (*q, *c / unit))
        .collect();
    let mut series = vec![Series::points("radial average", measured, 2)];
    if let Some(t) = target {
        let line: Vec<(f64, f64)> = radial
            .q
            .iter()
            .map(|&q| (q, t.eval_radial(q) / unit))
            .filter(|p| p.1 > 0.0)
            .collect();
        series.push(Series::line(format!("target, H = {}", t.hurst), line, 0));
    }
    let chart = XyChart {
        title: title.into(),
        x_label: "q [1/m]".into(),
        y_label: if k == 0.0 {
            "C(q) [m^4]".into()
        } else {
            format!("C(q) [1e{k} m^4]")
        },
        log_x: true,
        log_y: true,
        series,
    };
    plot::xy_chart(path, &chart)?;
    Ok(())
}
