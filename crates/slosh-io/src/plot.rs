//! PNG and SVG figures drawn with plotters, using the bundled DejaVu Sans font.
//!
//! Every function takes a path **without extension** and writes two files: `<path>.png`
//! (1000 × 600 pixels) and `<path>.svg` (the same figure as vector graphics). Data with NaN
//! or infinite values is tolerated: such points are skipped (a line is broken there), and a
//! figure with no finite data at all is drawn as an empty frame titled "(no data)". Constant
//! data gets a small range around its value. Inconsistent input (e.g. `xs` and `ys` of
//! different lengths) is an [`IoError::InvalidData`].

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{ensure_parent, IoError, Result};

/// Width of the PNG images, pixels.
pub const PNG_WIDTH: u32 = 1000;
/// Height of the PNG images, pixels.
pub const PNG_HEIGHT: u32 = 600;

/// The font family name under which the bundled font is registered.
const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static FONT_REGISTERED: OnceLock<bool> = OnceLock::new();

/// Registers the bundled DejaVu Sans with plotters (once per process); false if it failed.
fn ensure_font() -> bool {
    *FONT_REGISTERED
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok())
}

/// Title and axis labels of a figure. Put units in the labels, e.g. `"t (s)"`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PlotSpec {
    /// Title drawn above the chart.
    pub title: String,
    /// Horizontal axis label, with units.
    pub x_label: String,
    /// Vertical axis label, with units.
    pub y_label: String,
}

impl PlotSpec {
    /// A spec from its three texts.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// A solid line through the points in order.
    #[default]
    Line,
    /// A filled marker at each point, no line.
    Points,
    /// A dashed line (e.g. for theory curves).
    Dashed,
}

/// One data series of a figure. `xs` and `ys` must have the same length.
#[derive(Debug, Clone, PartialEq)]
pub struct Series<'a> {
    /// Legend text; empty for no legend entry.
    pub label: String,
    /// Horizontal coordinates.
    pub xs: &'a [f64],
    /// Vertical coordinates.
    pub ys: &'a [f64],
    /// Line, points or dashed.
    pub style: SeriesStyle,
    /// RGB colour; `None` picks the next colour of the built-in palette.
    pub color: Option<(u8, u8, u8)>,
}

impl<'a> Series<'a> {
    /// A series with the given style and a palette colour.
    pub fn new(label: impl Into<String>, xs: &'a [f64], ys: &'a [f64], style: SeriesStyle) -> Self {
        Self {
            label: label.into(),
            xs,
            ys,
            style,
            color: None,
        }
    }

    /// A solid-line series.
    pub fn line(label: impl Into<String>, xs: &'a [f64], ys: &'a [f64]) -> Self {
        Self::new(label, xs, ys, SeriesStyle::Line)
    }

    /// A markers-only series.
    pub fn points(label: impl Into<String>, xs: &'a [f64], ys: &'a [f64]) -> Self {
        Self::new(label, xs, ys, SeriesStyle::Points)
    }

    /// A dashed-line series.
    pub fn dashed(label: impl Into<String>, xs: &'a [f64], ys: &'a [f64]) -> Self {
        Self::new(label, xs, ys, SeriesStyle::Dashed)
    }

    /// The same series in an explicit RGB colour.
    pub fn with_color(mut self, r: u8, g: u8, b: u8) -> Self {
        self.color = Some((r, g, b));
        self
    }
}

/// A field sampled on a grid, for [`heatmap`]: `values[i * ys.len() + j]` is the value at
/// `(xs[i], ys[j])` (row-major with x, typically time, as the slow index, matching
/// [`crate::write_grid_csv`]). `xs` and `ys` must be finite and strictly increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct Field2d<'a> {
    /// Horizontal coordinates (e.g. time, s).
    pub xs: &'a [f64],
    /// Vertical coordinates (e.g. position along the roof, m).
    pub ys: &'a [f64],
    /// The values, `xs.len() * ys.len()` of them; NaN cells are drawn grey.
    pub values: &'a [f64],
    /// Colour-bar label, with units (e.g. `"p (Pa)"`).
    pub value_label: String,
}

