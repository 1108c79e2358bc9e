//! [`run_line`]: one line run from a validated [`LineConfig`] to a [`RunRecord`] — build the
//! discrete or continuum array, integrate it, and record series and profiles at the requested
//! times through [`crate::runner::run_recorded`]. No I/O; the CLI writes the record, benches
//! call [`integrate`] directly.
//!
//! On solver failure the record holds everything computed up to the failure and
//! `error: Some(message)`; outputs never contain NaN. The message names the cell whose stretch
//! the model last rejected (and its λ, from the last rejected step the run observed), not only
//! the integrator's failure kind and worst unknown.
//!
//! * [`LineModel`] — what a line model provides to be integrated and observed;
//! * [`LineRecorder`] — what a line run records of a state, and its failure messages;
//! * [`integrate`] (raw snapshots), [`run_model`], [`run_line`] — integration and recording.

use super::array::Line;
use super::config::{ContinuumScheme, LineConfig};
use super::observe::Snapshot;
use super::thesis_scheme::ThesisLine;
use crate::array::{ArrayProblem, CellArray};
use crate::drive::{drive_observed, DriveError, DriveObserver};
use crate::energy::StrainEnergy;
use crate::observe::{ModelKind, Profile, RunRecord, RunStats, Series};
use crate::runner::{run_recorded, ObservationError, Recorder, SeriesRow};
use integrators::observer::{Observer, RejectedStep};
use integrators::{ResidualError, SolveFailure, Stats};

/// The run settings (one type for every model; see [`crate::settings`]).
pub use crate::settings::SolveSettings;

/// The requested output times (one type for every model; see [`crate::runner`]).
pub use crate::runner::OutputTimes;

