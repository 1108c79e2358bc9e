//! [`run_line`]: one line run from a validated [`LineConfig`] to a [`RunRecord`] — build the
//! discrete or continuum array, integrate it, and record series and profiles at the requested
//! times. No I/O; the CLI writes the record, benches call [`integrate`] directly.
//!
//! On solver failure the record holds everything computed up to the failure and
//! `error: Some(message)`; outputs never contain NaN.

use super::array::Line;
use super::config::{ContinuumScheme, LineConfig, LineLaw};
use super::observe::Snapshot;
use super::thesis_scheme::ThesisLine;
use crate::array::{ArrayProblem, CellArray};
use crate::energy::StrainEnergy;
use crate::observe::{ModelKind, RunRecord, RunStats, Series};
use integrators::{MethodKind, Options, ResidualError, Stats};
use std::time::Instant;

/// Integrator choice and tolerances. `atol` is in cell units: positions get `atol × L₀`
/// (local reference cell length), growth stretches `atol` (DESIGN.md "Tolerances in cell
/// units").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveSettings {
    /// Method.
    pub method: MethodKind,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance in cell units.
    pub atol: f64,
}

impl Default for SolveSettings {
    fn default() -> Self {
        Self {
            method: MethodKind::Bdf,
            rtol: 1e-6,
            atol: 1e-8,
        }
    }
}

/// Requested output times (each list increasing, `t ≥ 0`; the run starts at `t = 0`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputTimes {
    /// Times of the scalar series.
    pub series: Vec<f64>,
    /// Times of the profiles.
    pub profiles: Vec<f64>,
}

impl OutputTimes {
    /// Sorted, deduplicated union of both lists.
    pub fn merged(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self
            .series
            .iter()
            .chain(&self.profiles)
            .copied()
            .filter(|t| t.is_finite())
            .collect();
        t.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
        t.dedup();
        t
    }
}

/// A line model that can be observed: the discrete/conservative [`Line`] and the thesis scheme.
pub trait LineModel: CellArray {
    /// Initial state.
    fn initial_state(&self) -> Vec<f64>;
    /// Initial guess for `ẏ`.
    fn initial_derivative_guess(&self) -> Vec<f64>;
    /// Per-cell (per-node) quantities at `(t, y, ẏ)`.
    fn observe(&self, t: f64, y: &[f64], yp: &[f64]) -> Result<Snapshot, ResidualError>;
}

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
}

/// States at output times produced by an integration (possibly partial).
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    /// Output times reached.
    pub t: Vec<f64>,
    /// States.
    pub y: Vec<Vec<f64>>,
    /// Derivatives.
    pub yp: Vec<Vec<f64>>,
    /// Work counters.
    pub stats: Stats,
    /// Error message if the solve failed.
    pub error: Option<String>,
}

/// Integrates `model` from `t = 0` to the output times `t_out` (increasing, may start at 0).
/// Errors that name an unknown are translated to the cell by the caller's message.
pub fn integrate<A: LineModel>(
    problem: &mut ArrayProblem<A>,
    settings: &SolveSettings,
    t_out: &[f64],
) -> Trajectory {
    let y0 = problem.array.initial_state();
    let opts = Options {
        rtol: settings.rtol,
        atol: settings.atol,
        ..Default::default()
    };
    crate::line::run::solver_glue::solve(problem, settings.method, opts, &y0, t_out)
}

/// The bridge to the `integrators` driver (one place to adapt if its API changes).
pub(crate) mod solver_glue {
    use super::{LineModel, Trajectory};
    use crate::array::ArrayProblem;
    use integrators::{MethodKind, Options};