/// The built-in palette (Tableau 10), used in order for series without a colour.
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// `path` + `.ext`, keeping any dots already in the file name.
fn with_ext(path: &Path, ext: &str) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Something that can draw itself on any plotters backend.
trait Figure {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String>;
}

fn err_string<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Draws `fig` into `<path>.png` and `<path>.svg`.
fn render<F: Figure>(path: &Path, fig: &F) -> Result<()> {
    render_two(path, fig, fig)
}

/// Draws `png_fig` into `<path>.png` and `svg_fig` into `<path>.svg`, each first into a
/// temporary sibling (`<path>.part.png`, `.part.svg`) renamed into place when complete, so a
/// plot is never seen half-drawn.
fn render_two<A: Figure, B: Figure>(path: &Path, png_fig: &A, svg_fig: &B) -> Result<()> {
    let (png_part, svg_part) = (with_ext(path, "part.png"), with_ext(path, "part.svg"));
    // The plotting library opens its files itself: each is made fresh first, never through a
    // link, and neither it nor the plot it replaces may be a link.
    crate::error::ensure_parent(&png_part)?;
    for ext in ["png", "svg"] {
        crate::error::refuse_link(&with_ext(path, ext))?;
    }
    let fresh = [&png_part, &svg_part].into_iter().try_for_each(|p| {
        crate::error::create_fresh(p)
            .map(drop)
            .map_err(|e| IoError::io(p, e))
    });
    let drawn = fresh
        .and_then(|()| draw_two(&png_part, &svg_part, png_fig, svg_fig))
        .and_then(|()| {
            for (part, ext) in [(&png_part, "png"), (&svg_part, "svg")] {
                let done = with_ext(path, ext);
                std::fs::rename(part, &done).map_err(|e| IoError::io(&done, e))?;
            }
            Ok(())
        });
    if drawn.is_err() {
        // Only the parts made here (files), never a link found in their place.
        for part in [&png_part, &svg_part] {
            if std::fs::symlink_metadata(part).is_ok_and(|m| m.is_file()) {
                let _ = std::fs::remove_file(part);
            }
        }
    }
    drawn
}

/// Draws the two figures into `png` and `svg`.
fn draw_two<A: Figure, B: Figure>(png: &Path, svg: &Path, png_fig: &A, svg_fig: &B) -> Result<()> {
    let (png, svg) = (png.to_path_buf(), svg.to_path_buf());
    ensure_parent(&png)?;
    if !ensure_font() {
        return Err(IoError::Plot {
            path: png,
            message: "the bundled font could not be loaded".into(),
        });
    }
    let plot_err = |path: &Path| {
        let path = path.to_path_buf();
        move |message| IoError::Plot { path, message }
    };
    {
        let root = BitMapBackend::new(&png, (PNG_WIDTH, PNG_HEIGHT)).into_drawing_area();
        png_fig
            .draw(&root)
            .and_then(|_| root.present().map_err(err_string))
            .map_err(plot_err(&png))?;
    }
    {
        let root = SVGBackend::new(&svg, (PNG_WIDTH, PNG_HEIGHT)).into_drawing_area();
        svg_fig
            .draw(&root)
            .and_then(|_| root.present().map_err(err_string))
            .map_err(plot_err(&svg))?;
    }
    Ok(())
}

