//! Entry points for the scenario layer: [`run_sheet`] and [`run_shear`] build the model
//! (discrete, or continuum on a grid), integrate it, and return a [`RunRecord`] with the Chapter 4
//! series and profiles (keys in [`super::observe`]). They write no files: [`crate::output`] draws
//! the VTK and PNG snapshots from the profiles.
//!
//! ```
//! use celltissue::observe::ModelKind;
//! use celltissue::sheet::{run::Outputs, run_sheet, SheetConfig};
//! use celltissue::SolveSettings;
//! let law = celltissue::NeoHookean::new(1.0)?;
//! let rec = run_sheet(&SheetConfig::default(), &law, ModelKind::Discrete, None,
//!                     &SolveSettings::default(), &Outputs::at(&[1.0, 2.0, 5.0, 10.0]))?;
//! assert_eq!(rec.series.t, [1.0, 2.0, 5.0, 10.0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::config::{ConfigError, ShearConfig, ShearForm, SheetConfig};
use super::observe::{
    push_shear_series, push_sheet_series, shear_observables, shear_profile, sheet_observables,
    sheet_profile, SheetColumns,
};
use super::shear::{ShearCellCentre, ShearColumn, ShearFields};
use super::uniaxial::UniaxialSheet;
use crate::array::{ArrayProblem, CellArray};
use crate::drive::drive;
use crate::energy::StrainEnergy;
use crate::observe::{ModelKind, RunRecord, RunStats, Series};
use crate::settings::SolveSettings;
use integrators::Stats;
use std::time::Instant;

/// What to record (the runners write no files: `crate::output` does, from the record).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outputs {
    /// Times of the scalar series (increasing, `>= 0`; `t = 0` is the initial state).
    pub times: Vec<f64>,
    /// Times of the per-cell profiles (from which the writers draw VTK and PNG snapshots).
    pub profile_times: Vec<f64>,
}

impl Outputs {
    /// Series at `times`, no profiles, no files.
    pub fn at(times: &[f64]) -> Self {
        Self {
            times: times.to_vec(),
            ..Default::default()
        }
    }
}

/// Why a run could not start. (Integrator failures do not raise this: they are reported in
/// [`RunRecord::error`] together with everything computed before the failure.)
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Invalid configuration (names the key and its valid range).
    #[error("invalid configuration: {0}")]
    Config(#[from] ConfigError),
    /// Invalid output request.
    #[error("invalid output request: {0}")]
    Outputs(String),
}

fn cfg_err(key: &str, value: impl ToString, expected: &str) -> RunError {
    RunError::Config(ConfigError {
        key: key.into(),
        value: value.to_string(),
        expected: expected.into(),
    })
}

/// All output times (series ∪ profiles), sorted and deduplicated, after checking them.
pub(crate) fn all_times(out: &Outputs) -> Result<Vec<f64>, RunError> {
    let mut t: Vec<f64> = out
        .times
        .iter()
        .chain(&out.profile_times)
        .copied()
        .collect();
    if let Some(bad) = t.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
        return Err(RunError::Outputs(format!(
            "output time {bad} must be finite and >= 0"
        )));
    }
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    t.dedup();
    Ok(t)
}

fn contains(ts: &[f64], t: f64) -> bool {
    ts.contains(&t)
}

/// What [`integrate`] returns: `(t, y)` at the reached output times, the work counters, and the
/// solver's error message if it failed (the states then stop at the failure).
pub type Integrated = (Vec<(f64, Vec<f64>)>, Stats, Option<String>);

/// Per-cell shear fields from a state (edge or cell-centre form).
type FieldsFn<'a> = Box<dyn Fn(&[f64]) -> ShearFields + 'a>;

/// Integrates a cell array from `(0, y0)` with [`drive`] and returns the states at `times`
/// (`t = 0` after the consistent initialisation). On failure returns the states reached and
/// the error message.
pub fn integrate<A: CellArray>(
    problem: &mut ArrayProblem<A>,
    y0: &[f64],
    times: &[f64],
    solver: &SolveSettings,
) -> Integrated {
    let mut states = Vec::new();
    let driven = drive(problem, solver, y0, times, &[], |_, t, y, _| {
        states.push((t, y.to_vec()));
        Ok(())
    });
    (states, driven.stats, driven.error.map(|e| e.to_string()))
}

