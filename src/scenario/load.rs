//! From a scenario file (plus `--set` overrides) to a validated [`Scenario`]: parse the TOML,
//! apply overrides, expand the sweep into one [`RunSpec`] per value and discretisation, and
//! validate every run's configuration — all before anything is run or written.

use super::error::{deserialize_at, ScenarioError};
use super::model::{parse_model, ModelConfig};
use super::overrides::{apply, parse_set};
use super::schema::{PlotSettings, RawScenario};
pub use super::sweep::SweepPoint;
use super::sweep::{expand, swept_keys, SweepSection};
use super::times::parse_times;
use crate::observe::ModelKind;
use crate::runner::OutputTimes;
use crate::settings::SolveSettings;
use integrators::LinearSolverChoice;
use std::path::Path;

/// One run: one discretisation of one parameter set.
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::scenario::{execute, load_str, ModelConfig};
/// let text = "name = \"one\"\n[output]\nseries = [0, 1]\nprofiles = [1]\n[model]\n\
///             kind = \"line\"\ncells = 8\nnodes = 16";
/// let s = load_str(text, "one.toml".as_ref(), &[])?;
/// let spec = &s.runs[1];
/// assert_eq!((spec.label.as_str(), spec.model, spec.nodes), ("continuum", ModelKind::Continuum, Some(16)));
/// assert!(matches!(spec.config, ModelConfig::Line(_)));
/// let rec = execute::run_spec(spec); // one run, as the CLI runs it
/// assert_eq!(rec.profiles[0].x_ref.len(), 16);
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Label used in legends and file names: model, then the swept value (`"discrete K=0.01"`).
    pub label: String,
    /// Discrete or continuum.
    pub model: ModelKind,
    /// Continuum grid size (`None`: the model's default).
    pub nodes: Option<usize>,
    /// Continuum grid of a sheet `(n, m)` (`None`: the model's default).
    pub grid: Option<(usize, usize)>,
    /// The model configuration (validated).
    pub config: ModelConfig,
    /// Integrator and tolerances.
    pub solver: SolveSettings,
    /// Output times.
    pub times: OutputTimes,
    /// The sweep point, if the scenario sweeps.
    pub sweep: Option<SweepPoint>,
    /// The earlier run (index in [`Scenario::runs`]) this one repeats exactly: a discrete run
    /// of a sweep point that differs from that run's only in what a continuum alone reads
    /// (`nodes`, `continuum_scheme`). `run` solves it once and gives both its record.
    pub repeats: Option<usize>,
}

impl RunSpec {
    /// Cell (or grid point) values the run records over its profile times: the profile times
    /// times the cells of a discrete model or the points of a continuum grid (for a dividing
    /// line, its initial cells: a lower bound). 0 for a registered mode, which the scenario
    /// cannot see into.
    ///
    /// ```
    /// use celltissue::scenario::load_str;
    /// let text = "name = \"p\"\n[output]\nseries = [1]\nprofiles = [0.5, 1]\n[model]\n\
    ///             kind = \"line\"\ncells = 50\nnodes = 11";
    /// let s = load_str(text, "p.toml".as_ref(), &[])?;
    /// let values: Vec<f64> = s.runs.iter().map(|r| r.profile_values()).collect();
    /// assert_eq!(values, [100.0, 22.0]); // discrete: 2 × 50 cells; continuum: 2 × 11 nodes
    /// # Ok::<(), celltissue::scenario::ScenarioError>(())
    /// ```
    pub fn profile_values(&self) -> f64 {
        let continuum = self.model == ModelKind::Continuum;
        let points = match &self.config {
            ModelConfig::Line(c) if continuum => self.nodes.unwrap_or(c.n_cells()),
            ModelConfig::Line(c) => c.n_cells(),
            ModelConfig::Proliferating(c) if continuum => self.nodes.unwrap_or(c.line.n_cells()),
            ModelConfig::Proliferating(c) => c.line.n_cells(),
            ModelConfig::Sheet(c, _) if continuum => {
                let (n, m) = self.grid.unwrap_or((2 * c.cells_x, 2 * c.cells_y));
                n.saturating_mul(m)
            }
            ModelConfig::Sheet(c, _) => c.cells_x.saturating_mul(c.cells_y),
            ModelConfig::Shear(c, _) if continuum => {
                self.nodes.unwrap_or(c.cells.saturating_mul(4))
            }
            ModelConfig::Shear(c, _) => c.cells,
            ModelConfig::Mode(_) => 0,
        };
        points as f64 * self.times.profiles.len() as f64
    }
}