/// Short tick labels: six significant digits at most, exponent form for large/small values,
/// and exactly `0` for a tick that is zero up to rounding noise relative to the axis `span`.
fn tick_label(v: f64, span: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 || v.abs() < 1e-9 * span.abs() {
        return "0".into();
    }
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    if (1e-3..1e5).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// The finite (min, max) of `values`, or `None` if there is none.
fn finite_range<'a>(values: impl IntoIterator<Item = &'a f64>) -> Option<(f64, f64)> {
    let mut r: Option<(f64, f64)> = None;
    for &v in values {
        if v.is_finite() {
            r = Some(match r {
                None => (v, v),
                Some((lo, hi)) => (lo.min(v), hi.max(v)),
            });
        }
    }
    r
}

/// Widens a data range for display: `pad` × width on each side; a constant or degenerate
/// range becomes a small interval around the value; no data gives 0..1.
fn display_range(r: Option<(f64, f64)>, pad: f64) -> (f64, f64) {
    match r {
        None => (0.0, 1.0),
        Some((lo, hi)) => {
            let scale = lo.abs().max(hi.abs());
            let w = hi - lo;
            if w <= 1e-12 * scale {
                let h = if scale > 0.0 { 0.1 * scale } else { 1.0 };
                (lo - h, hi + h)
            } else {
                let (a, b) = (lo - pad * w, hi + pad * w);
                if a.is_finite() && b.is_finite() {
                    (a, b)
                } else {
                    (lo, hi)
                }
            }
        }
    }
}

/// Splits the points of a series into runs of finite points (a NaN breaks a line).
fn finite_runs(xs: &[f64], ys: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut cur = Vec::new();
    for (&x, &y) in xs.iter().zip(ys) {
        if x.is_finite() && y.is_finite() {
            cur.push((x, y));
        } else if !cur.is_empty() {
            runs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}

fn check_series(path: &Path, series: &[Series]) -> Result<()> {
    for (i, s) in series.iter().enumerate() {
        if s.xs.len() != s.ys.len() {
            return Err(IoError::invalid(
                &with_ext(path, "png"),
                format!(
                    "series {i} (`{}`) has {} x values but {} y values",
                    s.label,
                    s.xs.len(),
                    s.ys.len()
                ),
            ));
        }
    }
    Ok(())
}

/// The figure of [`line_plot`] and [`scatter_with_identity`].
struct XyFigure<'s, 'a> {
    spec: &'s PlotSpec,
    series: &'s [Series<'a>],
    identity: bool,
}

/// Margin round the charts of the x-y plots and maps (px).
const CHART_MARGIN: u32 = 12;
/// Right margin of an x-y chart (px), room for the last tick label.
const XY_MARGIN_RIGHT: u32 = 28;
/// Height of the x tick labels and description below a chart (px).
const X_LABEL_AREA: u32 = 55;
/// Width of the y tick labels and description left of a chart (px).
const Y_LABEL_AREA: u32 = 90;

/// The size (px) at which `text` in the bundled font spans at most `room` px: `largest`, or
/// smaller down to 12 px (`largest` where the font cannot be measured).
fn fitted_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    largest: f64,
    room: f64,
) -> f64 {
    let wide = area
        .estimate_text_size(text, &(FONT, largest).into_font().color(&BLACK))
        .map_or(0.0, |(w, _)| w as f64);
    if wide > room {
        (largest * room / wide).floor().max(12.0)
    } else {
        largest
    }
}

/// The title's font: 26 px, smaller (down to 12 px) for a title wider than the figure, so
/// that a long one is not cut at both ends.
fn title_style<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> TextStyle<'static> {
    let room = 0.96 * root.dim_in_pixel().0 as f64;
    (FONT, fitted_size(root, title, 26.0, room))
        .into_font()
        .color(&BLACK)
}

