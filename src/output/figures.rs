//! The PNG set of a scenario run, laid out like the thesis's Chapter 2 figures (discrete runs as
//! symbols, continuum runs as lines):
//!
//! * `series_<quantity>.png` — `max p`, `min λ`, `l` (and model-specific series such as
//!   `cells`, `mean_pressure`, `top_displacement`) against `t`, every run (Figs 2.5c–d style
//!   time courses, 2.7c–d, 2.8c–d, 2.9a–b), colour = swept value;
//! * `profiles_pressure[_<value>].png`, `profiles_stretch[_<value>].png` — `p` and `λ` against
//!   `X` (or `x`) at each profile time, one pair per swept value (Figs 2.5a–b, 2.7a–b, 2.8a–b,
//!   2.10a–b), colour = time;
//! * `sweep_pressure.png`, `sweep_stretch.png` — `max p`/`min λ` at each profile time, and the
//!   peaks and troughs over all series times, against the swept value (Figs 2.5c–d, 2.10c–d);
//!   a growing line's stretch is its elastic stretch `α` (Figs 3.1b, 3.1d), and its axes say so
//!   (`StretchName`);
//!   `sweep_length.png` — `l` at each profile time against the swept value (Fig 3.1a inset);
//! * with `plots.sweep_profiles`: `sweep_profiles_pressure_t=<t>.png`,
//!   `sweep_profiles_stretch_t=<t>.png` — every swept value's profile at one time on one plot,
//!   colour = swept value (Fig 3.1b);
//! * with `plots.position`: `profiles_position[_<value>].png` — `x` against `X` with the
//!   uniform-strain line `x = (l/l₀)X` dashed (Fig 2.6), and `profiles_deviation[_<value>].png`
//!   — `x − (l/l₀)X`, which makes a heterogeneous line's departure from it visible;
//! * shear columns: `profiles_displacement[_<value>].png` — the edge positions `x_e` against
//!   their reference heights, base included (Fig 4.6d);
//! * with `plots.histories`: `histories_stretch[_<value>].png` — every cell's `λ` (`tan θ`)
//!   against `t` through the profile times (Fig 4.6c);
//! * with `plots.rectangles`: `cells_<label>.png` — cell rectangles coloured by pressure, one
//!   row per profile time (Fig 2.10e);
//! * sheets: `<label>_pressure_NNNN.png` — the array of cells coloured by pressure at each
//!   profile time (Figs 4.3a, 4.4a).

use super::files::slug;
use super::plot::{plot_chart, plot_rectangles, Axis, Chart, Curve, PlotError, Style};
use crate::observe::{ModelKind, Profile, RunRecord, Summary};
use crate::scenario::{format_number, ModelConfig, ProfileAxis, RunSpec, Scale, Scenario};
use crate::sheet::observe::sheet_cells;
use std::path::{Path, PathBuf};

fn axis(s: Scale) -> Axis {
    match s {
        Scale::Linear => Axis::Linear,
        Scale::Log => Axis::Log,
    }
}

fn style(m: ModelKind) -> Style {
    match m {
        ModelKind::Discrete => Style::Markers,
        ModelKind::Continuum => Style::Line,
    }
}

/// Runs grouped by swept value (one group without a sweep), in scenario order.
struct Group<'a> {
    /// The value's label (`None`: no sweep).
    label: Option<String>,
    runs: Vec<(&'a RunRecord, Option<&'a RunSpec>)>,
}

fn groups<'a>(scenario: &'a Scenario, summary: &'a Summary) -> Vec<Group<'a>> {
    let mut out: Vec<Group<'a>> = Vec::new();
    for (i, rec) in summary.runs.iter().enumerate() {
        let spec = scenario.runs.get(i).filter(|s| s.label == rec.label);
        let label = spec.and_then(|s| s.sweep.as_ref()).map(|p| p.label.clone());
        match out.iter_mut().find(|g| g.label == label) {
            Some(g) => g.runs.push((rec, spec)),
            None => out.push(Group {
                label,
                runs: vec![(rec, spec)],
            }),
        }
    }
    out
}

