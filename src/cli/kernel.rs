//! `viscoslide kernel ...`: influence coefficients of Eq. 4-6 for chosen
//! cell offsets (physics.md section 3) and the cell-averaged derivative used
//! by the friction stencil (physics.md section 5).

use crate::error::{Error, Result};
use crate::kernel::{non_finite, Axis, SlidingKernel, ThetaRule};
use crate::response::SlidingResponse;

#[derive(Debug, clap::Args)]
pub struct KernelArgs {
    /// TOML configuration file with `[material]` and optional `[layer]`
    /// (and `[loading] temperature`: the material at that temperature, as
    /// a solve sees it).
    #[arg(long)]
    pub config: std::path::PathBuf,
    /// Override any key, e.g. `--set layer.thickness=0.0075` (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// Side of the cell along x in m (and along y unless --cell-size-y).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cell_size: f64,
    /// Side of the cell along y in m, for rectangular cells (a scan with
    /// non-square pixels, physics.md section 11); default --cell-size.
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cell_size_y: Option<f64>,
    /// Sliding speed [m/s] (0: relaxed; `inf`: glassy).
    #[arg(long, value_name = "M/S", allow_negative_numbers = true)]
    pub speed: f64,
    /// Sliding direction, degrees from +x.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub direction_deg: f64,
    /// Cell offset `I,J` (i along x); repeatable.
    #[arg(long = "offset", value_name = "I,J", value_parser = parse_offset, required = true, allow_hyphen_values = true)]
    pub offsets: Vec<(i64, i64)>,
    /// Print a JSON array instead of a table.
    #[arg(long)]
    pub json: bool,
    /// With a `[layer]`: the paper's Eq. 6 collocation (`Theta` at the
    /// centre distance times the half-space's cell integral) instead of the
    /// cell integral of Eq. 5's Green's function.
    #[arg(long)]
    pub collocation: bool,
}

fn parse_offset(s: &str) -> std::result::Result<(i64, i64), String> {
    let (i, j) = s
        .split_once(',')
        .ok_or_else(|| format!("offset '{s}' must be I,J (two integers)"))?;
    let p = |t: &str| {
        t.trim()
            .parse::<i64>()
            .map_err(|e| format!("offset '{s}': '{t}' is not an integer ({e})"))
    };
    Ok((p(i)?, p(j)?))
}

pub fn run(args: KernelArgs) -> Result<()> {
    let cfg = super::ConfigArgs {
        config: args.config.clone(),
        set: args.set.clone(),
    }
    .load()?;
    // The material at `[loading] temperature` (its WLF shift), as the
    // solve's kernel sees it.
    let temperature = cfg.config.loading.as_ref().and_then(|l| l.temperature);
    let material = cfg.material()?.build(&cfg.base_dir)?.at(temperature)?;
    let layer = match &cfg.config.layer {
        Some(l) => Some(l.build()?),
        None => None,
    };
    if args.collocation && layer.is_none() {
        return Err(Error::Invalid(
            "--collocation is the paper's rule for a [layer] (Eq. 6); the config has no [layer], whose half-space kernel has no such choice: give --set layer.thickness=H --set layer.base=bonded or drop --collocation".into(),
        ));
    }
    if !args.direction_deg.is_finite() {
        return Err(Error::Invalid(format!(
            "--direction-deg {} must be finite",
            args.direction_deg
        )));
    }
    let response = SlidingResponse::new(
        &material,
        args.speed,
        crate::response::direction_rad(args.direction_deg),
        layer,
    )?;
    let kernel = SlidingKernel::new(&response)?.with_theta_rule(if args.collocation {
        ThetaRule::Collocation
    } else {
        ThetaRule::CellIntegral
    });
    let (a, ay) = (args.cell_size, args.cell_size_y.unwrap_or(args.cell_size));
    let warning = kernel.check_cells(a, ay)?;
    let mut rows = Vec::with_capacity(args.offsets.len());
    for &(i, j) in &args.offsets {
        let (dx, dy) = (i as f64 * a, j as f64 * ay);
        let c = kernel.coefficient(dx, dy, a, ay);
        let d = kernel.derivative(dx, dy, a, ay, Axis::X);
        let values = [
            ("K", c.total()),
            ("K_elastic", c.elastic),
            ("K_viscoelastic", c.viscoelastic),
            ("dK/dx", d),
        ];
        if let Some(&(name, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
            return Err(non_finite(name, (i, j), v, (a, ay)).into());
        }
        rows.push(serde_json::json!({
            "i": i,
            "j": j,
            "K": c.total(),
            "K_elastic": c.elastic,
            "K_viscoelastic": c.viscoelastic,
            "dK_dx": d,
        }));
    }
    if let Some(w) = warning {
        eprintln!("warning: {w}");
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).map_err(|e| Error::Invalid(e.to_string()))?
        );
        return Ok(());
    }
    println!(
        "{:>6} {:>6} {:>24} {:>24} {:>24} {:>24}",
        "i", "j", "K [m/Pa]", "K_elastic [m/Pa]", "K_viscoelastic [m/Pa]", "dK/dx [1/Pa]"
    );
    for r in &rows {
        println!(
            "{:>6} {:>6} {:>24.16e} {:>24.16e} {:>24.16e} {:>24.16e}",
            r["i"].as_i64().unwrap_or_default(),
            r["j"].as_i64().unwrap_or_default(),
            r["K"].as_f64().unwrap_or(f64::NAN),
            r["K_elastic"].as_f64().unwrap_or(f64::NAN),
            r["K_viscoelastic"].as_f64().unwrap_or(f64::NAN),
            r["dK_dx"].as_f64().unwrap_or(f64::NAN),
        );
    }
    Ok(())
}
