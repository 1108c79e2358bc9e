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

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Why a plot was not written.
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

fn draw_err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Axis scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Axis {
    /// Linear.
    #[default]
    Linear,
    /// Logarithmic: points with non-positive coordinates are dropped.
    Log,
}

/// How a curve is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Solid line (continuum runs).
    Line,
    /// Dashed line in the curve's colour (guide lines such as `x = (l/l₀)X`).
    Dashed,
    /// Dashed near-black line drawn over the runs (analytic reference solutions, which would
    /// vanish under a continuum line of the same colour).
    Reference,
    /// Symbols only (discrete runs); the shape cycles with the colour index.
    Markers,
}

/// One curve.
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

/// A chart: title, axis labels and scales, curves.
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

/// Colour of [`Style::Reference`] curves.
pub const REFERENCE_COLOR: RGBColor = RGBColor(25, 25, 25);

/// Size of chart images in pixels.
pub const CHART_SIZE: (u32, u32) = (900, 620);

fn keep(axis: Axis, v: f64) -> bool {
    v.is_finite() && (axis == Axis::Linear || v > 0.0)
}

/// The data range along one axis, padded so that it is never empty.
fn range(values: impl Iterator<Item = f64>, axis: Axis) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    Some(match axis {
        Axis::Linear => {
            let pad = if hi > lo {
                0.04 * (hi - lo)
            } else {
                0.05 * lo.abs().max(1e-9)
            };
            (lo - pad, hi + pad)
        }
        Axis::Log => {
            if hi > lo {
                let f = (hi / lo).powf(0.03);
                (lo / f, hi * f)
            } else {
                (lo / 1.2, hi * 1.2)
            }
        }
    })
}

