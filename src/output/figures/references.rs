//! The analytic reference curves the figures draw over the runs (thin dashed lines in the run's
//! hue): the series `max p`, `min λ`, the profiles at the profile times and the sweep plots'
//! values, all from the [`AnalyticReference`] the runner recorded for each run.

use super::{close, Group};
use crate::observe::AnalyticReference;
use crate::output::plot::{Curve, Style};

/// The analytic reference the group's runs carry (the runner's, for lines with a prescribed
/// end; the same for every run of a group).
fn group_reference<'a>(g: &Group<'a>) -> Option<&'a AnalyticReference> {
    g.runs.iter().find_map(|(rec, _)| rec.reference.as_ref())
}

/// The analytic `max p` or `min λ` against the group's series times (dashed, group colour).
pub(super) fn series_reference(g: &Group<'_>, key: &str) -> Option<(String, Vec<(f64, f64)>)> {
    let r = group_reference(g)?;
    let times = &g.runs.first()?.0.series.t;
    let values = match key {
        "max_pressure" => &r.series.max_pressure,
        _ => &r.series.min_stretch,
    };
    // where the reference does not apply the curve has a gap (NaN), not a bridging segment
    let pts: Vec<(f64, f64)> = times
        .iter()
        .map(|&t| match r.series.t.iter().position(|&s| close(s, t)) {
            Some(i) => (t, values[i]),
            None => (t, f64::NAN),
        })
        .collect();
    pts.iter()
        .any(|q| q.1.is_finite())
        .then_some((r.label.clone(), pts))
}

/// Dashed analytic profiles at each profile time (colour = time, as the runs): `p` or `λ`
/// against `X`, and for Fig 2.6's position plots the static equilibrium `x(X)` and its
/// deviation from uniform strain (`x − (x_N/X_N)·X`).
pub(super) fn profile_references(g: &Group<'_>, key: &str, times: &[f64]) -> Vec<Curve> {
    let mut out = Vec::new();
    let Some(r) = group_reference(g) else {
        return out;
    };
    for (ti, &t) in times.iter().enumerate() {
        let (what, pts): (&str, Vec<(f64, f64)>) = match key {
            "pressure" | "stretch" => {
                let Some(p) = r.profiles.iter().find(|p| close(p.t, t)) else {
                    continue;
                };
                let ys = if key == "pressure" {
                    &p.pressure
                } else {
                    &p.stretch
                };
                (
                    &r.label,
                    p.x_ref.iter().copied().zip(ys.iter().copied()).collect(),
                )
            }
            "position" | "deviation" => {
                let Some(e) = r.equilibrium.iter().find(|e| close(e.t, t)) else {
                    continue;
                };
                let ratio = match (e.x.last(), e.x_ref.last()) {
                    (Some(x), Some(xr)) if *xr > 0.0 => x / xr,
                    _ => continue,
                };
                let pts = e.x_ref.iter().zip(&e.x);
                let pts =
                    pts.map(|(&xr, &x)| (xr, if key == "position" { x } else { x - ratio * xr }));
                ("static equilibrium at l(t)", pts.collect())
            }
            _ => continue,
        };
        // one legend entry for all times (the runs' colours give the time)
        push_reference(&mut out, what, ti, pts);
    }
    out
}

/// Analytic `max p` / `min λ` at each profile time (`t > 0`) against the swept value (dashed),
/// from each swept value's own reference.
pub(super) fn sweep_references(groups: &[Group<'_>], key: &str) -> Vec<Curve> {
    let mut times: Vec<f64> = groups
        .iter()
        .filter_map(group_reference)
        .flat_map(|r| r.profiles.iter().map(|p| p.t))
        .filter(|t| *t > 0.0)
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| close(*a, *b));
    let mut out = Vec::new();
    for (ci, &t) in times.iter().enumerate() {
        let mut label = None;
        let pts: Vec<(f64, f64)> = groups
            .iter()
            .filter_map(|g| {
                let v = g
                    .runs
                    .iter()
                    .find_map(|(_, s)| (*s)?.sweep.as_ref()?.value)?;
                let r = group_reference(g)?;
                let p = r.profiles.iter().find(|p| close(p.t, t))?;
                label.get_or_insert(r.label.as_str());
                let y = if key == "pressure" {
                    p.pressure.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                } else {
                    p.stretch.iter().copied().fold(f64::INFINITY, f64::min)
                };
                Some((v, y))
            })
            .collect();
        if let (Some(what), false) = (label, pts.is_empty()) {
            push_reference(&mut out, what, ci, pts);
        }
    }
    out
}

/// Appends a reference curve of colour index `colour`, labelled only if it is the first: one
/// legend entry for every time (the colour gives the time, as for the runs).
fn push_reference(out: &mut Vec<Curve>, what: &str, colour: usize, pts: Vec<(f64, f64)>) {
    let label = if out.is_empty() {
        what.to_string()
    } else {
        String::new()
    };
    out.push(Curve::new(label, Style::Reference, colour, pts));
}
