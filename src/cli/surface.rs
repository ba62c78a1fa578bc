//! `viscoslide surface ...`: generate self-affine height maps or maps
//! following a tabulated PSD, analyse measured or generated maps, convert
//! between file formats and stitch the PSDs of several scans (physics.md
//! sections 8 and 11).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::plot::{self, Series, XyChart};
use crate::surface::{
    self, AnisotropyConfig, Detrend, GenerateConfig, LinePsd, MissingData, NpyPrecision, RadialPsd,
    ReadOptions, ScanPsd, SelfAffinePsd, SurfaceError, SurfaceFormat, SynthParams, TabulatedPsd,
    Topography, Window, WriteOptions, X3pType,
};

#[derive(Debug, clap::Subcommand)]
pub enum SurfaceCommand {
    /// Generate a self-affine random surface; writes heights.npy, psd.csv,
    /// psd.png and surface.json into --out (all or nothing).
    Generate(Box<GenerateArgs>),
    /// Statistics and PSDs of a height map (.x3p, .gwy, .npy or text):
    /// detrending, windowing, radial and line PSDs, rms values from the
    /// PSD and from real space, Hurst exponent.
    Stats(StatsArgs),
    /// Convert a height map between formats (by extension): .x3p, .gwy
    /// (read only), .npy, text.
    Convert(ConvertArgs),
    /// Stitch the PSDs of several scans of one surface (maps or PSD CSVs);
    /// writes psd.csv, psd.png and stitch.json into --out.
    PsdStitch(StitchArgs),
}

/// How a surface file is read (shared by stats, convert and psd-stitch).
#[derive(Debug, Clone, clap::Args)]
pub struct InputArgs {
    /// Side along x \[m\] (required for .npy and text; must agree with
    /// .x3p/.gwy files).
    #[arg(long, allow_negative_numbers = true)]
    pub length: Option<f64>,
    /// Side along y \[m\] (default: square pixels).
    #[arg(long, allow_negative_numbers = true)]
    pub length_y: Option<f64>,
    /// File format, overriding the extension: x3p, gwy, npy or text.
    #[arg(long, value_parser = parse_format)]
    pub format: Option<SurfaceFormat>,
    /// Fill missing points (NaN, x3p invalid mask) by harmonic
    /// interpolation instead of refusing the file.
    #[arg(long)]
    pub fill_missing: bool,
}

impl InputArgs {
    fn options(&self) -> ReadOptions {
        ReadOptions {
            format: self.format,
            length: self.length,
            length_y: self.length_y,
            missing: if self.fill_missing {
                MissingData::Fill
            } else {
                MissingData::Error
            },
        }
    }
}

fn parse_format(s: &str) -> std::result::Result<SurfaceFormat, String> {
    s.parse()
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
    /// Follow a tabulated PSD (CSV: q \[1/m\], C \[m^4\]) instead of the
    /// self-affine formula; needs --n, --length, optionally --ny, --seed.
    #[arg(long, conflicts_with_all = ["hurst", "scales", "q1", "ql", "rolloff_q0", "rms_height", "rms_slope", "anisotropy"])]
    pub psd: Option<PathBuf>,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(Debug, clap::Args)]