/// Writes `chart` as a PNG at `path`.
pub fn plot_chart(path: &Path, chart: &Chart) -> Result<(), PlotError> {
    let pts = |c: &Curve| -> Vec<(f64, f64)> {
        c.points
            .iter()
            .copied()
            .filter(|&(x, y)| keep(chart.x_axis, x) && keep(chart.y_axis, y))
            .collect()
    };
    let curves: Vec<(Curve, Vec<(f64, f64)>)> = chart
        .curves
        .iter()
        .map(|c| (c.clone(), pts(c)))
        .filter(|(_, p)| !p.is_empty())
        .collect();
    let xr = range(
        curves.iter().flat_map(|(_, p)| p.iter().map(|q| q.0)),
        chart.x_axis,
    )
    .ok_or(PlotError::NoData)?;
    let yr = range(
        curves.iter().flat_map(|(_, p)| p.iter().map(|q| q.1)),
        chart.y_axis,
    )
    .ok_or(PlotError::NoData)?;
    let root = BitMapBackend::new(path, CHART_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(draw_err)?;
    let norm = (Norm::new(xr, chart.x_axis), Norm::new(yr, chart.y_axis));
    match (chart.x_axis, chart.y_axis) {
        (Axis::Linear, Axis::Linear) => draw(&root, chart, &curves, xr.0..xr.1, yr.0..yr.1, norm),
        (Axis::Log, Axis::Linear) => draw(
            &root,
            chart,
            &curves,
            (xr.0..xr.1).log_scale(),
            yr.0..yr.1,
            norm,
        ),
        (Axis::Linear, Axis::Log) => draw(
            &root,
            chart,
            &curves,
            xr.0..xr.1,
            (yr.0..yr.1).log_scale(),
            norm,
        ),
        (Axis::Log, Axis::Log) => draw(
            &root,
            chart,
            &curves,
            (xr.0..xr.1).log_scale(),
            (yr.0..yr.1).log_scale(),
            norm,
        ),
    }?;
    root.present().map_err(draw_err)
}

fn draw<'b, X, Y>(
    root: &DrawingArea<BitMapBackend<'b>, Shift>,
    chart: &Chart,
    curves: &[(Curve, Vec<(f64, f64)>)],
    xr: X,
    yr: Y,
    norm: (Norm, Norm),
) -> Result<(), PlotError>
where
    X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
    Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    let mut ctx = ChartBuilder::on(root)
        .caption(&chart.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(xr, yr)
        .map_err(draw_err)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 18))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(draw_err)?;
    let (xr_norm, yr_norm) = norm;
    let mut labelled = false;
    for (curve, points) in curves {
        let c = color(curve.color);
        let style = ShapeStyle::from(&c).stroke_width(2);
        let anno = match curve.style {
            Style::Line => ctx
                .draw_series(LineSeries::new(points.iter().copied(), style))
                .map_err(draw_err)?,
            Style::Dashed => ctx
                .draw_series(DashedLineSeries::new(points.iter().copied(), 8, 5, style))
                .map_err(draw_err)?,
            Style::Reference => ctx
                .draw_series(DashedLineSeries::new(
                    points.iter().copied(),
                    6,
                    4,
                    ShapeStyle::from(&REFERENCE_COLOR).stroke_width(1),
                ))
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
                move |(x, y)| -> DynElement<'static, BitMapBackend<'b>, (i32, i32)> {
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
            .label_font(("sans-serif", 13))
            .position(legend_corner(curves, &xr_norm, &yr_norm))
            .draw()
            .map_err(draw_err)?;
    }
    Ok(())
}

/// Maps a data coordinate to `[0, 1]` across the plotted range.
#[derive(Clone, Copy, Debug)]
struct Norm {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Norm {
    fn new(r: (f64, f64), axis: Axis) -> Self {
        let log = axis == Axis::Log;
        let f = |v: f64| if log { v.ln() } else { v };
        Self {
            lo: f(r.0),
            hi: f(r.1),
            log,
        }
    }
    fn map(&self, v: f64) -> f64 {
        let v = if self.log { v.ln() } else { v };
        (v - self.lo) / (self.hi - self.lo)
    }
}

/// The corner whose legend box (about 40 % × 40 % of the plot) covers the fewest points.
fn legend_corner(curves: &[(Curve, Vec<(f64, f64)>)], x: &Norm, y: &Norm) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        curves
            .iter()
            .flat_map(|(_, p)| p.iter())
            .filter(|&&(px, py)| {
                let (u, v) = (x.map(px), y.map(py));
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
pub fn plot_rectangles(
    path: &Path,
    title: &str,
    rects: &[(f64, f64, f64, f64, f64)],
    colorbar_label: &str,
) -> Result<(), PlotError> {
    let rects: Vec<_> = rects
        .iter()
        .copied()
        .filter(|r| [r.0, r.1, r.2, r.3, r.4].iter().all(|v| v.is_finite()))
        .collect();
    let xr = range(rects.iter().flat_map(|r| [r.0, r.2]), Axis::Linear).ok_or(PlotError::NoData)?;
    let yr = range(rects.iter().flat_map(|r| [r.1, r.3]), Axis::Linear).ok_or(PlotError::NoData)?;
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
    let root = BitMapBackend::new(path, RECT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(draw_err)?;
    let (main, bar) = root.split_horizontally(RECT_SIZE.0 - 130);
    let mut ctx = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(draw_err)?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc("x")
        .y_desc("y")
        .label_style(("sans-serif", 15))
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
        .label_style(("sans-serif", 14))
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_padded_and_never_empty() {
        let (a, b) = range([1.0, 1.0].into_iter(), Axis::Linear).unwrap();
        assert!(a < 1.0 && b > 1.0);
        let (a, b) = range([1e-3, 1e3].into_iter(), Axis::Log).unwrap();
        assert!(a < 1e-3 && b > 1e3 && a > 0.0);
        assert!(range(std::iter::empty(), Axis::Linear).is_none());
    }

    #[test]
    fn colormap_ends() {
        assert_eq!(colormap(0.0), RGBColor(68, 1, 84));
        assert_eq!(colormap(1.0), RGBColor(253, 231, 37));
        assert_eq!(colormap(f64::NAN), RGBColor(68, 1, 84));
    }
}
