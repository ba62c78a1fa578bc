//! PNG figures with plotters: line/point charts on linear or log axes, and
//! colour maps with a colour bar. Text uses the bundled DejaVu Sans font, so
//! figures render identically on machines without fontconfig. The ticks of
//! the charts' axes are chosen in `ticks` so that their labels never run
//! into each other.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

mod heatmap;
mod ticks;

pub use heatmap::{colormap, heatmap, Field};
pub use ticks::{axis_ticks, format_digits, labels_fit, tick_labels, Ticks, LABEL_GAP};

/// Plotting failures (drawing backend or invalid data), naming the figure
/// by its file name (`figure_name`).
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("cannot draw {path}: {what}")]
    Draw { path: String, what: String },
    #[error("cannot draw {path}: no finite data")]
    NoData { path: String },
}

static FONT: Once = Once::new();
const DEJAVU: &[u8] = include_bytes!("DejaVuSans.ttf");

pub(crate) fn ensure_font() {
    FONT.call_once(|| {
        // The bundled font is a valid TrueType file; a failure here is a bug.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU);
    });
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    Line,
    Points,
    LineAndPoints,
}

/// One labelled data series.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub mark: Mark,
    /// Index into the figure palette.
    pub color: usize,
    /// Optional symmetric error bars (same length as `points`).
    pub errors: Option<Vec<f64>>,
}

impl Series {
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Self {
        Self {
            label: label.into(),
            points,
            mark: Mark::Line,
            color,
            errors: None,
        }
    }
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Self {
        Self {
            label: label.into(),
            points,
            mark: Mark::Points,
            color,
            errors: None,
        }
    }
}

/// A chart of several series.
#[derive(Debug, Clone)]
pub struct XyChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
}

/// Palette used for series colours.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(200, 30, 30),
    RGBColor(20, 140, 40),
    RGBColor(30, 70, 200),
    RGBColor(230, 140, 0),
    RGBColor(120, 40, 160),
    RGBColor(0, 0, 0),
];

/// The file name of the figure at `path`: outputs are drawn in a staging
/// directory and moved into place whole, so the full path would name a
/// directory the user never sees.
pub(crate) fn figure_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

fn draw_err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw {
        path: figure_name(path),
        what: e.to_string(),
    }
}

fn range(vals: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in vals {
        if v.is_finite() && (!log || v > 0.0) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        return None;
    }
    if log {
        if hi <= lo {
            hi = lo * 10.0;
            lo /= 10.0;
        }
        Some((lo / 1.3, hi * 1.3))
    } else {
        let span = if hi > lo {
            hi - lo
        } else {
            lo.abs().max(1e-300)
        };
        Some((lo - 0.05 * span, hi + 0.05 * span))
    }
}

