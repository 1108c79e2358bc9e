//! Figures of proliferating runs (thesis Fig. 3.3), drawn with the output module's chart
//! helpers; [`crate::output`] calls [`division_figures`] for every scenario and it draws
//! nothing when no run has divisions:
//!
//! * `divisions_scatter.png` — division events `x_d/l` against `t`, one colour per run
//!   (Figs 3.3c–d);
//! * `divisions_age.png` — each dividing cell's age (its cycle time) against where it divided,
//!   `x_d/l`, for the runs that follow individual cells (not the density continuum);
//! * `series_length_loglog.png`, `series_cells_loglog.png` — `l(t)` and `N(t)` on log–log axes
//!   for every run, with and without division (Figs 3.3a–b and insets);
//! * `clones_<label>.png` — for a run that traces lineage (the discrete line and ring), the
//!   number of cells in each initial cell's clone against that cell's index, one curve per
//!   profile time (at most six): where the tissue's cells came from.

use crate::observe::{ModelKind, RunRecord, Summary};
use crate::output::plot::{plot_chart, Axis, Chart, Curve, PlotError, Style};
use std::path::{Path, PathBuf};

fn style(m: ModelKind) -> Style {
    match m {
        ModelKind::Discrete => Style::Markers,
        ModelKind::Continuum => Style::Line,
    }
}

fn series<'a>(rec: &'a RunRecord, key: &str) -> &'a [f64] {
    match key {
        "length" => &rec.series.length,
        k => rec.series.extra.get(k).map_or(&[], |v| v.as_slice()),
    }
}

/// Writes the division figures into `dir` (titles prefixed by `title`); returns each path with
/// its outcome. Empty if no run divided.
pub(crate) fn division_figures(
    dir: &Path,
    title: &str,
    summary: &Summary,
) -> Vec<(PathBuf, Result<(), PlotError>)> {
    let mut out = Vec::new();
    if summary.runs.iter().all(|r| r.divisions.is_empty()) {
        return out;
    }
    let scatter = Chart {
        title: format!("{title}: division events"),
        x_label: "t".into(),
        y_label: "x_d / l(t)".into(),
        x_axis: Axis::Linear,
        y_axis: Axis::Linear,
        curves: summary
            .runs
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.divisions.is_empty())
            .map(|(i, r)| {
                let pts = r.divisions.iter().map(|d| (d.t, d.x_over_length)).collect();
                Curve::new(r.label.clone(), Style::Markers, i, pts)
            })
            .collect(),
    };
    let path = dir.join("divisions_scatter.png");
    out.push((path.clone(), plot_chart(&path, &scatter)));
    let aged: Vec<Curve> = summary
        .runs
        .iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let pts: Option<Vec<(f64, f64)>> = r
                .divisions
                .iter()
                .map(|d| d.age.map(|a| (d.x_over_length, a)))
                .collect();
            let pts = pts.filter(|p| !p.is_empty())?;
            Some(Curve::new(r.label.clone(), Style::Markers, i, pts))
        })
        .collect();
    if !aged.is_empty() {
        let chart = Chart {
            title: format!("{title}: age at division (cycle time)"),
            x_label: "x_d / l(t)".into(),
            y_label: "age at division".into(),
            x_axis: Axis::Linear,
            y_axis: Axis::Log,
            curves: aged,
        };
        let path = dir.join("divisions_age.png");
        out.push((path.clone(), plot_chart(&path, &chart)));
    }
    for r in &summary.runs {
        if let Some(chart) = clone_chart(title, r) {
            let path = dir.join(format!(
                "clones_{}.png",
                crate::output::files::slug(&r.label)
            ));
            out.push((path.clone(), plot_chart(&path, &chart)));
        }
    }
    for (key, ylabel, what) in [("length", "l", "length"), ("cells", "N", "number of cells")] {
        let curves = summary
            .runs
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let pts = r
                    .series
                    .t
                    .iter()
                    .copied()
                    .zip(series(r, key).iter().copied())
                    .filter(|(t, v)| *t > 0.0 && *v > 0.0)
                    .collect();
                Curve::new(r.label.clone(), style(r.model), i, pts)
            })
            .collect();
        let chart = Chart {
            title: format!("{title}: {what} (log-log)"),
            x_label: "t".into(),
            y_label: ylabel.into(),
            x_axis: Axis::Log,
            y_axis: Axis::Log,
            curves,
        };
        let path = dir.join(format!("series_{key}_loglog.png"));
        out.push((path.clone(), plot_chart(&path, &chart)));
    }
    out
}

/// Cells per clone against the initial cell's index (0 at x₀), one curve per profile time (at
/// most six, evenly spread) of a run whose profiles carry `ancestor`; `None` for any other run.
fn clone_chart(title: &str, r: &RunRecord) -> Option<Chart> {
    let n0 = r
        .profiles
        .iter()
        .filter_map(|p| p.extra.get("ancestor"))
        .flatten()
        .fold(None, |m: Option<f64>, &a| Some(m.map_or(a, |m| m.max(a))))? as usize
        + 1;
    // at most six profile times, evenly spread from the first to the last
    let (np, m) = (r.profiles.len(), r.profiles.len().min(6));
    let mut picked: Vec<usize> = if m <= 1 {
        vec![np - 1]
    } else {
        (0..m)
            .map(|k| (k * (np - 1) + (m - 1) / 2) / (m - 1))
            .collect()
    };
    picked.dedup();
    let curves = picked
        .into_iter()
        .map(|i| (i, &r.profiles[i]))
        .filter_map(|(i, p)| {
            let mut count = vec![0.0; n0];
            for &a in p.extra.get("ancestor")? {
                count[a as usize] += 1.0;
            }
            let pts = count
                .into_iter()
                .enumerate()
                .map(|(k, c)| (k as f64, c))
                .collect();
            Some(Curve::new(format!("t = {}", p.t), Style::Markers, i, pts))
        })
        .collect();
    Some(Chart {
        title: format!("{title}: {} — cells per clone", r.label),
        x_label: "initial cell (0 at x₀)".into(),
        y_label: "cells descended from it".into(),
        x_axis: Axis::Linear,
        // every clone holds at least its own cell
        y_axis: Axis::Log,
        curves,
    })
}
