//! `viscoslide solve CONFIG --out DIR`

use std::path::PathBuf;

use crate::backend::BackendChoice;
use crate::error::{Error, Result};
use crate::heating::{scale_extremes, scale_text, solve_heated, HeatingParams};
use crate::io::check_output_dir;
use crate::problem::{Executor, Problem};

use super::spinner::Spinner;

#[derive(Debug, clap::Args)]
pub struct SolveArgs {
    #[command(flatten)]
    pub config: super::ConfigArgs,
    /// Executor: auto (GPU when available), gpu or cpu; default from
    /// VISCOSLIDE_BACKEND, else auto.
    #[arg(long, value_name = "auto|gpu|cpu")]
    pub backend: Option<BackendChoice>,
    /// Output directory (created; files appear only when the solve succeeds).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: SolveArgs) -> Result<()> {
    let cfg = args.config.load()?;
    // Refuse an output place that cannot be written before solving.
    check_output_dir(&args.out)?;
    let problem = Problem::from_config(&cfg)?;
    problem.check_analysis()?;
    let choice = BackendChoice::resolve(args.backend).map_err(Error::Invalid)?;
    let (executor, line) = Executor::select(choice, &problem)?;
    eprintln!("{line}");
    eprintln!(
        "solving {} x {} cells, v = {:.4e} m/s{}",
        problem.surface.nx,
        problem.surface.ny,
        problem.speed,
        problem
            .xi()
            .map(|x| format!(" (xi = {x:.4e})"))
            .unwrap_or_default()
    );
    if let Some(note) =
        crate::surface::filled_note(problem.filled_points, problem.surface.heights.len())
    {
        eprintln!("note: {note}");
    }
    let mut spinner = Spinner::start("computing influence coefficients");
    let ambient = cfg.config.loading.as_ref().and_then(|l| l.temperature);
    let heating = match &cfg.config.heating {
        Some(h) => HeatingParams::from_config(h, &problem, ambient)?,
        None => None,
    };
    let (solution, heated, written) = match heating {
        Some(params) => {
            let heated = solve_heated(&problem, &params, &executor, &mut spinner);
            spinner.bar.finish_and_clear();
            let heated = heated?;
            for w in &heated.solution.warnings {
                eprintln!("warning: {w}");
            }
            let written = heated.write(&args.out)?;
            (heated.solution.clone(), Some(heated.report), written)
        }
        None => {
            let solution = problem.solve(&executor, &mut spinner);
            spinner.bar.finish_and_clear();
            let solution = solution?;
            for w in &solution.warnings {
                eprintln!("warning: {w}");
            }
            let written = solution.write(&args.out)?;
            (solution, None, written)
        }
    };
    if let Some(h) = &heated {
        // The scan grid's solves are counted beside the full grid's: they
        // are most of the solves, though not of the time.
        let scan = match h.coarse_grid {
            Some([cx, cy]) if h.coarse_evaluations > 0 => {
                format!(" and {} on the {cx} x {cy} scan grid", h.coarse_evaluations)
            }
            _ => String::new(),
        };
        println!(
            "heated: effective temperature {:.4} C (T0 = {} C, rise {:.4e} K, peak surface rise {:.4e} K), {} branch of {} found, {} isothermal solve{}{scan}; friction at T0 without heating {:.6e}; {:.2} s ({:.2} s solves, {:.2} s heat)",
            h.effective_temperature,
            h.ambient_temperature,
            h.temperature_rise.effective,
            h.temperature_rise.peak_surface,
            h.chosen_branch,
            h.branches.len(),
            h.fixed_point_evaluations,
            if h.fixed_point_evaluations == 1 { "" } else { "s" },
            h.isothermal_friction_coefficient,
            h.wall_time_s,
            h.solve_time_s,
            h.heat_time_s
        );
        // A tolerance not small against the rise accepts a temperature
        // (T0 itself, where the rise is below it) that differs from
        // T0 + Theta by much of Theta: say so beside the two numbers.
        let residual = h
            .branches
            .iter()
            .find(|b| b.temperature == h.effective_temperature)
            .map_or(0.0, |b| b.residual);
        if residual.abs() > 0.1 * h.temperature_rise.effective.abs() {
            println!(
                "note: T_eff - T0 = {:.4e} K beside a rise at T_eff of {:.4e} K: they agree only to |g| = {:.2e} K, within [heating] tolerance; a smaller tolerance resolves the rise",
                h.effective_temperature - h.ambient_temperature,
                h.temperature_rise.effective,
                residual.abs()
            );
        }
        if let Some((cold, hot)) = scale_extremes(&h.scales) {
            println!(
                "heated scales: the octaves of surface modes that carry the power dissipate at rises from {} to {} (summary.json heating.scales)",
                scale_text(cold),
                scale_text(hot)
            );
        }
    }
    println!(
        "friction coefficient {:.6e} (dissipation: {:.6e}), contact area fraction {:.5}, {} iterations, {} matvecs, residual {:.2e}, {:.2} s",
        solution.friction_coefficient,
        solution.friction_coefficient_dissipation,
        solution.stats.contact_area_fraction,
        solution.info.iterations,
        solution.info.matvecs,
        solution.info.residual,
        solution.timings.total_s
    );
    if solution.info.exact_matvecs > 0 {
        println!(
            "mixed precision: {} matvecs in f32, {} exact matvecs in f64 (the residuals of the GMRES restarts)",
            solution.info.matvecs,
            solution.info.exact_matvecs
        );
    }
    let pad_traffic = solution.smooth_pad.and_then(|p| p.device_traffic);
    for (what, t) in [
        ("the solve", solution.device_traffic),
        ("the smooth pad", pad_traffic),
    ] {
        if let Some(t) = t.filter(|t| t.round_trips > 0) {
            println!(
                "device round trips of {what}: {} ({:.1} MB to the device, {:.1} MB back), {:.2} s: host to device {:.2} s, device {:.2} s, back to the host {:.2} s",
                t.round_trips,
                t.bytes_to_device as f64 / 1e6,
                t.bytes_from_device as f64 / 1e6,
                t.total_s(),
                t.to_device_s,
                t.device_s,
                t.from_device_s
            );
        }
    }
    match &solution.persson {
        Ok(p) => {
            println!(
                "Persson's theory at this speed and {:.4e} Pa: friction coefficient {:.6e}, contact area fraction {:.5} ({} PSD)",
                p.nominal_pressure, p.friction_coefficient, p.contact_area_fraction, p.psd
            );
            for note in &p.notes {
                println!("note: {note}");
            }
        }
        Err(why) => println!("Persson's theory not evaluated: {why}"),
    }
    match solution.cells_per_shortest_wavelength() {
        Some(c) => println!("cells per shortest wavelength {c:.3}"),
        None => println!("cells per shortest wavelength: not defined (no roughness)"),
    }
    println!("wrote {} files to {}", written.len(), args.out.display());
    Ok(())
}