/// Runs the uniaxial sheet (docs/model.md §4.1–4.3).
///
/// * `model`: [`ModelKind::Discrete`] (`N × M` cells) or [`ModelKind::Continuum`] (conservative
///   scheme on `grid = (n, m)`; default `(2N, 2M)`). `grid` with a discrete model must be `None`
///   or `(N, M)`.
/// * `solver`: method and tolerances (`atol` in cell units, scaled by `h_X`, `h_Y`).
/// * `out`: series and profile times.
///
/// Series extra keys: `mean_pressure`, `mean_height`, `mean_stretch_z_over_y`,
/// `boundary_mismatch_mean`, `boundary_mismatch_max`, `max_stretch_y`, `min_stretch_y`, and
/// `mean_width` for a growing sheet.
pub fn run_sheet<E: StrainEnergy>(
    cfg: &SheetConfig,
    law: &E,
    model: ModelKind,
    grid: Option<(usize, usize)>,
    solver: &SolveSettings,
    out: &Outputs,
) -> Result<RunRecord, RunError> {
    cfg.validate()?;
    solver
        .options()
        .map_err(|e| cfg_err("solver", "options", &e.to_string()))?;
    let (n, m) = match (model, grid) {
        (ModelKind::Discrete, None) => (cfg.cells_x, cfg.cells_y),
        (ModelKind::Discrete, Some(g)) if g == (cfg.cells_x, cfg.cells_y) => g,
        (ModelKind::Discrete, Some(g)) => {
            return Err(cfg_err(
                "grid",
                format!("{g:?}"),
                "a discrete sheet has the grid (cells_x, cells_y); use model = continuum",
            ))
        }
        (ModelKind::Continuum, None) => (2 * cfg.cells_x, 2 * cfg.cells_y),
        (ModelKind::Continuum, Some((a, b))) if a >= 1 && b >= 1 => (a, b),
        (ModelKind::Continuum, Some(g)) => {
            return Err(cfg_err("grid", format!("{g:?}"), "both sizes must be >= 1"))
        }
    };
    let times = all_times(out)?;
    let sheet = UniaxialSheet::continuum(law, &cfg.params(), n, m)
        .map_err(|e| cfg_err("sheet", "", &e.to_string()))?
        .with_cell_atol(solver.atol);
    let y0 = sheet.initial_state();
    let mut problem = ArrayProblem::new(sheet);
    let start = Instant::now();
    let (states, stats, error) = integrate(&mut problem, &y0, &times, solver);
    let wall = start.elapsed().as_secs_f64();
    let sheet = &problem.array;

    let mut series = Series::default();
    let mut profiles = Vec::new();
    for (t, y) in &states {
        let cells = sheet.cells(*t, y);
        if contains(&out.times, *t) {
            push_sheet_series(&mut series, &sheet_observables(sheet, *t, y, &cells));
        }
        if contains(&out.profile_times, *t) {
            profiles.push(sheet_profile(*t, &cells, SheetColumns::of(sheet)));
        }
    }
    let parameters = serde_json::json!({
        "config": cfg,
        "drag_K": cfg.drag(),
        "grid": [n, m],
        "spacing": [sheet.spacing().0, sheet.spacing().1],
        "shear_modulus": law.shear_modulus(),
        "method": solver.method.name(),
        "rtol": solver.rtol,
        "atol": solver.atol,
    });
    let label = format!(
        "{} sheet {}x{} {:?} m={} K={}",
        match model {
            ModelKind::Discrete => "discrete",
            ModelKind::Continuum => "continuum",
        },
        n,
        m,
        cfg.top,
        cfg.drag_exponent,
        cfg.drag()
    )
    .to_lowercase();
    Ok(RunRecord {
        label,
        model,
        parameters,
        series,
        profiles,
        stats: RunStats::from_stats(&stats, wall),
        divisions: Vec::new(),
        error,
        reference: None,
    })
}

