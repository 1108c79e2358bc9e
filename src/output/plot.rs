//! Reusable PNG plots (plotters, bitmap backend): line/marker charts of series and profiles on
//! linear or log axes ([`plot_chart`]), and cell rectangles coloured by a value with a colour
//! bar ([`plot_rectangles`], Figs 2.10e, 4.3a, 4.4a). The convention of the thesis figures is
//! kept: discrete runs as symbols, continuum runs as lines.
//!
//! ```no_run
//! use celltissue::output::plot::{plot_chart, plot_rectangles, Chart, Curve, Style, Axis};
//! let chart = Chart {
//!     title: "max p".into(), x_label: "t".into(), y_label: "max p".into(),
//!     x_axis: Axis::Log, y_axis: Axis::Linear,
//!     curves: vec![Curve::new("discrete", Style::Markers, 0, vec![(0.1, 1.0), (1.0, 1.2)])],
//! };
//! plot_chart("max_p.png".as_ref(), &chart)?;
//! plot_rectangles("cells.png".as_ref(), "t = 1", &[(0.0, -0.5, 1.0, 0.5, 1.2)], "p")?;
//! # Ok::<(), celltissue::output::plot::PlotError>(())
//! ```

use super::fonts::FONT;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Why a plot was not written.
///
/// ```
/// use celltissue::output::plot::{plot_chart, Axis, Chart, Curve, PlotError, Style};
/// // only non-positive values on a log axis: nothing to draw, and no file
/// let chart = Chart { title: "t".into(), x_label: "x".into(), y_label: "y".into(),
///     x_axis: Axis::Log, y_axis: Axis::Linear,
///     curves: vec![Curve::new("c", Style::Line, 0, vec![(0.0, 1.0), (-1.0, 2.0)])] };
/// let path = std::env::temp_dir().join("celltissue_doc_nodata.png");
/// assert!(matches!(plot_chart(&path, &chart), Err(PlotError::NoData)));
/// ```
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// Nothing finite (and positive, on log axes) to plot.
    #[error("no data to plot")]
    NoData,
    /// The drawing backend failed (file, font…).
    #[error("drawing failed: {0}")]
    Draw(String),
}

impl From<std::io::Error> for PlotError {
    fn from(e: std::io::Error) -> Self {
        PlotError::Draw(e.to_string())
    }
}

fn draw_err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Axis scale.
///
/// ```
/// use celltissue::output::plot::{plot_chart, Axis, Chart, Curve, Style};
/// // on a log axis the point at y = 0 is dropped, the others are drawn
/// let chart = Chart {
///     title: "growth".into(), x_label: "t".into(), y_label: "N".into(),
///     x_axis: Axis::Linear, y_axis: Axis::Log,
///     curves: vec![Curve::new("N", Style::Line, 0, vec![(0.0, 0.0), (1.0, 10.0), (2.0, 1e3)])],
/// };
/// let path = std::env::temp_dir().join("celltissue_doc_axis.png");
/// assert!(plot_chart(&path, &chart).is_ok());
/// assert_eq!(Axis::default(), Axis::Linear);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Axis {
    /// Linear.
    #[default]
    Linear,
    /// Logarithmic: points with non-positive coordinates are dropped.
    Log,
}

/// How a curve is drawn.
///
/// ```
/// use celltissue::output::plot::{Curve, Style};
/// // one run drawn both ways: its discrete cells as symbols, its continuum as a line, in the
/// // same colour; the analytic solution over them as a reference
/// let t = [0.0, 1.0, 2.0];
/// let curves = [
///     Curve::new("discrete", Style::Markers, 3, t.iter().map(|&t| (t, 1.0 - 0.1 * t)).collect()),
///     Curve::new("continuum", Style::Line, 3, t.iter().map(|&t| (t, 1.0 - 0.1 * t)).collect()),
///     Curve::new("exact", Style::Reference, 3, t.iter().map(|&t| (t, 1.0 - 0.1 * t)).collect()),
/// ];
/// assert!(curves.iter().all(|c| c.color == 3));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Solid line (continuum runs).
    Line,
    /// Dashed line in the curve's colour (guide lines such as `x = (l/l₀)X`).
    Dashed,
    /// Thin dashed line in a darkened shade of the curve's colour, drawn over the runs
    /// (analytic reference solutions: visible on a continuum line of the same colour, and
    /// matched to its run by hue); its legend entry is a near-black dashed line.
    Reference,
    /// Symbols only (discrete runs); the shape cycles with the colour index.
    Markers,
}