/// The sweep as declared.
///
/// ```
/// use celltissue::scenario::load_str;
/// let text = "name = \"sw\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncells = 5\n\
///             models = [\"discrete\"]\n[sweep]\nparameter = \"K\"\nvalues = [0.1, 1]";
/// let info = load_str(text, "sw.toml".as_ref(), &[])?.sweep.unwrap();
/// assert_eq!((info.key.as_str(), info.name.as_str()), ("model.K", "K"));
/// assert_eq!(info.ensemble, None);
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SweepInfo {
    /// Full dotted key (`"model.K"`; several joined by commas).
    pub key: String,
    /// Short name (`"K"`; several joined by commas, as [`SweepPoint::name`]).
    pub name: String,
    /// Every swept key, in declaration order (`["model.k1", "model.drag_exponent"]`).
    pub parameters: Vec<String>,
    /// The ensemble's seed key (`"model.division.seed"`) when the sweep has an ensemble.
    pub ensemble: Option<String>,
}

/// A validated scenario, ready to run.
///
/// ```
/// use celltissue::scenario::{bundled, load_str};
/// let text = bundled::text("fig2_5").unwrap();
/// let s = load_str(text, "fig2_5.toml".as_ref(), &["model.cells=20".into()])?;
/// assert_eq!((s.name.as_str(), s.figure.as_deref()), ("fig2_5", Some("2.5")));
/// assert_eq!(s.runs.len(), 8); // 4 values of K × discrete, continuum
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Name (`"scenario"` in `summary.json`).
    pub name: String,
    /// What it runs.
    pub description: String,
    /// Thesis figure, e.g. `"2.5"`.
    pub figure: Option<String>,
    /// Plot settings.
    pub plots: PlotSettings,
    /// The sweep, if any.
    pub sweep: Option<SweepInfo>,
    /// Runs in order (sweep value, then discretisation).
    pub runs: Vec<RunSpec>,
    /// The scenario table after `--set` overrides (written beside the results).
    pub table: toml::Table,
}

/// Reads, overrides, expands and validates a scenario file.
///
/// ```no_run
/// let s = celltissue::scenario::load("models/fig2_5.toml", &["model.cells=20".to_string()])?;
/// assert_eq!(s.runs.len(), 8);
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn load(path: impl AsRef<Path>, sets: &[String]) -> Result<Scenario, ScenarioError> {
    load_with(path, sets, &[])
}

/// As [`load`], also removing the keys `unsets` (`--unset`, dotted) before the overrides, so
/// that they take their defaults.
///
/// ```no_run
/// // fig3_3 sets the BDF-only `solver.jacobian_age`: unset it to run another method
/// let s = celltissue::scenario::load_with(
///     "models/fig3_3.toml",
///     &["solver.method=radau".to_string()],
///     &["solver.jacobian_age".to_string()],
/// )?;
/// assert_eq!(s.runs[0].solver.method.name(), "radau");
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn load_with(
    path: impl AsRef<Path>,
    sets: &[String],
    unsets: &[String],
) -> Result<Scenario, ScenarioError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    load_str_with(&text, path, sets, unsets)
}

