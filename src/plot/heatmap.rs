//! Colour maps of a scalar field on a grid with a colour bar (the contact
//! maps of a solve and of the heat room); the colour scale is viridis.

use std::path::Path;

use plotters::prelude::*;

use super::{draw_err, ensure_font, format_tick, PlotError};

/// A scalar field on a grid for [`heatmap`]: `values[i * ny + j]` at
/// `x = x0 + (i + 0.5) dx`, `y = y0 + (j + 0.5) dy` (axis 0 = x).
#[derive(Debug, Clone)]
pub struct Field<'a> {
    pub nx: usize,
    pub ny: usize,
    pub values: &'a [f64],
    /// Physical extent `(x_min, x_max, y_min, y_max)`.
    pub extent: (f64, f64, f64, f64),
}

/// Draw a colour map of `field` with a colour bar labelled `bar_label`.
/// `window` (optional, in physical coordinates) restricts the view.
pub fn heatmap(
    path: &Path,
    title: &str,
    field: &Field<'_>,
    bar_label: &str,
    window: Option<(f64, f64, f64, f64)>,
) -> Result<(), PlotError> {
    ensure_font();
    let (x0, x1, y0, y1) = window.unwrap_or(field.extent);
    let (ex0, ex1, ey0, ey1) = field.extent;
    let dx = (ex1 - ex0) / field.nx as f64;
    let dy = (ey1 - ey0) / field.ny as f64;
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for &v in field.values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        return Err(PlotError::NoData {
            path: super::figure_name(path),
        });
    }
    if hi <= lo {
        hi = lo + 1.0;
    }
    let root = BitMapBackend::new(path, (860, 720)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let (main, bar) = root.split_horizontally(720);
    let mut ctx = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| draw_err(path, e))?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc("x [m] (sliding direction)")
        .y_desc("y [m]")
        .label_style(("sans-serif", 13))
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(|e| draw_err(path, e))?;
    let area = ctx.plotting_area();
    let (px, py) = area.get_pixel_range();
    let (w, h) = ((px.end - px.start).max(1), (py.end - py.start).max(1));
    for ix in 0..w {
        let x = x0 + (ix as f64 + 0.5) / w as f64 * (x1 - x0);
        let ci = ((x - ex0) / dx).floor();
        if ci < 0.0 || ci >= field.nx as f64 {
            continue;
        }
        for iy in 0..h {
            // Pixel rows grow downwards; y grows upwards.
            let y = y1 - (iy as f64 + 0.5) / h as f64 * (y1 - y0);
            let cj = ((y - ey0) / dy).floor();
            if cj < 0.0 || cj >= field.ny as f64 {
                continue;
            }
            let v = field.values[ci as usize * field.ny + cj as usize];
            let c = colormap((v - lo) / (hi - lo));
            root.draw_pixel((px.start + ix, py.start + iy), &c)
                .map_err(|e| draw_err(path, e))?;
        }
    }
    // Colour bar.
    let mut bctx = ChartBuilder::on(&bar)
        .margin_top(40)
        .margin_bottom(55)
        .margin_right(10)
        .y_label_area_size(0)
        .right_y_label_area_size(80)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(|e| draw_err(path, e))?;
    bctx.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(bar_label)
        .label_style(("sans-serif", 12))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(|e| draw_err(path, e))?;
    let steps = 200;
    bctx.draw_series((0..steps).map(|k| {
        let a = lo + (hi - lo) * k as f64 / steps as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            colormap((k as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(|e| draw_err(path, e))?;
    root.present().map_err(|e| draw_err(path, e))?;
    Ok(())
}

/// Perceptually ordered colour map (viridis anchors, linear in between).
pub fn colormap(t: f64) -> RGBColor {
    const V: [(f64, f64, f64); 6] = [
        (68.0, 1.0, 84.0),
        (65.0, 68.0, 135.0),
        (42.0, 120.0, 142.0),
        (34.0, 168.0, 132.0),
        (122.0, 209.0, 81.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (V.len() - 1) as f64;
    let k = (s.floor() as usize).min(V.len() - 2);
    let f = s - k as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(
        mix(V[k].0, V[k + 1].0),
        mix(V[k].1, V[k + 1].1),
        mix(V[k].2, V[k + 1].2),
    )
}