/// Writes every figure; returns each path with its outcome ([`PlotError::NoData`] = skipped).
pub(crate) fn write_figures(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
) -> Vec<(PathBuf, Result<(), PlotError>)> {
    let mut out = Vec::new();
    let groups = groups(scenario, summary);
    let sweep_name = scenario.sweep.as_ref().map(|s| s.name.clone());
    let title = |what: &str| match &scenario.figure {
        Some(f) => format!("Fig {f} ({}): {what}", scenario.name),
        None => format!("{}: {what}", scenario.name),
    };
    let mut emit = |name: String, r: Result<(), PlotError>| out.push((dir.join(name), r));

    // a shear column stores tan θ in the stretch fields and the top displacement in `length`
    // (docs/model.md §6): its axes are named for those quantities
    let shear = scenario
        .runs
        .iter()
        .any(|r| matches!(r.config, ModelConfig::Shear(..)));
    let stretch = stretch_name(scenario);
    // time courses
    let mut series: Vec<(&str, &str, &str)> = if shear {
        vec![
            ("max_pressure", "max p", "maximum pressure"),
            ("min_stretch", stretch.min_axis, stretch.min_words),
        ]
    } else {
        vec![
            ("max_pressure", "max_x p", "maximum pressure"),
            ("min_stretch", stretch.min_axis, stretch.min_words),
            ("length", "l", "length"),
        ]
    };
    let extras = [
        ("cells", "N", "number of cells"),
        ("mean_pressure", "mean p", "mean pressure"),
        ("mean_height", "mean H", "mean height"),
        ("mean_width", "w (mean top position)", "width"),
        ("mean_stretch_z_over_y", stretch.z_over_y, stretch.z_over_y),
        ("max_stretch_y", stretch.max_y_axis, stretch.max_y_words),
        (
            "boundary_mismatch_mean",
            "mean W_err",
            "shared-boundary mismatch",
        ),
        (
            "top_displacement",
            "x_e,M (top edge position)",
            "top displacement",
        ),
        ("shear_spread", "max tanθ − min tanθ", "shear spread"),
        ("mean_shear_angle", "mean θ", "mean shear angle"),
    ];
    let cells_change = cells_change(summary);
    for e in extras {
        if summary
            .runs
            .iter()
            .any(|r| r.series.extra.contains_key(e.0))
            && (e.0 != "cells" || cells_change)
        {
            series.push(e);
        }
    }
    // a registered mode's own series are drawn under their names
    let mode = scenario
        .runs
        .iter()
        .any(|r| matches!(r.config, ModelConfig::Mode(..)));
    if mode {
        for key in summary.runs.iter().flat_map(|r| r.series.extra.keys()) {
            if !series.iter().any(|s| s.0 == key.as_str()) {
                series.push((key.as_str(), key.as_str(), key.as_str()));
            }
        }
    }
    for (key, ylabel, what) in series {
        let mut curves = Vec::new();
        // one legend entry per meaning: the first reference curve of each kind is labelled,
        // the others share its entry (their colour gives the swept value, as the runs')
        let mut references: Vec<String> = Vec::new();
        for (gi, g) in groups.iter().enumerate() {
            for (rec, _) in &g.runs {
                let y = series_values(rec, key);
                let pts = rec
                    .series
                    .t
                    .iter()
                    .copied()
                    .zip(y.iter().copied())
                    .collect();
                curves.push(Curve::new(rec.label.clone(), style(rec.model), gi, pts));
            }
            if key == "max_pressure" || key == "min_stretch" {
                if let Some((label, pts)) = series_reference(g, key) {
                    let label = if references.contains(&label) {
                        String::new()
                    } else {
                        references.push(label.clone());
                        label
                    };
                    curves.push(Curve::new(label, Style::Reference, gi, pts));
                }
            }
        }
        let chart = Chart {
            title: title(&format!("{what} against time")),
            x_label: "t".into(),
            y_label: ylabel.into(),
            x_axis: axis(scenario.plots.time_axis),
            y_axis: if key == "cells" && scenario.plots.time_axis == Scale::Log {
                Axis::Log
            } else {
                Axis::Linear
            },
            curves,
        };
        let file = format!("series_{}.png", file_key(shear, key));
        emit(file.clone(), plot_chart(&dir.join(&file), &chart));
    }

    // profiles per swept value
    let (xname, xdesc) = match (shear, scenario.plots.profile_axis) {
        (true, ProfileAxis::Reference) => ("Y", "reference height Y"),
        (true, ProfileAxis::Current) => ("x", "cell centre position x"),
        (false, ProfileAxis::Reference) => ("X", "reference position X"),
        (false, ProfileAxis::Current) => ("x", "current position x"),
    };
    for g in &groups {
        let suffix = match (&g.label, &sweep_name) {
            (Some(l), Some(n)) => format!("_{}", slug(&format!("{n}={l}"))),
            _ => String::new(),
        };
        let at = match (&g.label, &sweep_name) {
            (Some(l), Some(n)) => format!(" ({n} = {l})"),
            _ => String::new(),
        };
        let mut quantities: Vec<(&str, &str, &str)> = if shear {
            vec![
                ("pressure", "p", "pressure"),
                ("stretch", stretch.symbol, stretch.words),
                ("displacement", "x_e (edge position)", "edge displacement"),
            ]
        } else {
            vec![
                ("pressure", "p", "pressure"),
                ("stretch", stretch.symbol, stretch.words),
            ]
        };
        if scenario.plots.position {
            quantities.push(("position", "x", "current position"));
            quantities.push(("deviation", "x − (l/l0)·X", "deviation from uniform strain"));
        }
        for (key, ylabel, what) in quantities {
            let mut curves = Vec::new();
            let times = profile_times(g);
            for (rec, _) in &g.runs {
                for p in &rec.profiles {
                    let ti = times.iter().position(|t| close(*t, p.t)).unwrap_or(0);
                    if key == "displacement" {
                        let Some(pts) = edge_displacement(p) else {
                            continue;
                        };
                        let label = format!("{} t={}", model_word(rec.model), format_number(p.t));
                        curves.push(Curve::new(label, style(rec.model), ti, pts));
                        continue;
                    }
                    let xs = match scenario.plots.profile_axis {
                        ProfileAxis::Reference => &p.x_ref,
                        ProfileAxis::Current => &p.x,
                    };
                    let ys: Vec<f64> = match key {
                        "pressure" => p.pressure.clone(),
                        "stretch" => p.stretch.clone(),
                        "deviation" => match strain_ratio(rec, p.t) {
                            Some(r) => p.x.iter().zip(&p.x_ref).map(|(x, xr)| x - r * xr).collect(),
                            None => continue,
                        },
                        _ => p.x.clone(),
                    };
                    let pts = xs.iter().copied().zip(ys).collect();
                    let label = format!("{} t={}", model_word(rec.model), format_number(p.t));
                    curves.push(Curve::new(label, style(rec.model), ti, pts));
                }
            }
            if key == "position" {
                for (ti, t) in times.iter().enumerate() {
                    if let Some(c) = uniform_line(g, *t) {
                        let label = format!("uniform x=(l/l0)X t={}", format_number(*t));
                        curves.push(Curve::new(label, Style::Dashed, ti, c));
                    }
                }
            }
            let on_reference_axis = scenario.plots.profile_axis == ProfileAxis::Reference;
            if on_reference_axis {
                curves.extend(profile_references(g, key, &times));
            }
            let chart = Chart {
                title: title(&format!("{what} profiles{at}")),
                x_label: match key {
                    "displacement" => "reference height Y of the edge".into(),
                    _ => xdesc.into(),
                },
                y_label: ylabel.into(),
                x_axis: Axis::Linear,
                y_axis: Axis::Linear,
                curves,
            };
            let name = format!("profiles_{}{suffix}.png", file_key(shear, key));
            emit(name.clone(), plot_chart(&dir.join(&name), &chart));
        }
        let _ = xname;
    }

    // extremes against the swept value
    if let Some(name) = &sweep_name {
        let numeric = scenario
            .runs
            .iter()
            .all(|r| r.sweep.as_ref().and_then(|p| p.value).is_some());
        // an ensemble's seed is not a parameter to plot against (see `super::ensemble`)
        let ensemble = scenario
            .sweep
            .as_ref()
            .is_some_and(|s| s.ensemble.is_some());
        if numeric && groups.len() >= 2 && !ensemble && scenario.plots.sweep_axis == Scale::Log {
            // a log axis cannot place them: say so rather than drop runs from the plots silently
            let left_out: Vec<String> = groups
                .iter()
                .filter_map(|g| {
                    let value = g.runs.first()?.1?.sweep.as_ref()?.value?;
                    (value <= 0.0).then(|| format!("{name} = {}", format_number(value)))
                })
                .collect();
            if !left_out.is_empty() {
                log::warn!(
                    "plots.sweep_axis = \"log\": {} not positive, left out of the sweep_*.png plots",
                    left_out.join(", ")
                );
            }
        }
        if numeric && groups.len() >= 2 && !ensemble {
            // a shear column's `length` is its top displacement
            let length = if shear {
                ("top displacement", "x_e,M (top edge position)")
            } else {
                ("length", "l")
            };
            for (key, ylabel) in [
                ("pressure", "p"),
                ("stretch", stretch.symbol),
                ("length", length.1),
            ] {
                let what = if shear && key == "stretch" {
                    stretch.words
                } else {
                    key
                };
                let chart = Chart {
                    title: title(&if key == "length" {
                        format!("{} at the profile times against {name}", length.0)
                    } else {
                        format!("{what} extremes against {name}")
                    }),
                    x_label: name.clone(),
                    y_label: ylabel.into(),
                    x_axis: axis(scenario.plots.sweep_axis),
                    y_axis: Axis::Linear,
                    curves: {
                        let mut c = sweep_curves(scenario, summary, key);
                        if key != "length" {
                            c.extend(sweep_references(&groups, key));
                        }
                        c
                    },
                };
                // a prescribed length is the same for every swept value: no plot
                let varies = chart.curves.iter().any(|c| {
                    let (lo, hi) = c
                        .points
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                            (a.0.min(p.1), a.1.max(p.1))
                        });
                    hi - lo > 1e-9 * hi.abs()
                });
                if key == "length" && !varies {
                    continue;
                }
                let file = format!("sweep_{}.png", file_key(shear, key));
                emit(file.clone(), plot_chart(&dir.join(&file), &chart));
            }
        }
    }

    // every swept value's profile at chosen times on one plot (Fig 3.1b)
    for (file, chart) in sweep_profile_charts(scenario, &groups, xdesc) {
        let chart = Chart {
            title: title(&chart.title),
            ..chart
        };
        emit(file.clone(), plot_chart(&dir.join(&file), &chart));
    }

    // per-cell histories through the profile times (Fig 4.6c)
    if scenario.plots.histories {
        let ylabel = stretch.symbol;
        for (gi, g) in groups.iter().enumerate() {
            let (suffix, at) = match (&g.label, &sweep_name) {
                (Some(l), Some(n)) => (
                    format!("_{}", slug(&format!("{n}={l}"))),
                    format!(" ({n} = {l})"),
                ),
                _ => (String::new(), String::new()),
            };
            let curves = g
                .runs
                .iter()
                .flat_map(|(rec, _)| histories(rec, gi))
                .collect();
            let chart = Chart {
                title: title(&format!("{ylabel} of every cell against time{at}")),
                x_label: "t".into(),
                y_label: ylabel.into(),
                x_axis: axis(scenario.plots.time_axis),
                y_axis: Axis::Linear,
                curves,
            };
            let file = format!("histories_{}{suffix}.png", file_key(shear, "stretch"));
            emit(file.clone(), plot_chart(&dir.join(&file), &chart));
        }
    }

    // sheets: each profile as the array of cells coloured by pressure (Figs 4.3a, 4.4a)
    let slugs = super::files::unique_slugs(summary.runs.iter().map(|r| r.label.as_str()));
    for ((rec, spec), slug) in summary.runs.iter().zip(&scenario.runs).zip(&slugs) {
        if !matches!(spec.config, ModelConfig::Sheet(..)) {
            continue;
        }
        for (k, p) in rec.profiles.iter().enumerate() {
            let rects: Vec<_> = sheet_cells(p)
                .iter()
                .map(|c| (c.x[0], c.y[0], c.x[1], c.y[1], c.pressure))
                .collect();
            let t = format!("{}: pressure, t = {}", rec.label, format_number(p.t));
            let file = format!("{slug}_pressure_{k:04}.png");
            emit(
                file.clone(),
                plot_rectangles(&dir.join(&file), &t, &rects, "pressure p"),
            );
        }
    }
    // cell rectangles: lines and rings only (a sheet's rows would overlap in a line's
    // rectangle plot; sheets are drawn above)
    if scenario.plots.rectangles {
        for (rec, _) in summary.runs.iter().zip(&scenario.runs).filter(|(r, s)| {
            r.model == ModelKind::Discrete
                && matches!(
                    s.config,
                    ModelConfig::Line(_) | ModelConfig::Proliferating(_)
                )
        }) {
            let rects = rectangles(&rec.profiles);
            let times: Vec<String> = rec.profiles.iter().map(|p| format_number(p.t)).collect();
            let t = format!(
                "{}: cells coloured by pressure, t = {} (top to bottom)",
                rec.label,
                times.join(", ")
            );
            let file = format!("cells_{}.png", slug(&rec.label));
            emit(
                file.clone(),
                plot_rectangles(&dir.join(&file), &t, &rects, "pressure p"),
            );
        }
    }
    // division scatter and log-log l(t), N(t) (Fig 3.3; nothing without divisions)
    out.extend(crate::events::plots::division_figures(
        dir,
        &title("proliferation"),
        summary,
    ));
    out
}

