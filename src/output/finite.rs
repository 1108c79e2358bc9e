//! No NaN in any output: `serde_json` would silently write `null`. [`sanitize`] cuts a record
//! back to its last finite data and says so in its `error`; [`check_summary`] is the final guard
//! before `summary.json` is written.

use crate::observe::{AnalyticReference, RunRecord, Summary};

/// Where the first non-finite number of a record is, e.g. `series.max_pressure[12]`.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::finite::first_non_finite;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// assert_eq!(first_non_finite(&rec), None);
/// rec.profiles.push(Profile { t: 1.0, stretch: vec![1.0, f64::NAN], ..Default::default() });
/// assert_eq!(first_non_finite(&rec).unwrap(), "profiles[0].stretch[1]");
/// ```
pub fn first_non_finite(rec: &RunRecord) -> Option<String> {
    let s = &rec.series;
    let mut named: Vec<(&str, &Vec<f64>)> = vec![
        ("t", &s.t),
        ("length", &s.length),
        ("max_pressure", &s.max_pressure),
        ("min_pressure", &s.min_pressure),
        ("max_stretch", &s.max_stretch),
        ("min_stretch", &s.min_stretch),
    ];
    named.extend(s.extra.iter().map(|(k, v)| (k.as_str(), v)));
    for (k, v) in named {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Some(format!("series.{k}[{i}]"));
        }
    }
    for (p, prof) in rec.profiles.iter().enumerate() {
        if !prof.t.is_finite() {
            return Some(format!("profiles[{p}].t"));
        }
        let mut named: Vec<(&str, &Vec<f64>)> = vec![
            ("X", &prof.x_ref),
            ("x", &prof.x),
            ("stretch", &prof.stretch),
            ("pressure", &prof.pressure),
        ];
        named.extend(prof.extra.iter().map(|(k, v)| (k.as_str(), v)));
        for (k, v) in named {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Some(format!("profiles[{p}].{k}[{i}]"));
            }
        }
    }
    let st = &rec.stats;
    if !st.wall_seconds.is_finite() {
        return Some("stats".into());
    }
    for (i, d) in rec.divisions.iter().enumerate() {
        if !division_is_finite(d) {
            return Some(format!("divisions[{i}]"));
        }
    }
    rec.reference.as_ref().and_then(reference_non_finite)
}

/// Where the first non-finite number of an analytic reference is.
fn reference_non_finite(r: &AnalyticReference) -> Option<String> {
    let s = &r.series;
    let mut named: Vec<(String, &Vec<f64>)> = vec![
        ("series.t".into(), &s.t),
        ("series.max_pressure".into(), &s.max_pressure),
        ("series.min_stretch".into(), &s.min_stretch),
    ];
    for (i, p) in r.profiles.iter().enumerate() {
        named.push((format!("profiles[{i}].X"), &p.x_ref));
        named.push((format!("profiles[{i}].stretch"), &p.stretch));
        named.push((format!("profiles[{i}].pressure"), &p.pressure));
    }
    for (i, e) in r.equilibrium.iter().enumerate() {
        named.push((format!("equilibrium[{i}].X"), &e.x_ref));
        named.push((format!("equilibrium[{i}].x"), &e.x));
    }
    let times = r
        .profiles
        .iter()
        .map(|p| p.t)
        .chain(r.equilibrium.iter().map(|e| e.t));
    if times.clone().any(|t| !t.is_finite()) {
        return Some("reference (a profile time)".into());
    }
    named.into_iter().find_map(|(k, v)| {
        v.iter()
            .position(|x| !x.is_finite())
            .map(|i| format!("reference.{k}[{i}]"))
    })
}