/// As [`load`], from text (`origin` is used in messages).
///
/// ```
/// use celltissue::scenario::load_str;
/// let text = "name = \"demo\"\n[output]\nseries = [1, 10]\n[model]\nkind = \"line\"\ncells = 20\n\
///             K = 0.1\n[sweep]\nparameter = \"K\"\nvalues = [0.1, 1.0]";
/// let s = load_str(text, "demo.toml".as_ref(), &["model.cells=40".to_string()])?;
/// assert_eq!((s.name.as_str(), s.runs.len()), ("demo", 4)); // 2 values × discrete, continuum
/// let bad = "name = \"x\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncels = 3";
/// let e = load_str(bad, "x.toml".as_ref(), &[]);
/// assert!(e.unwrap_err().to_string().contains("model.cels"));
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn load_str(text: &str, origin: &Path, sets: &[String]) -> Result<Scenario, ScenarioError> {
    load_str_with(text, origin, sets, &[])
}

/// As [`load_str`], also removing the keys `unsets` before the overrides (see [`load_with`]).
///
/// ```
/// use celltissue::scenario::load_str_with;
/// let text = "name = \"u\"\n[solver]\njacobian_age = 100\n[output]\nseries = [1]\n\
///             [model]\nkind = \"line\"\ncells = 5";
/// let radau = ["solver.method=radau".to_string()];
/// assert!(load_str_with(text, "u.toml".as_ref(), &radau, &[]).is_err()); // BDF-only key
/// let unset = ["solver.jacobian_age".to_string()];
/// let s = load_str_with(text, "u.toml".as_ref(), &radau, &unset)?;
/// assert_eq!(s.runs[0].solver.method.name(), "radau");
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn load_str_with(
    text: &str,
    origin: &Path,
    sets: &[String],
    unsets: &[String],
) -> Result<Scenario, ScenarioError> {
    let mut table: toml::Table =
        toml::from_str(text).map_err(|e| ScenarioError::syntax(origin, &e.to_string()))?;
    let mut set_keys = Vec::new();
    for key in unsets {
        let path = super::overrides::parse_path(key).ok_or_else(|| {
            ScenarioError::set(
                key,
                "the key must be dotted names, e.g. solver.jacobian_age",
            )
        })?;
        if let Some(s) = swept_under(&table, &path)? {
            return Err(ScenarioError::key(
                key.as_str(),
                format!(
                    "cannot be unset: `{s}` is swept, so every run takes it from [sweep]; \
                     change the swept values instead"
                ),
            ));
        }
        super::overrides::remove(&mut table, &path)
            .map_err(|e| e.with_note(&format!("from --unset {key}")))?;
    }
    for arg in sets {
        let (key, value) = parse_set(arg)?;
        apply(&mut table, &key, value).map_err(|e| e.with_note(&format!("from --set {arg}")))?;
        set_keys.push((arg, key));
    }
    check_set_against_sweep(&table, &set_keys)?;
    resolve(table)
}

/// A `--set` of a swept key (or of a key inside one) would be replaced by every swept value:
/// an error naming the conflict, never a silent ignore.
fn check_set_against_sweep(
    table: &toml::Table,
    sets: &[(&String, Vec<String>)],
) -> Result<(), ScenarioError> {
    for (arg, key) in sets {
        if let Some(s) = swept_under(table, key)? {
            return Err(ScenarioError::set(
                arg,
                format!(
                    "conflicts with the sweep: `{s}` is swept, so this value would be replaced \
                     by every swept value. Change the swept values instead (e.g. --set \
                     sweep.values=[0.1] for a one-parameter sweep), or edit [sweep]"
                ),
            ));
        }
    }
    Ok(())
}

/// The swept key that `key` is or lies inside, if the table sweeps one.
fn swept_under(table: &toml::Table, key: &[String]) -> Result<Option<String>, ScenarioError> {
    let Some(sweep) = table.get("sweep") else {
        return Ok(None);
    };
    let sw: SweepSection = deserialize_at("sweep", sweep.clone())?;
    // `--set K=…` means `model.K` exactly as a sweep's `parameter = "K"` does
    let full = super::sweep::sweep_key("", &key.join("."))?.join(".");
    Ok(swept_keys(&sw)?
        .into_iter()
        .find(|s| full == *s || full.starts_with(&format!("{s}."))))
}