/// `sweep_profiles_<quantity>_t=<t>.png` for each time of `plots.sweep_profiles`: pressure
/// and stretch (`tan θ` on a shear column) against the profile axis, one colour per swept
/// value, discrete runs as symbols and continuum runs as lines.
fn sweep_profile_charts(
    scenario: &Scenario,
    groups: &[Group<'_>],
    xdesc: &str,
) -> Vec<(String, Chart)> {
    let name = scenario.sweep.as_ref().map_or("", |s| s.name.as_str());
    let names = stretch_name(scenario);
    let (stretch, shear) = (names.symbol, names == SHEAR);
    let mut out = Vec::new();
    for &t in &scenario.plots.sweep_profiles {
        for (key, ylabel) in [("pressure", "p"), ("stretch", stretch)] {
            let mut curves = Vec::new();
            for (gi, g) in groups.iter().enumerate() {
                for (rec, _) in &g.runs {
                    let Some(p) = rec.profiles.iter().find(|p| close(p.t, t)) else {
                        continue;
                    };
                    let xs = match scenario.plots.profile_axis {
                        ProfileAxis::Reference => &p.x_ref,
                        ProfileAxis::Current => &p.x,
                    };
                    let ys = if key == "pressure" {
                        &p.pressure
                    } else {
                        &p.stretch
                    };
                    let label = format!(
                        "{} {name}={}",
                        model_word(rec.model),
                        g.label.as_deref().unwrap_or("")
                    );
                    let pts = xs.iter().copied().zip(ys.iter().copied()).collect();
                    curves.push(Curve::new(label, style(rec.model), gi, pts));
                }
            }
            let t_text = format_number(t);
            let chart = Chart {
                title: format!("{ylabel} profiles at t = {t_text}, every {name}"),
                x_label: xdesc.into(),
                y_label: ylabel.into(),
                x_axis: Axis::Linear,
                y_axis: Axis::Linear,
                curves,
            };
            let key = file_key(shear, key);
            out.push((slug(&format!("sweep_profiles_{key}_t={t_text}.png")), chart));
        }
    }
    out
}

/// Most per-cell curves one run draws in a histories plot (`plots.histories`).
pub const MAX_HISTORIES: usize = 60;

/// Each cell's stretch through a run's profile times: one curve per cell (every k-th cell when
/// there are more than [`MAX_HISTORIES`]); discrete runs dashed, continuum runs solid (as the
/// thesis draws Fig 4.6c) in colours of their own (`2·group`, `2·group + 1`), the run's label
/// on its first curve only.
fn histories(rec: &RunRecord, group: usize) -> Vec<Curve> {
    let color = 2 * group + usize::from(rec.model == ModelKind::Continuum);
    let cells = rec
        .profiles
        .iter()
        .map(|p| p.stretch.len())
        .min()
        .unwrap_or(0);
    let every = cells.div_ceil(MAX_HISTORIES).max(1);
    let style = match rec.model {
        ModelKind::Discrete => Style::Dashed,
        ModelKind::Continuum => Style::Line,
    };
    (0..cells)
        .step_by(every)
        .map(|j| {
            let pts = rec.profiles.iter().map(|p| (p.t, p.stretch[j])).collect();
            let label = if j == 0 {
                rec.label.clone()
            } else {
                String::new()
            };
            Curve::new(label, style, color, pts)
        })
        .collect()
}

/// A shear profile's edge positions against the edges' reference heights, base `(0, 0)`
/// included (Fig 4.6d): the profile holds each cell's centre height `Y` and its top edge's
/// position `x_edge`, and the edges sit where consecutive cells meet, `Y_top = 2Y − Y_below`.
fn edge_displacement(p: &Profile) -> Option<Vec<(f64, f64)>> {
    let x_edge = p.extra.get("x_edge")?;
    let mut below = 0.0;
    let mut pts = vec![(0.0, 0.0)];
    for (y, x) in p.x_ref.iter().zip(x_edge) {
        let top = 2.0 * y - below;
        pts.push((top, *x));
        below = top;
    }
    Some(pts)
}

fn model_word(m: ModelKind) -> &'static str {
    crate::scenario::load::model_name(m)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs())
}

