//! `viscoslide surface resample`: a height map onto another pixel size
//! (square cells from a scan with non-square pixels), by bicubic spline or
//! Fourier interpolation ([`crate::surface::resample`]).

use std::path::PathBuf;

use serde_json::json;

use crate::error::{Error, Result};
use crate::io::StagedOutput;
use crate::surface::{
    self, NpyPrecision, ResampleMethod, ResampleTarget, SurfaceFormat, WriteOptions, X3pType,
};

use super::{filled_note, json_bytes, read_input, InputArgs};

#[derive(Debug, clap::Args)]
pub struct ResampleArgs {
    /// Input file (.x3p, .gwy, .npy, text).
    pub input_file: PathBuf,
    #[command(flatten)]
    pub input: InputArgs,
    /// New pixel size DX[,DY] in m (DY defaults to DX: square pixels).
    #[arg(
        long,
        value_name = "DX[,DY]",
        conflicts_with = "n",
        required_unless_present = "n"
    )]
    pub pixel: Option<String>,
    /// New number of points NX[,NY] over the same extent (NY defaults to
    /// NX: one value gives NX x NX points).
    #[arg(long, value_name = "NX[,NY]")]
    pub n: Option<String>,
    /// Interpolation: spline (not-a-knot bicubic; any map) or fourier
    /// (band-limited; periodic maps: on a map whose opposite edges do not
    /// meet, a scan, it rings near the edges and says so).
    #[arg(long, default_value = "spline")]
    pub method: String,
    /// Format of the written heights: x3p, npy or text (default: the
    /// input's; x3p for a .gwy input).
    #[arg(long, value_parser = parse_output_format)]
    pub output_format: Option<SurfaceFormat>,
    /// z data type of an .x3p output: f64 (bit-exact), f32, i32.
    #[arg(long, default_value = "f64", value_parser = super::convert::parse_x3p_type)]
    pub x3p_type: X3pType,
    /// Write .npy as float32.
    #[arg(long)]
    pub f32: bool,
    /// Output directory (`heights.<ext>` and `resample.json`).
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_output_format(s: &str) -> std::result::Result<SurfaceFormat, String> {
    match s.parse::<SurfaceFormat>()? {
        SurfaceFormat::Gwy => Err("'gwy' cannot be written; use x3p, npy or text".into()),
        f => Ok(f),
    }
}

fn numbers(flag: &str, s: &str) -> Result<Vec<String>> {
    let parts: Vec<String> = s.split(',').map(|t| t.trim().to_string()).collect();
    if parts.is_empty() || parts.len() > 2 || parts.iter().any(|p| p.is_empty()) {
        return Err(Error::Invalid(format!(
            "--{flag} '{s}': give one value or two separated by a comma"
        )));
    }
    Ok(parts)
}

/// The grid asked for, and what the flag was taken to mean (a single
/// value stands for both axes).
fn target(args: &ResampleArgs) -> Result<(ResampleTarget, String)> {
    if let Some(p) = &args.pixel {
        let v = numbers("pixel", p)?
            .iter()
            .map(|t| {
                t.parse::<f64>()
                    .map_err(|_| Error::Invalid(format!("--pixel: '{t}' is not a number")))
            })
            .collect::<Result<Vec<f64>>>()?;
        let (dx, dy) = (v[0], *v.last().unwrap_or(&v[0]));
        let one = if v.len() == 1 {
            " (one value: square pixels)"
        } else {
            ""
        };
        return Ok((
            ResampleTarget::Pixel(dx, dy),
            format!("--pixel {p}: pixel {dx:e} m x {dy:e} m{one}"),
        ));
    }
    let s = args.n.as_deref().unwrap_or_default();
    let v = numbers("n", s)?
        .iter()
        .map(|t| {
            t.parse::<usize>().map_err(|_| {
                Error::Invalid(format!("--n: '{t}' is not a number of points (an integer)"))
            })
        })
        .collect::<Result<Vec<usize>>>()?;
    let (nx, ny) = (v[0], *v.last().unwrap_or(&v[0]));
    let one = if v.len() == 1 {
        " (one value: the same along x and y)"
    } else {
        ""
    };
    Ok((
        ResampleTarget::Shape(nx, ny),
        format!("--n {s}: {nx} x {ny} points{one}"),
    ))
}

