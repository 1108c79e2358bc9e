//! From a scenario file (plus `--set` overrides) to a validated [`Scenario`]: parse the TOML,
//! apply overrides, expand the sweep into one [`RunSpec`] per value and discretisation, and
//! validate every run's configuration — all before anything is run or written.

use super::error::{deserialize_at, ScenarioError};
use super::model::{parse_model, ModelConfig};
use super::overrides::{apply, parse_path, parse_set};
use super::schema::{PlotSettings, RawScenario, SolverChoice};
use super::times::parse_times;
use crate::observe::ModelKind;
use integrators::LinearSolverChoice;
use std::path::Path;

/// Output times of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Times {
    /// Times of the scalar series.
    pub series: Vec<f64>,
    /// Times of the profiles.
    pub profiles: Vec<f64>,
}

/// One point of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// Short parameter name for labels (last part of the key, e.g. `"K"`).
    pub name: String,
    /// The value as shown in labels (`"0.01"`, `"1e-5"`, or the given label).
    pub label: String,
    /// The numeric value, if the swept value is a number (used on sweep-plot axes).
    pub value: Option<f64>,
    /// The value as TOML.
    pub raw: toml::Value,
}

/// One run: one discretisation of one parameter set.
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
    pub solver: SolverChoice,
    /// Output times.
    pub times: Times,
    /// The sweep point, if the scenario sweeps.
    pub sweep: Option<SweepPoint>,
}

/// The sweep as declared.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepInfo {
    /// Full dotted key (`"model.K"`).
    pub key: String,
    /// Short name (`"K"`).
    pub name: String,
}

/// A validated scenario, ready to run.
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
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    load_str(&text, path, sets)
}

/// As [`load`], from text (`origin` is used in messages).
pub fn load_str(text: &str, origin: &Path, sets: &[String]) -> Result<Scenario, ScenarioError> {
    let mut table: toml::Table = toml::from_str(text).map_err(|e| ScenarioError::Syntax {
        path: origin.to_path_buf(),
        message: e.to_string().trim().to_string(),
    })?;
    for arg in sets {
        let (key, value) = parse_set(arg)?;
        apply(&mut table, &key, value).map_err(|e| match e {
            ScenarioError::Key { key, message } => ScenarioError::Key {
                key,
                message: format!("{message} (from --set {arg})"),
            },
            other => other,
        })?;
    }
    resolve(table)
}

/// Validates a scenario table (already overridden) and expands its sweep.
pub fn resolve(table: toml::Table) -> Result<Scenario, ScenarioError> {
    let raw: RawScenario = deserialize_at("", toml::Value::Table(table.clone()))?;
    if raw.name.trim().is_empty() {
        return Err(ScenarioError::key("name", "must not be empty"));
    }
    let points = match &raw.sweep {
        None => vec![None],
        Some(sw) => sweep_points(sw)?.into_iter().map(Some).collect(),
    };
    let sweep = match &raw.sweep {
        None => None,
        Some(sw) => {
            let key = sweep_key(&sw.parameter)?;
            let name = key.last().cloned().unwrap_or_default();
            Some(SweepInfo {
                key: key.join("."),
                name,
            })
        }
    };
    let mut runs = Vec::new();
    for point in points {
        let one = match (&point, &sweep) {
            (Some(p), Some(info)) => {
                let mut t = table.clone();
                let key: Vec<String> = info.key.split('.').map(str::to_string).collect();
                apply(&mut t, &key, p.raw.clone())?;
                deserialize_at::<RawScenario>("", toml::Value::Table(t))?
            }
            _ => raw.clone(),
        };
        let context = point
            .as_ref()
            .map(|p| format!("{}={}", p.name, p.label))
            .unwrap_or_default();
        let ctx = |e: ScenarioError| {
            if context.is_empty() {
                e
            } else {
                e.in_run(&context)
            }
        };
        let solver = one.solver.validate().map_err(ctx)?;
        let times = Times {
            series: parse_times("output.series", &one.output.series).map_err(ctx)?,
            profiles: match &one.output.profiles {
                None => Vec::new(),
                Some(v) => parse_times("output.profiles", v).map_err(ctx)?,
            },
        };
        let section = parse_model(&one.model).map_err(ctx)?;
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
        for &model in &section.models {
            let mut label = model_name(model).to_string();
            if let Some(p) = &point {
                label = format!("{label} {}={}", p.name, p.label);
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
            });
        }
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

/// `"discrete"` / `"continuum"`.
pub fn model_name(m: ModelKind) -> &'static str {
    match m {
        ModelKind::Discrete => "discrete",
        ModelKind::Continuum => "continuum",
    }
}

/// The full key of a sweep parameter: relative to `[model]` unless it starts with a section.
fn sweep_key(parameter: &str) -> Result<Vec<String>, ScenarioError> {
    let parts = parse_path(parameter).ok_or_else(|| {
        ScenarioError::key(
            "sweep.parameter",
            format!("`{parameter}` is not a dotted key such as \"K\" or \"model.eta\""),
        )
    })?;
    Ok(match parts[0].as_str() {
        "model" | "solver" | "output" => parts,
        _ => std::iter::once("model".to_string()).chain(parts).collect(),
    })
}

fn sweep_points(sw: &super::schema::SweepSection) -> Result<Vec<SweepPoint>, ScenarioError> {
    let key = sweep_key(&sw.parameter)?;
    let name = key.last().cloned().unwrap_or_default();
    if sw.values.is_empty() {
        return Err(ScenarioError::key(
            "sweep.values",
            "needs at least one value",
        ));
    }
    if let Some(labels) = &sw.labels {
        if labels.len() != sw.values.len() {
            return Err(ScenarioError::key(
                "sweep.labels",
                format!(
                    "has {} entries but sweep.values has {}; give one label per value",
                    labels.len(),
                    sw.values.len()
                ),
            ));
        }
    }
    let mut points = Vec::new();
    for (i, raw) in sw.values.iter().enumerate() {
        let value = match raw {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(n) => Some(*n as f64),
            _ => None,
        };
        let label = match (&sw.labels, raw) {
            (Some(l), _) => l[i].clone(),
            (None, toml::Value::String(s)) => s.clone(),
            (None, toml::Value::Boolean(b)) => b.to_string(),
            (None, _) if value.is_some() => format_number(value.unwrap_or_default()),
            (None, _) => {
                return Err(ScenarioError::key(
                    "sweep.labels",
                    format!(
                        "required when a swept value is a {} (value {i})",
                        raw.type_str()
                    ),
                ))
            }
        };
        if points.iter().any(|p: &SweepPoint| p.label == label) {
            return Err(ScenarioError::key(
                "sweep.values",
                format!("`{label}` appears twice; every run needs its own label"),
            ));
        }
        points.push(SweepPoint {
            name: name.clone(),
            label,
            value,
            raw: raw.clone(),
        });
    }
    Ok(points)
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
}
