//! Ensemble statistics of a scenario whose sweep has an `ensemble` (seeded realisations of a
//! stochastic model, `[sweep] ensemble = { realisations = 32 }`): the runs that differ only in
//! the seed form a group (one per model and per value of the other swept parameters), and each
//! group gets
//!
//! * `ensemble_<group>.csv` — at every series time, every series column's mean and 5, 25, 50,
//!   75 and 95 % quantiles over the realisations (`length_mean`, `length_p05`, …, `cells_p95`;
//!   quantiles interpolated linearly between order statistics, numpy's default), and the number
//!   of realisations used (`realisations`; a failed run is left out);
//! * `ensemble_divisions_<group>.csv` — the division locations `x_d/l` pooled over the
//!   realisations in 20 bins of [0, 1]: divisions per realisation in each bin, their mean and
//!   5–95 % quantiles, and the bin's fraction of all divisions;
//! * `ensemble_ages_<group>.csv` — the same for the dividing cells' ages (cycle times), in 20
//!   bins from the least to the largest age over the realisations (not for the density
//!   continuum, whose divisions have no age);
//! * with plots, `ensemble_length.png` and `ensemble_cells.png` — every group's mean with its
//!   5–95 % band — and `ensemble_divisions.png` and `ensemble_ages.png`, divisions per
//!   realisation against `x_d/l` and against age (mean and 5–95 % band).
//!
//! Each realisation is a deterministic function of its seed, and the statistics of the
//! realisations in seed order, so the files do not depend on `--jobs` or on sharding.

use super::files::{series_columns, slug};
use super::number::push_f64;
use super::OutputError;
use crate::observe::{RunRecord, Summary};
use crate::scenario::Scenario;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The quantiles written beside the mean, and their column suffixes.
pub const QUANTILES: [(f64, &str); 5] = [
    (0.05, "p05"),
    (0.25, "p25"),
    (0.5, "median"),
    (0.75, "p75"),
    (0.95, "p95"),
];

/// Bins of the ensemble histograms over a division quantity: the locations on [0, 1], the ages
/// from the least to the largest.
pub const LOCATION_BINS: usize = 20;

/// The realisations of one parameter set and model.
pub(crate) struct Group<'a> {
    /// `"discrete"`, or `"discrete K=0.01"` with other swept parameters.
    pub label: String,
    /// The realisations, in seed order.
    pub runs: Vec<&'a RunRecord>,
}

/// The scenario's ensemble groups (none without an ensemble).
pub(crate) fn groups<'a>(scenario: &Scenario, summary: &'a Summary) -> Vec<Group<'a>> {
    let Some(seed_key) = scenario.sweep.as_ref().and_then(|s| s.ensemble.as_deref()) else {
        return Vec::new();
    };
    let mut out: Vec<Group<'a>> = Vec::new();
    for (rec, spec) in summary.runs.iter().zip(&scenario.runs) {
        let others: Vec<String> = spec
            .sweep
            .iter()
            .flat_map(|p| &p.parts)
            .filter(|part| part.key != seed_key)
            .map(|part| format!("{}={}", part.name, part.label))
            .collect();
        let mut label = crate::scenario::load::model_name(rec.model).to_string();
        for o in others {
            label.push(' ');
            label.push_str(&o);
        }
        match out.iter_mut().find(|g| g.label == label) {
            Some(g) => g.runs.push(rec),
            None => out.push(Group {
                label,
                runs: vec![rec],
            }),
        }
    }
    out
}

/// The `q`-quantile of sorted values, interpolated linearly between order statistics
/// (numpy's default); `NaN` for no values.
///
/// ```
/// use celltissue::output::ensemble::quantile;
/// assert_eq!(quantile(&[1.0, 2.0, 3.0, 4.0], 0.25), 1.75);
/// assert_eq!(quantile(&[1.0, 2.0, 3.0, 4.0], 0.5), 2.5);
/// assert_eq!(quantile(&[7.0], 0.95), 7.0);
/// ```
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n => {
            let pos = q * (n - 1) as f64;
            let (lo, frac) = (pos.floor() as usize, pos - pos.floor());
            match sorted.get(lo + 1) {
                Some(hi) if frac > 0.0 => sorted[lo] + frac * (hi - sorted[lo]),
                _ => sorted[lo],
            }
        }
    }
}

/// Mean and [`QUANTILES`] of `values` (finite values only).
fn describe(values: &mut [f64]) -> [f64; 6] {
    values.sort_by(f64::total_cmp);
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut out = [mean; 6];
    for (o, (q, _)) in out[1..].iter_mut().zip(QUANTILES) {
        *o = quantile(values, q);
    }
    out
}

/// The realisations a group's statistics use: those without an error whose series times are
/// the first such run's.
fn usable<'a>(g: &Group<'a>) -> Vec<&'a RunRecord> {
    let ok: Vec<&RunRecord> = g
        .runs
        .iter()
        .copied()
        .filter(|r| r.error.is_none())
        .collect();
    match ok.first() {
        None => Vec::new(),
        Some(first) => ok
            .iter()
            .copied()
            .filter(|r| r.series.t == first.series.t)
            .collect(),
    }
}

