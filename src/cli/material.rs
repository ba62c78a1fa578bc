//! `viscoslide material ...`: fit DMA data to a creep spectrum, show a
//! material. The numerics live in [`crate::material`].

use std::fmt::Write as _;
use std::path::PathBuf;

use num_complex::Complex64;

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::material::eval::log_space;
use crate::material::{
    fit_spectrum, fit_warnings, material_toml, DmaData, DynamicModuli, FitParams, FitRecord,
    Material, Wlf, LOG10_SHIFT_MAX,
};
use crate::plot::{xy_chart, Series, XyChart};

#[derive(Debug, clap::Subcommand)]
pub enum MaterialCommand {
    /// Print the creep spectrum and a table of E(w).
    Show(ShowArgs),
    /// Fit a creep spectrum to DMA data (E1, E2 vs frequency) and write
    /// material.toml, fit.csv and fit.png.
    Fit(FitArgs),
}

/// `material show`.
#[derive(Debug, clap::Args)]
pub struct ShowArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Lowest angular frequency of the table [rad/s] (default: a decade below
    /// the slowest time's reach).
    #[arg(long)]
    pub from: Option<f64>,
    /// Highest angular frequency of the table [rad/s].
    #[arg(long)]
    pub to: Option<f64>,
    /// Number of rows, log-spaced (default: 4 per decade).
    #[arg(long)]
    pub points: Option<usize>,
}

/// `material fit`.
#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// CSV with a header: frequency_hz or omega_rad_s, e1_pa, e2_pa, optional
    /// temperature_c; `#` lines are comments.
    pub data: PathBuf,
    /// Number of characteristic times (geometric progression).
    #[arg(long, default_value_t = 34)]
    pub terms: usize,
    /// Ratio of consecutive times: a number > 1, or `e`.
    #[arg(long, default_value = "e")]
    pub ratio: String,
    /// WLF constants `C1,C2,TREF` (C2 in K, TREF in C) for data at several
    /// temperatures.
    #[arg(long, value_name = "C1,C2,TREF")]
    pub wlf: Option<String>,
    /// Temperature (C) the material should describe (default: TREF with
    /// --wlf, else the data's temperature).
    #[arg(long)]
    pub temperature: Option<f64>,
    /// Poisson ratio written into material.toml.
    #[arg(long, default_value_t = 0.5)]
    pub poisson: f64,
    /// Output directory (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(cmd: MaterialCommand) -> Result<()> {
    match cmd {
        MaterialCommand::Show(args) => show(&args),
        MaterialCommand::Fit(args) => fit(&args),
    }
}

fn show(args: &ShowArgs) -> Result<()> {
    let m = if is_material_file(&args.config.config) {
        // The file `material fit` writes (a `[material]` and its `[fit]`
        // record), shown as a config's `model = "file"` would load it.
        if !args.config.set.is_empty() {
            return Err(Error::Invalid(format!(
                "{} is a material file (it has a [fit] record); --set applies to configs: load it from one with [material] model = \"file\"",
                args.config.config.display()
            )));
        }
        crate::material::load_material_file(&args.config.config, None)?
    } else {
        // The material at the config's `[loading] temperature`, as a
        // solve sees it.
        let cfg = args.config.load()?;
        let temperature = cfg.config.loading.as_ref().and_then(|l| l.temperature);
        let m = cfg.material()?.build(&cfg.base_dir)?.at(temperature)?;
        if let Some(w) = m.extrapolated_shift_warning() {
            eprintln!("warning: {w}");
        }
        m
    };
    print!("{}", describe(&m, args.from, args.to, args.points)?);
    Ok(())
}

/// Whether `path` is a material file `material fit` wrote: a TOML table
/// with a `[fit]` record, which no config has. A file that cannot be read
/// or parsed is left to the config's loader, whose errors name it.
fn is_material_file(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|doc| doc.contains_key("fit"))
}

/// Bytes one frequency of `material show` holds: its moduli and loss
/// tangent and its printed line.
const BYTES_PER_POINT: u64 = 256;