fn series_values<'a>(rec: &'a RunRecord, key: &str) -> &'a [f64] {
    let s = &rec.series;
    match key {
        "length" => &s.length,
        "max_pressure" => &s.max_pressure,
        "min_pressure" => &s.min_pressure,
        "max_stretch" => &s.max_stretch,
        "min_stretch" => &s.min_stretch,
        other => s.extra.get(other).map_or(&[], |v| v.as_slice()),
    }
}

/// All profile times in a group, sorted.
fn profile_times(g: &Group<'_>) -> Vec<f64> {
    let mut t: Vec<f64> = g
        .runs
        .iter()
        .flat_map(|(r, _)| r.profiles.iter().map(|p| p.t))
        .collect();
    t.sort_by(f64::total_cmp);
    t.dedup_by(|a, b| close(*a, *b));
    t
}

/// `x = (l(t)/l(0))·X` over the X range of the group's first profile at `t`.
fn uniform_line(g: &Group<'_>, t: f64) -> Option<Vec<(f64, f64)>> {
    let (rec, p) = g
        .runs
        .iter()
        .find_map(|(r, _)| r.profiles.iter().find(|p| close(p.t, t)).map(|p| (*r, p)))?;
    let ratio = strain_ratio(rec, t)?;
    let (lo, hi) = (p.x_ref.first()?, p.x_ref.last()?);
    Some(vec![(*lo, ratio * lo), (*hi, ratio * hi)])
}

