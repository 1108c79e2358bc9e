//! The sheet as coloured rectangles (Figs 4.3a, 4.4a): the geometry as data
//! ([`sheet_rects`]) for any plotting layer, and a self-contained PNG writer
//! ([`write_sheet_png`], plotters) colouring each cell `[x_b(j−1,k), x_b(j,k)] ×
//! [y_b(j,k−1), y_b(j,k)]` by its pressure, with a colour bar.

use super::uniaxial::SheetCell;
use plotters::prelude::*;
use std::path::Path;

/// One cell rectangle and its value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// `[x_min, x_max]`.
    pub x: [f64; 2],
    /// `[y_min, y_max]`.
    pub y: [f64; 2],
    /// The plotted value (e.g. pressure).
    pub value: f64,
}

/// The cells as rectangles carrying the chosen per-cell value.
///
/// ```
/// use celltissue::sheet::{plot::sheet_rects, uniaxial::SheetCell};
/// let c = SheetCell { x: [0.0, 1.0], y: [0.0, 2.0], pressure: 1.5, ..Default::default() };
/// let r = sheet_rects(&[c], |c| c.pressure);
/// assert_eq!(r[0].value, 1.5);
/// ```
pub fn sheet_rects(cells: &[SheetCell], value: impl Fn(&SheetCell) -> f64) -> Vec<Rect> {
    cells
        .iter()
        .map(|c| Rect {
            x: c.x,
            y: c.y,
            value: value(c),
        })
        .collect()
}

/// A PNG could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);

impl From<std::io::Error> for PlotError {
    fn from(x: std::io::Error) -> Self {
        PlotError(x.to_string())
    }
}

fn e<T: std::fmt::Debug>(x: T) -> PlotError {
    PlotError(format!("{x:?}"))
}

/// Viridis-like colour map on `[0, 1]`.
fn colour(s: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let i = STOPS.iter().position(|(p, _)| *p >= s).unwrap_or(4).max(1);
    let (p0, c0) = STOPS[i - 1];
    let (p1, c1) = STOPS[i];
    let w = (s - p0) / (p1 - p0);
    let c = |k: usize| (c0[k] + w * (c1[k] - c0[k])).round() as u8;
    RGBColor(c(0), c(1), c(2))
}

/// Writes the sheet coloured by pressure to a PNG. `range` fixes the colour scale (default:
/// the snapshot's min/max).
pub fn write_sheet_png(
    path: &Path,
    cells: &[SheetCell],
    title: &str,
    range: Option<(f64, f64)>,
) -> Result<(), PlotError> {
    let rects = sheet_rects(cells, |c| c.pressure);
    write_rects_png(path, &rects, title, "pressure", range)
}

/// Writes any coloured rectangles to a PNG with a colour bar labelled `label`.
pub fn write_rects_png(
    path: &Path,
    rects: &[Rect],
    title: &str,
    label: &str,
    range: Option<(f64, f64)>,
) -> Result<(), PlotError> {
    if rects.is_empty() {
        return Err(PlotError("no cells".into()));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    let (mut v0, mut v1) = (f64::MAX, f64::MIN);
    for r in rects {
        x0 = x0.min(r.x[0]);
        x1 = x1.max(r.x[1]);
        y0 = y0.min(r.y[0]);
        y1 = y1.max(r.y[1]);
        if r.value.is_finite() {
            v0 = v0.min(r.value);
            v1 = v1.max(r.value);
        }
    }
    let (v0, v1) = range.unwrap_or((v0, v1));
    let span = if v1 > v0 { v1 - v0 } else { 1.0 };
    let pad = 0.03 * (x1 - x0).max(y1 - y0);
    crate::output::fonts::register();
    crate::output::atomic::with_temp_file(path, |tmp| {
        let root = BitMapBackend::new(tmp, (900, 760)).into_drawing_area();
        root.fill(&WHITE).map_err(e)?;
        let (main, bar) = root.split_horizontally(780);
        let mut chart = ChartBuilder::on(&main)
            .caption(title, (crate::output::fonts::FONT, 24))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d((x0 - pad)..(x1 + pad), (y0 - pad)..(y1 + pad))
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x")
            .y_desc("y")
            .draw()
            .map_err(e)?;
        // cell borders only when they are resolvable
        let border = rects.len() <= 10_000;
        chart
            .draw_series(rects.iter().map(|r| {
                Rectangle::new(
                    [(r.x[0], r.y[0]), (r.x[1], r.y[1])],
                    colour((r.value - v0) / span).filled(),
                )
            }))
            .map_err(e)?;
        if border {
            chart
                .draw_series(rects.iter().map(|r| {
                    Rectangle::new([(r.x[0], r.y[0]), (r.x[1], r.y[1])], BLACK.stroke_width(1))
                }))
                .map_err(e)?;
        }
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(60)
            .margin_bottom(52)
            .margin_right(8)
            .y_label_area_size(70)
            .caption(label, (crate::output::fonts::FONT, 16))
            .build_cartesian_2d(0.0..1.0, v0..(v0 + span))
            .map_err(e)?;
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_labels(6)
            .draw()
            .map_err(e)?;
        let nb = 100;
        cb.draw_series((0..nb).map(|i| {
            let a = v0 + span * i as f64 / nb as f64;
            let b = v0 + span * (i + 1) as f64 / nb as f64;
            Rectangle::new([(0.0, a), (1.0, b)], colour((a - v0) / span).filled())
        }))
        .map_err(e)?;
        root.present().map_err(e)
    })
}
