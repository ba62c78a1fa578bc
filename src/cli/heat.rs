//! `viscoslide heat FLUX.npy ...`: the steady surface temperature rise of
//! a rubber half-space sliding past a surface heat flux map (physics.md
//! section 14; the numerics are `crate::heat`'s). Writes `temperature.npy`,
//! `temperature.png` and `heat.json` together, or nothing.

use std::path::PathBuf;
use std::time::Instant;

use serde_json::json;

use crate::error::{Error, Result};
use crate::heat::{Conduction, HeatDomain, HeatSetup, HeatSolver, Temperature};
use crate::io::{npy, StagedOutput};
use crate::plot;
use crate::response::Grid;

/// The files one run writes (a new run replaces the whole set).
const HEAT_FILES: &[&str] = &["temperature.npy", "temperature.png", "heat.json"];

#[derive(Debug, clap::Args)]
pub struct HeatArgs {
    /// Surface heat flux map [W/m^2]: a 2-D .npy (float64 or float32),
    /// axis 0 = x, one value per cell.
    pub flux: PathBuf,
    /// Side of a cell along x \[m\] (and along y unless --cell-size-y).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cell_size: f64,
    /// Side of a cell along y \[m\], for rectangular cells; default
    /// --cell-size.
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cell_size_y: Option<f64>,
    /// Sliding speed [m/s].
    #[arg(long, value_name = "M/S", allow_negative_numbers = true)]
    pub speed: f64,
    /// Thermal conductivity of the rubber [W/(m K)].
    #[arg(long, value_name = "W/(M K)", allow_negative_numbers = true)]
    pub conductivity: f64,
    /// Thermal diffusivity of the rubber [m^2/s] (conductivity / (density
    /// x specific heat)).
    #[arg(long, value_name = "M^2/S", allow_negative_numbers = true)]
    pub diffusivity: f64,
    /// The map is one period of a periodic cell (default: a pad on an
    /// unbounded half-space).
    #[arg(long)]
    pub periodic: bool,
    /// Length of the sliding block along the sliding direction \[m\]: the
    /// periodic cell's mean rise is the block's background heating over a
    /// passage (without it the rise is given about its mean).
    #[arg(
        long,
        value_name = "M",
        requires = "periodic",
        allow_negative_numbers = true
    )]
    pub block_length: Option<f64>,
    /// Sliding direction, degrees from +x.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub direction_deg: f64,
    /// Output directory (temperature.npy, temperature.png, heat.json).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: HeatArgs) -> Result<()> {
    if !args.direction_deg.is_finite() {
        return Err(Error::Invalid(format!(
            "--direction-deg {} must be finite",
            args.direction_deg
        )));
    }
    let (nx, ny, flux) = npy::read_2d(&args.flux)?;
    let setup = HeatSetup {
        grid: Grid::new(
            nx,
            ny,
            (args.cell_size, args.cell_size_y.unwrap_or(args.cell_size)),
        )?,
        conduction: Conduction {
            conductivity: args.conductivity,
            diffusivity: args.diffusivity,
        },
        speed: args.speed,
        direction_rad: args.direction_deg.to_radians(),
        domain: if args.periodic {
            HeatDomain::Periodic {
                block_length: args.block_length,
            }
        } else {
            HeatDomain::Pad
        },
    };
    let t0 = Instant::now();
    let temperature = crate::heat::surface_temperature(setup, &flux)?;
    let wall = t0.elapsed().as_secs_f64();
    let note = HeatSolver::note_for(&setup);
    let doc = report(&args, &setup, &flux, &temperature, note, wall);

    let mut out = StagedOutput::new(&args.out)?;
    out.replaces(HEAT_FILES);
    out.write(
        "temperature.npy",
        &npy::encode_f64(&[nx, ny], &temperature.rise),
    )?;
    let png = out.path("temperature.png");
    let g = setup.grid;
    plot::heatmap(
        &png,
        &format!(
            "Surface temperature rise, v = {:.3e} m/s, {:.0} deg",
            args.speed, args.direction_deg
        ),
        &plot::Field {
            nx,
            ny,
            values: &temperature.rise,
            extent: (0.0, nx as f64 * g.cell().0, 0.0, ny as f64 * g.cell().1),
        },
        "T - T0 [K]",
        None,
    )?;
    let mut bytes = serde_json::to_vec_pretty(&doc)
        .map_err(|e| Error::Invalid(format!("cannot encode JSON: {e}")))?;
    bytes.push(b'\n');
    out.write("heat.json", &bytes)?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    if let Some(n) = note {
        eprintln!("note: {n}");
    }
    let background = temperature
        .background
        .map(|b| format!(", background {b:.4e} K"))
        .unwrap_or_default();
    println!(
        "heat: {nx} x {ny} cells, Peclet v a/kappa = {:.3e}, max rise {:.4e} K, mean {:.4e} K{background}, {:.3} s: {}",
        setup.peclet(),
        temperature.max(),
        temperature.mean(),
        wall,
        dir.display()
    );
    Ok(())
}

/// `heat.json`: the inputs, the Peclet number, the rise and the power.
fn report(
    args: &HeatArgs,
    setup: &HeatSetup,
    flux: &[f64],
    t: &Temperature,
    note: Option<&str>,
    wall: f64,
) -> serde_json::Value {
    let g = setup.grid;
    let power = flux.iter().sum::<f64>() * g.cell_area();
    json!({
        "version": crate::version::VERSION,
        "input": args.flux.display().to_string(),
        "grid": [g.nx(), g.ny()],
        "cell_size_m": [g.cell().0, g.cell().1],
        "speed_m_per_s": setup.speed,
        "direction_deg": args.direction_deg,
        "conductivity_w_per_m_k": setup.conduction.conductivity,
        "diffusivity_m2_per_s": setup.conduction.diffusivity,
        "formulation": if setup.is_periodic() { "periodic" } else { "non-periodic" },
        "block_length_m": args.block_length,
        "contact_time_s": setup.contact_time(),
        "peclet_number": setup.peclet(),
        "peclet_definition": "v a / kappa, a the cell size along x",
        "max_rise_k": t.max(),
        "mean_rise_k": t.mean(),
        "min_rise_k": t.rise.iter().copied().fold(f64::INFINITY, f64::min),
        "background_rise_k": t.background,
        "total_power_w": power,
        "mean_flux_w_per_m2": power / (g.cells() as f64 * g.cell_area()),
        "notes": note.into_iter().collect::<Vec<_>>(),
        "wall_time_s": wall,
        "files": HEAT_FILES,
        "conventions": {
            "temperature": "rise T - T0 [K] at the cell centres, axis 0 = x as in the input",
            "model": "steady moving heat source on a half-space, physics.md section 14",
        },
    })
}