/// `l(t)/l(0)` from a run's series (needs `t = 0` and `t` among the series times).
fn strain_ratio(rec: &RunRecord, t: f64) -> Option<f64> {
    let s = &rec.series;
    let l0 = *s.length.first().filter(|_| s.t.first() == Some(&0.0))?;
    let k = s.t.iter().position(|st| close(*st, t))?;
    Some(s.length[k] / l0)
}

/// Curves of extremes against the swept value, per model: at each profile time, and over all
/// series times (peaks and troughs).
fn sweep_curves(scenario: &Scenario, summary: &Summary, key: &str) -> Vec<Curve> {
    let mut curves = Vec::new();
    let stretch = stretch_name(scenario);
    let shear = stretch == SHEAR;
    let mut times: Vec<f64> = scenario
        .runs
        .iter()
        .flat_map(|r| r.times.profiles.iter().copied())
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| close(*a, *b));
    for model in [ModelKind::Discrete, ModelKind::Continuum] {
        let runs: Vec<(f64, &RunRecord)> = summary
            .runs
            .iter()
            .zip(&scenario.runs)
            .filter(|(r, _)| r.model == model)
            .filter_map(|(r, s)| Some((s.sweep.as_ref()?.value?, r)))
            .collect();
        if runs.is_empty() {
            continue;
        }
        let word = model_word(model);
        let mut color = 0;
        for &t in times.iter().filter(|t| **t > 0.0) {
            let pts: Vec<(f64, f64)> = runs
                .iter()
                .filter_map(|(v, r)| {
                    if key == "length" {
                        // l at the profile time, from the series (Fig 3.1a inset: l(100) vs K)
                        let k = r.series.t.iter().position(|s| close(*s, t))?;
                        return Some((*v, *r.series.length.get(k)?));
                    }
                    let p = r.profiles.iter().find(|p| close(p.t, t))?;
                    let y = if key == "pressure" {
                        p.pressure.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                    } else {
                        p.stretch.iter().copied().fold(f64::INFINITY, f64::min)
                    };
                    Some((*v, y))
                })
                .collect();
            let what = match key {
                "pressure" => "max p",
                "length" if shear => "top displacement",
                "length" => "l",
                _ => stretch.min_legend,
            };
            curves.push(Curve::new(
                format!("{word} {what} at t={}", format_number(t)),
                style(model),
                color,
                pts,
            ));
            color += 1;
        }
        if key == "length" {
            continue;
        }
        let (hi_key, lo_key) = if key == "pressure" {
            ("max_pressure", "min_pressure")
        } else {
            ("max_stretch", "min_stretch")
        };
        let peaks: Vec<(f64, f64)> = runs
            .iter()
            .map(|(v, r)| {
                (
                    *v,
                    series_values(r, hi_key)
                        .iter()
                        .copied()
                        .fold(f64::NEG_INFINITY, f64::max),
                )
            })
            .collect();
        let troughs: Vec<(f64, f64)> = runs
            .iter()
            .map(|(v, r)| {
                (
                    *v,
                    series_values(r, lo_key)
                        .iter()
                        .copied()
                        .fold(f64::INFINITY, f64::min),
                )
            })
            .collect();
        curves.push(Curve::new(
            format!("{word} peaks (max over t)"),
            style(model),
            color,
            peaks,
        ));
        curves.push(Curve::new(
            format!("{word} troughs (min over t)"),
            style(model),
            color + 1,
            troughs,
        ));
    }
    curves
}

