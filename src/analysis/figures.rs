//! PNG figures of the contact analysis (paper Fig. 8-10): contact map with a
//! magnified window, polar diagram of `m2(theta)` (Eq. 13), `C_chi` contours
//! with their fitted ellipses, pressure and displacement maps, and the
//! histogram of spot areas.

use std::f64::consts::PI;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::report::{AnalysisInputs, AnalysisReport};
use crate::plot::{self, format_tick, Field, PlotError, PALETTE};

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        path: path.display().to_string(),
        what: e.to_string(),
    }
}

fn speed_label(inputs: &AnalysisInputs<'_>) -> String {
    match inputs.xi {
        Some(xi) => format!(", xi = {xi:.3e}"),
        None => String::new(),
    }
}

/// The magnified window of the contact map: a square of side
/// `min(Lx, Ly) / 4` at the centre of the map (the same region for every
/// speed, as in Fig. 8), in m.
pub fn zoom_window(inputs: &AnalysisInputs<'_>) -> (f64, f64, f64, f64) {
    let (lx, ly) = (
        inputs.nx as f64 * inputs.cell_size,
        inputs.ny as f64 * inputs.cell_size_y,
    );
    let side = 0.25 * lx.min(ly);
    let (cx, cy) = (0.5 * lx, 0.5 * ly);
    (
        cx - 0.5 * side,
        cx + 0.5 * side,
        cy - 0.5 * side,
        cy + 0.5 * side,
    )
}

/// Draw the contact cells (black on white) of `inputs` restricted to `view`
/// into `area`, with a title and axes in m; `mark` outlines a rectangle.
fn contact_panel(
    path: &Path,
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    title: &str,
    inputs: &AnalysisInputs<'_>,
    view: (f64, f64, f64, f64),
    mark: Option<(f64, f64, f64, f64)>,
) -> Result<(), PlotError> {
    let (x0, x1, y0, y1) = view;
    let mut ctx = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(path, e))?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc("x [m] (sliding direction)")
        .y_desc("y [m]")
        .label_style(("sans-serif", 12))
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(|e| err(path, e))?;
    let (ax, ay) = (inputs.cell_size, inputs.cell_size_y);
    let cells = |lo: f64, hi: f64, n: usize, a: f64| {
        let first = ((lo / a).floor().max(0.0) as usize).min(n);
        let last = ((hi / a).ceil().max(0.0) as usize).min(n);
        first..last
    };
    let (ri, rj) = (cells(x0, x1, inputs.nx, ax), cells(y0, y1, inputs.ny, ay));
    let clip = |v: f64, lo: f64, hi: f64| v.clamp(lo, hi);
    ctx.draw_series(
        ri.flat_map(|i| rj.clone().map(move |j| (i, j)))
            .filter(|&(i, j)| inputs.contact[i * inputs.ny + j] > 0.5)
            .map(|(i, j)| {
                let (xa, xb) = (i as f64 * ax, (i + 1) as f64 * ax);
                let (ya, yb) = (j as f64 * ay, (j + 1) as f64 * ay);
                Rectangle::new(
                    [
                        (clip(xa, x0, x1), clip(ya, y0, y1)),
                        (clip(xb, x0, x1), clip(yb, y0, y1)),
                    ],
                    BLACK.filled(),
                )
            }),
    )
    .map_err(|e| err(path, e))?;
    if let Some((m0, m1, n0, n1)) = mark {
        ctx.draw_series(std::iter::once(Rectangle::new(
            [(m0, n0), (m1, n1)],
            PALETTE[0].stroke_width(2),
        )))
        .map_err(|e| err(path, e))?;
    }
    Ok(())
}