/// Removes non-finite data: series are cut before the first output time with a non-finite
/// value, profiles and division records with one are dropped, a non-finite wall time
/// becomes 0. Returns `true` (and appends to `error`) if anything was removed.
///
/// ```
/// use celltissue::observe::*;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![],
///     reference: None, accuracy_check: None };
/// rec.series.t = vec![0.0, 1.0];
/// rec.series.length = vec![1.0, f64::NAN];
/// rec.series.max_pressure = vec![1.0, 1.0];
/// rec.series.min_pressure = vec![1.0, 1.0];
/// rec.series.max_stretch = vec![1.0, 1.0];
/// rec.series.min_stretch = vec![1.0, 1.0];
/// assert!(celltissue::output::finite::sanitize(&mut rec));
/// assert_eq!(rec.series.t, vec![0.0]);
/// assert!(rec.error.unwrap().contains("series.length[1]"));
/// ```
pub fn sanitize(rec: &mut RunRecord) -> bool {
    let Some(first) = first_non_finite(rec) else {
        return false;
    };
    let s = &mut rec.series;
    let n = s.t.len();
    let mut cut = n;
    {
        let cols = [
            &s.t,
            &s.length,
            &s.max_pressure,
            &s.min_pressure,
            &s.max_stretch,
            &s.min_stretch,
        ];
        for v in cols.into_iter().chain(s.extra.values()) {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                cut = cut.min(i);
            }
        }
    }
    for v in [
        &mut s.t,
        &mut s.length,
        &mut s.max_pressure,
        &mut s.min_pressure,
        &mut s.max_stretch,
        &mut s.min_stretch,
    ]
    .into_iter()
    .chain(s.extra.values_mut())
    {
        v.truncate(cut);
    }
    let finite = |v: &Vec<f64>| v.iter().all(|x| x.is_finite());
    rec.profiles.retain(|p| {
        p.t.is_finite()
            && finite(&p.x_ref)
            && finite(&p.x)
            && finite(&p.stretch)
            && finite(&p.pressure)
            && p.extra.values().all(finite)
    });
    rec.divisions.retain(division_is_finite);
    if !rec.stats.wall_seconds.is_finite() {
        rec.stats.wall_seconds = 0.0;
    }
    // an analytic reference with a non-finite value is dropped whole (it is a comparison,
    // not the run's data)
    if rec
        .reference
        .as_ref()
        .is_some_and(|r| reference_non_finite(r).is_some())
    {
        rec.reference = None;
    }
    let note = format!("non-finite value at {first}; output cut back to the last finite data");
    rec.error = Some(match rec.error.take() {
        Some(e) => format!("{e}; {note}"),
        None => note,
    });
    true
}

/// The first non-finite number of a summary: its run and its place in the run (see
/// [`check_summary`]).
///
/// ```
/// let e = celltissue::output::finite::NonFiniteError { label: "discrete".into(), place: "series.t[0]".into() };
/// assert_eq!(e.to_string(), "run `discrete`: series.t[0]");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("run `{label}`: {place}")]
pub struct NonFiniteError {
    /// The run's label.
    pub label: String,
    /// Where in the run (series, profile or field and index).
    pub place: String,
}

/// The first non-finite number in the summary, if any.
///
/// ```
/// use celltissue::observe::*;
/// use celltissue::output::finite::check_summary;
/// let mut rec = RunRecord { label: "r".into(), model: ModelKind::Discrete,
///     parameters: serde_json::json!({}), series: Series::default(), profiles: vec![],
///     stats: RunStats::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// rec.reference = Some(AnalyticReference {
///     label: "exact".into(),
///     series: ReferenceSeries { t: vec![1.0], max_pressure: vec![f64::INFINITY], min_stretch: vec![0.9] },
///     ..Default::default()
/// });
/// let summary = Summary { scenario: "s".into(), runs: vec![rec] };
/// let e = check_summary(&summary).unwrap_err();
/// assert_eq!(e.to_string(), "run `r`: reference.series.max_pressure[0]");
/// // sanitising drops such a reference whole, and says so
/// let mut rec = summary.runs[0].clone();
/// assert!(celltissue::output::finite::sanitize(&mut rec));
/// assert!(rec.reference.is_none() && rec.error.unwrap().contains("reference.series"));
/// ```
pub fn check_summary(summary: &Summary) -> Result<(), NonFiniteError> {
    for rec in &summary.runs {
        if let Some(place) = first_non_finite(rec) {
            return Err(NonFiniteError {
                label: rec.label.clone(),
                place,
            });
        }
    }
    Ok(())
}

/// Whether every number of a division record is finite.
fn division_is_finite(d: &crate::observe::DivisionRecord) -> bool {
    d.t.is_finite()
        && d.x.is_finite()
        && d.x_over_length.is_finite()
        && d.age.is_none_or(f64::is_finite)
}
