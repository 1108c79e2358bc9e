//! Observations: what a run records at its output times, in the shape of `summary.json`
//! (a stable schema: keys may be added, never renamed). Builders and drivers fill a
//! [`RunRecord`]; writers in `output/` turn records into JSON, CSV and plots.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Which model produced a run.
///
/// ```
/// use celltissue::observe::ModelKind;
/// assert_eq!(serde_json::to_string(&ModelKind::Continuum)?, "\"continuum\"");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// N cells, one ODE per boundary.
    Discrete,
    /// The continuum PDE on n grid points.
    Continuum,
}

/// Scalar time series, one entry per output time. Standard keys are fields; model-specific
/// series (e.g. `"cells"`, `"mean_pressure"`, `"top_displacement"`) go in `extra` and are
/// flattened into the same JSON object.
///
/// ```
/// use celltissue::observe::Series;
/// let mut s = Series::default();
/// s.t.push(1.0);
/// s.extra.insert("cells".into(), vec![120.0]);
/// // model-specific series sit next to the standard ones in JSON
/// assert!(serde_json::to_string(&s)?.contains("\"cells\":[120.0]"));
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// Output times.
    pub t: Vec<f64>,
    /// Array length `l(t)` (line) or extent in x (sheet).
    pub length: Vec<f64>,
    /// Maximum cell pressure.
    pub max_pressure: Vec<f64>,
    /// Minimum cell pressure.
    pub min_pressure: Vec<f64>,
    /// Maximum (elastic) axial stretch.
    pub max_stretch: Vec<f64>,
    /// Minimum (elastic) axial stretch.
    pub min_stretch: Vec<f64>,
    /// Further series by name.
    #[serde(flatten)]
    pub extra: BTreeMap<String, Vec<f64>>,
}

impl Series {
    /// Appends the values of one series time (see [`crate::runner::SeriesRow`] for an
    /// example); an extra series first seen here starts at this row.
    ///
    /// ```
    /// use celltissue::observe::Series;
    /// use celltissue::runner::SeriesRow;
    /// let mut s = Series::default();
    /// s.push_row(0.0, &SeriesRow { length: 10.0, ..Default::default() });
    /// s.push_row(1.0, &SeriesRow { length: 9.5, extra: vec![("cells".into(), 12.0)], ..Default::default() });
    /// assert_eq!(s.length, [10.0, 9.5]);
    /// assert_eq!(s.extra["cells"], [12.0]); // starts at the row it first appears in
    /// ```
    pub fn push_row(&mut self, t: f64, row: &crate::runner::SeriesRow) {
        self.t.push(t);
        self.length.push(row.length);
        self.max_pressure.push(row.max_pressure);
        self.min_pressure.push(row.min_pressure);
        self.max_stretch.push(row.max_stretch);
        self.min_stretch.push(row.min_stretch);
        for (k, v) in &row.extra {
            self.extra.entry(k.clone()).or_default().push(*v);
        }
    }
}

/// A per-cell (discrete) or per-node (continuum) snapshot at one time.
///
/// ```
/// use celltissue::observe::Profile;
/// let p = Profile { t: 1.0, x_ref: vec![0.5], x: vec![0.45], stretch: vec![0.9], pressure: vec![1.2],
///                   ..Default::default() };
/// let json = serde_json::to_string(&p)?;
/// assert!(json.contains("\"X\":[0.5]")); // the reference position is written `X`
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Time.
    pub t: f64,
    /// Reference position (initial cell centre, or node/segment centre).
    #[serde(rename = "X")]
    pub x_ref: Vec<f64>,
    /// Current position (cell centre or node).
    pub x: Vec<f64>,
    /// Axial stretch (elastic stretch α when growing).
    pub stretch: Vec<f64>,
    /// Pressure.
    pub pressure: Vec<f64>,
    /// Further per-cell fields by name (e.g. `"g"`, `"sigma"`, `"width"`).
    #[serde(flatten)]
    pub extra: BTreeMap<String, Vec<f64>>,
}

