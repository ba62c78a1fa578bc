//! `viscoslide persson CONFIG --out DIR`: Persson's friction and contact
//! area against speed for the config's material, surface and pressure
//! (physics.md section 10), written as `persson.json`, `persson.csv` and
//! `persson.png` (all or nothing).

use std::path::{Path, PathBuf};

use crate::config::{LoadedConfig, XiScale};
use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::persson::{self, Persson, PerssonParams, PerssonPoint};
use crate::plot::{self, Series, XyChart};
use crate::problem::persson::{theory_inputs, TheoryInputs};
use crate::surface::Window;

#[derive(Debug, clap::Args)]
pub struct PerssonArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Output directory (persson.json, persson.csv, persson.png).
    #[arg(long)]
    pub out: PathBuf,
    /// Log-spaced speeds MIN,MAX,COUNT in m/s. Default: the range of the
    /// config's `[sweep]` speeds (speed, speed_range, xi or xi_range) at 100
    /// points, else four decades centred on the loss peak of the material.
    #[arg(long, value_name = "MIN,MAX,COUNT", value_parser = parse_speeds)]
    pub speeds: Option<(f64, f64, usize)>,
    /// Tabulated PSD (CSV whose first two columns are q in 1/m and C in m^4,
    /// as `surface stats --out` writes) instead of the config's surface.
    #[arg(long, value_name = "CSV")]
    pub psd: Option<PathBuf>,
    /// Window of the PSD of a surface file: none, hann, blackman-harris
    /// (default: `[surface] window`, hann for a scan, none for a map with
    /// `periodic = true`).
    #[arg(long, value_parser = crate::surface::parse_window, conflicts_with = "hann")]
    pub window: Option<Window>,
    /// Same as --window hann.
    #[arg(long)]
    pub hann: bool,
}

fn parse_speeds(s: &str) -> std::result::Result<(f64, f64, usize), String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [a, b, n] = parts.as_slice() else {
        return Err(format!("expected MIN,MAX,COUNT, got '{s}'"));
    };
    let num = |t: &str| {
        t.parse::<f64>()
            .map_err(|_| format!("'{t}' is not a number"))
    };
    let (a, b) = (num(a)?, num(b)?);
    let n: usize = n
        .parse()
        .map_err(|_| format!("'{n}' is not a whole number of speeds"))?;
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b >= a) || n == 0 || (n == 1 && b != a) {
        return Err(format!(
            "need 0 < MIN <= MAX (m/s) and COUNT >= 1 (COUNT = 1 only with MIN = MAX), got '{s}'"
        ));
    }
    Ok((a, b, n))
}

/// Speeds of the config's `[sweep]` as `(min, max)` \[m/s\] of its positive
/// speeds (`xi` converted with `xi_scale`), if it has any.
fn sweep_speed_range(cfg: &LoadedConfig, xi_scale: Option<XiScale>) -> Result<Option<(f64, f64)>> {
    let Some(sw) = &cfg.config.sweep else {
        return Ok(None);
    };
    let (values, is_xi): (Vec<f64>, bool) = if let Some(r) = sw.speed_range {
        (vec![r[0], r[1]], false)
    } else if let Some(r) = sw.xi_range {
        (vec![r[0], r[1]], true)
    } else if let Some(v) = &sw.speed {
        (v.clone(), false)
    } else if let Some(v) = &sw.xi {
        (v.clone(), true)
    } else {
        return Ok(None);
    };
    let scale = if is_xi {
        match xi_scale {
            Some(x) => x.speed(1.0),
            None => {
                return Err(Error::Invalid(
                    "[sweep] gives xi, which needs a single-relaxation material and a surface length; give --speeds MIN,MAX,COUNT".into(),
                ))
            }
        }
    } else {
        1.0
    };
    let pos = values
        .iter()
        .map(|v| v * scale)
        .filter(|v| v.is_finite() && *v > 0.0);
    let lo = pos.clone().fold(f64::INFINITY, f64::min);
    let hi = pos.fold(0.0, f64::max);
    Ok((hi > 0.0).then_some((lo, hi)))
}

/// Points of the default curve.
const DEFAULT_COUNT: usize = 100;

/// Bytes one speed of the curve holds: its point, its rows of the CSV and
/// the JSON and its chart data.
const BYTES_PER_SPEED: u64 = 1024;

