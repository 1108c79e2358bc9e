//! Running a validated [`Scenario`]: each [`RunSpec`] goes to its model's run function
//! (e.g. [`crate::line::run_line`]); the record gets the scenario's label and its resolved
//! parameters (model configuration, sweep point, solver). No I/O.

use super::load::{RunSpec, Scenario};
use super::model::ModelConfig;
use crate::line::{run_line, OutputTimes, SolveSettings};
use crate::observe::{RunRecord, Summary};

/// Runs one spec with the real model code.
pub fn run_spec(spec: &RunSpec) -> RunRecord {
    let mut rec = match &spec.config {
        ModelConfig::Line(cfg) => {
            let solver = SolveSettings {
                method: spec.solver.method,
                rtol: spec.solver.rtol,
                atol: spec.solver.atol,
            };
            let times = OutputTimes {
                series: spec.times.series.clone(),
                profiles: spec.times.profiles.clone(),
            };
            run_line(cfg, spec.model, spec.nodes, &solver, &times)
        }
        ModelConfig::Proliferating(cfg) => {
            let solver = SolveSettings {
                method: spec.solver.method,
                rtol: spec.solver.rtol,
                atol: spec.solver.atol,
            };
            let times = OutputTimes {
                series: spec.times.series.clone(),
                profiles: spec.times.profiles.clone(),
            };
            crate::events::run_proliferation(cfg, spec.model, spec.nodes, &solver, &times)
        }
    };
    finish(spec, &mut rec);
    rec
}

/// Gives a record the spec's label, drops `null` (absent) parameters and adds `"kind"`,
/// `"sweep"` and `"solver"` to its parameters.
pub fn finish(spec: &RunSpec, rec: &mut RunRecord) {
    rec.label = spec.label.clone();
    rec.model = spec.model;
    if !rec.parameters.is_object() {
        rec.parameters = spec.config.to_json();
    }
    if let serde_json::Value::Object(m) = &mut rec.parameters {
        // absent options are left out rather than written as `null` (which reads like a NaN)
        m.retain(|_, v| !v.is_null());
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
            m.insert(
                "sweep".into(),
                serde_json::json!({ "parameter": p.name, "label": p.label, "value": value }),
            );
        }
    }
}

/// Runs every spec in order with `runner`, reporting each finished run to `progress`.
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