impl Profile {
    /// Each cell's current ends `(left, right)` along the line: `x ∓ ℓ/2` with `ℓ` the current
    /// cell length (the `"length"` field a line records); for a profile without one, `ℓ` is
    /// the total stretch (`"lambda"`, else `stretch`) times the spacing of the reference
    /// centres (one-sided at the ends), exact for cells of equal reference length.
    ///
    /// ```
    /// use celltissue::observe::Profile;
    /// // two cells of current lengths 2 and 1.5, as a line records them
    /// let mut p = Profile { t: 1.0, x_ref: vec![0.5, 1.25], x: vec![1.0, 2.75],
    ///     stretch: vec![1.0, 1.0], pressure: vec![1.0, 1.0], ..Default::default() };
    /// p.extra.insert("length".into(), vec![2.0, 1.5]);
    /// assert_eq!(p.cell_ends(), [(0.0, 2.0), (2.0, 3.5)]);
    /// // without lengths: λ times the centres' spacing
    /// p.extra.clear();
    /// p.extra.insert("lambda".into(), vec![2.0, 2.0]);
    /// assert_eq!(p.cell_ends(), [(0.25, 1.75), (2.0, 3.5)]);
    /// ```
    pub fn cell_ends(&self) -> Vec<(f64, f64)> {
        let n = self.x_ref.len().min(self.x.len()).min(self.stretch.len());
        let field = |name: &str| self.extra.get(name).filter(|v| v.len() >= n);
        let lengths: Vec<f64> = match field("length") {
            Some(l) => l[..n].to_vec(),
            None => {
                let lam = field("lambda").unwrap_or(&self.stretch);
                let x = &self.x_ref;
                (0..n)
                    .map(|j| {
                        let spacing = match n {
                            0 | 1 => 1.0,
                            _ if j == 0 => x[1] - x[0],
                            _ if j == n - 1 => x[n - 1] - x[n - 2],
                            _ => 0.5 * (x[j + 1] - x[j - 1]),
                        };
                        lam[j] * spacing
                    })
                    .collect()
            }
        };
        (0..n)
            .map(|j| (self.x[j] - 0.5 * lengths[j], self.x[j] + 0.5 * lengths[j]))
            .collect()
    }
}

/// Integrator work for a run.
///
/// ```
/// use celltissue::observe::RunStats;
/// let s = integrators::Stats { steps: 12, rejected_steps: 2, ..Default::default() };
/// let r = RunStats::from_stats(&s, 0.5);
/// assert_eq!((r.steps, r.extra["rejected_steps"]), (12, 2));
/// // every counter is an integer in JSON; wall time is the only float
/// let json = serde_json::to_value(&r).unwrap();
/// assert_eq!(json["rejected_steps"], 2);
/// assert_eq!(json["wall_seconds"], 0.5);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunStats {
    /// Accepted steps.
    pub steps: usize,
    /// Residual evaluations.
    pub residual_calls: usize,
    /// Jacobian evaluations.
    pub jacobians: usize,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
    /// Further counters by name (rejections, factorisations, Newton iterations, events…);
    /// integers, written as JSON integers.
    #[serde(flatten)]
    pub extra: BTreeMap<String, u64>,
}

impl RunStats {
    /// The record of a solve's work: `steps`, `residual_calls`, `jacobians` and every other
    /// counter of [`integrators::Stats`] under its own name (one mapping for every model).
    ///
    /// ```
    /// let s = integrators::Stats { steps: 4, jacobian_evals: 2, events: 1, ..Default::default() };
    /// let r = celltissue::observe::RunStats::from_stats(&s, 0.5);
    /// assert_eq!((r.steps, r.jacobians, r.extra["events"]), (4, 2, 1));
    /// assert_eq!(r.extra.len(), 13);
    /// ```
    pub fn from_stats(s: &integrators::Stats, wall_seconds: f64) -> Self {
        Self {
            steps: s.steps,
            residual_calls: s.residual_calls,
            jacobians: s.jacobian_evals,
            wall_seconds,
            extra: s
                .counters()
                .into_iter()
                .filter(|(k, _)| !matches!(*k, "steps" | "residual_calls" | "jacobian_evals"))
                .map(|(k, v)| (k.to_string(), v as u64))
                .collect(),
        }
    }
}