/// One curve.
///
/// ```
/// use celltissue::output::plot::{Curve, Style};
/// let guide = Curve::new("", Style::Dashed, 0, vec![(0.0, 0.0), (10.0, 9.0)]); // x = (l/l₀)X
/// assert!(guide.label.is_empty()); // no legend entry
/// assert_eq!(guide.points.len(), 2);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Legend entry (empty: not in the legend).
    pub label: String,
    /// Line or symbols.
    pub style: Style,
    /// Index into the colour (and symbol) cycle.
    pub color: usize,
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

impl Curve {
    /// A curve from its parts.
    ///
    /// ```
    /// use celltissue::output::plot::{Curve, Style};
    /// let c = Curve::new("K = 0.01", Style::Markers, 1, vec![(0.0, 1.0), (1.0, 0.9)]);
    /// assert_eq!((c.label.as_str(), c.color, c.points.len()), ("K = 0.01", 1, 2));
    /// ```
    pub fn new(
        label: impl Into<String>,
        style: Style,
        color: usize,
        points: Vec<(f64, f64)>,
    ) -> Self {
        Self {
            label: label.into(),
            style,
            color,
            points,
        }
    }
}

/// A chart: title, axis labels and scales, curves. Discrete runs are drawn as symbols,
/// continuum runs as lines, analytic references dashed:
///
/// ```
/// use celltissue::output::plot::{plot_chart, Axis, Chart, Curve, Style};
/// let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
/// let chart = Chart {
///     title: "decay".into(), x_label: "t".into(), y_label: "y".into(),
///     x_axis: Axis::Linear, y_axis: Axis::Log,
///     curves: vec![
///         Curve::new("run", Style::Markers, 0, t.iter().map(|&t| (t, (-t).exp())).collect()),
///         Curve::new("exact", Style::Reference, 0, t.iter().map(|&t| (t, (-t).exp())).collect()),
///     ],
/// };
/// let path = std::env::temp_dir().join("celltissue_doc_chart.png");
/// plot_chart(&path, &chart).unwrap();
/// assert_eq!(&std::fs::read(&path).unwrap()[1..4], b"PNG");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// Caption.
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Vertical axis label.
    pub y_label: String,
    /// Horizontal scale.
    pub x_axis: Axis,
    /// Vertical scale.
    pub y_axis: Axis,
    /// Curves.
    pub curves: Vec<Curve>,
}