pub struct StatsArgs {
    /// Height map: .x3p, .gwy, .npy (float64/float32) or text matrix (rows = x).
    pub file: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    /// Polynomial to remove first: none, mean, plane, quadratic (default:
    /// plane for .x3p/.gwy, none for .npy/text).
    #[arg(long, value_parser = parse_detrend)]
    pub detrend: Option<Detrend>,
    /// Window: none, hann, blackman-harris (default: hann for .x3p/.gwy,
    /// none for .npy/text, which are taken as periodic).
    #[arg(long, value_parser = parse_window, conflicts_with = "hann")]
    pub window: Option<Window>,
    /// Same as --window hann.
    #[arg(long)]
    pub hann: bool,
    /// Fit the Hurst exponent over QMIN,QMAX [1/m] (default: the trusted band).
    #[arg(long, value_name = "QMIN,QMAX", value_parser = parse_pair)]
    pub fit: Option<(f64, f64)>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write stats.json, psd.csv, psd_line_x.csv, psd_line_y.csv,
    /// psd.png and psd_lines.png into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

#[derive(Debug, clap::Args)]
pub struct ConvertArgs {
    /// Input file.
    pub input_file: PathBuf,
    /// Output file: .x3p, .npy or text (any other extension).
    pub output_file: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    /// z data type of an .x3p output: f64 (bit-exact), f32, i32.
    #[arg(long, default_value = "f64", value_parser = parse_x3p_type)]
    pub x3p_type: X3pType,
    /// Write .npy as float32.
    #[arg(long)]
    pub f32: bool,
}

#[derive(Debug, clap::Args)]
pub struct StitchArgs {
    /// Scans: height maps (.x3p, .gwy, .npy, text) or PSD tables (.csv with
    /// q, C columns).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Side along x \[m\] of .npy/text maps (applies to all of them).
    #[arg(long, allow_negative_numbers = true)]
    pub length: Option<f64>,
    /// Fill missing points by harmonic interpolation.
    #[arg(long)]
    pub fill_missing: bool,
    /// Detrending of the maps.
    #[arg(long, default_value = "plane", value_parser = parse_detrend)]
    pub detrend: Detrend,
    /// Window of the maps.
    #[arg(long, default_value = "hann", value_parser = parse_window)]
    pub window: Window,
    /// Log-spaced bins per decade.
    #[arg(long, default_value_t = 10)]
    pub bins_per_decade: usize,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_detrend(s: &str) -> std::result::Result<Detrend, String> {
    match s {
        "none" => Ok(Detrend::None),
        "mean" => Ok(Detrend::Mean),
        "plane" => Ok(Detrend::Plane),
        "quadratic" => Ok(Detrend::Quadratic),
        _ => Err(format!("'{s}': use none, mean, plane or quadratic")),
    }
}

fn parse_window(s: &str) -> std::result::Result<Window, String> {
    match s {
        "none" => Ok(Window::None),
        "hann" => Ok(Window::Hann),
        "blackman-harris" => Ok(Window::BlackmanHarris),
        _ => Err(format!("'{s}': use none, hann or blackman-harris")),
    }
}

fn parse_x3p_type(s: &str) -> std::result::Result<X3pType, String> {
    match s {
        "f64" => Ok(X3pType::F64),
        "f32" => Ok(X3pType::F32),
        "i32" => Ok(X3pType::I32),
        _ => Err(format!("'{s}': use f64, f32 or i32")),
    }
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
        SurfaceCommand::Convert(a) => run_convert(a),
        SurfaceCommand::PsdStitch(a) => run_stitch(a),
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
            psd: self.psd.clone(),
        }
    }
}