/// The text `material show` prints.
fn describe(
    m: &Material,
    from: Option<f64>,
    to: Option<f64>,
    points: Option<usize>,
) -> Result<String> {
    let s = &m.spectrum;
    let mut out = String::new();
    let e0 = s.relaxed_modulus();
    let einf = s.glassy_modulus;
    let _ = writeln!(out, "creep spectrum (Eq. 2), poisson = {}", m.poisson);
    let _ = writeln!(out, "  relaxed modulus E0    = {e0:.6e} Pa");
    let _ = writeln!(out, "  glassy modulus  E_inf = {einf:.6e} Pa");
    let _ = writeln!(out, "  terms: {}", s.terms.len());
    if !s.terms.is_empty() {
        let _ = writeln!(
            out,
            "  {:>4}  {:>14}  {:>14}",
            "k", "C_k [1/Pa]", "tau_k [s]"
        );
        for (k, t) in s.terms.iter().enumerate() {
            let _ = writeln!(
                out,
                "  {:>4}  {:>14.6e}  {:>14.6e}",
                k + 1,
                t.compliance,
                t.time
            );
        }
    }
    if let Some(t) = m.temperature {
        let _ = writeln!(out, "  spectrum at T = {t} C");
    }
    if let Some([lo, hi]) = m.frequency_range {
        let _ = writeln!(
            out,
            "  fitted to data from {lo:.4e} to {hi:.4e} rad/s: solves that excite frequencies a decade beyond them warn"
        );
    }
    if let Some(w) = &m.wlf {
        let tr = w.reference_temperature;
        let _ = writeln!(
            out,
            "WLF shift (physics.md sections 2 and 12): C1 = {}, C2 = {} K, T_ref = {tr} C; log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref), valid at T >= {} C (|log10 a_T| <= {LOG10_SHIFT_MAX}; the pole T_ref - C2 = {} C)",
            w.c1,
            w.c2,
            w.lowest_temperature_quoted(),
            tr - w.c2
        );
        let mut shifts = String::new();
        for dt in [-20.0, -10.0, 10.0, 20.0, 40.0] {
            if let Ok(a) = w.shift_factor(tr + dt) {
                let _ = write!(shifts, "  {} C: {a:.4e}", tr + dt);
            }
        }
        let _ = writeln!(out, "  a_T at{shifts}");
        match w.data_range {
            Some([lo, hi]) => {
                let _ = writeln!(
                    out,
                    "  fitted to data from {lo} to {hi} C: beyond them a_T is extrapolated (solves there warn)"
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "  the data's temperatures are not recorded: nothing warns of an extrapolated a_T ([material] wlf_range = [lowest, highest] records them)"
                );
            }
        }
    }
    let tmin = s.terms.iter().map(|t| t.time).fold(f64::INFINITY, f64::min);
    let tmax = s.terms.iter().map(|t| t.time).fold(0.0, f64::max);
    // Relaxation times are shorter than creep times by up to E0/E_inf, so the
    // upper end reaches a decade beyond the fastest relaxation.
    let (dfrom, dto) = if s.terms.is_empty() {
        (1e-2, 1e6)
    } else {
        (0.1 / tmax, 10.0 * einf / (e0 * tmin))
    };
    let from = from.unwrap_or(dfrom);
    let to = to.unwrap_or(dto);
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to > from) {
        return Err(Error::Invalid(format!(
            "--from {from} and --to {to} rad/s must satisfy 0 < from < to"
        )));
    }
    let n = points.unwrap_or(((to / from).log10() * 4.0).ceil() as usize + 1);
    if n < 2 {
        return Err(Error::Invalid(format!("--points {n} must be at least 2")));
    }
    crate::io::memory::check_count(
        || format!("modulus table of {n} points (--points)"),
        n as u64,
        BYTES_PER_POINT,
    )
    .map_err(|e| Error::Invalid(e.to_string()))?;
    let d = DynamicModuli::evaluate(s, &log_space(from, to, n));
    let _ = writeln!(
        out,
        "  {:>12}  {:>13}  {:>13}  {:>11}",
        "w [rad/s]", "E1 [Pa]", "E2 [Pa]", "tan delta"
    );
    for i in 0..n {
        let _ = writeln!(
            out,
            "  {:>12.4e}  {:>13.5e}  {:>13.5e}  {:>11.4e}",
            d.omega[i], d.storage[i], d.loss[i], d.tan_delta[i]
        );
    }
    Ok(out)
}

