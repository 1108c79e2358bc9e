//! Entry points for the scenario layer: [`run_sheet`] and [`run_shear`] build the model
//! (discrete, or continuum on a grid), integrate it, and return a [`RunRecord`] with the Chapter 4
//! series and profiles (keys in [`super::observe`]). They write no files: [`crate::output`] draws
//! the VTK and PNG snapshots from the profiles.
//!
//! ```
//! use celltissue::observe::ModelKind;
//! use celltissue::runner::OutputTimes;
//! use celltissue::sheet::{run_sheet, SheetConfig};
//! use celltissue::SolveSettings;
//! let law = celltissue::NeoHookean::new(1.0)?;
//! let rec = run_sheet(&SheetConfig::default(), &law, ModelKind::Discrete, None,
//!                     &SolveSettings::default(), &OutputTimes::at(&[1.0, 2.0, 5.0, 10.0]))?;
//! assert_eq!(rec.series.t, [1.0, 2.0, 5.0, 10.0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::config::{ConfigError, RightEdge, ShearConfig, ShearForm, SheetConfig};
use super::observe::{
    shear_observables, shear_profile, shear_series_row, sheet_observables, sheet_profile,
    sheet_series_row, SheetColumns,
};
use super::shear::{ShearCellCentre, ShearColumn, ShearFields};
use super::uniaxial::UniaxialSheet;
use crate::array::{ArrayProblem, CellArray};
use crate::energy::StrainEnergy;
use crate::observe::{ModelKind, Profile, RunRecord};
use crate::runner::OutputTimes;
use crate::runner::{
    run_recorded, ObservationError, OutputTimeError, Recorder, Recording, SeriesRow,
};
use crate::settings::SolveSettings;