/// Validates a scenario table (already overridden) and expands its sweep.
///
/// ```
/// use celltissue::scenario::resolve;
/// let t: toml::Table = toml::from_str("name = \"r\"\n[output]\nseries = [0, 1]\n[model]\n\
///     kind = \"line\"\ncells = 5\nmodels = [\"discrete\"]\n[sweep]\nparameter = \"K\"\n\
///     values = [0.1, 1]")?;
/// let s = resolve(t)?;
/// let labels: Vec<&str> = s.runs.iter().map(|r| r.label.as_str()).collect();
/// assert_eq!(labels, ["discrete K=0.1", "discrete K=1"]);
/// assert_eq!(s.runs[0].times.series, [0.0, 1.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn resolve(table: toml::Table) -> Result<Scenario, ScenarioError> {
    let raw: RawScenario = deserialize_at("", toml::Value::Table(table.clone()))?;
    if raw.name.trim().is_empty() {
        return Err(ScenarioError::key("name", "must not be empty"));
    }
    let points = match &raw.sweep {
        None => vec![None],
        Some(sw) => expand(sw)?.into_iter().map(Some).collect(),
    };
    let sweep = match &raw.sweep {
        None => None,
        Some(sw) => {
            let parameters = swept_keys(sw)?;
            let ensemble = crate::scenario::sweep::ensemble_key(sw)?;
            Some(SweepInfo {
                ensemble,
                key: parameters.join(","),
                name: points
                    .first()
                    .and_then(|p| p.as_ref())
                    .map(|p| p.name.clone())
                    .unwrap_or_default(),
                parameters,
            })
        }
    };
    table.iter().try_for_each(|(k, v)| reject_subnormal(k, v))?;
    let mut runs = Vec::new();
    let mut slugs = std::collections::HashMap::new();
    for point in points {
        let ctx = |e: ScenarioError| match &point {
            None => e,
            Some(p) => sweep_context(e, p),
        };
        let one = match &point {
            Some(p) => {
                let mut t = table.clone();
                for part in &p.parts {
                    let key: Vec<String> = part.key.split('.').map(str::to_string).collect();
                    reject_subnormal(&part.key, &part.raw).map_err(ctx)?;
                    apply(&mut t, &key, part.raw.clone()).map_err(ctx)?;
                }
                deserialize_at::<RawScenario>("", toml::Value::Table(t)).map_err(ctx)?
            }
            None => raw.clone(),
        };
        let solver = one.solver.validate().map_err(ctx)?;
        let times = OutputTimes {
            series: parse_times("output.series", &one.output.series).map_err(ctx)?,
            profiles: match &one.output.profiles {
                // none: the key absent or an empty list
                None => Vec::new(),
                Some(toml::Value::Array(a)) if a.is_empty() => Vec::new(),
                Some(v) => parse_times("output.profiles", v).map_err(ctx)?,
            },
        };
        let section = parse_model(&one.model).map_err(ctx)?;
        super::roundoff::check_section(&section, &solver).map_err(ctx)?;
        if solver.accuracy_check {
            let tight = super::accuracy_check::tightened(&solver);
            super::roundoff::check_section_for(&section, &tight, super::roundoff::Asker::Check)
                .map_err(ctx)?;
        }
        super::impulse::check_section(&section, &solver).map_err(ctx)?;
        super::growth_stress::check_section(&section, &solver).map_err(ctx)?;
        if solver.linear_solver != LinearSolverChoice::Direct
            && !matches!(section.config, ModelConfig::Sheet(..))
        {
            return Err(ctx(ScenarioError::key(
                "solver.linear_solver",
                "= \"iterative\" applies to sheet models only (sparse Jacobians); lines, rings \
                 and the shear column use the banded or sparse LU"
                    .to_string(),
            )));
        }
        if solver.interpolate_rates && section.config.outputs_read_rates() == Some(false) {
            return Err(ctx(ScenarioError::key(
                "solver.interpolate_rates",
                "applies to models whose outputs read rates (Kelvin–Voigt cells, η > 0), and \
                 this model's cells have none: remove it"
                    .to_string(),
            )));
        }
        for &model in &section.models {
            let mut label = model_name(model).to_string();
            if let Some(p) = &point {
                label = format!("{label} {}", p.assignment());
            }
            // labels become file names: they must stay distinct as file names
            let slug = crate::output::files::slug(&label);
            if let Some(other) = slugs.insert(slug.clone(), label.clone()) {
                return Err(ScenarioError::key(
                    "sweep.labels",
                    format!(
                        "runs `{other}` and `{label}` would write the same files ({slug}); \
                         give labels that differ in letters or digits"
                    ),
                ));
            }
            runs.push(RunSpec {
                label,
                model,
                nodes: section.nodes,
                grid: section.grid,
                config: section.config.clone(),
                solver,
                times: times.clone(),
                sweep: point.clone(),
                repeats: None,
            });
        }
    }
    mark_repeats(&mut runs);
    check_sweep_profiles(&raw.plots.sweep_profiles, sweep.is_some(), &runs)?;
    check_line_plots(&raw.plots, &runs)?;
    // each run alone must fit (wherever it runs; `run` checks the runs it holds together)
    for r in &runs {
        super::limits::check_profiles(r.profile_values(), 1)
            .map_err(|e| e.with_note(&format!("in run `{}`", r.label)))?;
    }
    Ok(Scenario {
        name: raw.name,
        description: raw.description,
        figure: raw.figure,
        plots: raw.plots,
        sweep,
        runs,
        table,
    })
}