/// The `[loading]` keys `persson` reads or could be misread from, checked
/// as a solve checks them: one of `normal_load`, `mean_pressure` and
/// `approach`, one of `speed` and `xi`, and finite values
/// ([`crate::config::LoadingConfig::check_finite`]). The curve's
/// speeds are its own, but a config a solve would refuse is not answered.
fn check_loading(cfg: &LoadedConfig) -> Result<()> {
    let Some(l) = &cfg.config.loading else {
        return Ok(());
    };
    let invalid = |m: &str| Error::Invalid(m.into());
    l.check_finite().map_err(Error::Invalid)?;
    l.pressing().map_err(invalid)?;
    if l.speed.is_some() || l.xi.is_some() {
        l.sliding().map_err(invalid)?;
    }
    for (key, value, unit) in [("speed", l.speed, " m/s"), ("xi", l.xi, "")] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(Error::Invalid(format!(
                "[loading] {key} = {v}{unit} must be finite and >= 0"
            )));
        }
    }
    for (key, value, unit) in [
        ("normal_load", l.normal_load, "N"),
        ("mean_pressure", l.mean_pressure, "Pa"),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::Invalid(format!(
                "[loading] {key} = {v} {unit} must be positive and finite"
            )));
        }
    }
    Ok(())
}

pub fn run(args: PerssonArgs) -> Result<()> {
    let cfg = args.config.load()?;
    check_loading(&cfg)?;
    if cfg.heated() {
        eprintln!(
            "note: Persson's theory here is isothermal, at the config's temperature; [heating] is not applied (a heated solve reports Persson's friction at its effective temperature)"
        );
    }
    let window = args.window.or(args.hann.then_some(Window::Hann));
    let inputs = theory_inputs(&cfg, args.psd.as_deref(), window)?;
    let theory = Persson::new(
        &inputs.material,
        &inputs.psd,
        inputs.nominal_pressure,
        PerssonParams::default(),
    )?;
    let (from, to, count, origin) = match args.speeds {
        Some((a, b, n)) => (a, b, n, "--speeds".to_string()),
        None => match sweep_speed_range(&cfg, inputs.xi_scale())? {
            Some((a, b)) if b > a => (a, b, DEFAULT_COUNT, "[sweep] speed range".to_string()),
            Some((a, _)) => (
                a / 100.0,
                a * 100.0,
                DEFAULT_COUNT,
                "four decades around the [sweep] speed".to_string(),
            ),
            None => {
                let vc = theory.peak_speed_estimate().ok_or_else(|| {
                    Error::Invalid(
                        "the material is elastic (no loss peak): give --speeds MIN,MAX,COUNT"
                            .into(),
                    )
                })?;
                (
                    vc / 100.0,
                    vc * 100.0,
                    DEFAULT_COUNT,
                    "four decades around the loss peak (w_peak / q_slope)".to_string(),
                )
            }
        },
    };
    crate::io::memory::check_count(
        || format!("Persson curve of {count} speeds ({origin})"),
        count as u64,
        BYTES_PER_SPEED,
    )
    .map_err(|e| Error::Invalid(e.to_string()))?;
    let speeds = persson::log_speeds(from, to, count);
    // The frequencies the curve's slowest and fastest speeds excite over
    // the PSD's wavenumbers, against the material's data.
    let beyond =
        crate::problem::persson::curve_frequency_warnings(&inputs.material, &inputs.psd, from, to);
    let mut inputs = inputs;
    inputs.warnings.extend(beyond);
    for n in &inputs.notes {
        eprintln!("note: {n}");
    }
    for w in &inputs.warnings {
        eprintln!("warning: {w}");
    }
    let t0 = std::time::Instant::now();
    let curve = theory.curve(&speeds)?;
    let elapsed = t0.elapsed().as_secs_f64();
    let xi: Option<Vec<f64>> = inputs
        .xi_scale()
        .map(|x| curve.iter().map(|p| x.xi(p.speed)).collect());

    let json = report_json(
        &cfg,
        &inputs,
        &theory,
        &curve,
        xi.as_deref(),
        (from, to, count, &origin),
        elapsed,
    );
    let mut out = StagedOutput::new(&args.out)?;
    let mut bytes = serde_json::to_vec_pretty(&json)
        .map_err(|e| Error::Invalid(format!("cannot encode JSON: {e}")))?;
    bytes.push(b'\n');
    out.write("persson.json", &bytes)?;
    out.write("persson.csv", curve_csv(&curve, xi.as_deref()).as_bytes())?;
    let png = out.path("persson.png");
    plot_curve(&png, &curve, inputs.nominal_pressure)?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    let peak = curve
        .iter()
        .max_by(|a, b| a.friction_coefficient.total_cmp(&b.friction_coefficient))
        .expect("at least one speed");
    println!(
        "Persson: {} speeds from {:.3e} to {:.3e} m/s ({origin}), sigma0 = {:.4e} Pa, peak mu = {:.5e} at v = {:.4e} m/s (A/A0 = {:.4e}), {:.3} s: {}",
        curve.len(),
        from,
        to,
        inputs.nominal_pressure,
        peak.friction_coefficient,
        peak.speed,
        peak.contact_area_fraction,
        elapsed,
        dir.display()
    );
    Ok(())
}

