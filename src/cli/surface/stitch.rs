//! `viscoslide surface psd-stitch`: one PSD from several scans of a
//! surface (maps or PSD tables).

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::io::StagedOutput;
use crate::plot::Series;
use crate::surface::{self, Detrend, ScanPsd, Window};

use super::{
    filled_note, json_bytes, log_plot, pairs, parse_detrend, parse_window, read_input, InputArgs,
};

#[derive(Debug, clap::Args)]
pub struct StitchArgs {
    /// Scans: height maps (.x3p, .gwy, .npy, text) or PSD tables (.csv with
    /// q, C columns).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Side along x in m of .npy/text maps (applies to all of them).
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

pub(super) fn run(args: StitchArgs) -> Result<()> {
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
        "version": crate::version::VERSION,
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
    series.push(Series::line("stitched", pairs(&st.q, &st.c), 0));
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