pub(super) fn run(args: ResampleArgs) -> Result<()> {
    let (target, asked) = target(&args)?;
    let method: ResampleMethod = args
        .method
        .parse()
        .map_err(|e| Error::Invalid(format!("--method {e}")))?;
    let (topo, in_format) = read_input(&args.input_file, &args.input)?;
    let grid = surface::resample_grid(&topo, target, method)?;
    let out_format = args.output_format.unwrap_or(match in_format {
        SurfaceFormat::Gwy => SurfaceFormat::X3p,
        f => f,
    });
    let ext = match out_format {
        SurfaceFormat::X3p => "x3p",
        SurfaceFormat::Npy => "npy",
        _ => "txt",
    };
    let resampled = surface::resample(&topo, &grid, method)?;
    let note = filled_note(&topo);
    let method_name = match method {
        ResampleMethod::Spline => "not-a-knot bicubic spline",
        ResampleMethod::Fourier => "band-limited Fourier interpolation",
    };
    let mut what = format!(
        "resampled from {} ({} x {} points, pixel {:e} m x {:e} m) by {method_name} by viscoslide",
        args.input_file.display(),
        topo.nx,
        topo.ny,
        topo.dx,
        topo.dy
    );
    if let Some(n) = &note {
        what.push_str(&format!("; {n}"));
    }
    let mut warnings = Vec::new();
    if method == ResampleMethod::Fourier {
        warnings.extend(surface::fourier_edge_warning(&topo));
    }
    if let ResampleTarget::Pixel(dx, dy) = target {
        let off = |got: f64, want: f64| (got / want - 1.0).abs() > 1e-9;
        if off(grid.dx, dx) || off(grid.dy, dy) {
            warnings.push(format!(
                "Fourier resampling keeps the period: the pixel is {:e} m x {:e} m, not the {dx:e} m x {dy:e} m asked for",
                grid.dx, grid.dy
            ));
        }
    }
    let file = format!("heights.{ext}");
    let opts = WriteOptions {
        format: Some(out_format),
        x3p_type: args.x3p_type,
        npy_precision: if args.f32 {
            NpyPrecision::F32
        } else {
            NpyPrecision::F64
        },
        comment: Some(what.clone()),
    };
    let bytes = surface::encode_topography(&resampled, out_format, &opts)?;
    let grid_json = |nx: usize, ny: usize, dx: f64, dy: f64| {
        json!({
            "shape": [nx, ny],
            "pixel_m": [dx, dy],
            "size_m": [nx as f64 * dx, ny as f64 * dy],
        })
    };
    let doc = json!({
        "version": crate::version::VERSION,
        "input": args.input_file.display().to_string(),
        "method": method,
        "requested": asked,
        "description": what,
        "from": grid_json(topo.nx, topo.ny, topo.dx, topo.dy),
        "to": grid_json(grid.nx, grid.ny, grid.dx, grid.dy),
        "offset_m": [grid.offset_x, grid.offset_y],
        "missing": note,
        "warnings": warnings,
        "files": [file.clone(), "resample.json"],
    });
    let mut out = StagedOutput::new(&args.out)?;
    out.write(&file, &bytes)?;
    out.write("resample.json", &json_bytes(&doc)?)?;
    let dir = out.dir().join(&file);
    out.commit()?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    println!("{asked}");
    println!(
        "{} x {} points, pixel {:e} m x {:e} m -> {} x {} points, pixel {:e} m x {:e} m ({:.6e} m x {:.6e} m) by {method_name}: {}",
        topo.nx,
        topo.ny,
        topo.dx,
        topo.dy,
        grid.nx,
        grid.ny,
        grid.dx,
        grid.dy,
        grid.nx as f64 * grid.dx,
        grid.ny as f64 * grid.dy,
        dir.display()
    );
    Ok(())
}