/// A group's series statistics as CSV (see the module docs).
pub(crate) fn statistics_csv(g: &Group<'_>) -> String {
    let runs = usable(g);
    let Some(first) = runs.first() else {
        return "t,realisations\n".into();
    };
    let names: Vec<String> = series_columns(first)
        .into_iter()
        .map(|(k, _)| k)
        .filter(|k| k != "t")
        .collect();
    let mut out = String::from("t,realisations");
    for name in &names {
        let _ = write!(out, ",{name}_mean");
        for (_, suffix) in QUANTILES {
            let _ = write!(out, ",{name}_{suffix}");
        }
    }
    out.push('\n');
    let columns: Vec<Vec<(String, &Vec<f64>)>> = runs.iter().map(|r| series_columns(r)).collect();
    for (i, t) in first.series.t.iter().enumerate() {
        push_f64(&mut out, *t);
        let _ = write!(out, ",{}", runs.len());
        for name in &names {
            let mut v: Vec<f64> = columns
                .iter()
                .filter_map(|cols| cols.iter().find(|(k, _)| k == name))
                .filter_map(|(_, col)| col.get(i).copied())
                .filter(|x| x.is_finite())
                .collect();
            if v.is_empty() {
                out.push_str(",,,,,,");
                continue;
            }
            for x in describe(&mut v) {
                out.push(',');
                push_f64(&mut out, x);
            }
        }
        out.push('\n');
    }
    out
}

/// A division quantity binned over the realisations: where cells divide (`x_d/l` on [0, 1])
/// and how old they are (their ages on the pooled range).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Binned {
    /// `x_d/l` in [`LOCATION_BINS`] bins of [0, 1].
    Location,
    /// The dividing cells' ages in [`LOCATION_BINS`] bins from the least to the largest age
    /// over all realisations (only where every division has one).
    Age,
}

impl Binned {
    fn value(self, d: &crate::observe::DivisionRecord) -> Option<f64> {
        match self {
            Binned::Location => Some(d.x_over_length.clamp(0.0, 1.0)),
            Binned::Age => d.age,
        }
    }
}

/// A group's histogram of `what` as CSV (see the module docs); `None` when no realisation
/// divided (or, for ages, when a division has none).
pub(crate) fn divisions_csv(g: &Group<'_>, what: Binned) -> Option<String> {
    let hist = histogram(g, what)?;
    let total: f64 = hist.iter().map(|(_, _, d)| d[0]).sum();
    let mut out = String::from("bin_lo,bin_hi,per_realisation_mean");
    for (_, suffix) in QUANTILES {
        let _ = write!(out, ",per_realisation_{suffix}");
    }
    out.push_str(",fraction\n");
    for (lo, hi, d) in &hist {
        push_f64(&mut out, *lo);
        out.push(',');
        push_f64(&mut out, *hi);
        for x in d {
            out.push(',');
            push_f64(&mut out, *x);
        }
        // the mean count over the total of the means is the bin's share of all divisions
        out.push(',');
        push_f64(&mut out, d[0] / total);
        out.push('\n');
    }
    Some(out)
}

/// Divisions per realisation in each bin of `what`: the bin's edges and the mean and
/// [`QUANTILES`] over the realisations; `None` when no realisation divided (or, for ages,
/// when a division has none).
fn histogram(g: &Group<'_>, what: Binned) -> Option<Vec<(f64, f64, [f64; 6])>> {
    let runs = usable(g);
    let values: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| r.divisions.iter().map(|d| what.value(d)).collect())
        .collect::<Option<_>>()?;
    if values.iter().all(Vec::is_empty) {
        return None;
    }
    let (lo, hi) = match what {
        Binned::Location => (0.0, 1.0),
        Binned::Age => values
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &a| {
                (l.min(a), h.max(a))
            }),
    };
    let nb = LOCATION_BINS as f64;
    // every age the same: one bin's width around it
    let width = if hi > lo {
        (hi - lo) / nb
    } else {
        lo.abs().max(1.0) / nb
    };
    let bin = |x: f64| (((x - lo) / width) as usize).min(LOCATION_BINS - 1);
    let counts: Vec<[f64; LOCATION_BINS]> = values
        .iter()
        .map(|v| {
            let mut c = [0.0; LOCATION_BINS];
            for &x in v {
                c[bin(x)] += 1.0;
            }
            c
        })
        .collect();
    let hist = (0..LOCATION_BINS)
        .map(|b| {
            let mut v: Vec<f64> = counts.iter().map(|c| c[b]).collect();
            let edge = |k: usize| lo + k as f64 * width;
            (edge(b), edge(b + 1), describe(&mut v))
        })
        .collect();
    Some(hist)
}

