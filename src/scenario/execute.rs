//! Running a validated [`Scenario`]: each [`RunSpec`] goes to its model's run function
//! (e.g. [`crate::line::run_line`]); the record gets the scenario's label and its resolved
//! parameters (model configuration, sweep point, solver). No I/O.

use super::load::{RunSpec, Scenario};
use super::model::ModelConfig;
use crate::line::run_line;
use crate::observe::{RunRecord, RunStats, Series, Summary};
use crate::sheet::{run_shear, run_sheet};

/// Runs one spec with the real model code (no files written: the writers of
/// [`crate::output`] draw every file from the returned record).
///
/// ```
/// use celltissue::scenario::{execute, load_str};
/// let text = "name = \"demo\"\n[output]\nseries = [1]\n[model]\nkind = \"sheet\"\nmodels = [\"discrete\"]\ncells_x = 3\ncells_y = 3";
/// let s = load_str(text, "demo.toml".as_ref(), &[])?;
/// let rec = execute::run_spec(&s.runs[0]);
/// assert_eq!(rec.series.t, [1.0]);
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn run_spec(spec: &RunSpec) -> RunRecord {
    // grid sizes apply to the continuum only
    let is_continuum = spec.model == crate::observe::ModelKind::Continuum;
    let grid = spec.grid.filter(|_| is_continuum);
    let nodes = spec.nodes.filter(|_| is_continuum);
    let mut rec = match &spec.config {
        ModelConfig::Sheet(cfg, law) => {
            run_sheet(cfg, law, spec.model, grid, &spec.solver, &spec.times)
                .unwrap_or_else(|e| failed(spec, e.to_string()))
        }
        ModelConfig::Shear(cfg, law) => {
            run_shear(cfg, law, spec.model, nodes, &spec.solver, &spec.times)
                .unwrap_or_else(|e| failed(spec, e.to_string()))
        }
        ModelConfig::Mode(mode) => mode.law().run(spec.model, nodes, &spec.solver, &spec.times),
        ModelConfig::Line(cfg) => run_line(cfg, spec.model, spec.nodes, &spec.solver, &spec.times),
        ModelConfig::Proliferating(cfg) => {
            crate::events::run_proliferation(cfg, spec.model, spec.nodes, &spec.solver, &spec.times)
        }
    };
    finish(spec, &mut rec);
    rec.notes.extend(continuum_is_the_discrete_line(spec));
    rec.notes.extend(thesis_scheme_samples_jumps(spec));
    if spec.solver.accuracy_check && rec.error.is_none() {
        let (check, note) = super::accuracy_check::check(spec, &rec);
        rec.accuracy_check = Some(check);
        rec.notes.extend(note);
    }
    rec
}

/// A note for a line's continuum that is its discrete line: the conservative scheme on one
/// segment per cell of equal cells (docs/model.md §3.3a), as `nodes` left at its default
/// gives; comparing the two then shows nothing.
fn continuum_is_the_discrete_line(spec: &RunSpec) -> Option<String> {
    let ModelConfig::Line(cfg) = &spec.config else {
        return None;
    };
    let cells = cfg.n_cells();
    (spec.model == crate::observe::ModelKind::Continuum
        && cfg.continuum_scheme == crate::line::config::ContinuumScheme::Conservative
        && spec.nodes.unwrap_or(cells) == cells
        && cfg.equal_cells())
    .then(|| {
        format!(
            "this continuum has one segment per cell (`nodes` = {cells}{}): it is the \
                 discrete line itself; set `nodes` for a continuum on its own grid",
            if spec.nodes.is_none() {
                ", the default"
            } else {
                ""
            }
        )
    })
}

/// A note for a line's thesis-scheme continuum over fields that jump from cell to cell: it
/// reads them at its nodes, where the conservative scheme gives each segment its cells'
/// effective values (docs/model.md §3.3).
fn thesis_scheme_samples_jumps(spec: &RunSpec) -> Option<String> {
    let ModelConfig::Line(cfg) = &spec.config else {
        return None;
    };
    if spec.model != crate::observe::ModelKind::Continuum
        || cfg.continuum_scheme != crate::line::config::ContinuumScheme::Thesis
    {
        return None;
    }
    let cells = cfg.n_cells();
    let jumping: Vec<&str> = [("mu", &cfg.mu), ("eta", &cfg.eta), ("K", &cfg.k)]
        .into_iter()
        .filter(|(_, f)| crate::line::homogenise::jumps_between_cells(f, cells))
        .map(|(key, _)| key)
        .collect();
    (!jumping.is_empty()).then(|| {
        format!(
            "the thesis scheme reads `{}`, which jumps from cell to cell, at its nodes: it does \
             not give a node the effective value of the cells around it; the conservative \
             scheme does (docs/model.md §3.3)",
            jumping.join("`, `")
        )
    })
}

/// The record of a run that was not run, with the reason as its error (e.g. a sweep
/// interrupted before it reached the run).
///
/// ```
/// use celltissue::scenario::{execute, load_str};
/// let s = load_str("name = \"x\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncells = 3",
///                  "x.toml".as_ref(), &[])?;
/// let rec = execute::not_run(&s.runs[0], "interrupted before it started");
/// assert_eq!(rec.label, s.runs[0].label);
/// assert!(rec.series.t.is_empty() && rec.error.unwrap().contains("interrupted"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn not_run(spec: &RunSpec, why: &str) -> RunRecord {
    let mut rec = failed(spec, why.to_string());
    finish(spec, &mut rec);
    rec
}

/// An empty record carrying an error.
fn failed(spec: &RunSpec, error: String) -> RunRecord {
    RunRecord {
        label: spec.label.clone(),
        model: spec.model,
        parameters: spec.config.to_json(),
        series: Series::default(),
        profiles: Vec::new(),
        stats: RunStats::default(),
        divisions: Vec::new(),
        error: Some(error),
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    }
}