/// One division event: when, which cell, where, the cell count after it, the dividing cell's
/// age (its cycle time) and, for lineage tracing, its identity and its daughters'.
///
/// ```
/// use celltissue::observe::DivisionRecord;
/// let d = DivisionRecord { t: 2.0, parent: 3, x: 2.5, x_over_length: 0.5, cells_after: 6,
///                          age: Some(2.0), cell: Some(2), daughters: Some([4, 5]) };
/// assert_eq!(serde_json::to_value(&d)?["cells_after"], 6);
/// // a model without individual cells (the density continuum) has no age: the key is absent
/// let d = DivisionRecord { age: None, ..d };
/// assert!(serde_json::to_value(&d)?.get("age").is_none());
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DivisionRecord {
    /// Time of division.
    pub t: f64,
    /// Index (1-based, as in docs/model.md) of the parent cell before division.
    pub parent: usize,
    /// Position of the new boundary.
    pub x: f64,
    /// `x / l(t)`.
    pub x_over_length: f64,
    /// Number of cells after the division.
    pub cells_after: usize,
    /// Age of the dividing cell: the time since its birth (its cycle time), counted from
    /// t = 0 for a cell present at the start. `None` where cells have no history of their own
    /// (the proliferating density continuum, whose divisions are its density crossing whole
    /// cells).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub age: Option<f64>,
    /// Identity of the dividing cell (lineage tracing: the initial cells are `0..N₀`, each
    /// division gives its daughters the next two unused numbers). `None` where cells have no
    /// identity of their own (the proliferating continua).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cell: Option<u64>,
    /// Identities of the two daughters, lower (nearer x₀) first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub daughters: Option<[u64; 2]>,
}

/// Everything one run (one model at one parameter set) produced.
///
/// ```
/// use celltissue::observe::{ModelKind, RunRecord};
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, SheetConfig};
/// use celltissue::SolveSettings;
/// let cfg = SheetConfig { cells_x: 3, cells_y: 3, ..Default::default() };
/// let rec: RunRecord = run_sheet(&cfg, &cfg.law, ModelKind::Discrete, None,
///                                &SolveSettings::default(), &OutputTimes::at(&[1.0]))?;
/// assert!(rec.error.is_none() && rec.stats.steps > 0);
/// assert_eq!(rec.series.t, [1.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Label shown in legends, e.g. `"discrete K=0.01"`.
    pub label: String,
    /// Discrete or continuum.
    pub model: ModelKind,
    /// Parameters of this run (as resolved from the scenario).
    pub parameters: serde_json::Value,
    /// Scalar series.
    pub series: Series,
    /// Snapshots at the requested profile times.
    pub profiles: Vec<Profile>,
    /// Work counters.
    pub stats: RunStats,
    /// Division events (empty without division).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub divisions: Vec<DivisionRecord>,
    /// If the solver failed: its message (the record holds what was computed before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// What the reader of a finished run should know about its numbers, each a sentence (a
    /// dividing line that reached its `max_cells` cap and divided no more, for one).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The analytic solution of the run's own configuration, where one applies (lines with a
    /// prescribed end; see [`crate::line::analytic`]), at the requested times.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<AnalyticReference>,
    /// The run compared with itself at a tenfold tighter tolerance, where `solver.accuracy_check`
    /// asks for it ([`crate::scenario::accuracy_check`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy_check: Option<AccuracyCheck>,
}