/// Contact map (left) and the magnified central window (right), Fig. 8.
pub fn contact_map(
    path: &Path,
    inputs: &AnalysisInputs<'_>,
    report: &AnalysisReport,
) -> Result<(), PlotError> {
    plot::ensure_font();
    let full = (
        0.0,
        inputs.nx as f64 * inputs.cell_size,
        0.0,
        inputs.ny as f64 * inputs.cell_size_y,
    );
    let zoom = zoom_window(inputs);
    let root = BitMapBackend::new(path, (1400, 720)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let (left, right) = root.split_horizontally(700);
    contact_panel(
        path,
        &left,
        &format!(
            "Contact area, A/A0 = {:.4}{}",
            report.contact_area_fraction,
            speed_label(inputs)
        ),
        inputs,
        full,
        Some(zoom),
    )?;
    contact_panel(
        path,
        &right,
        &format!("Magnified window, {} spots", report.spots.count),
        inputs,
        zoom,
        None,
    )?;
    root.present().map_err(|e| err(path, e))?;
    Ok(())
}

/// Tick label on an axis spanning `[-r, r]`: round-off zeros print as 0.
fn axis_tick(v: f64, r: f64) -> String {
    if v.abs() < 1e-9 * r {
        "0".into()
    } else {
        format_tick(v)
    }
}

/// Square chart on `[-r, r]^2` with axis labels.
fn square_chart<'a, 'b>(
    path: &Path,
    root: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    title: &str,
    r: f64,
    x_desc: &str,
    y_desc: &str,
) -> Result<
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    PlotError,
> {
    let mut ctx = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 18))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(-r..r, -r..r)
        .map_err(|e| err(path, e))?;
    ctx.configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 12))
        .x_label_formatter(&|v| axis_tick(*v, r))
        .y_label_formatter(&|v| axis_tick(*v, r))
        .light_line_style(WHITE)
        .draw()
        .map_err(|e| err(path, e))?;
    Ok(ctx)
}

/// Polar diagram of `m2(theta) / m2_max` (Eq. 13, Fig. 9) with the unit
/// circle (isotropy) and the principal direction `theta_P`.
pub fn m2_polar(
    path: &Path,
    inputs: &AnalysisInputs<'_>,
    report: &AnalysisReport,
) -> Result<(), PlotError> {
    plot::ensure_font();
    let t = &report.tensor;
    let scale = if t.m2_max > 0.0 { t.m2_max } else { 1.0 };
    let root = BitMapBackend::new(path, (760, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let title = format!(
        "m2(theta)/m2_max: gamma = {:.3}, theta_P = {:.1} deg{}",
        t.gamma,
        t.theta_p_deg,
        speed_label(inputs)
    );
    let mut ctx = square_chart(path, &root, &title, 1.15, "x (sliding)", "y")?;
    let grey = RGBColor(170, 170, 170);
    for r in [0.25, 0.5, 0.75, 1.0] {
        let circle: Vec<(f64, f64)> = (0..=360)
            .map(|k| {
                let th = 2.0 * PI * k as f64 / 360.0;
                (r * th.cos(), r * th.sin())
            })
            .collect();
        ctx.draw_series(LineSeries::new(circle, grey.stroke_width(1)))
            .map_err(|e| err(path, e))?;
    }
    let curve: Vec<(f64, f64)> = super::anisotropy::polar_samples(t, 720)
        .into_iter()
        .map(|(th, m)| (m / scale * th.cos(), m / scale * th.sin()))
        .collect();
    ctx.draw_series(LineSeries::new(curve, PALETTE[2].stroke_width(3)))
        .map_err(|e| err(path, e))?
        .label("m2(theta), Eq. 11")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[2].stroke_width(3)));
    let tn = &report.tensor_normalised;
    let sn = if tn.m2_max > 0.0 { tn.m2_max } else { 1.0 };
    let curve_n: Vec<(f64, f64)> = super::anisotropy::polar_samples(tn, 720)
        .into_iter()
        .map(|(th, m)| (m / sn * th.cos(), m / sn * th.sin()))
        .collect();
    ctx.draw_series(LineSeries::new(curve_n, PALETTE[3].stroke_width(2)))
        .map_err(|e| err(path, e))?
        .label("normalised, Eq. 12")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[3].stroke_width(2)));
    let th = t.theta_p_deg.to_radians();
    ctx.draw_series(LineSeries::new(
        vec![(-th.cos(), -th.sin()), (th.cos(), th.sin())],
        PALETTE[0].stroke_width(2),
    ))
    .map_err(|e| err(path, e))?
    .label("theta_P")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], PALETTE[0].stroke_width(2)));
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))?;
    Ok(())
}