/// Colour cycle (Tableau 10).
///
/// ```
/// use celltissue::output::plot::color;
/// assert_eq!(color(0), color(10)); // ten colours, cycled
/// assert_ne!(color(0), color(1));
/// ```
pub fn color(i: usize) -> RGBColor {
    const C: [(u8, u8, u8); 10] = [
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
    let (r, g, b) = C[i % C.len()];
    RGBColor(r, g, b)
}

/// A colour halfway to black.
fn darken(c: RGBColor) -> RGBColor {
    RGBColor(c.0 / 2, c.1 / 2, c.2 / 2)
}

/// Legend colour of [`Style::Reference`] curves.
pub const REFERENCE_COLOR: RGBColor = RGBColor(25, 25, 25);

/// Size of chart images in pixels.
pub const CHART_SIZE: (u32, u32) = (900, 620);

/// A data coordinate as drawn: itself on a linear axis, `log10` of it on a log axis (`None` if
/// it cannot be drawn: non-finite, or not positive on a log axis).
///
/// Log axes are drawn as linear axes in `log10` space with `10^v` tick labels rather than with
/// plotters' logarithmic coordinate, whose tick search loops without end (or allocates until
/// the process aborts) on ranges reaching down to 1e-300 or a subnormal number.
fn transform(axis: Axis, v: f64) -> Option<f64> {
    match axis {
        Axis::Linear => v.is_finite().then_some(v),
        Axis::Log => (v.is_finite() && v > 0.0).then(|| v.log10()),
    }
}

/// The range of drawn (transformed) coordinates, padded by 4 % so that it is never empty and
/// always finite (a span that would overflow is clamped to ±`f64::MAX`).
fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    // halves first: `hi − lo` overflows for data spanning ±1e308
    let half_span = 0.5 * hi - 0.5 * lo;
    let pad = if half_span > 0.0 {
        0.08 * half_span
    } else {
        0.05 * lo.abs().max(1e-9)
    };
    // at most ±f64::MAX/4 so that plotters' `hi − lo` and tick steps stay finite
    const BIG: f64 = f64::MAX / 4.0;
    let lo = (lo - pad).max(-BIG);
    let hi = (hi + pad).min(BIG);
    // a span of at least 1e-12 of the magnitude: far below it plotters' tick steps fall under
    // the spacing of f64 and its tick search never advances (a hang)
    let min_span = 1e-12 * lo.abs().max(hi.abs()).max(1e-300);
    if hi - lo < min_span {
        let mid = 0.5 * lo + 0.5 * hi;
        return Some((mid - min_span, mid + min_span));
    }
    Some((lo, hi))
}

/// A tick label for the drawn coordinate `v` on an axis whose ticks are about `step` apart.
/// Linear axes get as many digits as the tick spacing needs (ticks of a range 1 ± 1e-9 read
/// `1.000000001`, not all `1.0`); log axes label `10^v`.
///
/// ```
/// use celltissue::output::plot::{tick_label, Axis};
/// assert_eq!(tick_label(Axis::Linear, 0.25, 0.05), "0.25");
/// assert_eq!(tick_label(Axis::Linear, 1.000000001, 1e-9), "1.000000001");
/// ```
pub fn tick_label(axis: Axis, v: f64, step: f64) -> String {
    match axis {
        Axis::Linear => number_label(v, step),
        Axis::Log => {
            let x = 10f64.powf(v);
            if (v - v.round()).abs() < 1e-9 {
                let k = v.round() as i32;
                if (-3..=4).contains(&k) {
                    number_label(x, x)
                } else {
                    format!("1e{k}")
                }
            } else {
                // inside a decade (narrow log ranges): enough digits to tell ticks apart
                let rel = (10f64.powf(step) - 1.0).max(1e-15);
                number_label(x, rel * x)
            }
        }
    }
}