fn parse_ratio(s: &str) -> Result<f64> {
    let t = s.trim();
    let r = if t.eq_ignore_ascii_case("e") {
        std::f64::consts::E
    } else {
        t.parse::<f64>()
            .map_err(|_| Error::Invalid(format!("--ratio '{s}': expected a number > 1 or 'e'")))?
    };
    if !(r.is_finite() && r > 1.0) {
        return Err(Error::Invalid(format!("--ratio {s}: must be > 1")));
    }
    Ok(r)
}

fn parse_wlf(s: &str) -> Result<Wlf> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| Error::Invalid(format!("--wlf '{s}': expected three numbers C1,C2,TREF")))?;
    if v.len() != 3 {
        return Err(Error::Invalid(format!(
            "--wlf '{s}': expected three numbers C1,C2,TREF (C2 in K, TREF in C)"
        )));
    }
    Wlf::new(v[0], v[1], v[2]).map_err(|e| Error::Invalid(format!("--wlf '{s}': {e}")))
}

fn fit(args: &FitArgs) -> Result<()> {
    let ratio = parse_ratio(&args.ratio)?;
    let wlf = args.wlf.as_deref().map(parse_wlf).transpose()?;
    let data = DmaData::read(&args.data)?;
    let (points, temperature) = data.reduced(wlf.as_ref(), args.temperature)?;
    let omega: Vec<f64> = points.iter().map(|p| p.omega).collect();
    let measured: Vec<Complex64> = points
        .iter()
        .map(|p| Complex64::new(p.storage, p.loss))
        .collect();
    let params = FitParams {
        terms: args.terms,
        ratio,
        shortest_time: None,
    };
    let fit = fit_spectrum(&omega, &measured, &params)?;
    let material = Material::new(fit.creep.clone(), args.poisson)?;
    let info = &fit.info;
    let warnings = fit_warnings(&data, &fit);
    let record = FitRecord {
        data: args.data.display().to_string(),
        points: info.points,
        terms: args.terms,
        ratio,
        shortest_time: info.shortest_time,
        longest_time: info.longest_time,
        nonzero_terms: info.nonzero_terms,
        wlf_c1: wlf.map(|w| w.c1),
        wlf_c2: wlf.map(|w| w.c2),
        wlf_reference_temperature: wlf.map(|w| w.reference_temperature),
        wlf_range: wlf.and(data.temperature_span()),
        frequency_range: Some(info.frequency_range),
        temperature,
        weighting: "relative per component: (E1_fit - E1)/E1 and (E2_fit - E2)/E2".into(),
        rms_relative_error_e1: info.rms_relative_storage,
        rms_relative_error_e2: info.rms_relative_loss,
        max_relative_error_e1: info.max_relative_storage,
        max_relative_error_e2: info.max_relative_loss,
        relaxed_modulus: fit.creep.relaxed_modulus(),
        warnings: warnings.clone(),
        version: crate::version::VERSION.into(),
    };
    let toml_text = material_toml(&material, Some(&record))?;

    // fit.csv: data in the order given, frequencies at the fit temperature.
    let mut csv = String::from(
        "omega_rad_s,temperature_c,e1_measured_pa,e2_measured_pa,e1_fit_pa,e2_fit_pa\n",
    );
    for (p, (&w, e)) in data.points.iter().zip(omega.iter().zip(&measured)) {
        let f = fit.creep.modulus(w);
        let t = p.temperature.map(|t| t.to_string()).unwrap_or_default();
        let _ = writeln!(csv, "{w:e},{t},{:e},{:e},{:e},{:e}", e.re, e.im, f.re, f.im);
    }

    // fit.png: E1 and E2 against w on log-log axes (the paper's Fig. 2).
    let wmin = omega.iter().copied().fold(f64::INFINITY, f64::min);
    let wmax = omega.iter().copied().fold(0.0, f64::max);
    let curve = DynamicModuli::evaluate(&fit.creep, &log_space(wmin / 3.0, wmax * 3.0, 300));
    let t_label = temperature
        .map(|t| format!(" at {t} C"))
        .unwrap_or_default();
    let chart = XyChart {
        title: format!("DMA fit, {} times{}", args.terms, t_label),
        x_label: "angular frequency w [rad/s]".into(),
        y_label: "modulus [Pa]".into(),
        log_x: true,
        log_y: true,
        series: vec![
            Series::points(
                "E1 measured",
                omega
                    .iter()
                    .zip(&measured)
                    .map(|(&w, e)| (w, e.re))
                    .collect(),
                0,
            ),
            Series::points(
                "E2 measured",
                omega
                    .iter()
                    .zip(&measured)
                    .map(|(&w, e)| (w, e.im))
                    .collect(),
                2,
            ),
            Series::line(
                "E1 fit",
                curve
                    .omega
                    .iter()
                    .copied()
                    .zip(curve.storage.iter().copied())
                    .collect(),
                0,
            ),
            Series::line(
                "E2 fit",
                curve
                    .omega
                    .iter()
                    .copied()
                    .zip(curve.loss.iter().copied())
                    .collect(),
                2,
            ),
        ],
    };

    let mut out = StagedOutput::new(&args.out)?;
    out.write("material.toml", toml_text.as_bytes())?;
    out.write("fit.csv", csv.as_bytes())?;
    let png = out.path("fit.png");
    xy_chart(&png, &chart)?;
    let written = out.commit()?;
    println!(
        "fitted {} points with {} times (ratio {ratio:.6}), {} non-zero",
        info.points, args.terms, info.nonzero_terms
    );
    println!(
        "  E0 = {:.4e} Pa, E_inf = {:.4e} Pa, temperature {}",
        fit.creep.relaxed_modulus(),
        fit.creep.glassy_modulus,
        temperature
            .map(|t| format!("{t} C"))
            .unwrap_or_else(|| "unknown".into())
    );
    println!(
        "  rms relative error: E1 {:.3e}, E2 {:.3e} (max {:.3e}, {:.3e})",
        info.rms_relative_storage,
        info.rms_relative_loss,
        info.max_relative_storage,
        info.max_relative_loss
    );
    println!(
        "  time grid {:.3e} .. {:.3e} s, margin beyond data {:.2} / {:.2} decades (high / low frequency)",
        info.shortest_time, info.longest_time, info.margin_decades.0, info.margin_decades.1
    );
    if info.margin_decades.0 < 0.5 || info.margin_decades.1 < 0.5 {
        println!(
            "  note: the time grid reaches less than half a decade beyond the data at one end; consider more --terms or a larger --ratio"
        );
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    // The fit's temperature beyond the data's: every modulus of the file
    // is the WLF shift's extrapolation (a solve with it warns again).
    let beyond = wlf
        .zip(record.wlf_range)
        .zip(temperature)
        .and_then(|((w, range), t)| w.with_data_range(range).ok()?.extrapolation(t));
    if let Some(phrase) = beyond {
        eprintln!("warning: the fit's temperature {phrase}; fit nearer the data");
    }
    for p in written {
        println!("  wrote {}", p.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::CreepSpectrum;

    #[test]
    fn show_lists_terms_and_table() {
        let s = CreepSpectrum::standard_linear_solid(1e7 / 3.0, 1e7, 0.01).unwrap();
        let m = Material::new(s, 0.5).unwrap();
        let text = describe(&m, None, None, Some(5)).unwrap();
        assert!(text.contains("2.000000e-7"), "{text}");
        assert!(text.contains("tan delta"));
        assert_eq!(text.lines().count(), 4 + 2 + 1 + 5);
        assert!(describe(&m, Some(10.0), Some(1.0), None).is_err());
        assert_eq!(parse_ratio("e").unwrap(), std::f64::consts::E);
        assert!(parse_ratio("1").is_err());
        assert!(parse_wlf("8.86,101.6").is_err());
    }
}