/// The axis descriptions' font size (px) for a chart on `area` with the label areas and
/// margins of this module's charts: 19 px, smaller (down to 12 px) where a description is
/// longer than its axis (a sweep plot's y axis naming several columns), so that it is not cut
/// at the figure's edge.
fn axis_desc_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x_desc: &str,
    y_desc: &str,
) -> f64 {
    const LARGEST: f64 = 19.0;
    let (w, h) = area.dim_in_pixel();
    // The axes' lengths: less the label areas and the margins (the wider right margin of an
    // x-y chart for both kinds).
    let x_room = 0.95 * (w as f64 - (Y_LABEL_AREA + CHART_MARGIN + XY_MARGIN_RIGHT) as f64);
    let y_room = 0.95 * (h as f64 - (X_LABEL_AREA + 2 * CHART_MARGIN) as f64);
    fitted_size(area, x_desc, LARGEST, x_room).min(fitted_size(area, y_desc, LARGEST, y_room))
}

impl Figure for XyFigure<'_, '_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
        root.fill(&WHITE).map_err(err_string)?;
        let xr = finite_range(self.series.iter().flat_map(|s| s.xs.iter()));
        let yr = finite_range(self.series.iter().flat_map(|s| s.ys.iter()));
        let no_data = xr.is_none() || yr.is_none();
        let has_points = self.series.iter().any(|s| s.style == SeriesStyle::Points);
        let ((x0, x1), (y0, y1)) = if self.identity {
            // Same range on both axes so that y = x is the diagonal.
            let both = match (xr, yr) {
                (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
                (a, b) => a.or(b),
            };
            let r = display_range(both, 0.05);
            (r, r)
        } else {
            let (y0, y1) = display_range(yr, 0.05);
            // Head room for the legend box in the upper right corner, so it hides no data.
            let entries = self.series.iter().filter(|s| !s.label.is_empty()).count();
            let room = if entries > 0 && yr.is_some() {
                (0.06 + 0.09 * entries as f64) * (y1 - y0)
            } else {
                0.0
            };
            (
                display_range(xr, if has_points { 0.03 } else { 0.0 }),
                (y0, y1 + room),
            )
        };

        let title = if no_data {
            format!("{} (no data)", self.spec.title)
        } else {
            self.spec.title.clone()
        };
        let xfmt = |v: &f64| tick_label(*v, x1 - x0);
        let yfmt = |v: &f64| tick_label(*v, y1 - y0);
        let area = root
            .titled(&title, title_style(root, &title))
            .map_err(err_string)?;
        let mut chart = ChartBuilder::on(&area)
            .margin(CHART_MARGIN)
            .margin_right(XY_MARGIN_RIGHT)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err_string)?;
        chart
            .configure_mesh()
            .x_desc(self.spec.x_label.as_str())
            .y_desc(self.spec.y_label.as_str())
            .label_style((FONT, 16))
            .axis_desc_style((
                FONT,
                axis_desc_size(&area, &self.spec.x_label, &self.spec.y_label),
            ))
            .x_label_formatter(&xfmt)
            .y_label_formatter(&yfmt)
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .x_labels(10)
            .y_labels(8)
            .draw()
            .map_err(err_string)?;

        let mut any_label = false;
        if self.identity {
            let style = ShapeStyle::from(&RGBColor(90, 90, 90)).stroke_width(2);
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(x0, x0), (x1, x1)],
                    10,
                    6,
                    style,
                ))
                .map_err(err_string)?
                .label("y = x")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
            any_label = true;
        }

        for (i, s) in self.series.iter().enumerate() {
            let (r, g, b) = s.color.unwrap_or(PALETTE[i % PALETTE.len()]);
            let color = RGBColor(r, g, b);
            let runs = finite_runs(s.xs, s.ys);
            if runs.is_empty() {
                continue;
            }
            let line_style = ShapeStyle::from(&color).stroke_width(2);
            for run in runs {
                if run.len() == 1 && s.style != SeriesStyle::Points {
                    // An isolated point of a line (neighbours are NaN) is shown as a dot.
                    chart
                        .draw_series(std::iter::once(Circle::new(run[0], 2, color.filled())))
                        .map_err(err_string)?;
                    continue;
                }
                match s.style {
                    SeriesStyle::Line => chart.draw_series(LineSeries::new(run, line_style)),
                    SeriesStyle::Dashed => {
                        chart.draw_series(DashedLineSeries::new(run, 10, 6, line_style))
                    }
                    SeriesStyle::Points => chart.draw_series(
                        run.into_iter()
                            .map(|p| Circle::new(p, 3, ShapeStyle::from(&color).filled())),
                    ),
                }
                .map_err(err_string)?;
            }
            if !s.label.is_empty() {
                any_label = true;
                let style = s.style;
                // An empty series carries the legend entry, drawn once per series.
                chart
                    .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                    .map_err(err_string)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        // One element shape for all styles: a marker and two line segments,
                        // the unused parts drawn transparent.
                        let (marker, lines) = match style {
                            SeriesStyle::Points => (color.filled(), TRANSPARENT.into()),
                            _ => (TRANSPARENT.filled(), line_style),
                        };
                        let gap = if style == SeriesStyle::Dashed { 3 } else { 0 };
                        EmptyElement::at((x, y))
                            + Circle::new((12, 0), 4, marker)
                            + PathElement::new(vec![(0, 0), (12 - gap, 0)], lines)
                            + PathElement::new(vec![(12 + gap, 0), (24, 0)], lines)
                    });
            }
        }
        if any_label {
            chart
                .configure_series_labels()
                .position(if self.identity {
                    // The diagonal runs through the upper right corner.
                    SeriesLabelPosition::UpperLeft
                } else {
                    SeriesLabelPosition::UpperRight
                })
                .margin(10)
                .legend_area_size(30)
                .label_font((FONT, 16))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(120, 120, 120))
                .draw()
                .map_err(err_string)?;
        }
        Ok(())
    }
}