    /// Runs the integrator; returns what was computed.
    pub fn solve<A: LineModel>(
        problem: &mut ArrayProblem<A>,
        method: MethodKind,
        opts: Options,
        y0: &[f64],
        t_out: &[f64],
    ) -> Trajectory {
        let _ = (problem, method, opts, y0, t_out);
        Trajectory {
            error: Some("integrators::Solver is not available yet".into()),
            ..Default::default()
        }
    }
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
    };
    if let Err(e) = cfg.validate() {
        rec.error = Some(e.to_string());
        return rec;
    }
    if let Some(&bad) = times
        .series
        .iter()
        .chain(&times.profiles)
        .find(|t| !(t.is_finite() && **t >= 0.0))
    {
        rec.error = Some(format!("output time {bad} must be finite and >= 0"));
        return rec;
    }
    match &cfg.law {
        LineLaw::NeoHookean(e) => run_with_law(cfg, *e, model, nodes, solver, times, &mut rec),
        LineLaw::MooneyRivlin(e) => run_with_law(cfg, *e, model, nodes, solver, times, &mut rec),
        LineLaw::Ogden(e) => run_with_law(cfg, e.clone(), model, nodes, solver, times, &mut rec),
    }
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
            Ok(line) => run_model(line, solver, times, rec),
            Err(e) => rec.error = Some(e.to_string()),
        },
        (ModelKind::Continuum, ContinuumScheme::Conservative) => {
            match super::build::continuum(energy, &params, n) {
                Ok(line) => run_model(line, solver, times, rec),
                Err(e) => rec.error = Some(e.to_string()),
            }
        }
        (ModelKind::Continuum, ContinuumScheme::Thesis) => {
            match ThesisLine::new(energy, &params, n) {
                Ok(line) => run_model(line, solver, times, rec),
                Err(e) => rec.error = Some(e.to_string()),
            }
        }
    }
}

/// Integrates a built model and records its observables into `rec` (no I/O).
pub fn run_model<A: LineModel>(
    array: A,
    solver: &SolveSettings,
    times: &OutputTimes,
    rec: &mut RunRecord,
) {
    let start = Instant::now();
    let t_out = times.merged();
    let mut problem = ArrayProblem::new(array);
    let traj = integrate(&mut problem, solver, &t_out);
    rec.stats = RunStats {
        steps: traj.stats.steps,
        residual_calls: traj.stats.residual_calls,
        jacobians: traj.stats.jacobian_evals,
        wall_seconds: start.elapsed().as_secs_f64(),
        extra: [
            ("rejected_steps", traj.stats.rejected_steps),
            ("directional_calls", traj.stats.directional_calls),
            ("factorizations", traj.stats.factorizations),
            ("newton_iterations", traj.stats.newton_iterations),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v as f64))
        .collect(),
    };
    rec.error = traj.error.clone();
    record(&problem.array, &traj, times, rec);
}

/// Fills series and profiles from a trajectory (skips any non-finite snapshot and reports it).
pub fn record<A: LineModel>(
    array: &A,
    traj: &Trajectory,
    times: &OutputTimes,
    rec: &mut RunRecord,
) {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs());
    let mut extra_names: Vec<&str> = vec!["end_reaction", "mean_alpha"];
    for (k, &t) in traj.t.iter().enumerate() {
        let snap = match array.observe(t, &traj.y[k], &traj.yp[k]) {
            Ok(s) => s,
            Err(e) => {
                if rec.error.is_none() {
                    rec.error = Some(format!("observation at t = {t} failed: {e:?}"));
                }
                break;
            }
        };
        let finite = snap
            .pressure
            .iter()
            .chain(&snap.alpha)
            .chain(&snap.x)
            .all(|v| v.is_finite());
        if !finite {
            if rec.error.is_none() {
                rec.error = Some(format!("non-finite state at t = {t}"));
            }
            break;
        }
        if times.series.iter().any(|&s| close(s, t)) {
            let s = &mut rec.series;
            s.t.push(t);
            s.length.push(snap.length());
            s.max_pressure.push(snap.max_pressure());
            s.min_pressure.push(snap.min_pressure());
            s.max_stretch.push(snap.max_stretch());
            s.min_stretch.push(snap.min_stretch());
            let mean_alpha = snap.alpha.iter().sum::<f64>() / snap.alpha.len() as f64;
            s.extra
                .entry("end_reaction".into())
                .or_default()
                .push(snap.end_reaction());
            s.extra
                .entry("mean_alpha".into())
                .or_default()
                .push(mean_alpha);
            s.extra.entry("x0".into()).or_default().push(snap.x[0]);
            if snap.g.iter().any(|&g| g != 1.0) {
                let mean_g = snap.g.iter().sum::<f64>() / snap.g.len() as f64;
                s.extra.entry("mean_g".into()).or_default().push(mean_g);
                extra_names.push("mean_g");
            }
        }
        if times.profiles.iter().any(|&s| close(s, t)) {
            rec.profiles.push(snap.profile());
        }
    }
    // keep every extra series aligned with `t`
    let n = rec.series.t.len();
    rec.series.extra.retain(|_, v| v.len() == n);
}

/// Runs with the thesis parameters for a quick check (used by docs and tests).
pub fn default_times(t_end: f64, n: usize) -> OutputTimes {
    let series = (0..=n).map(|k| t_end * k as f64 / n as f64).collect();
    OutputTimes {
        series,
        profiles: vec![t_end],
    }
}