/// Gives a record the spec's label, drops `null` (absent) parameters and adds `"kind"`,
/// `"sweep"` and `"solver"` to its parameters.
///
/// ```
/// use celltissue::scenario::{execute, load_str};
/// let text = "name = \"k\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\ncells = 4\nK = 1.0\n\
///             [sweep]\nparameter = \"K\"\nvalues = [1.0, 2.0]";
/// let s = load_str(text, "k.toml".as_ref(), &[])?;
/// let spec = &s.runs[1];
/// let mut rec = execute::run_spec(spec);
/// rec.label.clear();
/// execute::finish(spec, &mut rec);
/// assert_eq!(rec.label, spec.label);
/// assert_eq!(rec.parameters["kind"], "line");
/// assert!(rec.parameters.get("sweep").is_some());
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn finish(spec: &RunSpec, rec: &mut RunRecord) {
    rec.label = spec.label.clone();
    rec.model = spec.model;
    if !rec.parameters.is_object() {
        rec.parameters = spec.config.to_json();
    }
    if let serde_json::Value::Object(m) = &mut rec.parameters {
        // absent options are left out rather than written as `null` (which reads like a NaN)
        m.retain(|_, v| !v.is_null());
        // the scenario's configuration fills keys the model did not report (e.g. `energy`)
        if let serde_json::Value::Object(cfg) = spec.config.to_json() {
            for (k, v) in cfg {
                if !v.is_null() {
                    m.entry(k).or_insert(v);
                }
            }
        }
        m.insert("kind".into(), spec.config.kind().into());
        if let Some(n) = spec.nodes {
            m.entry("nodes").or_insert(n.into());
        }
        m.insert(
            "solver".into(),
            serde_json::to_value(spec.solver).unwrap_or_default(),
        );
        if let Some(p) = &spec.sweep {
            let value = serde_json::to_value(&p.raw).unwrap_or_default();
            let mut sweep =
                serde_json::json!({ "parameter": p.name, "label": p.label, "value": value });
            if p.parts.len() > 1 {
                // several swept parameters: one entry each
                let parts: Vec<serde_json::Value> = p
                    .parts
                    .iter()
                    .map(|q| {
                        serde_json::json!({
                            "parameter": q.name,
                            "label": q.label,
                            "value": serde_json::to_value(&q.raw).unwrap_or_default(),
                        })
                    })
                    .collect();
                sweep["parts"] = parts.into();
            }
            m.insert("sweep".into(), sweep);
        }
    }
}

/// The note a run that repeats an earlier one ([`RunSpec::repeats`]) carries, naming it.
///
/// ```
/// use celltissue::scenario::{execute::repeat_note, load_str};
/// let text = "name = \"n\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncells = 8\n\
///             [sweep]\nparameter = \"nodes\"\nvalues = [4, 8]";
/// let s = load_str(text, "n.toml".as_ref(), &[])?;
/// assert_eq!(repeat_note(&s, &s.runs[0]), None);
/// assert!(repeat_note(&s, &s.runs[2]).unwrap().contains("`discrete nodes=4`"));
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn repeat_note(scenario: &Scenario, spec: &RunSpec) -> Option<String> {
    let source = scenario.runs.get(spec.repeats?)?;
    Some(format!(
        "the same discrete line as `{}` (the sweep changes only the continuum there): `run` \
         solves it once for both",
        source.label
    ))
}

/// `spec`'s record made from `source`, the record of the run it repeats
/// ([`RunSpec::repeats`]): the same solve under `spec`'s label, sweep point and grid, with
/// [`repeat_note`].
///
/// ```
/// use celltissue::scenario::{execute, load_str};
/// let text = "name = \"n\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\ncells = 8\n\
///             [sweep]\nparameter = \"nodes\"\nvalues = [4, 16]";
/// let s = load_str(text, "n.toml".as_ref(), &[])?;
/// let first = execute::run_spec(&s.runs[0]);
/// let again = execute::repeated(&s, &s.runs[2], first);
/// let solved = execute::run_spec(&s.runs[2]); // what solving it again would give
/// assert_eq!((&again.label, &again.parameters), (&solved.label, &solved.parameters));
/// assert_eq!(again.series.min_stretch, solved.series.min_stretch);
/// assert!(again.notes[0].contains("`discrete nodes=4`"));
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn repeated(scenario: &Scenario, spec: &RunSpec, source: RunRecord) -> RunRecord {
    let mut rec = source;
    if let serde_json::Value::Object(m) = &mut rec.parameters {
        m.remove("sweep");
        m.remove("nodes");
    }
    finish(spec, &mut rec);
    rec.notes.extend(repeat_note(scenario, spec));
    rec
}

/// Runs every spec in order with `runner`, reporting each finished run to `progress`.
///
/// ```
/// use celltissue::scenario::{execute, load_str};
/// let text = "name = \"demo\"\n[output]\nseries = [1]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 10";
/// let s = load_str(text, "demo.toml".as_ref(), &[])?;
/// let mut seen = 0;
/// let summary = execute::run_all(&s, execute::run_spec, |_| seen += 1);
/// assert_eq!((summary.runs.len(), seen), (1, 1));
/// assert!(summary.runs[0].error.is_none());
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn run_all(
    scenario: &Scenario,
    mut runner: impl FnMut(&RunSpec) -> RunRecord,
    mut progress: impl FnMut(&RunRecord),
) -> Summary {
    let runs = scenario
        .runs
        .iter()
        .map(|spec| {
            let rec = runner(spec);
            progress(&rec);
            rec
        })
        .collect();
    Summary {
        scenario: scenario.name.clone(),
        runs,
    }
}