/// Draws the series as lines/points/dashed lines on one pair of axes, with a legend box for
/// labelled series, into `<path>.png` and `<path>.svg`.
pub fn line_plot(path: impl AsRef<Path>, spec: &PlotSpec, series: &[Series]) -> Result<()> {
    let path = path.as_ref();
    check_series(path, series)?;
    render(
        path,
        &XyFigure {
            spec,
            series,
            identity: false,
        },
    )
}

/// A "computed vs reference" plot: the series (usually [`SeriesStyle::Points`], x = theory,
/// y = SPH) on equal axis ranges with a dashed y = x line, into `<path>.png` and `.svg`.
pub fn scatter_with_identity(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    series: &[Series],
) -> Result<()> {
    let path = path.as_ref();
    check_series(path, series)?;
    render(
        path,
        &XyFigure {
            spec,
            series,
            identity: true,
        },
    )
}

/// Viridis-like colour map: `t` in 0..=1 to RGB (linear between five anchor colours).
pub fn colormap(t: f64) -> (u8, u8, u8) {
    const ANCHORS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (ANCHORS.len() - 1) as f64;
    let i = (s.floor() as usize).min(ANCHORS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |p: f64, q: f64| (p + f * (q - p)).round().clamp(0.0, 255.0) as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Cell edges around strictly increasing centres: midpoints inside, half a spacing outside.
fn cell_edges(c: &[f64]) -> Vec<f64> {
    match c.len() {
        0 => Vec::new(),
        1 => {
            let h = if c[0] != 0.0 { 0.1 * c[0].abs() } else { 0.5 };
            vec![c[0] - h, c[0] + h]
        }
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(c[0] - 0.5 * (c[1] - c[0]));
            for w in c.windows(2) {
                e.push(0.5 * (w[0] + w[1]));
            }
            e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
            e
        }
    }
}

struct HeatFigure<'s, 'a> {
    spec: &'s PlotSpec,
    field: &'s Field2d<'a>,
    /// Draw every `stride`-th x row only (SVG size limit).
    stride: usize,
}

impl Figure for HeatFigure<'_, '_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
        root.fill(&WHITE).map_err(err_string)?;
        let f = self.field;
        let vr = finite_range(f.values.iter());
        let no_data = vr.is_none() || f.xs.is_empty() || f.ys.is_empty();
        let (v0, v1) = match vr {
            Some((a, b)) if b > a => (a, b),
            other => display_range(other, 0.0),
        };
        let xe = cell_edges(f.xs);
        let ye = cell_edges(f.ys);
        let (x0, x1) = if xe.is_empty() {
            (0.0, 1.0)
        } else {
            (xe[0], xe[xe.len() - 1])
        };
        let (y0, y1) = if ye.is_empty() {
            (0.0, 1.0)
        } else {
            (ye[0], ye[ye.len() - 1])
        };

        let title = if no_data {
            format!("{} (no data)", self.spec.title)
        } else {
            self.spec.title.clone()
        };
        let xfmt = |v: &f64| tick_label(*v, x1 - x0);
        let yfmt = |v: &f64| tick_label(*v, y1 - y0);
        let vfmt = |v: &f64| tick_label(*v, v1 - v0);
        let area = root
            .titled(&title, title_style(root, &title))
            .map_err(err_string)?;
        let (w, _) = area.dim_in_pixel();
        let (main, bar) = area.split_horizontally(w.saturating_sub(135));

        let mut chart = ChartBuilder::on(&main)
            .margin(CHART_MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err_string)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(self.spec.x_label.as_str())
            .y_desc(self.spec.y_label.as_str())
            .label_style((FONT, 16))
            .axis_desc_style((
                FONT,
                axis_desc_size(&main, &self.spec.x_label, &self.spec.y_label),
            ))
            .x_label_formatter(&xfmt)
            .y_label_formatter(&yfmt)
            .draw()
            .map_err(err_string)?;

        let ny = f.ys.len();
        let color_of = |v: f64| -> RGBColor {
            if v.is_finite() {
                let (r, g, b) = colormap((v - v0) / (v1 - v0));
                RGBColor(r, g, b)
            } else {
                RGBColor(190, 190, 190)
            }
        };
        let stride = self.stride.max(1);
        let rows: Vec<usize> = (0..f.xs.len()).step_by(stride).collect();
        chart
            .draw_series(rows.iter().enumerate().flat_map(|(k, &i)| {
                // A drawn row covers the cells up to the next drawn row.
                let xa = xe[i];
                let xb = rows.get(k + 1).map_or(xe[xe.len() - 1], |&n| xe[n]);
                let ye = &ye;
                (0..ny).map(move |j| {
                    let v = f.values[i * ny + j];
                    Rectangle::new([(xa, ye[j]), (xb, ye[j + 1])], color_of(v).filled())
                })
            }))
            .map_err(err_string)?;

        // Colour bar: a thin chart whose y axis is the value range.
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(12)
            .margin_bottom(12)
            .margin_left(10)
            .margin_right(5)
            .x_label_area_size(X_LABEL_AREA)
            .right_y_label_area_size(85)
            .build_cartesian_2d(0.0..1.0, v0..v1)
            .map_err(err_string)?;
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(f.value_label.as_str())
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 18))
            .y_label_formatter(&vfmt)
            .y_labels(8)
            .draw()
            .map_err(err_string)?;
        let n = 128;
        cb.draw_series((0..n).map(|k| {
            let a = v0 + (v1 - v0) * k as f64 / n as f64;
            let b = v0 + (v1 - v0) * (k + 1) as f64 / n as f64;
            let (r, g, bl) = colormap((k as f64 + 0.5) / n as f64);
            Rectangle::new([(0.0, a), (1.0, b)], RGBColor(r, g, bl).filled())
        }))
        .map_err(err_string)?;
        cb.draw_series(std::iter::once(Rectangle::new(
            [(0.0, v0), (1.0, v1)],
            ShapeStyle::from(&BLACK).stroke_width(1),
        )))
        .map_err(err_string)?;
        Ok(())
    }
}

