//! `viscoslide heat FLUX.npy ...`: the steady surface temperature rise of
//! a rubber half-space sliding past a surface heat flux map (physics.md
//! section 14; the numerics are `crate::heat`'s); `viscoslide heat
//! --from-run DIR ...`: the same for the heat source of a solved contact
//! (the output directory of `viscoslide solve`), with its energy balance
//! (`crate::problem::ContactHeating`). Writes `temperature.npy`,
//! `temperature.png` and `heat.json` together, or nothing.

use std::path::PathBuf;
use std::time::Instant;

use serde_json::json;

use crate::error::{Error, Result};
use crate::heat::{Conduction, HeatDomain, HeatSetup, SourceKind, Temperature};
use crate::io::{npy, StagedOutput};
use crate::plot;
use crate::response::Grid;

/// The files one run writes (a new run replaces the whole set).
pub(super) const HEAT_FILES: &[&str] = &["temperature.npy", "temperature.png", "heat.json"];

#[derive(Debug, clap::Args)]
pub struct HeatArgs {
    /// Surface heat flux map [W/m^2]: a 2-D .npy (float64 or float32),
    /// axis 0 = x, one value per cell.
    #[arg(required_unless_present = "from_run", conflicts_with = "from_run")]
    pub flux: Option<PathBuf>,
    /// Output directory of `viscoslide solve` (summary.json, pressure.npy):
    /// heat the solved contact by its own heat source; the grid, speed,
    /// direction, material and formulation are the run's.
    #[arg(long, value_name = "DIR")]
    pub from_run: Option<PathBuf>,
    /// With --from-run: the creep elements' dissipation density on depth
    /// layers (`volume`, periodic cells on a half-space) or the surface
    /// work of the contact pressure (`surface`); default `volume` on a
    /// periodic cell on a half-space, `surface` on a pad or a layer.
    #[arg(long, value_name = "KIND", requires = "from_run")]
    pub source: Option<SourceKind>,
    /// With --from-run and the volume source: the refined depth layers
    /// (boundary ratio sqrt 2, 4 Gauss points; depth integrals to about
    /// 5e-9 instead of 5e-5, the weighted rise to about 3e-4 instead of
    /// 2e-3).
    #[arg(long, requires = "from_run")]
    pub refined_layers: bool,
    /// Side of a cell along x in m (and along y unless --cell-size-y).
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        required_unless_present = "from_run",
        conflicts_with = "from_run"
    )]
    pub cell_size: Option<f64>,
    /// Side of a cell along y in m, for rectangular cells; default
    /// --cell-size.
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        conflicts_with = "from_run"
    )]
    pub cell_size_y: Option<f64>,
    /// Sliding speed [m/s].
    #[arg(
        long,
        value_name = "M/S",
        allow_negative_numbers = true,
        required_unless_present = "from_run",
        conflicts_with = "from_run"
    )]
    pub speed: Option<f64>,
    /// Thermal conductivity of the rubber [W/(m K)].
    #[arg(long, value_name = "W/(M K)", allow_negative_numbers = true)]
    pub conductivity: f64,
    /// Thermal diffusivity of the rubber [m^2/s] (conductivity / (density
    /// x specific heat)).
    #[arg(long, value_name = "M^2/S", allow_negative_numbers = true)]
    pub diffusivity: f64,
    /// The map is one period of a periodic cell (default: a pad on an
    /// unbounded half-space).
    #[arg(long, conflicts_with = "from_run")]
    pub periodic: bool,
    /// Length of the sliding block along the sliding direction in m: the
    /// periodic cell's mean rise is the block's background heating over a
    /// passage (without it the rise is given about its mean). Periodic
    /// cells only (--periodic, or a periodic run).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub block_length: Option<f64>,
    /// Sliding direction, degrees from +x.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        conflicts_with = "from_run"
    )]
    pub direction_deg: f64,
    /// Output directory (temperature.npy, temperature.png, heat.json).
    #[arg(long)]
    pub out: PathBuf,
}

/// Refuse a numeric option that is not positive and finite, naming its
/// flag (the heat problem's own checks name the quantity, for Python and
/// configs alike): the conductivity, diffusivity and block length of
/// both forms, the cell sides and speed of a flux map.
pub(super) fn check_numbers(args: &HeatArgs) -> Result<()> {
    let given = [
        ("--conductivity", Some(args.conductivity), "W/(m K)"),
        ("--diffusivity", Some(args.diffusivity), "m^2/s"),
        ("--block-length", args.block_length, "m"),
        ("--cell-size", args.cell_size, "m"),
        ("--cell-size-y", args.cell_size_y, "m"),
        ("--speed", args.speed, "m/s"),
    ];
    for (flag, value, unit) in given {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::Invalid(format!(
                "{flag} {v} must be positive and finite ({unit})"
            )));
        }
    }
    if !args.direction_deg.is_finite() {
        return Err(Error::Invalid(format!(
            "--direction-deg {} must be finite",
            args.direction_deg
        )));
    }
    Ok(())
}