fn run_generate(args: GenerateArgs) -> Result<()> {
    let flags = args.flags();
    let (merged, base_dir, config_doc) = match &args.config {
        None => (flags.clone(), PathBuf::from("."), None),
        Some(path) => {
            let loaded = crate::config::load(path, &args.set)?;
            let sc = loaded.surface()?;
            let base = sc.generate.clone().unwrap_or_default();
            let mut m = base.merged(&flags);
            if m.length.is_none() {
                m.length = sc.length;
            }
            (
                m,
                loaded.base_dir.clone(),
                Some((path.clone(), loaded.document.clone())),
            )
        }
    };
    if let Some((table_path, sp)) = merged.synth_params(None)? {
        // A --psd flag is relative to the working directory, a config key to the config.
        let table_path = if args.psd.is_some() {
            table_path
        } else {
            base_dir.join(table_path)
        };
        return run_generate_psd(&args.out, &table_path, sp, config_doc);
    }
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

fn run_generate_psd(
    out_dir: &Path,
    table_path: &Path,
    sp: SynthParams,
    config_doc: Option<(PathBuf, toml::Table)>,
) -> Result<()> {
    let table = TabulatedPsd::from_csv(table_path)?;
    let map = surface::generate_from_table(&table, &sp)?;
    let stats = surface::stats(&map)?;
    let radial = surface::radial_average(&surface::psd_2d(&map, Window::None)?);
    let qn = std::f64::consts::PI / map.cell_size;
    let band_lo = table
        .q_min()
        .max(2.0 * std::f64::consts::PI / map.length_x().max(map.length_y()));
    let band_hi = table.q_max().min(qn);
    let json = serde_json::json!({
        "version": crate::VERSION,
        "seed": sp.seed,
        "psd_table": table_path.display().to_string(),
        "synth_params": sp,
        "table_rms_height": table.moment(0).sqrt(),
        "table_rms_slope": table.moment(2).sqrt(),
        "grid_band_per_m": [band_lo, band_hi],
        "stats": stats,
        "config": config_doc.as_ref().map(|(p, d)| serde_json::json!({
            "path": p.display().to_string(),
            "document": d,
        })),
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
    let target: Vec<(f64, f64)> = table
        .q()
        .iter()
        .zip(table.c())
        .map(|(q, c)| (*q, *c))
        .collect();
    let measured: Vec<(f64, f64)> = radial
        .q
        .iter()
        .zip(&radial.c)
        .map(|(q, c)| (*q, *c))
        .collect();
    log_plot(
        &png,
        "PSD of the surface generated from a table",
        "m^4",
        vec![
            Series::points("radial average", measured, 2),
            Series::line("tabulated PSD", target, 0),
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

fn read_input(file: &Path, input: &InputArgs) -> Result<(Topography, SurfaceFormat)> {
    let format = input
        .format
        .unwrap_or_else(|| SurfaceFormat::from_path(file));
    let topo = surface::read_topography(file, &input.options())?;
    Ok((topo, format))
}

fn filled_note(topo: &Topography) -> Option<String> {
    (topo.filled > 0).then(|| {
        format!(
            "{} of {} points ({:.3} %) were missing and filled by harmonic (Laplace) interpolation",
            topo.filled,
            topo.heights.len(),
            100.0 * topo.filled as f64 / topo.heights.len() as f64
        )
    })
}

fn run_stats(args: StatsArgs) -> Result<()> {
    let (topo, format) = read_input(&args.file, &args.input)?;
    let measured = format.is_measured();
    let trend = args.detrend.unwrap_or(if measured {
        Detrend::Plane
    } else {
        Detrend::None
    });
    let window = match (args.window, args.hann) {
        (Some(w), _) => w,
        (None, true) => Window::Hann,
        (None, false) if measured => Window::Hann,
        _ => Window::None,
    };
    let an = surface::analyse(&topo, trend, window, args.fit)?;
    let fit = an.hurst;
    let json = serde_json::json!({
        "version": crate::VERSION,
        "file": args.file.display().to_string(),
        "format": format,
        "missing": {
            "filled_points": topo.filled,
            "method": (topo.filled > 0).then_some("harmonic (Laplace) interpolation"),
        },
        "stats": an.stats,
        "hurst_fit": fit,
        "conventions": {
            "radial_psd": "C(q) [m^4], <h^2> = sum C dqx dqy = 2 pi Int q C dq",
            "line_psd": "C1(q) [m^3], <h^2> = 2 Int_0^inf C1 dq",
        },
    });
    if let Some(dir) = &args.out {
        write_stats_dir(dir, &json, &an.radial, &an.line_x, &an.line_y)?;
    }
    if args.json {
        println!("{}", String::from_utf8_lossy(&json_bytes(&json)?));
    } else {
        if let Some(n) = filled_note(&topo) {
            println!("note: {n}");
        }
        print!("{}", an.stats);
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

fn write_stats_dir(
    dir: &Path,
    json: &serde_json::Value,
    radial: &RadialPsd,
    lx: &LinePsd,
    ly: &LinePsd,
) -> Result<()> {
    let mut out = StagedOutput::new(dir)?;
    out.write("stats.json", &json_bytes(json)?)?;
    let mut csv = String::from("q_per_m,c_radial_m4,modes\n");
    for i in 0..radial.q.len() {
        csv.push_str(&format!(
            "{:.10e},{:.10e},{}\n",
            radial.q[i], radial.c[i], radial.count[i]
        ));
    }
    out.write("psd.csv", csv.as_bytes())?;
    for (name, l) in [("psd_line_x.csv", lx), ("psd_line_y.csv", ly)] {
        let mut csv = format!("q_per_m,c1_m3  # {} lines averaged\n", l.lines);
        for (q, c) in l.q.iter().zip(&l.c) {
            csv.push_str(&format!("{q:.10e},{c:.10e}\n"));
        }
        out.write(name, csv.as_bytes())?;
    }
    let png = out.path("psd.png");
    psd_plot(&png, radial, None, "radial PSD")?;
    let png = out.path("psd_lines.png");
    let pts = |l: &LinePsd| {
        l.q.iter()
            .zip(&l.c)
            .map(|(q, c)| (*q, *c))
            .collect::<Vec<_>>()
    };
    log_plot(
        &png,
        "line PSDs",
        "m^3",
        vec![
            Series::line("along x", pts(lx), 0),
            Series::line("along y", pts(ly), 1),
        ],
    )?;
    out.commit()?;
    Ok(())
}

fn run_convert(args: ConvertArgs) -> Result<()> {
    let (topo, _) = read_input(&args.input_file, &args.input)?;
    let note = filled_note(&topo);
    let opts = WriteOptions {
        format: None,
        x3p_type: args.x3p_type,
        npy_precision: if args.f32 {
            NpyPrecision::F32
        } else {
            NpyPrecision::F64
        },
        comment: Some(match &note {
            Some(n) => format!(
                "converted from {} by viscoslide; {n}",
                args.input_file.display()
            ),
            None => format!("converted from {} by viscoslide", args.input_file.display()),
        }),
    };
    surface::write_topography(&topo, &args.output_file, &opts)?;
    println!(
        "{} x {} points, {:.6e} m x {:.6e} m: {}{}",
        topo.nx,
        topo.ny,
        topo.length_x(),
        topo.length_y(),
        args.output_file.display(),
        note.map(|n| format!(" ({n})")).unwrap_or_default()
    );
    Ok(())
}

fn run_stitch(args: StitchArgs) -> Result<()> {
    let mut scans = Vec::new();
    let mut notes = Vec::new();
    for f in &args.files {
        let is_csv = f.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        if is_csv {
            scans.push(ScanPsd::from_csv(f)?);
        } else {
            let input = InputArgs {
                length: args.length,
                length_y: None,
                format: None,
                fill_missing: args.fill_missing,
            };
            let (topo, _) = read_input(f, &input)?;
            if let Some(n) = filled_note(&topo) {
                notes.push(format!("{}: {n}", f.display()));
            }
            scans.push(ScanPsd::from_topography(
                &f.display().to_string(),
                &topo,
                args.detrend,
                args.window,
            )?);
        }
    }
    let st = surface::stitch(&scans, args.bins_per_decade)?;
    let json = serde_json::json!({
        "version": crate::VERSION,
        "rule": "maps: trusted for 2 pi / (L_min / 4) <= q <= (2/3) pi / max(dx, dy) (Jacobs, Junge & Pastewka, Surf. Topogr. Metrol. Prop. 5, 013001, 2017); tables: whole range; log bins averaged with weights = number of modes",
        "detrend": args.detrend,
        "window": args.window,
        "bins_per_decade": args.bins_per_decade,
        "scans": scans.iter().map(|s| serde_json::json!({
            "file": s.name,
            "trusted_q_min": s.q_lo,
            "trusted_q_max": s.q_hi,
        })).collect::<Vec<_>>(),
        "missing": notes,
        "files": ["psd.csv", "psd.png", "stitch.json"],
    });
    let mut out = StagedOutput::new(&args.out)?;
    out.write("psd.csv", st.to_csv().as_bytes())?;
    let png = out.path("psd.png");
    let mut series = Vec::new();
    for (k, s) in scans.iter().enumerate() {
        let label = Path::new(&s.name)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| s.name.clone());
        let trusted: Vec<(f64, f64)> =
            s.q.iter()
                .zip(&s.c)
                .filter(|(q, c)| **q >= s.q_lo && **q <= s.q_hi && **c > 0.0)
                .map(|(q, c)| (*q, *c))
                .collect();
        series.push(Series::points(
            format!("{label} (trusted {:.2e}..{:.2e} 1/m)", s.q_lo, s.q_hi),
            trusted,
            k + 1,
        ));
    }
    series.push(Series::line(
        "stitched",
        st.q.iter().zip(&st.c).map(|(q, c)| (*q, *c)).collect(),
        0,
    ));
    log_plot(&png, "stitched PSD", "m^4", series)?;
    out.write("stitch.json", &json_bytes(&json)?)?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    println!(
        "{} scans stitched into {} bins over {:.3e}..{:.3e} 1/m: {}",
        scans.len(),
        st.q.len(),
        st.q[0],
        st.q[st.q.len() - 1],
        dir.display()
    );
    Ok(())
}

/// A log-log chart of positive values, drawn in units of 10^k `unit` with
/// the largest value in [1, 10) (plotters places no ticks on log axes over
/// very small values).
fn log_plot(path: &Path, title: &str, unit: &str, mut series: Vec<Series>) -> Result<()> {
    let peak = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0, f64::max);
    let floor = peak * 1e-14;
    let k = if peak > 0.0 {
        peak.log10().floor()
    } else {
        0.0
    };
    let scale = 10f64.powf(k);
    for s in &mut series {
        s.points.retain(|p| p.1 > floor && p.0 > 0.0);
        for p in &mut s.points {
            p.1 /= scale;
        }
    }
    series.retain(|s| !s.points.is_empty());
    let chart = XyChart {
        title: title.into(),
        x_label: "q [1/m]".into(),
        y_label: if k == 0.0 {
            format!("C(q) [{unit}]")
        } else {
            format!("C(q) [1e{k} {unit}]")
        },
        log_x: true,
        log_y: true,
        series,
    };
    plot::xy_chart(path, &chart)?;
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
