//! `viscoslide analyze DIR`: anisotropy of the deformed surface (Eq. 11-13),
//! `C_chi` contours and contact spots of a finished solve; writes
//! `analysis.json` and the figures into DIR, all or nothing. Its defaults
//! are the solve's own: the same settings reproduce the `analysis.json`
//! the solve wrote.

use std::path::PathBuf;

use crate::analysis::{analyze_dir, AnalysisOverrides, ANALYSIS_FILES};
use crate::error::Result;
use crate::surface::{parse_window, Window};

#[derive(Debug, clap::Args)]
pub struct AnalyzeArgs {
    /// Output directory of a solve (summary.json, displacement.npy,
    /// contact.npy, pressure.npy).
    pub dir: PathBuf,
    /// Lower band factor: |q| >= zeta1 q0, q0 = 2 pi / L (default: the
    /// solve's `[analysis] zeta1`, else 1).
    #[arg(long)]
    pub zeta1: Option<f64>,
    /// Upper band factor: |q| <= zeta2 q0 (default: the solve's `[analysis]
    /// zeta2`, else the surface's number of scales, else n/2).
    #[arg(long)]
    pub zeta2: Option<f64>,
    /// Levels of C_chi(q)/C_chi(0) for the contour ellipses (default: the
    /// solve's `[analysis] chi_levels`, else 0.5,0.3).
    #[arg(long, value_delimiter = ',')]
    pub levels: Option<Vec<f64>>,
    /// Radius of the C_chi estimator window in cells (default: from the
    /// area-weighted spot size).
    #[arg(long)]
    pub chi_window: Option<f64>,
    /// Taper of the displacement before its PSD: none, hann,
    /// blackman-harris (default: the solve's own, none for a periodic
    /// solve and hann otherwise, from summary.json `formulation`).
    #[arg(long, value_parser = parse_window, conflicts_with = "periodic")]
    pub window: Option<Window>,
    /// Same as --window none.
    #[arg(long)]
    pub periodic: bool,
}

pub fn run(args: AnalyzeArgs) -> Result<()> {
    let overrides = AnalysisOverrides {
        zeta1: args.zeta1,
        zeta2: args.zeta2,
        chi_levels: args.levels,
        chi_window_cells: args.chi_window,
        window: args.window.or(args.periodic.then_some(Window::None)),
    };
    let r = analyze_dir(&args.dir, &overrides)?;
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "gamma = {:.4}, theta_P = {:.2} deg (band {} < |q|/q0 < {}, {} modes)",
        r.gamma, r.theta_p_deg, r.band.zeta1, r.band.zeta2, r.band.modes
    );
    match (r.lambda, r.ellipse_angle_deg, r.lambda_level) {
        (Some(l), Some(a), Some(lev)) => {
            println!("lambda = {l:.4}, ellipse major axis {a:.2} deg (C_chi/C_chi(0) = {lev})")
        }
        _ => println!("lambda: no ellipse could be fitted"),
    }
    println!(
        "spots: {} (4-connected; {} 8-connected), {} touching the edge, mean {:.2} cells",
        r.spots.count, r.spots.count_8_connected, r.spots.touching_edge, r.spots.mean_area_cells
    );
    println!(
        "wrote {} files into {}",
        ANALYSIS_FILES.len(),
        args.dir.display()
    );
    Ok(())
}