/// Whether some run's number of cells changes (something divides): a number of cells that
/// never changes is not plotted, neither against time nor over an ensemble.
pub(crate) fn cells_change(summary: &Summary) -> bool {
    summary.runs.iter().any(|r| {
        r.series
            .extra
            .get("cells")
            .is_some_and(|n| n.iter().any(|v| *v != n[0]))
    })
}

/// A shear column's names: its `stretch` fields hold tan θ.
const SHEAR: StretchName = StretchName {
    symbol: "tan θ",
    words: "shear tan θ",
    min_axis: "min tan θ",
    min_words: "minimum shear tan θ",
    min_legend: "min tan θ",
    z_over_y: "",
    max_y_axis: "",
    max_y_words: "",
};

/// The file-name stem of a plotted quantity: a shear column's records keep tan θ in the
/// stretch fields and its top displacement in `length`; its files are named for what they
/// hold (`series_min_tan_theta.png`, `sweep_top_displacement.png`).
fn file_key(shear: bool, key: &str) -> String {
    match key {
        "length" if shear => "top_displacement".into(),
        _ if shear => key.replace("stretch", "tan_theta"),
        _ => key.into(),
    }
}

/// What the `stretch` fields hold, for axis labels and titles: a shear column's tan θ; the
/// elastic stretch α when any of the scenario's lines or sheets grows (their profiles and
/// series record α = λ/g; the total stretch λ is the profile's `lambda`); else the stretch λ.
#[derive(Clone, Copy, Debug, PartialEq)]
struct StretchName {
    /// The symbol on a profile axis.
    symbol: &'static str,
    /// In words.
    words: &'static str,
    /// The series' minimum over the cells, on an axis.
    min_axis: &'static str,
    /// The series' minimum, in words.
    min_words: &'static str,
    /// The minimum in a legend.
    min_legend: &'static str,
    /// A sheet's series `mean_stretch_z_over_y`, on an axis and in words.
    z_over_y: &'static str,
    /// A sheet's series `max_stretch_y` (transverse), on an axis.
    max_y_axis: &'static str,
    /// The same in words.
    max_y_words: &'static str,
}