/// Writes every group's statistics (nothing without an ensemble); returns the paths.
pub(crate) fn write_ensemble(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut files = Vec::new();
    let mut put = |name: String, text: &str| -> Result<(), OutputError> {
        let path = dir.join(name);
        super::atomic::write(&path, text.as_bytes()).map_err(|source| OutputError::Write {
            path: path.clone(),
            source,
        })?;
        files.push(path);
        Ok(())
    };
    for g in groups(scenario, summary) {
        let s = slug(&g.label);
        put(format!("ensemble_{s}.csv"), &statistics_csv(&g))?;
        if let Some(text) = divisions_csv(&g, Binned::Location) {
            put(format!("ensemble_divisions_{s}.csv"), &text)?;
        }
        if let Some(text) = divisions_csv(&g, Binned::Age) {
            put(format!("ensemble_ages_{s}.csv"), &text)?;
        }
    }
    Ok(files)
}

/// The ensemble plots: for `length` and `cells`, every group's mean (solid) and its 5–95 %
/// band (dashed), against `t`.
#[cfg(feature = "plots")]
pub(crate) fn ensemble_figures(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Vec<(PathBuf, Result<(), super::plot::PlotError>)> {
    use super::plot::{plot_chart, Axis, Chart, Curve, Style};
    let groups = groups(scenario, summary);
    if groups.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::new();
    let cells_change = super::figures::cells_change(summary);
    for (key, what) in [("length", "length l"), ("cells", "number of cells N")] {
        if key == "cells" && !cells_change {
            continue;
        }
        let mut curves = Vec::new();
        for (gi, g) in groups.iter().enumerate() {
            let runs = usable(g);
            let Some(first) = runs.first() else { continue };
            let series: Vec<&Vec<f64>> = runs
                .iter()
                .filter_map(|r| {
                    series_columns(r)
                        .into_iter()
                        .find(|(k, _)| k == key)
                        .map(|(_, v)| v)
                })
                .collect();
            if series.len() != runs.len() {
                continue;
            }
            let mut mean = Vec::new();
            let (mut lo, mut hi) = (Vec::new(), Vec::new());
            for (i, &t) in first.series.t.iter().enumerate() {
                let mut v: Vec<f64> = series.iter().filter_map(|s| s.get(i).copied()).collect();
                let d = describe(&mut v);
                mean.push((t, d[0]));
                lo.push((t, d[1]));
                hi.push((t, d[5]));
            }
            curves.push(Curve::new(
                format!("{} mean", g.label),
                Style::Line,
                gi,
                mean,
            ));
            curves.push(Curve::new(
                format!("{} 5–95 %", g.label),
                Style::Dashed,
                gi,
                lo,
            ));
            curves.push(Curve::new(String::new(), Style::Dashed, gi, hi));
        }
        if curves.is_empty() {
            continue;
        }
        let chart = Chart {
            title: format!(
                "{}: {what} over {} realisations",
                scenario.name,
                groups.first().map_or(0, |g| g.runs.len())
            ),
            x_label: "t".into(),
            y_label: key.into(),
            x_axis: match scenario.plots.time_axis {
                crate::scenario::Scale::Log => Axis::Log,
                crate::scenario::Scale::Linear => Axis::Linear,
            },
            y_axis: Axis::Linear,
            curves,
        };
        let path = dir.join(format!("ensemble_{key}.png"));
        let result = plot_chart(&path, &chart);
        out.push((path, result));
    }
    // division locations and ages: divisions per realisation in each bin, mean and 5–95 %
    for (what, file, x_label, title) in [
        (
            Binned::Location,
            "ensemble_divisions.png",
            "x_d / l",
            format!(
                "{}: where cells divide (bins of {} of the length)",
                scenario.name,
                1.0 / LOCATION_BINS as f64
            ),
        ),
        (
            Binned::Age,
            "ensemble_ages.png",
            "age at division (cycle time)",
            format!("{}: how old cells are when they divide", scenario.name),
        ),
    ] {
        let mut curves = Vec::new();
        for (gi, g) in groups.iter().enumerate() {
            let Some(h) = histogram(g, what) else {
                continue;
            };
            let at = |k: usize| {
                h.iter()
                    .map(|(lo, hi, d)| (0.5 * (lo + hi), d[k]))
                    .collect::<Vec<_>>()
            };
            curves.push(Curve::new(
                format!("{} mean", g.label),
                Style::Line,
                gi,
                at(0),
            ));
            curves.push(Curve::new(
                format!("{} 5–95 %", g.label),
                Style::Dashed,
                gi,
                at(1),
            ));
            curves.push(Curve::new(String::new(), Style::Dashed, gi, at(5)));
        }
        if curves.is_empty() {
            continue;
        }
        let chart = Chart {
            title,
            x_label: x_label.into(),
            y_label: "divisions per realisation".into(),
            x_axis: Axis::Linear,
            y_axis: Axis::Linear,
            curves,
        };
        let path = dir.join(file);
        let result = plot_chart(&path, &chart);
        out.push((path, result));
    }
    out
}