/// Largest number of cells drawn into the SVG twin of a heatmap; above it every k-th x row is
/// drawn (the PNG always shows every cell).
pub const SVG_MAX_CELLS: usize = 10_000;

/// Draws a field on an (x, y) grid, e.g. roof pressure over time × position, as coloured
/// cells with a colour bar, into `<path>.png` and `<path>.svg`.
pub fn heatmap(path: impl AsRef<Path>, spec: &PlotSpec, field: &Field2d) -> Result<()> {
    let path = path.as_ref();
    let png = with_ext(path, "png");
    if field.values.len() != field.xs.len() * field.ys.len() {
        return Err(IoError::invalid(
            &png,
            format!(
                "heatmap grid has {} × {} points but {} values",
                field.xs.len(),
                field.ys.len(),
                field.values.len()
            ),
        ));
    }
    for (name, c) in [("x", field.xs), ("y", field.ys)] {
        if c.iter().any(|v| !v.is_finite()) || c.windows(2).any(|w| w[1] <= w[0]) {
            return Err(IoError::invalid(
                &png,
                format!("heatmap {name} coordinates must be finite and strictly increasing"),
            ));
        }
    }
    let cells = field.values.len();
    let svg_stride = cells.div_ceil(SVG_MAX_CELLS).max(1);
    // Render PNG with every cell, SVG with the stride.
    let png_fig = HeatFigure {
        spec,
        field,
        stride: 1,
    };
    let svg_fig = HeatFigure {
        spec,
        field,
        stride: svg_stride,
    };
    render_two(path, &png_fig, &svg_fig)
}