/// The [`StretchName`] of `scenario`'s runs.
fn stretch_name(scenario: &Scenario) -> StretchName {
    if scenario
        .runs
        .iter()
        .any(|r| matches!(r.config, ModelConfig::Shear(..)))
    {
        return SHEAR;
    }
    let growing = scenario.runs.iter().any(|r| match &r.config {
        ModelConfig::Line(c) => c.growth.is_some(),
        ModelConfig::Sheet(c, _) => c.growth.is_some(),
        ModelConfig::Proliferating(_) => true,
        _ => false,
    });
    if growing {
        StretchName {
            symbol: "α (elastic stretch)",
            words: "elastic stretch",
            min_axis: "min_x α",
            min_words: "minimum elastic stretch",
            min_legend: "min α",
            z_over_y: "mean λ3 / mean α2",
            max_y_axis: "max α2",
            max_y_words: "maximum transverse elastic stretch",
        }
    } else {
        StretchName {
            symbol: "λ",
            words: "stretch",
            min_axis: "min_x λ",
            min_words: "minimum stretch",
            min_legend: "min λ",
            z_over_y: "mean λ3 / mean λ2",
            max_y_axis: "max λ2",
            max_y_words: "maximum transverse stretch",
        }
    }
}

/// Cell rectangles `[left, right] × [−W/2, W/2]` per profile, one row per profile (the first on
/// top): each cell's current extent ([`Profile::cell_ends`]: its current length λ·L about its
/// centre), `W` from the profile's `"width"` field or `1/λ` (incompressible unit cell).
pub(crate) fn rectangles(profiles: &[Profile]) -> Vec<(f64, f64, f64, f64, f64)> {
    let mut out = Vec::new();
    let max_w = profiles
        .iter()
        .flat_map(|p| (0..p.stretch.len()).map(move |j| width(p, j)))
        .fold(0.0_f64, f64::max);
    let gap = 1.4 * max_w.max(1e-9);
    for (row, p) in profiles.iter().enumerate() {
        let yc = -(row as f64) * gap;
        for (j, &(left, right)) in p.cell_ends().iter().enumerate().take(p.pressure.len()) {
            let w = width(p, j);
            out.push((left, yc - 0.5 * w, right, yc + 0.5 * w, p.pressure[j]));
        }
    }
    out
}