/// A line model that can be observed: the discrete/conservative [`Line`] and the thesis scheme.
///
/// ```
/// use celltissue::line::build::LineParams;
/// use celltissue::line::run::LineModel;
/// use celltissue::line::thesis_scheme::ThesisLine;
/// use celltissue::NeoHookean;
/// // the thesis's finite-difference scheme on 11 nodes, observed like a line of cells
/// let model = ThesisLine::new(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(10), 11).unwrap();
/// let y = model.initial_state();
/// let s = model.observe(0.0, &y, &model.initial_derivative_guess()).unwrap();
/// assert_eq!(s.length(), 10.0);
/// assert!(model.breakpoints().is_empty()); // a constant end: nothing to restart at
/// ```
pub trait LineModel: CellArray {
    /// Initial state.
    fn initial_state(&self) -> Vec<f64>;
    /// Initial guess for `ẏ`.
    fn initial_derivative_guess(&self) -> Vec<f64>;
    /// Per-cell (per-node) quantities at `(t, y, ẏ)`.
    fn observe(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError>;
    /// Human-readable name of unknown `k` (e.g. "x_99, the boundary between cells 99 and 100").
    fn unknown_name(&self, k: usize) -> String {
        format!("unknown {k}")
    }
    /// Times where the forcing is not smooth; integration restarts there.
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// Writes, inside an `impl LineModel for Wrapper` block, methods of [`LineModel`] that call
/// the same method on a field: `forward_line_model!(field: method, …)`, with `method` one of
/// `initial_state`, `initial_derivative_guess`, `observe`, `unknown_name`, `breakpoints`. The
/// [`LineModel`] counterpart of [`integrators::forward_problem!`], which forwards the
/// [`CellArray`] methods.
macro_rules! forward_line_model {
    ($f:tt : $($m:ident),+ $(,)?) => {
        $($crate::line::run::forward_line_model!(@one $f $m);)+
    };
    (@one $f:tt initial_state) => {
        fn initial_state(&self) -> Vec<f64> {
            $crate::line::run::LineModel::initial_state(&self.$f)
        }
    };
    (@one $f:tt initial_derivative_guess) => {
        fn initial_derivative_guess(&self) -> Vec<f64> {
            $crate::line::run::LineModel::initial_derivative_guess(&self.$f)
        }
    };
    (@one $f:tt observe) => {
        fn observe(
            &self,
            t: f64,
            y: &[f64],
            yp: &[f64],
        ) -> Result<$crate::line::observe::Snapshot, integrators::ResidualError> {
            $crate::line::run::LineModel::observe(&self.$f, t, y, yp)
        }
    };
    (@one $f:tt unknown_name) => {
        fn unknown_name(&self, k: usize) -> String {
            $crate::line::run::LineModel::unknown_name(&self.$f, k)
        }
    };
    (@one $f:tt breakpoints) => {
        fn breakpoints(&self) -> Vec<f64> {
            $crate::line::run::LineModel::breakpoints(&self.$f)
        }
    };
}
pub(crate) use forward_line_model;

impl<E: StrainEnergy> LineModel for Line<E> {
    fn initial_state(&self) -> Vec<f64> {
        Line::initial_state(self)
    }
    fn initial_derivative_guess(&self) -> Vec<f64> {
        Line::initial_derivative_guess(self)
    }
    fn observe(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError> {
        self.snapshot(t, y, yp)
    }
    fn unknown_name(&self, k: usize) -> String {
        Line::unknown_name(self, k)
    }
    fn breakpoints(&self) -> Vec<f64> {
        match &self.right {
            crate::boundary::RightEnd::Prescribed(r) => r.breakpoints(),
            _ => Vec::new(),
        }
    }
}

/// What an integration produced at its output times (possibly partial).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::{integrate, SolveSettings};
/// use celltissue::{ArrayProblem, NeoHookean};
/// let line = discrete(NeoHookean::new(1.0)?, &LineParams::unit_cells(10))?;
/// let traj = integrate(&mut ArrayProblem::new(line), &SolveSettings::default(), &[1.0, 10.0]);
/// assert!(traj.error.is_none());
/// assert_eq!(traj.snapshots.len(), 2);
/// assert_eq!(traj.snapshots[1].x.len(), 11); // boundaries x₀ … x₁₀
/// assert!(traj.stats.steps > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    /// Observations at the output times reached (taken inside the solver's observer, so they
    /// follow the array through resizes).
    pub snapshots: Vec<Snapshot>,
    /// Final state.
    pub y_last: Vec<f64>,
    /// Work counters.
    pub stats: Stats,
    /// Error message if the solve (or an observation) failed.
    pub error: Option<String>,
}

/// Integrates `problem` from `t = 0` and observes it at the output times `t_out` (increasing,
/// `≥ 0`). Solver failures become `error` with the unknown translated into the cell or boundary.
///
/// ```no_run
/// use celltissue::line::build::{LineParams, discrete};
/// use celltissue::line::run::{integrate, SolveSettings};
/// use celltissue::{ArrayProblem, NeoHookean};
/// let mut p = LineParams::unit_cells(100);
/// p.k = 1.0.into();
/// let mut prob = ArrayProblem::new(discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap());
/// let traj = integrate(&mut prob, &SolveSettings::default(), &[0.0, 1.0]);
/// assert!(traj.error.is_none());
/// ```
pub fn integrate<A: LineModel>(
    problem: &mut ArrayProblem<A>,
    settings: &SolveSettings,
    t_out: &[f64],
) -> Trajectory {
    let y0 = problem.array.initial_state();
    let breakpoints = problem.array.breakpoints();
    let mut watch = Watch::default();
    let driven = drive_observed(problem, settings, &y0, t_out, &breakpoints, &mut watch);
    Trajectory {
        snapshots: watch.snapshots,
        error: driven.error.map(|e| match e {
            DriveError::Solver(f) => failure_message(&problem.array, &f, watch.rejected.as_ref()),
            other => other.to_string(),
        }),
        y_last: driven.y_last,
        stats: driven.stats,
    }
}

/// What [`integrate`] observes: a snapshot at every output, and the last step the model
/// rejected (for the failure message).
#[derive(Default)]
struct Watch {
    snapshots: Vec<Snapshot>,
    rejected: Option<RejectedStep>,
    refusal: Option<String>,
}

impl<A: LineModel> Observer<ArrayProblem<A>> for Watch {
    fn output(&mut self, p: &ArrayProblem<A>, t: f64, y: &[f64], yp: &[f64]) {
        match p.array.observe(t, y, yp) {
            Ok(s) => self.snapshots.push(s),
            Err(e) => {
                self.refusal = Some(format!(
                    "observation at t = {} failed: {e}",
                    integrators::error::short_number(t)
                ))
            }
        }
    }

    fn rejected(&mut self, _: &ArrayProblem<A>, step: &RejectedStep) {
        if crate::runner::rejected_by_the_model(step) {
            self.rejected = Some(step.clone());
        }
    }
}

impl<A: LineModel> DriveObserver<ArrayProblem<A>> for Watch {
    fn take_refusal(&mut self) -> Option<String> {
        self.refusal.take()
    }
}

/// Explains a solver failure in cell terms, most specific first:
///
/// 1. the model's reason for rejecting the failing step (e.g. "cell 4000 has non-positive or
///    non-finite stretch (λ = −1.2e-3, g = 1)"), the last rejected step the observer saw if
///    it started at or after the failing step, while the solver's own error says only
///    "non-finite value" or "step size too small" and the worst unknown, for a collapsing cell
///    one of its boundaries;
/// 2. the solver's error with that unknown named (`x_j (boundary between cells j and j+1)`);
/// 3. the most compressed and the most stretched cell of the last accepted state, with their
///    stretches.
fn failure_message<A: LineModel>(
    model: &A,
    f: &SolveFailure,
    rejected: Option<&RejectedStep>,
) -> String {
    let mut parts: Vec<String> = crate::runner::model_reason(f, rejected)
        .into_iter()
        .collect();
    let mut solver = f.error.to_string();
    if let Some(k) = f.error.component {
        if k < model.dim() {
            solver.push_str(&format!(" [{}]", model.unknown_name(k)));
        }
    }
    if parts.is_empty() {
        parts.push(solver);
    } else {
        parts.push(format!("solver: {solver}"));
    }
    let (t, y) = (f.partial.t_last, &f.partial.y_last);
    if y.len() == model.dim() {
        if let Ok(s) = model.observe(t, y, &vec![0.0; y.len()]) {
            let cells = || s.alpha.iter().enumerate();
            let least = cells().min_by(|a, b| a.1.total_cmp(b.1));
            let most = cells().max_by(|a, b| a.1.total_cmp(b.1));
            if let (Some((i, a)), Some((j, b))) = (least, most) {
                parts.push(format!(
                    "last accepted state t = {t}: most compressed cell {} (λ = {a:.6e}), \
                     most stretched cell {} (λ = {b:.6e})",
                    i + 1,
                    j + 1
                ));
            }
        }
    }
    parts.join("; ")
}

/// Runs one line model and fills a [`RunRecord`]: the scalar series (`length`, pressure and
/// stretch extremes, plus `end_reaction`, `mean_g`…) at `times.series` and profiles at
/// `times.profiles`.
///
/// * `model`: discrete (N cells) or continuum (`nodes` segments for the conservative scheme,
///   nodes for the thesis scheme; default `N`).
/// * Invalid configuration: a record with no data and `error` naming the key.
///
/// ```no_run
/// use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
/// use celltissue::observe::ModelKind;
/// let cfg = LineConfig { k: 0.01.into(), ..Default::default() };
/// let times = OutputTimes { series: vec![0.0, 0.5, 1.0], profiles: vec![1.0] };
/// let rec = run_line(&cfg, ModelKind::Discrete, None, &SolveSettings::default(), &times);
/// assert!(rec.error.is_none());
/// ```
pub fn run_line(
    cfg: &LineConfig,
    model: ModelKind,
    nodes: Option<usize>,
    solver: &SolveSettings,
    times: &OutputTimes,
) -> RunRecord {
    let mut parameters = serde_json::to_value(cfg).unwrap_or(serde_json::Value::Null);
    if let serde_json::Value::Object(m) = &mut parameters {
        if let Some(n) = nodes {
            m.insert("nodes".into(), n.into());
        }
    }
    let label = match model {
        ModelKind::Discrete => format!("discrete N={}", cfg.n_cells()),
        ModelKind::Continuum => format!("continuum n={}", nodes.unwrap_or(cfg.n_cells())),
    };
    let mut rec = RunRecord {
        label,
        model,
        parameters,
        series: Series::default(),
        profiles: Vec::new(),
        stats: RunStats::default(),
        divisions: Vec::new(),
        error: None,
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    };
    if let Err(e) = cfg.validate() {
        rec.error = Some(e.to_string());
        return rec;
    }
    if let Err(e) = times.check() {
        rec.error = Some(e.to_string());
        return rec;
    }
    run_with_law(cfg, cfg.law.clone(), model, nodes, solver, times, &mut rec);
    rec.reference = super::analytic::reference(cfg, &times.series, &times.profiles);
    rec
}

fn run_with_law<E: StrainEnergy + Clone>(
    cfg: &LineConfig,
    energy: E,
    model: ModelKind,
    nodes: Option<usize>,
    solver: &SolveSettings,
    times: &OutputTimes,
    rec: &mut RunRecord,
) {
    let params = cfg.params(solver.atol);
    let n = nodes.unwrap_or(cfg.n_cells());
    match (model, cfg.continuum_scheme) {
        (ModelKind::Discrete, _) => match super::build::discrete(energy, &params) {
            Ok(line) => {
                run_model(line, solver, times, rec);
            }
            Err(e) => rec.error = Some(e.to_string()),
        },
        (ModelKind::Continuum, ContinuumScheme::Conservative) => {
            match super::build::continuum(energy, &params, n) {
                Ok(line) => {
                    run_model(line, solver, times, rec);
                }
                Err(e) => rec.error = Some(e.to_string()),
            }
        }
        (ModelKind::Continuum, ContinuumScheme::Thesis) => {
            match ThesisLine::new(energy, &params, n) {
                Ok(line) => {
                    run_model(line, solver, times, rec);
                }
                Err(e) => rec.error = Some(e.to_string()),
            }
        }
    }
}

/// Integrates a built model and records its observables into `rec` (no I/O): the series
/// (`length`, pressure and stretch extremes, plus `end_reaction`, `mean_alpha`, `x0`, `cells`,
/// `mean_g`, `min_g`) at `times.series` and the profiles at `times.profiles`, through
/// [`crate::runner::run_recorded`] with [`LineRecorder`]. Returns the problem (its array
/// as the run left it, e.g. a proliferating line's division log).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::run_model;
/// use celltissue::line::{OutputTimes, SolveSettings};
/// use celltissue::observe::{ModelKind, RunRecord};
/// let line = discrete(celltissue::NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(6)).unwrap();
/// let mut rec = RunRecord { label: "six cells".into(), model: ModelKind::Discrete,
///     parameters: serde_json::Value::Null, series: Default::default(), profiles: vec![],
///     stats: Default::default(), divisions: vec![], error: None, notes: vec![], reference: None, accuracy_check: None };
/// let times = OutputTimes { series: vec![0.0, 1.0], profiles: vec![1.0] };
/// let problem = run_model(line, &SolveSettings::default(), &times, &mut rec);
/// assert!(rec.error.is_none());
/// assert_eq!((rec.series.t.len(), rec.profiles.len()), (2, 1));
/// assert_eq!(problem.array.n_cells(), 6);
/// ```
pub fn run_model<A: LineModel>(
    array: A,
    solver: &SolveSettings,
    times: &OutputTimes,
    rec: &mut RunRecord,
) -> ArrayProblem<A> {
    let y0 = array.initial_state();
    let breakpoints = array.breakpoints();
    let mut problem = ArrayProblem::new(array);
    let r = run_recorded(
        &mut problem,
        &y0,
        &breakpoints,
        solver,
        times,
        &mut LineRecorder,
    );
    rec.series = r.series;
    rec.profiles = r.profiles;
    rec.stats = r.stats;
    rec.error = r.error;
    problem
}

/// What a line run records (any [`LineModel`]: line, ring, thesis scheme, proliferating
/// line and continuum): from its [`Snapshot`], the series with the extra keys `end_reaction`,
/// `mean_alpha`, `x0`, `cells`, `mean_g`, `min_g`, and the per-cell profile; failures explained
/// in cell terms (the cell the model rejected, the boundary the solver names, the most
/// compressed cell).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::LineRecorder;
/// use celltissue::line::OutputTimes;
/// use celltissue::runner::run_recorded;
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(8)).unwrap();
/// let y0 = line.initial_state();
/// let times = OutputTimes { series: vec![0.0, 1.0], profiles: vec![] };
/// let r = run_recorded(&mut ArrayProblem::new(line), &y0, &[], &SolveSettings::default(),
///                      &times, &mut LineRecorder);
/// assert_eq!(r.series.extra["cells"], [8.0, 8.0]);
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct LineRecorder;

/// `Σ v` with Neumaier's compensation, so that a continuum's cell count `N = Σ h/L` over its
/// segments comes out as the whole number it is (101 segments of 100/101 cells add up to
/// 99.99999999999984 one by one). Eight lines; no crate is worth a dependency for them.
fn compensated_sum(v: impl IntoIterator<Item = f64>) -> f64 {
    let (mut sum, mut carry) = (0.0f64, 0.0f64);
    for x in v {
        let t = sum + x;
        carry += if sum.abs() >= x.abs() {
            (sum - t) + x
        } else {
            (x - t) + sum
        };
        sum = t;
    }
    sum + carry
}

impl<A: LineModel> Recorder<A> for LineRecorder {
    fn series_row(
        &mut self,
        array: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<SeriesRow, ObservationError> {
        let snap = array.observe(t, y, yp)?;
        // a proliferating continuum's segments stand for several cells each
        let w = snap.cell_counts.as_deref();
        let n = w.map_or(snap.alpha.len() as f64, |w| {
            compensated_sum(w.iter().copied())
        });
        let mean = |v: &[f64]| match w {
            None => v.iter().sum::<f64>() / n,
            Some(w) => compensated_sum(v.iter().zip(w).map(|(v, w)| v * w)) / n,
        };
        let extra = [
            ("end_reaction", snap.end_reaction()),
            ("mean_alpha", mean(&snap.alpha)),
            ("x0", snap.x[0]),
            ("cells", n),
            ("mean_g", mean(&snap.g)),
            (
                "min_g",
                snap.g.iter().copied().fold(f64::INFINITY, f64::min),
            ),
        ];
        Ok(SeriesRow {
            length: snap.length(),
            max_pressure: snap.max_pressure(),
            min_pressure: snap.min_pressure(),
            max_stretch: snap.max_stretch(),
            min_stretch: snap.min_stretch(),
            extra: extra.into_iter().map(|(k, v)| (k.to_string(), v)).collect(),
        })
    }

    fn profile(
        &mut self,
        array: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<Profile, ObservationError> {
        let snap = array.observe(t, y, yp)?;
        Ok(snap.profile())
    }

    fn explain(&self, array: &A, f: &SolveFailure, rejected: Option<&RejectedStep>) -> String {
        failure_message(array, f, rejected)
    }
}

/// Runs with the thesis parameters for a quick check (used by docs and tests).
///
/// ```
/// let t = celltissue::line::run::default_times(10.0, 5);
/// assert_eq!((t.series, t.profiles), (vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0], vec![10.0]));
/// ```
pub fn default_times(t_end: f64, n: usize) -> OutputTimes {
    let series = (0..=n).map(|k| t_end * k as f64 / n as f64).collect();
    OutputTimes {
        series,
        profiles: vec![t_end],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::line::build::{discrete, LineParams};
    use crate::NeoHookean;
    use integrators::observer::RejectCause;
    use integrators::{ErrorKind, RecoverableCause, SolverError};

    /// When the solver's error says only "step size too small", the model's reason from the
    /// last rejected step is put first, with the step; the solver's worst unknown is named in
    /// cell terms.
    #[test]
    fn failure_message_puts_the_models_reason_first() {
        let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
        let fail = SolveFailure {
            error: SolverError::new(ErrorKind::StepSizeTooSmall { h: 1e-15 }, 2.0, Some(1)),
            partial: Box::default(),
        };
        let rejected = RejectedStep {
            t: 2.0,
            h: 1e-3,
            cause: RejectCause::Recoverable(RecoverableCause::Rejected("cell 2 collapsed".into())),
            component: Some(1),
        };
        let m = failure_message(&line, &fail, Some(&rejected));
        assert!(
            m.starts_with("cell 2 collapsed in the step from t = 2 (h = 1.0e-3); solver: "),
            "{m}"
        );
        assert!(m.contains("[x_2 (boundary between cells 2 and 3)]"), "{m}");
        // a rejection from before the failing step is not the reason
        let earlier = RejectedStep { t: 1.0, ..rejected };
        let m = failure_message(&line, &fail, Some(&earlier));
        assert!(!m.contains("collapsed"), "{m}");
    }
}