/// Swept keys only a continuum reads.
const CONTINUUM_ONLY: [&str; 2] = ["model.nodes", "model.continuum_scheme"];

/// Sets [`RunSpec::repeats`]: where a sweep varies a key only a continuum reads, each discrete
/// run equal to an earlier one but for those keys (and its label) repeats it.
fn mark_repeats(runs: &mut [RunSpec]) {
    let continuum_swept = runs.iter().any(|r| {
        r.sweep.as_ref().is_some_and(|p| {
            p.parts
                .iter()
                .any(|q| CONTINUUM_ONLY.contains(&q.key.as_str()))
        })
    });
    if !continuum_swept {
        return;
    }
    // what a discrete run solves: the spec without its label, sweep point and grid
    let solved = |r: &RunSpec| {
        (r.model == ModelKind::Discrete).then(|| {
            let mut c = r.clone();
            c.label.clear();
            (c.sweep, c.nodes, c.grid) = (None, None, None);
            if let ModelConfig::Line(line) = &mut c.config {
                line.continuum_scheme = Default::default();
            }
            c
        })
    };
    let solves: Vec<Option<RunSpec>> = runs.iter().map(solved).collect();
    for i in 0..runs.len() {
        let Some(me) = &solves[i] else { continue };
        runs[i].repeats =
            (0..i).find(|&j| runs[j].repeats.is_none() && solves[j].as_ref() == Some(me));
    }
}

/// `plots.position` (x against X along a line, Fig 2.6) and `plots.rectangles` (a line's cells
/// as one row of rectangles per profile time, Fig 2.10e) draw a line: a sheet (whose rows
/// would be drawn end to end as one sawtooth line, and which draws its own cell arrays) or a
/// shear column (whose profile coordinate is the height) would get a meaningless plot or
/// none, so the keys are rejected there; the rectangles also need a discrete run.
fn check_line_plots(plots: &PlotSettings, runs: &[RunSpec]) -> Result<(), ScenarioError> {
    let keys = [
        ("plots.position", plots.position),
        ("plots.rectangles", plots.rectangles),
    ];
    for (key, on) in keys {
        if !on {
            continue;
        }
        if let Some(run) = runs
            .iter()
            .find(|r| matches!(r.config, ModelConfig::Sheet(..) | ModelConfig::Shear(..)))
        {
            return Err(ScenarioError::key(
                key,
                match run.config {
                    ModelConfig::Sheet(..) => format!(
                        "= true draws a line of cells, not a sheet (run `{}`): remove it; a \
                         sheet's cells are drawn at every profile time anyway \
                         (`<run>_pressure_NNNN.png`)",
                        run.label
                    ),
                    _ => format!(
                        "= true draws a line of cells, not a shear column (run `{}`): remove \
                         it; the column's edges are drawn in `profiles_displacement*.png`",
                        run.label
                    ),
                },
            ));
        }
    }
    if plots.rectangles && !runs.iter().any(|r| r.model == ModelKind::Discrete) {
        return Err(ScenarioError::key(
            "plots.rectangles",
            "= true draws the cells of discrete runs, and this scenario has none (models)",
        ));
    }
    Ok(())
}