#[cfg(test)]
mod title_tests {
    use super::*;

    /// Runs `f` on a bitmap of the files' size, with the bundled font registered.
    fn on_figure<R>(f: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> R) -> R {
        assert!(ensure_font());
        let mut pixels = vec![0u8; (PNG_WIDTH * PNG_HEIGHT * 3) as usize];
        let root =
            BitMapBackend::with_buffer(&mut pixels, (PNG_WIDTH, PNG_HEIGHT)).into_drawing_area();
        f(&root)
    }

    /// A short title keeps the full size; one wider than the figure at that size shrinks until
    /// it fits (the sweep plots' titles name the case, the columns and the groups).
    #[test]
    fn a_long_title_shrinks_to_the_figure() {
        let long = "paper_2d_roof_sweep — plot_max_roof_force_up_vs_post_clearance_ratio_actual\
                    _by_width_dx";
        on_figure(|root| {
            assert_eq!(title_style(root, "Free decay").font.get_size(), 26.0);
            let style = title_style(root, long);
            let size = style.font.get_size();
            assert!((12.0..26.0).contains(&size), "{size}");
            let (wide, _) = root.estimate_text_size(long, &style).unwrap();
            assert!(wide <= PNG_WIDTH, "{wide} px");
        });
    }

    /// A y description longer than the y axis (a sweep plot of two columns) is set smaller
    /// so that it spans the axis at most; a short one keeps 19 px.
    #[test]
    fn a_long_axis_description_shrinks_to_its_axis() {
        let long = "max_roof_force_up [N/m in 2D, N in 3D], max_roof_force_up_lp [N/m in 2D, N \
                    in 3D]";
        on_figure(|root| {
            let area = root.titled("t", title_style(root, "t")).unwrap();
            assert_eq!(axis_desc_size(&area, "time (s)", "eta_left (m)"), 19.0);
            let size = axis_desc_size(&area, "post_clearance_ratio_actual", long);
            assert!((12.0..19.0).contains(&size), "{size}");
            let (tall, _) = area
                .estimate_text_size(long, &(FONT, size).into_font().color(&BLACK))
                .unwrap();
            let axis = area.dim_in_pixel().1 - X_LABEL_AREA - 2 * CHART_MARGIN;
            assert!(tall <= axis, "{tall} px on a {axis} px axis");
        });
    }
}