/// Runs the shear column (docs/model.md §4.4–4.6).
///
/// * `model`: discrete (`M` cells, edge or cell-centre form per `cfg.form`) or continuum
///   (edge-form conservative scheme on `grid` segments, default `4M`; cell-centre form is
///   discrete only).
///
/// Series: `length` = top displacement, `max/min_stretch` = `max/min tan θ`; extra keys
/// `top_displacement`, `shear_spread` (max − min tan θ), `mean_shear_angle`. Profiles against the
/// reference height: `stretch` = `tan θ`, extra `theta`, `tau`, `x_edge`.
pub fn run_shear<E: StrainEnergy>(
    cfg: &ShearConfig,
    law: &E,
    model: ModelKind,
    grid: Option<usize>,
    solver: &SolveSettings,
    out: &Outputs,
) -> Result<RunRecord, RunError> {
    cfg.validate()?;
    solver
        .options()
        .map_err(|e| cfg_err("solver", "options", &e.to_string()))?;
    let times = all_times(out)?;
    let params = cfg.params();
    let m = match (model, grid, cfg.form) {
        (ModelKind::Continuum, _, ShearForm::CellCentre) => {
            return Err(cfg_err(
                "form",
                "cell_centre",
                "the cell-centre form is discrete only; use form = \"edge\" for the continuum",
            ))
        }
        (ModelKind::Discrete, None, _) => cfg.cells,
        (ModelKind::Discrete, Some(g), _) if g == cfg.cells => g,
        (ModelKind::Discrete, Some(g), _) => {
            return Err(cfg_err("grid", g, "a discrete column has grid = cells"))
        }
        (ModelKind::Continuum, None, _) => 4 * cfg.cells,
        (ModelKind::Continuum, Some(g), _) if g >= 1 => g,
        (ModelKind::Continuum, Some(g), _) => return Err(cfg_err("grid", g, "must be >= 1")),
    };
    let start = Instant::now();
    let bad = |e: super::shear::ShearBuildError| cfg_err("shear", "", &e.to_string());
    let (states, stats, error, fields): (_, _, _, FieldsFn<'_>) = match cfg.form {
        ShearForm::Edge => {
            let col = ShearColumn::continuum(law, &params, m).map_err(bad)?;
            let y0 = col.initial_state();
            let mut problem = ArrayProblem::new(col);
            let (s, st, e) = integrate(&mut problem, &y0, &times, solver);
            let col = problem.array;
            (s, st, e, Box::new(move |y| col.fields(y)))
        }
        ShearForm::CellCentre => {
            let col = ShearCellCentre::new(law, &params).map_err(bad)?;
            let y0 = col.initial_state();
            let mut problem = ArrayProblem::new(col);
            let (s, st, e) = integrate(&mut problem, &y0, &times, solver);
            let col = problem.array;
            (s, st, e, Box::new(move |y| col.fields(y)))
        }
    };
    let wall = start.elapsed().as_secs_f64();
    let mut series = Series::default();
    let mut profiles = Vec::new();
    for (t, y) in &states {
        let f = fields(y);
        if contains(&out.times, *t) {
            push_shear_series(&mut series, &shear_observables(*t, &f));
        }
        if contains(&out.profile_times, *t) {
            profiles.push(shear_profile(*t, &f));
        }
    }
    let parameters = serde_json::json!({
        "config": cfg,
        "drag_K": cfg.drag(),
        "grid": m,
        "shear_modulus": law.shear_modulus(),
        "method": solver.method.name(),
        "rtol": solver.rtol,
        "atol": solver.atol,
    });
    let label = format!(
        "{} shear M={} m={} {:?}",
        match model {
            ModelKind::Discrete => "discrete",
            ModelKind::Continuum => "continuum",
        },
        cfg.cells,
        m,
        cfg.form
    )
    .to_lowercase();
    Ok(RunRecord {
        label,
        model,
        parameters,
        series,
        profiles,
        stats: RunStats::from_stats(&stats, wall),
        divisions: Vec::new(),
        error,
        reference: None,
    })
}