/// `plots.sweep_profiles`: only with a sweep, each time finite and one of every run's profile
/// times (a comparison across swept values needs every value's profile at that time).
fn check_sweep_profiles(times: &[f64], swept: bool, runs: &[RunSpec]) -> Result<(), ScenarioError> {
    if times.is_empty() {
        return Ok(());
    }
    if !swept {
        return Err(ScenarioError::key(
            "plots.sweep_profiles",
            "compares the profiles of swept values: it needs a [sweep]",
        ));
    }
    for (i, &t) in times.iter().enumerate() {
        let key = format!("plots.sweep_profiles.{i}");
        if !t.is_finite() {
            return Err(ScenarioError::key(key, format!("time {t} must be finite")));
        }
        if let Some(run) = runs.iter().find(|r| !r.times.profiles.contains(&t)) {
            let valid = run
                .times
                .profiles
                .iter()
                .map(|v| format_number(*v))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(ScenarioError::key(
                key,
                format!(
                    "time {} is not one of the profile times of run `{}` (output.profiles: \
                     [{valid}])",
                    format_number(t),
                    run.label
                ),
            ));
        }
    }
    Ok(())
}

/// Rejects any nonzero number below the smallest normal double (2.2e-308) in magnitude, naming
/// its key (`model.K`, `output.series[1]`): such a value keeps only a few significant bits,
/// halving or squaring it gives 0 (a sheet's `k_th = 5e-324` became `K = 0` without a word),
/// and the terms it scales underflow in the solver's matrices. Exactly 0 stays allowed.
fn reject_subnormal(path: &str, v: &toml::Value) -> Result<(), ScenarioError> {
    let child = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match v {
        toml::Value::Float(f) if crate::cell::subnormal(*f) => Err(ScenarioError::key(
            path,
            format!("= {}", crate::cell::subnormal_text(*f)),
        )),
        toml::Value::Table(t) => t
            .iter()
            .try_for_each(|(k, v)| reject_subnormal(&child(k), v)),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .try_for_each(|(i, v)| reject_subnormal(&format!("{path}[{i}]"), v)),
        _ => Ok(()),
    }
}

/// `"discrete"` / `"continuum"`.
pub(crate) fn model_name(m: ModelKind) -> &'static str {
    match m {
        ModelKind::Discrete => "discrete",
        ModelKind::Continuum => "continuum",
    }
}

/// A sweep point's validation error: the key stays the model's (`model.k1`); the message
/// says which swept value it came from (`sweep.values[1] = 1.5`) and the run. An error on a
/// key that no swept value sets or lies inside names the run only: the swept values may
/// have nothing to do with it (a bad `solver.jacobian_age` in an ensemble).
fn sweep_context(e: ScenarioError, p: &SweepPoint) -> ScenarioError {
    let Some(key) = e.key_name().map(str::to_string) else {
        return e;
    };
    let inside = |part: &super::sweep::SweepPart| {
        key == part.key
            || key.starts_with(&format!("{}.", part.key))
            || part.key.starts_with(&format!("{key}."))
    };
    let from: Vec<_> = p.parts.iter().filter(|part| inside(part)).collect();
    if from.is_empty() {
        return e.with_note(&format!("in run `{}`", p.assignment()));
    }
    let values = from
        .iter()
        .map(|part| format!("{} = {}", part.origin, value_text(&part.raw)))
        .collect::<Vec<_>>()
        .join(", ");
    e.with_note(&format!(
        "swept value {values}; in run `{}`",
        p.assignment()
    ))
}

/// A TOML value as short text (numbers as written, tables inline).
fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => format_number(*f),
        other => other.to_string(),
    }
}