fn report_json(
    cfg: &LoadedConfig,
    inputs: &TheoryInputs,
    theory: &Persson,
    curve: &[PerssonPoint],
    xi: Option<&[f64]>,
    speeds: (f64, f64, usize, &str),
    elapsed: f64,
) -> serde_json::Value {
    let s = &inputs.material.spectrum;
    let psd = theory.psd();
    // The isothermal temperature and its WLF shift factor, as summary.json.
    let shift = inputs.material.temperature_shift();
    serde_json::json!({
        "version": crate::version::VERSION,
        "temperature": shift.map(|t| t.temperature),
        "shift_factor": shift.map(|t| t.shift_factor),
        "reference_temperature": shift.map(|t| t.reference_temperature),
        "theory": "Persson (J. Chem. Phys. 115, 3840 (2001); J. Phys.: Condens. Matter 18, 7789 (2006))",
        "speed": curve.iter().map(|p| p.speed).collect::<Vec<_>>(),
        "xi": xi,
        "friction_coefficient": curve.iter().map(|p| p.friction_coefficient).collect::<Vec<_>>(),
        "contact_area_fraction": curve.iter().map(|p| p.contact_area_fraction).collect::<Vec<_>>(),
        "g_q1": curve.iter().map(|p| p.g_q1).collect::<Vec<_>>(),
        "inputs": {
            "sigma0_pa": inputs.nominal_pressure,
            "sigma0_from": inputs.pressure_from,
            "q0_per_m": theory.q_min(),
            "q1_per_m": theory.q_max(),
            "psd": {
                "source": inputs.source,
                "convention": "<h^2> = 2 pi Int q C(q) dq",
                "rms_height_m": psd.moment(0).sqrt(),
                "rms_slope": psd.moment(2).sqrt(),
            },
            "material": {
                "relaxed_modulus_pa": s.relaxed_modulus(),
                "glassy_modulus_pa": s.glassy_modulus,
                "poisson": inputs.material.poisson,
                "creep_terms": s.terms.len(),
                "loss_peak_rad_per_s": persson::loss_peak(s),
            },
            "xi_definition": xi.map(|_| "v tau / L, tau the creep time, L the surface's side along x"),
            "speeds": {"from_m_per_s": speeds.0, "to_m_per_s": speeds.1, "count": speeds.2, "origin": speeds.3},
            "quadrature": theory.params(),
        },
        "notes": inputs.notes,
        "warnings": inputs.warnings,
        "wall_time_s": elapsed,
        "config": {"path": cfg.path.display().to_string(), "document": cfg.document},
        "files": ["persson.json", "persson.csv", "persson.png"],
    })
}

fn curve_csv(curve: &[PerssonPoint], xi: Option<&[f64]>) -> String {
    let mut s = String::from("speed_m_per_s,xi,friction_coefficient,contact_area_fraction,g_q1\n");
    for (i, p) in curve.iter().enumerate() {
        let x = xi.map(|x| format!("{:.10e}", x[i])).unwrap_or_default();
        s.push_str(&format!(
            "{:.10e},{x},{:.10e},{:.10e},{:.10e}\n",
            p.speed, p.friction_coefficient, p.contact_area_fraction, p.g_q1
        ));
    }
    s
}

fn plot_curve(path: &Path, curve: &[PerssonPoint], sigma0: f64) -> Result<()> {
    let mu: Vec<(f64, f64)> = curve
        .iter()
        .map(|p| (p.speed, p.friction_coefficient))
        .collect();
    let area: Vec<(f64, f64)> = curve
        .iter()
        .map(|p| (p.speed, p.contact_area_fraction))
        .collect();
    let charts = [
        XyChart {
            title: format!("Persson's theory, sigma0 = {sigma0:.3e} Pa"),
            x_label: "v [m/s]".into(),
            y_label: "friction coefficient".into(),
            log_x: true,
            log_y: false,
            series: vec![Series::line("Persson mu", mu, 0)],
        },
        XyChart {
            title: String::new(),
            x_label: "v [m/s]".into(),
            y_label: "A / A0".into(),
            log_x: true,
            log_y: false,
            series: vec![Series::line("Persson A/A0", area, 2)],
        },
    ];
    plot::xy_charts_stacked(path, &charts)?;
    Ok(())
}