/// Why a run could not start. (Integrator failures do not raise this: they are reported in
/// [`RunRecord::error`] together with everything computed before the failure.)
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, run::RunError, SheetConfig};
/// use celltissue::SolveSettings;
/// let law = celltissue::NeoHookean::new(1.0).unwrap();
/// let e = run_sheet(&SheetConfig::default(), &law, ModelKind::Discrete, None,
///                   &SolveSettings::default(), &OutputTimes::at(&[-1.0])).unwrap_err();
/// assert!(matches!(e, RunError::Outputs(_)));
/// assert_eq!(e.to_string(), "invalid output request: output time -1 must be finite and >= 0");
/// ```
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Invalid configuration (names the key and its valid range).
    #[error("invalid configuration: {0}")]
    Config(#[from] ConfigError),
    /// Invalid output request.
    #[error("invalid output request: {0}")]
    Outputs(#[from] OutputTimeError),
}

fn cfg_err(key: &str, value: impl ToString, expected: &str) -> RunError {
    RunError::Config(ConfigError {
        key: key.into(),
        value: value.to_string(),
        expected: expected.into(),
    })
}

/// What a sheet run records: [`sheet_series_row`] of [`sheet_observables`] and the per-cell
/// [`sheet_profile`] with the sheet's optional columns.
struct SheetRecorder(SheetColumns);

impl<E: StrainEnergy> Recorder<UniaxialSheet<E>> for SheetRecorder {
    fn series_row(
        &mut self,
        sheet: &UniaxialSheet<E>,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<SeriesRow, ObservationError> {
        let cells = sheet.cells(t, y, yp);
        Ok(sheet_series_row(&sheet_observables(sheet, t, y, &cells)))
    }

    fn profile(
        &mut self,
        sheet: &UniaxialSheet<E>,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<Profile, ObservationError> {
        Ok(sheet_profile(t, &sheet.cells(t, y, yp), self.0))
    }
}

/// The two forms of the shear column: per-cell fields from a state.
trait ShearFieldsOf {
    fn shear_fields(&self, y: &[f64], yp: &[f64]) -> ShearFields;
}

impl<E: StrainEnergy> ShearFieldsOf for ShearColumn<E> {
    fn shear_fields(&self, y: &[f64], yp: &[f64]) -> ShearFields {
        self.fields(y, yp)
    }
}

impl<E: StrainEnergy> ShearFieldsOf for ShearCellCentre<E> {
    fn shear_fields(&self, y: &[f64], yp: &[f64]) -> ShearFields {
        self.fields(y, yp)
    }
}

/// Runs either form of the shear column from `y0` and records it.
fn record_column<A: CellArray + ShearFieldsOf>(
    col: A,
    y0: &[f64],
    solver: &SolveSettings,
    out: &OutputTimes,
) -> Recording {
    run_recorded(
        &mut ArrayProblem::new(col),
        y0,
        &[],
        solver,
        out,
        &mut ShearRecorder,
    )
}

/// What a shear-column run records: [`shear_series_row`] and [`shear_profile`] of its fields.
struct ShearRecorder;

impl<A: ShearFieldsOf> Recorder<A> for ShearRecorder {
    fn series_row(
        &mut self,
        col: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<SeriesRow, ObservationError> {
        Ok(shear_series_row(&shear_observables(
            t,
            &col.shear_fields(y, yp),
        )))
    }

    fn profile(
        &mut self,
        col: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<Profile, ObservationError> {
        Ok(shear_profile(t, &col.shear_fields(y, yp)))
    }
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
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_sheet, SheetConfig};
/// use celltissue::SolveSettings;
/// let cfg = SheetConfig { cells_x: 4, cells_y: 3, ..Default::default() };
/// let law = celltissue::NeoHookean::new(1.0)?;
/// let out = OutputTimes { series: vec![0.0, 2.0], profiles: vec![2.0] };
/// let rec = run_sheet(&cfg, &law, ModelKind::Discrete, None, &SolveSettings::default(), &out)?;
/// assert!(rec.error.is_none());
/// assert_eq!(rec.profiles[0].pressure.len(), 12); // one value per cell
/// // a bad grid is refused before anything runs, naming the key
/// let e = run_sheet(&cfg, &law, ModelKind::Discrete, Some((8, 6)), &SolveSettings::default(), &out);
/// assert!(e.unwrap_err().to_string().contains("grid"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_sheet<E: StrainEnergy>(
    cfg: &SheetConfig,
    law: &E,
    model: ModelKind,
    grid: Option<(usize, usize)>,
    solver: &SolveSettings,
    out: &OutputTimes,
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
    out.check()?;
    let sheet = UniaxialSheet::continuum(law, &cfg.params(), n, m)
        .map_err(|e| cfg_err("sheet", "", &e.to_string()))?
        .with_cell_atol(solver.atol);
    let y0 = sheet.initial_state();
    let spacing = sheet.spacing();
    let mut recorder = SheetRecorder(SheetColumns::of(&sheet));
    let mut problem = ArrayProblem::new(sheet);
    // a prescribed edge's ramp end is a kink in l''(t): the solver restarts there
    let breakpoints = match cfg.right {
        RightEdge::Prescribed => cfg.ramp.breakpoints(),
        RightEdge::Free => Vec::new(),
    };
    let r = run_recorded(&mut problem, &y0, &breakpoints, solver, out, &mut recorder);
    let parameters = serde_json::json!({
        "config": cfg,
        "drag_K": cfg.drag(),
        "grid": [n, m],
        "spacing": [spacing.0, spacing.1],
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
    Ok(record(label, model, parameters, r))
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
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::runner::OutputTimes;
/// use celltissue::sheet::{run_shear, ShearConfig};
/// use celltissue::SolveSettings;
/// let cfg = ShearConfig { cells: 5, force: 0.1, ..Default::default() };
/// let law = celltissue::NeoHookean::new(1.0)?;
/// let rec = run_shear(&cfg, &law, ModelKind::Discrete, None, &SolveSettings::default(),
///                     &OutputTimes::at(&[0.0, 200.0]))?;
/// // steady simple shear of a neo-Hookean cell: μ tan θ = F_A
/// assert!((rec.series.max_stretch[1] - 0.1).abs() < 1e-4);
/// assert!(rec.series.extra["shear_spread"][1] < 1e-4); // every cell at the same angle
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_shear<E: StrainEnergy>(
    cfg: &ShearConfig,
    law: &E,
    model: ModelKind,
    grid: Option<usize>,
    solver: &SolveSettings,
    out: &OutputTimes,
) -> Result<RunRecord, RunError> {
    cfg.validate()?;
    solver
        .options()
        .map_err(|e| cfg_err("solver", "options", &e.to_string()))?;
    out.check()?;
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
    let bad = |e: super::shear::ShearBuildError| cfg_err("shear", "", &e.to_string());
    let r = match cfg.form {
        ShearForm::Edge => {
            let col = ShearColumn::continuum(law, &params, m).map_err(bad)?;
            let y0 = col.initial_state();
            record_column(col, &y0, solver, out)
        }
        ShearForm::CellCentre => {
            let col = ShearCellCentre::new(law, &params).map_err(bad)?;
            let y0 = col.initial_state();
            record_column(col, &y0, solver, out)
        }
    };
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
    Ok(record(label, model, parameters, r))
}

/// A sheet or shear-column record from its label, parameters and recording.
fn record(
    label: String,
    model: ModelKind,
    parameters: serde_json::Value,
    r: Recording,
) -> RunRecord {
    RunRecord {
        label,
        model,
        parameters,
        series: r.series,
        profiles: r.profiles,
        stats: r.stats,
        divisions: Vec::new(),
        error: r.error,
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    }
}