pub fn run(args: HeatArgs) -> Result<()> {
    let (Some(flux_path), Some(cell_size), Some(speed)) = (&args.flux, args.cell_size, args.speed)
    else {
        unreachable!("clap requires the flux, --cell-size and --speed without --from-run, which the dispatch took")
    };
    // The options of a solved run's heat source: a flux map is its own
    // surface source (clap's `requires` does not hold them to --from-run
    // beside the positional flux).
    for (given, flag) in [
        (args.source.is_some(), "--source"),
        (args.refined_layers, "--refined-layers"),
    ] {
        if given {
            return Err(Error::Invalid(format!(
                "{flag} is for --from-run (the heat source of a solved contact); a flux map is the surface flux itself: drop {flag}"
            )));
        }
    }
    if args.block_length.is_some() && !args.periodic {
        return Err(Error::Invalid(
            "--block-length is for a periodic cell: give --periodic too".into(),
        ));
    }
    let (nx, ny, flux) = npy::read_2d(flux_path)?;
    let setup = HeatSetup {
        grid: Grid::new(nx, ny, (cell_size, args.cell_size_y.unwrap_or(cell_size)))?,
        conduction: Conduction {
            conductivity: args.conductivity,
            diffusivity: args.diffusivity,
        },
        speed,
        direction_rad: crate::response::direction_rad(args.direction_deg),
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
    let notes = setup.notes();
    let power = power(&flux, &setup.grid)?;
    let doc = report(&args, flux_path, &setup, power, &temperature, &notes, wall);
    let dir = write(&args.out, &setup, args.direction_deg, &temperature, &doc)?;
    for n in &notes {
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

/// Write `temperature.npy`, `temperature.png` and `heat.json` into `out`,
/// all or none; returns the directory.
pub(super) fn write(
    out: &std::path::Path,
    setup: &HeatSetup,
    direction_deg: f64,
    temperature: &Temperature,
    doc: &serde_json::Value,
) -> Result<PathBuf> {
    refuse_heated_solve(out)?;
    let g = setup.grid;
    let (nx, ny) = g.size();
    let mut out = StagedOutput::new(out)?;
    out.replaces(HEAT_FILES);
    out.write(
        "temperature.npy",
        &npy::encode_f64(&[nx, ny], &temperature.rise),
    )?;
    let png = out.path("temperature.png");
    plot::heatmap(
        &png,
        &format!(
            "Surface temperature rise, v = {:.3e} m/s, {:.0} deg",
            setup.speed, direction_deg
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
    let mut bytes = serde_json::to_vec_pretty(doc)
        .map_err(|e| Error::Invalid(format!("cannot encode JSON: {e}")))?;
    bytes.push(b'\n');
    out.write("heat.json", &bytes)?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    Ok(dir)
}

/// Refuse `out` where it holds a heated solve (its `summary.json` with a
/// `heating` object): its `temperature.npy` and `temperature.png` are the
/// coupled solve's rise, which this run's would replace beside the
/// summary and `temperature_depth.csv` that describe them.
fn refuse_heated_solve(out: &std::path::Path) -> Result<()> {
    let heated = std::fs::read(out.join("summary.json"))
        .ok()
        .and_then(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok())
        .is_some_and(|doc| doc.get("heating").is_some_and(|h| h.is_object()));
    if heated {
        return Err(Error::Invalid(format!(
            "--out {} holds a heated solve, whose temperature.npy and temperature.png (the coupled solve's rise, described by its summary.json) this would replace: give another --out",
            out.display()
        )));
    }
    Ok(())
}

/// The map's mean flux \[W/m^2\] (each value divided before the sum,
/// which f64 then holds) and its total power \[W\]; a power beyond f64
/// (huge cells under a huge flux whose rise a huge conductivity keeps
/// finite) is refused: `heat.json` holds numbers, not `null`.
fn power(flux: &[f64], grid: &Grid) -> Result<(f64, f64)> {
    let n = flux.len() as f64;
    let mean = flux.iter().map(|q| q / n).sum::<f64>();
    let area = n * grid.cell_area();
    let total = mean * area;
    if !total.is_finite() {
        return Err(Error::Invalid(format!(
            "the total power of the flux, {mean:e} W/m^2 on average over {area:e} m^2, is beyond the range of f64: give the flux in other units or smaller cells"
        )));
    }
    Ok((mean, total))
}

/// `heat.json`: the inputs, the Peclet number, the rise and the power
/// (`(mean flux, total power)`).
fn report(
    args: &HeatArgs,
    flux_path: &std::path::Path,
    setup: &HeatSetup,
    (mean_flux, power): (f64, f64),
    t: &Temperature,
    notes: &[String],
    wall: f64,
) -> serde_json::Value {
    let g = setup.grid;
    json!({
        "version": crate::version::VERSION,
        "input": flux_path.display().to_string(),
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
        "peclet_definition": "v a / kappa, a a cell's length along the sliding direction (its chord through the centre along e_v)",
        "max_rise_k": t.max(),
        "mean_rise_k": t.mean(),
        "min_rise_k": t.rise.iter().copied().fold(f64::INFINITY, f64::min),
        "background_rise_k": t.background,
        "total_power_w": power,
        "mean_flux_w_per_m2": mean_flux,
        "notes": notes,
        "wall_time_s": wall,
        "files": HEAT_FILES,
        "conventions": {
            "temperature": "rise T - T0 [K] at the cell centres, axis 0 = x as in the input",
            "model": "steady moving heat source on a half-space, physics.md section 14",
        },
    })
}