/// Contour points of `C_chi / C_chi(0)` (dots, one colour per level) and
/// the fitted ellipses (black), in units of `q0` (Fig. 10).
pub fn chi_contours(
    path: &Path,
    inputs: &AnalysisInputs<'_>,
    report: &AnalysisReport,
) -> Result<(), PlotError> {
    plot::ensure_font();
    let root = BitMapBackend::new(path, (760, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let Some(chi) = &report.chi else {
        root.draw(&Text::new(
            "no contact: C_chi undefined",
            (200, 380),
            ("sans-serif", 24).into_font(),
        ))
        .map_err(|e| err(path, e))?;
        root.present().map_err(|e| err(path, e))?;
        return Ok(());
    };
    let rmax = chi
        .levels
        .iter()
        .flat_map(|l| l.contour.iter().map(|p| p[0].hypot(p[1])))
        .chain(
            chi.levels
                .iter()
                .filter_map(|l| l.ellipse.map(|e| e.semi_major)),
        )
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    let r = if rmax > 0.0 { 1.15 * rmax } else { 1.0 };
    let title = match (report.lambda, report.ellipse_angle_deg) {
        (Some(l), Some(a)) => format!(
            "C_chi/C_chi(0) contours: lambda = {l:.3}, major axis {a:.1} deg{}",
            speed_label(inputs)
        ),
        _ => format!(
            "C_chi/C_chi(0) contours (no ellipse){}",
            speed_label(inputs)
        ),
    };
    let mut ctx = square_chart(path, &root, &title, r, "q_x / q0", "q_y / q0")?;
    for (k, level) in chi.levels.iter().enumerate() {
        let color = PALETTE[(k * 2) % PALETTE.len()];
        ctx.draw_series(
            level
                .contour
                .iter()
                .map(|p| Circle::new((p[0], p[1]), 3, color.filled())),
        )
        .map_err(|e| err(path, e))?
        .label(format!("C_chi/C_chi(0) = {}", level.level))
        .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
        if let Some(e) = level.ellipse {
            let phi = e.angle_deg.to_radians();
            let (s, c) = phi.sin_cos();
            let pts: Vec<(f64, f64)> = (0..=360)
                .map(|k| {
                    let t = 2.0 * PI * k as f64 / 360.0;
                    let (u, v) = (e.semi_major * t.cos(), e.semi_minor * t.sin());
                    (u * c - v * s, u * s + v * c)
                })
                .collect();
            ctx.draw_series(LineSeries::new(pts, BLACK.stroke_width(2)))
                .map_err(|e| err(path, e))?;
        }
    }
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))?;
    Ok(())
}

/// A scalar field with a colour bar ([`crate::plot::heatmap`]).
pub fn field_map(
    path: &Path,
    inputs: &AnalysisInputs<'_>,
    title: &str,
    values: &[f64],
    bar_label: &str,
) -> Result<(), PlotError> {
    let (ax, ay) = (inputs.cell_size, inputs.cell_size_y);
    plot::heatmap(
        path,
        &format!("{title}{}", speed_label(inputs)),
        &Field {
            nx: inputs.nx,
            ny: inputs.ny,
            values,
            extent: (0.0, inputs.nx as f64 * ax, 0.0, inputs.ny as f64 * ay),
        },
        bar_label,
        None,
    )
}

/// Bar chart of the spot-area histogram (octave bins, 4-connected spots).
pub fn spot_areas(path: &Path, report: &AnalysisReport) -> Result<(), PlotError> {
    plot::ensure_font();
    let h = &report.spots.histogram;
    let nb = h.len().max(1);
    let ymax = h.iter().map(|b| b.count).max().unwrap_or(0).max(1) as f64;
    let root = BitMapBackend::new(path, (800, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    let mut ctx = ChartBuilder::on(&root)
        .caption(
            format!(
                "Spot areas: {} spots (4-connected), mean {:.1} cells, median {:.1}",
                report.spots.count, report.spots.mean_area_cells, report.spots.median_area_cells
            ),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d((0..nb - 1).into_segmented(), 0.0..1.1 * ymax)
        .map_err(|e| err(path, e))?;
    let labels: Vec<String> = h
        .iter()
        .map(|b| {
            if b.min_cells == b.max_cells {
                format!("{}", b.min_cells)
            } else {
                format!("{}-{}", b.min_cells, b.max_cells)
            }
        })
        .collect();
    ctx.configure_mesh()
        .disable_x_mesh()
        .x_desc("spot area [cells]")
        .y_desc("spots")
        .x_labels(nb)
        .x_label_formatter(&|v| match v {
            SegmentValue::CenterOf(k) => labels.get(*k).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .y_label_formatter(&|v| format_tick(*v))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(|e| err(path, e))?;
    ctx.draw_series(h.iter().enumerate().map(|(k, b)| {
        let mut bar = Rectangle::new(
            [
                (SegmentValue::Exact(k), 0.0),
                (SegmentValue::Exact(k + 1), b.count as f64),
            ],
            PALETTE[2].filled(),
        );
        bar.set_margin(0, 0, 6, 6);
        bar
    }))
    .map_err(|e| err(path, e))?;
    root.present().map_err(|e| err(path, e))?;
    Ok(())
}