/// A run against the same run at a tighter tolerance (`solver.accuracy_check`): the largest
/// differences over the cells and profiles of the two, an estimate of the run's own error
/// where its error falls with the tolerance (docs/model.md §8.1).
///
/// ```
/// use celltissue::observe::AccuracyCheck;
/// let c = AccuracyCheck { rtol: 1e-7, atol: 1e-9, steps: 180, profiles_compared: 3,
///     stretch_difference: 2.0e-6, stretch_over_rtol: 2.0, t: 1.0, cell: 7,
///     pressure_difference: 5.0e-6, series_times_compared: 11, series_stretch_over_rtol: 1.5,
///     series_t: 0.5, ..Default::default() };
/// let json = serde_json::to_value(&c)?;
/// assert_eq!(json["stretch_over_rtol"], 2.0);
/// assert!(json.get("profiles_skipped").is_none()); // 0 is left out
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AccuracyCheck {
    /// The tighter run's relative tolerance (the run's over the check's factor).
    pub rtol: f64,
    /// The tighter run's absolute tolerance.
    pub atol: f64,
    /// The tighter run's steps.
    pub steps: usize,
    /// Profiles compared: those where both runs hold the same cells or points.
    pub profiles_compared: usize,
    /// Profiles left out because the two runs hold different cells there (a division on
    /// either side of the output time). Left out when 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub profiles_skipped: usize,
    /// Largest stretch difference in the contract's weight, |Δλ| / (|λ| + atol/rtol) with the
    /// run's tolerances and the tighter run's λ (both directions on a sheet; tan θ on a shear
    /// column).
    pub stretch_difference: f64,
    /// [`Self::stretch_difference`] over the run's rtol: the contract holds the run's own
    /// error to 10.
    pub stretch_over_rtol: f64,
    /// Profile time of the largest stretch difference.
    pub t: f64,
    /// Cell or grid point (from 0) of the largest stretch difference.
    pub cell: usize,
    /// Largest pressure difference, |Δp| / (|p| + atol/rtol).
    pub pressure_difference: f64,
    /// Series times compared: those where both runs' smallest and largest stretch are finite.
    /// Left out when 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub series_times_compared: usize,
    /// Largest difference of the series' smallest and largest stretch (`min_stretch`,
    /// `max_stretch`; tan θ on a shear column) over rtol, in the same weight: the check at every
    /// series time, of the extremes only.
    #[serde(default)]
    pub series_stretch_over_rtol: f64,
    /// Series time of the largest series difference.
    #[serde(default)]
    pub series_t: f64,
    /// Why the tighter run could not be compared, if it failed (the other fields are then 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl RunRecord {
    /// The record's label, model, parameters, counters and error, without its data (series,
    /// profiles, divisions, reference): what a progress line reads, at no copy of the
    /// profiles.
    ///
    /// ```
    /// use celltissue::observe::{ModelKind, Profile, RunRecord, RunStats};
    /// let mut rec = RunRecord { label: "discrete".into(), model: ModelKind::Discrete,
    ///     parameters: serde_json::json!({"K": 1.0}), series: Default::default(),
    ///     profiles: vec![Profile::default()], stats: RunStats { steps: 7, ..Default::default() },
    ///     divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
    /// let light = rec.without_data();
    /// assert!(light.profiles.is_empty() && light.stats.steps == 7 && light.label == "discrete");
    /// ```
    pub fn without_data(&self) -> RunRecord {
        RunRecord {
            label: self.label.clone(),
            model: self.model,
            parameters: self.parameters.clone(),
            series: Series::default(),
            profiles: Vec::new(),
            stats: self.stats.clone(),
            divisions: Vec::new(),
            error: self.error.clone(),
            notes: self.notes.clone(),
            reference: None,
            accuracy_check: self.accuracy_check.clone(),
        }
    }
}