/// Draw `chart` into a PNG at `path` (800x600 pixels).
pub fn xy_chart(path: &Path, chart: &XyChart) -> Result<(), PlotError> {
    ensure_font();
    let root = BitMapBackend::new(path, (800, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    draw_chart(&root, path, chart)?;
    root.present().map_err(|e| draw_err(path, e))?;
    Ok(())
}

/// Draw `charts` one above the other into a PNG at `path` (800 pixels wide,
/// 450 per chart).
pub fn xy_charts_stacked(path: &Path, charts: &[XyChart]) -> Result<(), PlotError> {
    ensure_font();
    let n = charts.len().max(1);
    let root = BitMapBackend::new(path, (800, 450 * n as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    for (area, chart) in root.split_evenly((n, 1)).iter().zip(charts) {
        draw_chart(area, path, chart)?;
    }
    root.present().map_err(|e| draw_err(path, e))?;
    Ok(())
}

/// Size of the tick labels of an [`XyChart`] \[px\].
const TICK_LABEL_SIZE: f64 = 14.0;

/// Width and height in pixels of `text` in the charts' font at `size`
/// pixels, as plotters lays it out.
pub(crate) fn label_extent(text: &str, size: f64) -> (f64, f64) {
    ensure_font();
    let font: FontDesc<'_> = ("sans-serif", size).into_font();
    match font.box_size(text) {
        Ok((w, h)) => (f64::from(w), f64::from(h).max(size)),
        // Without the font: a generous estimate of its advance widths.
        Err(_) => (0.65 * size * text.chars().count() as f64, size),
    }
}

/// The layout of an [`XyChart`] in its drawing area.
fn chart_builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80);
    b
}

/// Lengths in pixels of the x and y axes of a chart titled `title` in a
/// `w x h` area: the layout drawn once into a scratch buffer.
fn axis_lengths(w: u32, h: u32, title: &str) -> (f64, f64) {
    let mut buffer = vec![0u8; (w as usize) * (h as usize) * 3];
    let area = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
    let lengths = match chart_builder(&area, title).build_cartesian_2d(0.0..1.0, 0.0..1.0) {
        Ok(ctx) => {
            let (px, py) = ctx.plotting_area().get_pixel_range();
            (f64::from(px.end - px.start), f64::from(py.end - py.start))
        }
        Err(_) => (f64::from(w), f64::from(h)),
    };
    lengths
}

/// A chart axis from `lo` to `hi`, linear or logarithmic, with the ticks
/// [`axis_ticks`] chose: the labelled ones as plotters' bold key points,
/// the grid lines between them as its light points.
struct TickedAxis {
    lo: f64,
    hi: f64,
    log: bool,
    ticks: Ticks,
}

impl plotters::coord::ranged1d::Ranged for TickedAxis {
    type FormatOption = plotters::coord::ranged1d::DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = ticks::pixel(*value, self.lo, self.hi, self.log, 1.0);
        // Zero and below on a log axis: below the axis.
        let t = if t.is_finite() {
            t.clamp(-100.0, 100.0)
        } else if t > 0.0 {
            100.0
        } else {
            -100.0
        };
        (f64::from(limit.0) + f64::from(limit.1 - limit.0) * t).round() as i32
    }

    fn key_points<H: plotters::coord::ranged1d::KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.ticks.minor.clone()
        } else {
            self.ticks.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

fn draw_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    path: &Path,
    chart: &XyChart,
) -> Result<(), PlotError> {
    let xs = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = chart.series.iter().flat_map(|s| {
        s.points.iter().enumerate().flat_map(move |(i, p)| {
            let e = s.errors.as_ref().map(|e| e[i].abs()).unwrap_or(0.0);
            [p.1 - e, p.1 + e]
        })
    });
    let nodata = || PlotError::NoData {
        path: figure_name(path),
    };
    let (x0, x1) = range(xs, chart.log_x).ok_or_else(nodata)?;
    let (y0, y1) = range(ys, chart.log_y).ok_or_else(nodata)?;
    let (w, h) = area.dim_in_pixel();
    let (x_len, y_len) = axis_lengths(w, h, &chart.title);
    let x = TickedAxis {
        lo: x0,
        hi: x1,
        log: chart.log_x,
        ticks: axis_ticks(x0, x1, chart.log_x, x_len, &|s| {
            label_extent(s, TICK_LABEL_SIZE).0
        }),
    };
    let y = TickedAxis {
        lo: y0,
        hi: y1,
        log: chart.log_y,
        ticks: axis_ticks(y0, y1, chart.log_y, y_len, &|s| {
            label_extent(s, TICK_LABEL_SIZE).1
        }),
    };
    draw_xy(area, path, chart, x, y)
}

fn draw_xy<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    path: &Path,
    chart: &XyChart,
    x: TickedAxis,
    y: TickedAxis,
) -> Result<(), PlotError> {
    let (xt, yt) = (x.ticks.clone(), y.ticks.clone());
    let mut ctx = chart_builder(root, &chart.title)
        .build_cartesian_2d(x, y)
        .map_err(|e| draw_err(path, e))?;
    ctx.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .label_style(("sans-serif", TICK_LABEL_SIZE))
        .axis_desc_style(("sans-serif", 16))
        .x_label_formatter(&|v| xt.label(*v))
        .y_label_formatter(&|v| yt.label(*v))
        .draw()
        .map_err(|e| draw_err(path, e))?;
    // A log axis shows positive values only.
    let shown = |p: &(f64, f64)| {
        p.0.is_finite()
            && p.1.is_finite()
            && (!chart.log_x || p.0 > 0.0)
            && (!chart.log_y || p.1 > 0.0)
    };
    for s in &chart.series {
        let color = PALETTE[s.color % PALETTE.len()];
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(shown).collect();
        let mut labelled = false;
        if matches!(s.mark, Mark::Line | Mark::LineAndPoints) {
            ctx.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(|e| draw_err(path, e))?
                .label(&s.label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            labelled = true;
        }
        if matches!(s.mark, Mark::Points | Mark::LineAndPoints) {
            let ann = ctx
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|e| draw_err(path, e))?;
            if !labelled {
                ann.label(&s.label)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            }
        }
        if let Some(err) = &s.errors {
            ctx.draw_series(
                s.points
                    .iter()
                    .zip(err)
                    .filter(|(p, e)| shown(p) && e.is_finite())
                    .map(|(&(x, y), &e)| {
                        ErrorBar::new_vertical(
                            x,
                            y - e.abs(),
                            y,
                            y + e.abs(),
                            color.stroke_width(1),
                            6,
                        )
                    }),
            )
            .map_err(|e| draw_err(path, e))?;
        }
    }
    // The legend goes into the corner where it hides the least data.
    let pixels: Vec<Vec<(i32, i32)>> = chart
        .series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .filter(|p| shown(p))
                .map(|p| ctx.backend_coord(p))
                .collect()
        })
        .collect();
    let (px, py) = ctx.plotting_area().get_pixel_range();
    let labels: Vec<&str> = chart.series.iter().map(|s| s.label.as_str()).collect();
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(legend_corner(&pixels, &labels, (px, py)))
        .draw()
        .map_err(|e| draw_err(path, e))?;
    Ok(())
}

