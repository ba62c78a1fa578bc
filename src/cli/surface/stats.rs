//! `viscoslide surface stats`: statistics and PSDs of a height map.

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::io::StagedOutput;
use crate::plot::Series;
use crate::surface::{self, Detrend, LinePsd, Preprocessing, RadialPsd, Window};

use super::{
    filled_note, json_bytes, log_plot, pairs, parse_detrend, parse_pair, parse_window, psd_plot,
    read_input, InputArgs,
};

#[derive(Debug, clap::Args)]
pub struct StatsArgs {
    /// Height map: .x3p, .gwy, .npy (float64/float32) or text matrix (rows = x).
    pub file: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    /// Polynomial to remove first: none, mean, plane, quadratic (default:
    /// plane, whatever the format; none with --periodic).
    #[arg(long, value_parser = parse_detrend)]
    pub detrend: Option<Detrend>,
    /// Window: none, hann, blackman-harris (default: hann, whatever the
    /// format; none with --periodic).
    #[arg(long, value_parser = parse_window, conflicts_with = "hann")]
    pub window: Option<Window>,
    /// The map is one period of a periodic surface (a generated map): no
    /// detrending and no window by default.
    #[arg(long)]
    pub periodic: bool,
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

pub(super) fn run(args: StatsArgs) -> Result<()> {
    let (topo, format) = read_input(&args.file, &args.input)?;
    let window = args.window.or(args.hann.then_some(Window::Hann));
    let pre = Preprocessing::resolve(args.periodic, args.detrend, window);
    let an = surface::analyse(&topo, pre.detrend, pre.window, args.fit)
        .map_err(|e| surface::SurfaceError::Invalid(format!("{}: {e}", args.file.display())))?;
    let warnings: Vec<String> = surface::slope_warning(
        an.stats.rms_slope_fd_psd,
        an.stats.rms_slope_real,
        "the radial PSD of this map",
    )
    .into_iter()
    .chain(surface::empty_band_reason(&topo).map(|r| {
        format!(
            "{r}: the Hurst fit and the PSD's low end are not to be trusted; measure a wider map"
        )
    }))
    .collect();
    if args.out.is_some() && an.radial.c.iter().all(|c| *c == 0.0) {
        return Err(crate::error::Error::Invalid(format!(
            "{}: the map is flat after detrending (rms height {:.3e} m): its PSD is zero and there is nothing to draw; surface stats without --out prints its statistics",
            args.file.display(),
            an.stats.rms_height_real
        )));
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let fit = an.hurst;
    let json = serde_json::json!({
        "version": crate::version::VERSION,
        "file": args.file.display().to_string(),
        "format": format,
        "missing": {
            "filled_points": topo.filled,
            "method": (topo.filled > 0).then_some("harmonic (Laplace) interpolation"),
        },
        "preprocessing": pre,
        "stats": an.stats,
        "warnings": warnings,
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
    log_plot(
        &png,
        "line PSDs",
        "m^3",
        vec![
            Series::line("along x", pairs(&lx.q, &lx.c), 0),
            Series::line("along y", pairs(&ly.q, &ly.c), 1),
        ],
    )?;
    out.commit()?;
    Ok(())
}