fn width(p: &Profile, j: usize) -> f64 {
    p.extra
        .get("width")
        .and_then(|w| w.get(j).copied())
        .unwrap_or_else(|| 1.0 / p.stretch[j])
}

mod references;
use references::{profile_references, series_reference, sweep_references};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::load_str;
    use std::path::Path;

    fn scenario(model: &str) -> Scenario {
        let text = format!("name = \"s\"\n[output]\nseries = [0, 1]\n[model]\n{model}\n");
        load_str(&text, Path::new("s.toml"), &[]).unwrap()
    }

    #[test]
    fn the_stretch_axes_name_what_each_kind_records() {
        let growing = "kind = \"line\"\nright_end = \"free\"\nK = 0.01\ngrowth = { sigma0 = 0.1 }";
        assert_eq!(
            stretch_name(&scenario(growing)).symbol,
            "α (elastic stretch)"
        );
        let dividing = format!("{growing}\ndivision = {{ rule = \"area\" }}");
        assert_eq!(stretch_name(&scenario(&dividing)).min_legend, "min α");
        assert_eq!(stretch_name(&scenario("kind = \"line\"")).symbol, "λ");
        let sheet = "kind = \"sheet\"\ncells_x = 2\ncells_y = 2";
        assert_eq!(stretch_name(&scenario(sheet)).symbol, "λ");
        assert_eq!(stretch_name(&scenario(sheet)).max_y_axis, "max λ2");
        let growing_sheet = format!("{sheet}\nright = \"free\"\ngrowth = {{ sigma0 = 0.1 }}");
        let name = stretch_name(&scenario(&growing_sheet));
        assert_eq!(
            (name.symbol, name.z_over_y),
            ("α (elastic stretch)", "mean λ3 / mean α2")
        );
        let shear = stretch_name(&scenario("kind = \"shear\"\ncells = 4"));
        assert_eq!((shear.symbol, shear.min_legend), ("tan θ", "min tan θ"));
    }
}
