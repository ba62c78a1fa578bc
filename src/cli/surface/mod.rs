//! `viscoslide surface ...`: generate self-affine height maps or maps
//! following a tabulated PSD, analyse measured or generated maps, convert
//! between file formats and stitch the PSDs of several scans (physics.md
//! sections 8 and 11).

//!
//! One file per subcommand (`generate`, `stats`, `convert`, `resample`, `stitch` for
//! `psd-stitch`); this one holds what they share: reading a surface file,
//! the flag parsers and the PSD charts (`charts`).

use std::path::Path;

use crate::error::{Error, Result};
use crate::surface::{self, Detrend, MissingData, ReadOptions, SurfaceFormat, Topography, Window};

mod charts;
mod convert;
mod generate;
mod resample;
mod stats;
mod stitch;

use charts::{log_plot, pairs, psd_plot};
pub use convert::ConvertArgs;
pub use generate::GenerateArgs;
pub use resample::ResampleArgs;
pub use stats::StatsArgs;
pub use stitch::StitchArgs;

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
    /// Resample a height map to another pixel size (e.g. square pixels from
    /// a scan with non-square ones) by bicubic spline or Fourier
    /// interpolation; writes `heights.<ext>` and `resample.json` into --out.
    Resample(Box<ResampleArgs>),
    /// Stitch the PSDs of several scans of one surface (maps or PSD CSVs);
    /// writes psd.csv, psd.png and stitch.json into --out.
    PsdStitch(StitchArgs),
}

/// How a surface file is read (shared by stats, convert and psd-stitch).
#[derive(Debug, Clone, clap::Args)]
pub struct InputArgs {
    /// Side along x in m (required for .npy and text; must agree with
    /// .x3p/.gwy files).
    #[arg(long, allow_negative_numbers = true)]
    pub length: Option<f64>,
    /// Side along y in m (default: square pixels).
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

pub(super) fn parse_detrend(s: &str) -> std::result::Result<Detrend, String> {
    surface::parse_detrend(s)
}

pub(super) fn parse_window(s: &str) -> std::result::Result<Window, String> {
    surface::parse_window(s)
}

pub(super) fn parse_pair(s: &str) -> std::result::Result<(f64, f64), String> {
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

pub fn run(cmd: SurfaceCommand) -> Result<()> {
    match cmd {
        SurfaceCommand::Generate(a) => generate::run(*a),
        SurfaceCommand::Stats(a) => stats::run(a),
        SurfaceCommand::Convert(a) => convert::run(a),
        SurfaceCommand::Resample(a) => resample::run(*a),
        SurfaceCommand::PsdStitch(a) => stitch::run(a),
    }
}

pub(super) fn read_input(file: &Path, input: &InputArgs) -> Result<(Topography, SurfaceFormat)> {
    let format = input
        .format
        .unwrap_or_else(|| SurfaceFormat::from_path(file));
    let topo = surface::read_topography(file, &input.options())?;
    Ok((topo, format))
}

pub(super) fn filled_note(topo: &Topography) -> Option<String> {
    surface::filled_note(topo.filled, topo.heights.len())
}

pub(super) fn json_bytes(v: &serde_json::Value) -> Result<Vec<u8>> {
    let mut b = serde_json::to_vec_pretty(v)
        .map_err(|e| Error::Invalid(format!("cannot encode JSON: {e}")))?;
    b.push(b'\n');
    Ok(b)
}
