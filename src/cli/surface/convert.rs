//! `viscoslide surface convert`: a height map from one file format to
//! another.

use std::path::PathBuf;

use crate::error::Result;
use crate::surface::{self, NpyPrecision, WriteOptions, X3pType};

use super::{filled_note, read_input, InputArgs};

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

pub(super) fn parse_x3p_type(s: &str) -> std::result::Result<X3pType, String> {
    match s {
        "f64" => Ok(X3pType::F64),
        "f32" => Ok(X3pType::F32),
        "i32" => Ok(X3pType::I32),
        _ => Err(format!("'{s}': use f64, f32 or i32")),
    }
}

pub(super) fn run(args: ConvertArgs) -> Result<()> {
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