/// A number as a short label: `1e-5`, `0.01`, `1`, `10`, `2.5e6`.
///
/// ```
/// use celltissue::scenario::format_number;
/// assert_eq!(format_number(1e-5), "1e-5");
/// assert_eq!(format_number(0.01), "0.01");
/// assert_eq!(format_number(10.0), "10");
/// ```
pub fn format_number(v: f64) -> String {
    let a = v.abs();
    if v != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BASE: &str = r#"
name = "t"
description = "test"
[output]
series = [0, 1]
profiles = [1]
[model]
kind = "line"
cells = 10
K = 1.0
"#;

    fn load(text: &str, sets: &[&str]) -> Result<Scenario, ScenarioError> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        load_str(text, Path::new("test.toml"), &sets)
    }

    #[test]
    fn no_sweep_gives_one_run_per_model() {
        let s = load(BASE, &[]).unwrap();
        let labels: Vec<&str> = s.runs.iter().map(|r| r.label.as_str()).collect();
        assert_eq!(labels, ["discrete", "continuum"]);
        assert_eq!(s.runs[0].times.series, vec![0.0, 1.0]);
        assert_eq!(s.runs[0].solver.method, integrators::MethodKind::Bdf);
    }

    #[test]
    fn sweep_expands_values_times_models() {
        let text = format!("{BASE}[sweep]\nparameter = \"K\"\nvalues = [1e-5, 0.01, 1, 10]\n");
        let s = load(&text, &[]).unwrap();
        assert_eq!(s.runs.len(), 8);
        assert_eq!(s.runs[2].label, "discrete K=0.01");
        assert_eq!(s.runs[7].label, "continuum K=10");
        assert_eq!(s.runs[0].label, "discrete K=1e-5");
        let ModelConfig::Line(cfg) = &s.runs[2].config else {
            panic!("a line")
        };
        assert_eq!(cfg.k.eval(0.0, 1.0), 0.01);
        assert_eq!(s.runs[2].sweep.as_ref().unwrap().value, Some(0.01));
        assert_eq!(s.sweep.as_ref().unwrap().key, "model.K");
    }

    #[test]
    fn sweep_of_tables_needs_labels() {
        let text = format!(
            "{BASE}[sweep]\nparameter = \"mu\"\nvalues = [1.0, {{ type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }}]\n"
        );
        let e = load(&text, &[]).unwrap_err();
        assert_eq!(e.key_name(), Some("sweep.labels"));
        let s = load(
            &format!("{text}labels = [\"uniform\", \"gaussian\"]\n"),
            &[],
        )
        .unwrap();
        assert_eq!(s.runs[3].label, "continuum mu=gaussian");
    }

    #[test]
    fn a_bad_sweep_value_is_reported_with_its_run() {
        let text = format!("{BASE}[sweep]\nparameter = \"k1\"\nvalues = [0.1, 1.5]\n");
        let e = load(&text, &[]).unwrap_err();
        assert_eq!(e.key_name(), Some("model.k1"));
        assert!(e.to_string().contains("k1=1.5"), "{e}");
    }

    #[test]
    fn set_overrides_apply_before_validation() {
        let s = load(
            BASE,
            &[
                "model.K=0.1",
                "solver.method=radau",
                "model.models=[\"continuum\"]",
            ],
        )
        .unwrap();
        assert_eq!(s.runs.len(), 1);
        assert_eq!(s.runs[0].solver.method, integrators::MethodKind::Radau);
        let ModelConfig::Line(cfg) = &s.runs[0].config else {
            panic!("a line")
        };
        assert_eq!(cfg.k.eval(0.0, 1.0), 0.1);
        let e = load(BASE, &["model.Kay=0.1"]).unwrap_err();
        assert_eq!(e.key_name(), Some("model.Kay"));
        let e = load(BASE, &["solver.method=euler"]).unwrap_err();
        assert_eq!(e.key_name(), Some("solver.method"));
        let e = load(BASE, &["model.cells=0"]).unwrap_err();
        assert_eq!(e.key_name(), Some("model.cells"));
    }

    #[test]
    fn iterative_linear_solver_is_parsed_for_sheets_and_checked() {
        let sheet = r#"
name = "s"
description = "test"
[output]
series = [0, 1]
[model]
kind = "sheet"
cells_x = 4
cells_y = 3
[solver]
linear_solver = "iterative"
krylov_rtol = 1e-6
"#;
        let s = load(sheet, &["solver.newton_factor=0.05"]).unwrap();
        assert_eq!(
            s.runs[0].solver.linear_solver,
            LinearSolverChoice::Iterative(integrators::IterativeSettings {
                rtol: 1e-6,
                max_iters: 200,
                newton_factor: 0.05,
            })
        );
        for (set, key) in [
            ("solver.krylov_rtol=1.5", "solver.krylov_rtol"),
            ("solver.krylov_max_iters=0", "solver.krylov_max_iters"),
            ("solver.newton_factor=-0.1", "solver.newton_factor"),
            ("solver.linear_solver=\"lu\"", "solver.linear_solver"),
            ("solver.threads=0", "solver.threads"),
            ("solver.threads=3", "solver.threads"),
        ] {
            let e = load(sheet, &[set]).unwrap_err();
            assert_eq!(e.key_name(), Some(key), "{set}: {e}");
        }
        let e = load(BASE, &["solver.linear_solver=iterative"]).unwrap_err();
        assert_eq!(e.key_name(), Some("solver.linear_solver"));
        assert_eq!(
            load(BASE, &[]).unwrap().runs[0].solver.linear_solver,
            LinearSolverChoice::Direct
        );
    }

    #[test]
    fn top_level_errors_name_keys() {
        let key = |t: String| load(&t, &[]).unwrap_err().key_name().map(str::to_string);
        assert_eq!(
            key(format!("colour = 1\n{BASE}")).as_deref(),
            Some("colour")
        );
        assert_eq!(
            key(format!("{BASE}[solver]\nrtol = 2.0\n")).as_deref(),
            Some("solver.rtol")
        );
        assert_eq!(
            key(format!("{BASE}[solver]\nrtol = \"x\"\n")).as_deref(),
            Some("solver.rtol")
        );
        assert_eq!(
            key(format!("{BASE}[plots]\ntime_axis = \"ln\"\n")).as_deref(),
            Some("plots.time_axis")
        );
        assert_eq!(
            key(BASE.replace("series = [0, 1]", "series = [1, 0]")).as_deref(),
            Some("output.series")
        );
    }

    #[test]
    fn syntax_errors_are_reported() {
        assert!(matches!(
            load("name = ", &[]),
            Err(ScenarioError::Syntax { .. })
        ));
    }

    #[test]
    fn discrete_runs_repeat_where_the_sweep_changes_only_the_continuum() {
        let text = |sweep: &str| {
            format!(
                "name = \"r\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncells = 8\n\
                 [sweep]\n{sweep}\n"
            )
        };
        let repeats = |sweep: &str| -> Vec<Option<usize>> {
            let s = load_str(&text(sweep), Path::new("r.toml"), &[]).unwrap();
            s.runs.iter().map(|r| r.repeats).collect()
        };
        // runs: discrete, continuum per value
        let grid = "parameter = \"nodes\"\nvalues = [4, 8, 16]";
        assert_eq!(repeats(grid), [None, None, Some(0), None, Some(0), None]);
        let scheme = "parameter = \"continuum_scheme\"\nvalues = [\"conservative\", \"thesis\"]";
        assert_eq!(repeats(scheme), [None, None, Some(0), None]);
        assert!(repeats("parameter = \"K\"\nvalues = [1, 2]")
            .iter()
            .all(Option::is_none));
        // nodes × K: the discrete runs of one K repeat each other only
        let both = "grid = [{ parameter = \"K\", values = [1, 2] }, \
                    { parameter = \"nodes\", values = [4, 8] }]";
        assert_eq!(
            repeats(both),
            [None, None, Some(0), None, None, None, Some(4), None]
        );
    }
}