/// The corner of the plotting area `(x pixels, y pixels)` whose legend box
/// (as large as the `labels` make it) covers the fewest of the series'
/// points `pixels`, lines between them sampled every few pixels; upper
/// right on a tie.
fn legend_corner(
    pixels: &[Vec<(i32, i32)>],
    labels: &[&str],
    (px, py): (std::ops::Range<i32>, std::ops::Range<i32>),
) -> SeriesLabelPosition {
    let width = labels
        .iter()
        .map(|l| label_extent(l, 14.0).0)
        .fold(0.0, f64::max)
        + 50.0;
    let height = labels.len() as f64 * 20.0 + 14.0;
    let mut samples = Vec::new();
    for line in pixels {
        samples.extend(line.iter().map(|&(x, y)| (f64::from(x), f64::from(y))));
        for w in line.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
            let steps = (dx.hypot(dy) / 4.0).ceil().min(1000.0) as usize;
            samples.extend((1..steps).map(|k| {
                let t = k as f64 / steps as f64;
                (f64::from(a.0) + t * dx, f64::from(a.1) + t * dy)
            }));
        }
    }
    let (x0, x1) = (f64::from(px.start), f64::from(px.end));
    let (y0, y1) = (f64::from(py.start), f64::from(py.end));
    let corners = [
        (SeriesLabelPosition::UpperRight, x1 - width, y0),
        (SeriesLabelPosition::UpperLeft, x0, y0),
        (SeriesLabelPosition::LowerRight, x1 - width, y1 - height),
        (SeriesLabelPosition::LowerLeft, x0, y1 - height),
    ];
    let covered = |&(_, left, top): &(SeriesLabelPosition, f64, f64)| {
        samples
            .iter()
            .filter(|&&(x, y)| x >= left && x <= left + width && y >= top && y <= top + height)
            .count()
    };
    let best = corners
        .iter()
        .min_by_key(|c| covered(c))
        .map(|c| c.0.clone());
    best.unwrap_or(SeriesLabelPosition::UpperRight)
}

/// Compact tick label: plain for moderate magnitudes (three decimals at
/// most), scientific with two significant digits otherwise (`2.5e6`,
/// `1e-4`).
pub fn format_tick(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format_digits(v, 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charts_render_to_png() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("c.png");
        let chart = XyChart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: true,
            log_y: true,
            series: vec![
                Series::line(
                    "a",
                    (1..50).map(|i| (i as f64, 1.0 / i as f64)).collect(),
                    0,
                ),
                Series::points(
                    "b",
                    (1..50).map(|i| (i as f64, 2.0 / i as f64)).collect(),
                    1,
                ),
            ],
        };
        xy_chart(&p, &chart).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let vals: Vec<f64> = (0..64).map(|k| (k as f64).sin()).collect();
        let f = Field {
            nx: 8,
            ny: 8,
            values: &vals,
            extent: (0.0, 1.0, 0.0, 1.0),
        };
        let q = tmp.path().join("h.png");
        heatmap(&q, "h", &f, "v", None).unwrap();
        assert_eq!(&std::fs::read(&q).unwrap()[1..4], b"PNG");
    }

    #[test]
    fn empty_data_is_an_error() {
        let tmp = tempfile::tempdir().unwrap();
        let chart = XyChart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: true,
            log_y: false,
            series: vec![Series::line("a", vec![(-1.0, 1.0)], 0)],
        };
        assert!(matches!(
            xy_chart(&tmp.path().join("c.png"), &chart),
            Err(PlotError::NoData { .. })
        ));
    }
}