/// `v` with the digits that a resolution `step` needs; scientific notation for very large or
/// small magnitudes.
fn number_label(v: f64, step: f64) -> String {
    // a tick placed by adding steps (−0.4 + 2 × 0.2 = −5.6e-17) is zero at the axis's resolution
    if v == 0.0 || v.abs() < 1e-9 * step.abs() {
        return "0".into();
    }
    let step = step.abs().max(v.abs() * 1e-15);
    let mag = v.abs().log10().floor();
    let res = step.log10().floor();
    if !(-4.0..6.0).contains(&mag) {
        let digits = ((mag - res).max(0.0) as usize).min(15);
        return format!("{v:.digits$e}");
    }
    let decimals = ((-res).max(0.0) as usize).min(17);
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Writes `chart` as a PNG at `path` (atomically: drawn to a temporary file, then renamed).
///
/// ```
/// use celltissue::output::plot::{plot_chart, Axis, Chart, Curve, Style};
/// // nothing drawable on a log axis: an error, and no file is left behind
/// let path = std::env::temp_dir().join("celltissue_doc_plot_chart_empty.png");
/// let _ = std::fs::remove_file(&path);
/// let chart = Chart {
///     title: "pressure".into(), x_label: "t".into(), y_label: "p".into(),
///     x_axis: Axis::Linear, y_axis: Axis::Log,
///     curves: vec![Curve::new("p", Style::Line, 0, vec![(0.0, 0.0), (1.0, -1.0)])],
/// };
/// assert!(plot_chart(&path, &chart).is_err());
/// assert!(!path.exists());
/// ```
pub fn plot_chart(path: &Path, chart: &Chart) -> Result<(), PlotError> {
    super::fonts::register();
    let curves: Vec<(Curve, Vec<(f64, f64)>)> = chart
        .curves
        .iter()
        .map(|c| {
            // a point that cannot be drawn breaks a line (a gap is not bridged by a straight
            // segment that would look like data)
            let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for &(x, y) in &c.points {
                match (transform(chart.x_axis, x), transform(chart.y_axis, y)) {
                    (Some(x), Some(y)) => segments.last_mut().unwrap().push((x, y)),
                    _ if c.style != Style::Markers => segments.push(Vec::new()),
                    _ => {}
                }
            }
            segments.retain(|s| !s.is_empty());
            let pts: Vec<(f64, f64)> = match c.style {
                Style::Markers => thin_markers(segments.concat()),
                _ => {
                    // thinned piecewise; a NaN pair separates the pieces
                    let mut v = Vec::new();
                    for s in segments {
                        if !v.is_empty() {
                            v.push((f64::NAN, f64::NAN));
                        }
                        v.extend(thin_line(s));
                    }
                    v
                }
            };
            (c.clone(), pts)
        })
        .filter(|(_, p)| !p.is_empty())
        .collect();
    let finite = |v: &f64| v.is_finite();
    let xr = range(
        curves
            .iter()
            .flat_map(|(_, p)| p.iter().map(|q| q.0))
            .filter(finite),
    )
    .ok_or(PlotError::NoData)?;
    let yr = range(
        curves
            .iter()
            .flat_map(|(_, p)| p.iter().map(|q| q.1))
            .filter(finite),
    )
    .ok_or(PlotError::NoData)?;
    super::atomic::with_temp_file(path, |tmp| {
        let root = BitMapBackend::new(tmp, CHART_SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        draw(&root, chart, &curves, xr, yr)?;
        root.present().map_err(draw_err)
    })
}

/// Most points drawn per curve: beyond this, curves are thinned (a 900-pixel-wide chart cannot
/// show more, and drawing 10⁶ markers per profile made the write phase cost more than the solve).
pub const MAX_POINTS: usize = 2400;

/// Every k-th marker, so that at most [`MAX_POINTS`] remain (first and last kept).
fn thin_markers(p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if p.len() <= MAX_POINTS {
        return p;
    }
    let k = p.len().div_ceil(MAX_POINTS);
    let last = *p.last().unwrap_or(&(0.0, 0.0));
    let mut out: Vec<_> = p.into_iter().step_by(k).collect();
    if out.last() != Some(&last) {
        out.push(last);
    }
    out
}

/// A line thinned to about [`MAX_POINTS`] points keeping, in each run of consecutive points,
/// the lowest and highest value in their order (peaks survive thinning).
fn thin_line(p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if p.len() <= MAX_POINTS {
        return p;
    }
    let k = (2 * p.len()).div_ceil(MAX_POINTS);
    let mut out = Vec::with_capacity(MAX_POINTS + 2);
    for chunk in p.chunks(k) {
        let lo = chunk
            .iter()
            .enumerate()
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let hi = chunk
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        if let (Some((i, a)), Some((j, b))) = (lo, hi) {
            if i == j {
                out.push(*a);
            } else if i < j {
                out.extend([*a, *b]);
            } else {
                out.extend([*b, *a]);
            }
        }
    }
    out
}

fn draw(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    chart: &Chart,
    curves: &[(Curve, Vec<(f64, f64)>)],
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), PlotError> {
    let mut ctx = ChartBuilder::on(root)
        .caption(&chart.title, (FONT, 22))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(84)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(draw_err)?;
    let (xstep, ystep) = ((xr.1 - xr.0) / 10.0, (yr.1 - yr.0) / 10.0);
    let (xa, ya) = (chart.x_axis, chart.y_axis);
    let xfmt = move |v: &f64| tick_label(xa, *v, xstep);
    let yfmt = move |v: &f64| tick_label(ya, *v, ystep);
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 18))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(draw_err)?;
    let mut labelled = false;
    for (curve, points) in curves {
        let c = color(curve.color);
        let style = ShapeStyle::from(&c).stroke_width(2);
        let all: &[(f64, f64)] = points;
        let pieces: Vec<&[(f64, f64)]> = all.split(|q| q.0.is_nan()).collect();
        let (last, first) = pieces.split_last().unwrap_or((&all, &[]));
        let reference = ShapeStyle::from(&darken(c)).stroke_width(1);
        for piece in first {
            match curve.style {
                Style::Line => ctx.draw_series(LineSeries::new(piece.iter().copied(), style)),
                Style::Dashed => {
                    ctx.draw_series(DashedLineSeries::new(piece.iter().copied(), 8, 5, style))
                }
                _ => ctx.draw_series(DashedLineSeries::new(
                    piece.iter().copied(),
                    6,
                    4,
                    reference,
                )),
            }
            .map_err(draw_err)?;
        }
        let anno = match curve.style {
            Style::Line => ctx
                .draw_series(LineSeries::new(last.iter().copied(), style))
                .map_err(draw_err)?,
            Style::Dashed => ctx
                .draw_series(DashedLineSeries::new(last.iter().copied(), 8, 5, style))
                .map_err(draw_err)?,
            Style::Reference => ctx
                .draw_series(DashedLineSeries::new(last.iter().copied(), 6, 4, reference))
                .map_err(draw_err)?,
            Style::Markers => {
                let mstyle = ShapeStyle::from(&c).stroke_width(1);
                match curve.color % 3 {
                    0 => ctx
                        .draw_series(points.iter().map(|&p| Circle::new(p, 3, mstyle)))
                        .map_err(draw_err)?,
                    1 => ctx
                        .draw_series(points.iter().map(|&p| TriangleMarker::new(p, 4, mstyle)))
                        .map_err(draw_err)?,
                    _ => ctx
                        .draw_series(points.iter().map(|&p| Cross::new(p, 3, mstyle)))
                        .map_err(draw_err)?,
                }
            }
        };
        if !curve.label.is_empty() {
            labelled = true;
            let kind = curve.style;
            let shape = curve.color % 3;
            anno.label(curve.label.as_str()).legend(
                move |(x, y)| -> DynElement<'static, BitMapBackend<'_>, (i32, i32)> {
                    match kind {
                        Style::Markers => match shape {
                            0 => Circle::new((x + 10, y), 3, ShapeStyle::from(&c)).into_dyn(),
                            1 => {
                                TriangleMarker::new((x + 10, y), 4, ShapeStyle::from(&c)).into_dyn()
                            }
                            _ => Cross::new((x + 10, y), 3, ShapeStyle::from(&c)).into_dyn(),
                        },
                        Style::Reference => PathElement::new(
                            vec![(x, y), (x + 20, y)],
                            ShapeStyle::from(&REFERENCE_COLOR).stroke_width(1),
                        )
                        .into_dyn(),
                        _ => PathElement::new(
                            vec![(x, y), (x + 20, y)],
                            ShapeStyle::from(&c).stroke_width(2),
                        )
                        .into_dyn(),
                    }
                },
            );
        }
    }
    if labelled {
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .label_font((FONT, 13))
            .position(legend_corner(curves, xr, yr))
            .draw()
            .map_err(draw_err)?;
    }
    Ok(())
}