/// An analytic solution beside a run, evaluated by the runner at the run's requested times
/// where it applies (times where it does not are left out; nothing is NaN). The plots draw it
/// dashed.
///
/// ```
/// use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
/// use celltissue::observe::ModelKind;
/// // K = 0, η = 1: the exact uniform solution applies at every time
/// let cfg = LineConfig { k: 0.0.into(), eta: 1.0.into(), ..Default::default() };
/// let times = OutputTimes { series: vec![0.0, 1.0], profiles: vec![1.0] };
/// let rec = run_line(&cfg, ModelKind::Discrete, None, &SolveSettings::default(), &times);
/// let r = rec.reference.unwrap();
/// assert_eq!(r.label, "exact (K = 0, uniform)");
/// assert_eq!(r.series.t, [0.0, 1.0]);
/// let (exact, run) = (r.series.min_stretch[1], rec.series.min_stretch[1]);
/// assert!((exact - run).abs() < 1e-5, "{exact} vs {run}");
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AnalyticReference {
    /// What the solution is (legend text), e.g. `exact (K = 0, uniform)`.
    pub label: String,
    /// Its `max_x p` and `min_x λ` at the series times where it applies.
    pub series: ReferenceSeries,
    /// Its `λ` and `p` against the reference position at the profile times where it applies.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub profiles: Vec<ReferenceProfile>,
    /// The static equilibrium at `l(t)`: boundary positions `x` against `X`, at the profile
    /// times where the quasi-static limit applies (Fig 2.6).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub equilibrium: Vec<ReferencePositions>,
}

/// [`AnalyticReference::series`]: extremes against time.
///
/// ```
/// use celltissue::observe::ReferenceSeries;
/// let s = ReferenceSeries { t: vec![1.0], max_pressure: vec![1.2], min_stretch: vec![0.9] };
/// // written to summary.json under the run's `reference.series`
/// assert_eq!(serde_json::to_value(&s).unwrap()["min_stretch"][0], 0.9);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSeries {
    /// Times.
    pub t: Vec<f64>,
    /// `max_x p` at each time.
    pub max_pressure: Vec<f64>,
    /// `min_x λ` at each time.
    pub min_stretch: Vec<f64>,
}

/// [`AnalyticReference::profiles`]: one profile (at cell centres, at most a few hundred of
/// them for the closed forms).
///
/// ```
/// use celltissue::line::analytic::reference;
/// use celltissue::line::LineConfig;
/// // 10⁴ cells, K = 0: the exact profile is sampled, not evaluated at every cell
/// let cfg = LineConfig { cells: 10_000, k: 0.0.into(), eta: 1.0.into(), ..Default::default() };
/// let p = &reference(&cfg, &[], &[5.0]).unwrap().profiles[0];
/// assert!(p.x_ref.len() <= celltissue::line::analytic::PROFILE_SAMPLES);
/// assert_eq!(p.stretch.len(), p.x_ref.len());
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ReferenceProfile {
    /// Time.
    pub t: f64,
    /// Reference positions `X`.
    #[serde(rename = "X")]
    pub x_ref: Vec<f64>,
    /// `λ` at each.
    pub stretch: Vec<f64>,
    /// `p` at each.
    pub pressure: Vec<f64>,
}

/// [`AnalyticReference::equilibrium`]: boundary positions at one time.
///
/// ```
/// use celltissue::line::analytic::reference;
/// use celltissue::line::LineConfig;
/// let cfg = LineConfig { cells: 20, k: 1e-5.into(), ..Default::default() };
/// let e = &reference(&cfg, &[], &[20.0]).unwrap().equilibrium[0];
/// assert_eq!((e.x_ref.len(), e.x.len()), (21, 21)); // x₀ … x_N
/// assert_eq!((e.x[0], e.x_ref[20]), (0.0, 20.0));
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ReferencePositions {
    /// Time.
    pub t: f64,
    /// Reference boundary positions `X₀ … X_N`.
    #[serde(rename = "X")]
    pub x_ref: Vec<f64>,
    /// Current positions `x₀ … x_N`.
    pub x: Vec<f64>,
}

/// The whole `summary.json`.
///
/// ```
/// use celltissue::observe::Summary;
/// let s = Summary { scenario: "demo".into(), runs: vec![] };
/// assert_eq!(serde_json::to_value(&s)?["scenario"], "demo");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Scenario name.
    pub scenario: String,
    /// Runs in scenario order.
    pub runs: Vec<RunRecord>,
}