/// The corner whose legend box (about 40 % × 40 % of the plot) covers the fewest points.
fn legend_corner(
    curves: &[(Curve, Vec<(f64, f64)>)],
    xr: (f64, f64),
    yr: (f64, f64),
) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let map = |v: f64, r: (f64, f64)| (v - r.0) / (r.1 - r.0);
    let count = |right: bool, upper: bool| {
        curves
            .iter()
            .flat_map(|(_, p)| p.iter())
            .filter(|&&(px, py)| {
                let (u, v) = (map(px, xr), map(py, yr));
                (if right { u > 0.55 } else { u < 0.45 })
                    && (if upper { v > 0.55 } else { v < 0.45 })
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|&(_, r, u)| count(r, u))
        .map(|c| c.0)
        .unwrap_or(SeriesLabelPosition::UpperRight)
}

/// Viridis-like colour map on `[0, 1]`.
///
/// ```
/// use celltissue::output::plot::colormap;
/// let (lo, hi) = (colormap(0.0), colormap(1.0));
/// assert!(lo.2 > lo.1 && hi.1 > hi.2); // dark blue-violet to yellow
/// assert_eq!(colormap(-1.0), lo); // clamped
/// ```
pub fn colormap(u: f64) -> RGBColor {
    const A: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let u = if u.is_finite() {
        u.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = u * (A.len() - 1) as f64;
    let i = (s.floor() as usize).min(A.len() - 2);
    let f = s - i as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(
        mix(A[i].0, A[i + 1].0),
        mix(A[i].1, A[i + 1].1),
        mix(A[i].2, A[i + 1].2),
    )
}

/// Size of rectangle images in pixels.
pub const RECT_SIZE: (u32, u32) = (1200, 520);

/// Draws axis-aligned rectangles `(x0, y0, x1, y1, value)` filled by a colour map of `value`,
/// with a colour bar labelled `colorbar_label`. Used for cell snapshots (line ring Fig 2.10e,
/// sheet Figs 4.3a/4.4a). Non-finite rectangles are skipped.
///
/// ```
/// use celltissue::output::plot::plot_rectangles;
/// let cells = [(0.0, 0.0, 1.0, 1.0, 1.0), (1.0, 0.0, 2.1, 0.9, 1.2)];
/// let path = std::env::temp_dir().join("celltissue_doc_rectangles.png");
/// plot_rectangles(&path, "two cells", &cells, "pressure p").unwrap();
/// assert_eq!(&std::fs::read(&path).unwrap()[1..4], b"PNG");
/// ```
pub fn plot_rectangles(
    path: &Path,
    title: &str,
    rects: &[(f64, f64, f64, f64, f64)],
    colorbar_label: &str,
) -> Result<(), PlotError> {
    super::fonts::register();
    let rects: Vec<_> = rects
        .iter()
        .copied()
        .filter(|r| [r.0, r.1, r.2, r.3, r.4].iter().all(|v| v.is_finite()))
        .collect();
    let xr = range(rects.iter().flat_map(|r| [r.0, r.2])).ok_or(PlotError::NoData)?;
    let yr = range(rects.iter().flat_map(|r| [r.1, r.3])).ok_or(PlotError::NoData)?;
    let (mut vlo, mut vhi) = rects
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r.4), b.max(r.4))
        });
    if vhi <= vlo {
        let pad = 0.05 * vlo.abs().max(1e-9);
        vlo -= pad;
        vhi += pad;
    }
    super::atomic::with_temp_file(path, |tmp| {
        let root = BitMapBackend::new(tmp, RECT_SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let (main, bar) = root.split_horizontally(RECT_SIZE.0 - 130);
        let mut ctx = ChartBuilder::on(&main)
            .caption(title, (FONT, 22))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(draw_err)?;
        ctx.configure_mesh()
            .disable_mesh()
            .x_desc("x")
            .y_desc("y")
            .label_style((FONT, 15))
            .draw()
            .map_err(draw_err)?;
        ctx.draw_series(rects.iter().map(|r| {
            let c = colormap((r.4 - vlo) / (vhi - vlo));
            Rectangle::new([(r.0, r.1), (r.2, r.3)], c.filled())
        }))
        .map_err(draw_err)?;
        ctx.draw_series(rects.iter().map(|r| {
            Rectangle::new(
                [(r.0, r.1), (r.2, r.3)],
                RGBColor(40, 40, 40).mix(0.35).stroke_width(1),
            )
        }))
        .map_err(draw_err)?;
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(50)
            .margin_bottom(56)
            .margin_right(8)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..1.0, vlo..vhi)
            .map_err(draw_err)?;
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(colorbar_label)
            .label_style((FONT, 14))
            .draw()
            .map_err(draw_err)?;
        let steps = 200;
        cb.draw_series((0..steps).map(|k| {
            let a = vlo + (vhi - vlo) * k as f64 / steps as f64;
            let b = vlo + (vhi - vlo) * (k + 1) as f64 / steps as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                colormap(k as f64 / (steps - 1) as f64).filled(),
            )
        }))
        .map_err(draw_err)?;
        root.present().map_err(draw_err)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_padded_and_never_empty() {
        let (a, b) = range([1.0, 1.0].into_iter()).unwrap();
        assert!(a < 1.0 && b > 1.0);
        let (a, b) = range([-3.0, 3.0].into_iter()).unwrap();
        assert!(a < -3.0 && b > 3.0);
        let (a, b) = range([-f64::MAX, f64::MAX].into_iter()).unwrap();
        assert!(a.is_finite() && b.is_finite() && a < b);
        let (a, b) = range([1.0, 1.0 + f64::EPSILON].into_iter()).unwrap();
        assert!(a < 1.0 && b > 1.0 + f64::EPSILON && b - a >= 1e-12);
        assert!(range(std::iter::empty()).is_none());
    }

    #[test]
    fn tick_labels_resolve_their_spacing() {
        // ticks 1e-10 apart around 1 are distinguishable
        assert_eq!(tick_label(Axis::Linear, 1.0 + 2e-9, 1e-10), "1.000000002");
        assert_eq!(tick_label(Axis::Linear, 0.5, 0.1), "0.5");
        // a tick at 0 reached by adding steps is labelled 0, not -6e-17
        assert_eq!(tick_label(Axis::Linear, -5.551115123125783e-17, 0.17), "0");
        assert_eq!(tick_label(Axis::Linear, 1e-12, 1e-11), "1e-12");
        assert_eq!(tick_label(Axis::Linear, 2.0e7, 1e6), "2.0e7");
        assert_eq!(tick_label(Axis::Log, -300.0, 30.0), "1e-300");
        assert_eq!(tick_label(Axis::Log, 2.0, 0.3), "100");
        assert_eq!(tick_label(Axis::Log, 0.0, 0.3), "1");
    }

    #[test]
    fn thinning_keeps_extremes_and_bounds_the_count() {
        let p: Vec<(f64, f64)> = (0..1_000_000)
            .map(|i| (i as f64, if i == 777_777 { 50.0 } else { (i % 7) as f64 }))
            .collect();
        let last = *p.last().unwrap();
        let t = thin_line(p.clone());
        assert!(t.len() <= MAX_POINTS + 2);
        // a one-point spike survives
        assert!(t.contains(&(777_777.0, 50.0)));
        assert!(t.iter().any(|q| q.1 == 0.0));
        let m = thin_markers(p);
        assert!(m.len() <= MAX_POINTS + 1);
        assert_eq!(m.last(), Some(&last));
    }

    #[test]
    fn colormap_ends() {
        assert_eq!(colormap(0.0), RGBColor(68, 1, 84));
        assert_eq!(colormap(1.0), RGBColor(253, 231, 37));
        assert_eq!(colormap(f64::NAN), RGBColor(68, 1, 84));
    }
}
