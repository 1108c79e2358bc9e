//! The `[model]` table: `kind` picks the model, `models` and `nodes` say which discretisations
//! run, and every other key belongs to the model's own configuration type (e.g.
//! [`LineConfig`], which rejects unknown keys and validates ranges). This module only
//! dispatches; it does not duplicate any model field.
//!
//! ```toml
//! [model]
//! kind = "line"                        # line | sheet | shear
//! models = ["discrete", "continuum"]   # which discretisations run (default: both)
//! nodes = 101                          # continuum grid size (default: as many as cells)
//! cells = 100                          # … the rest is LineConfig
//! K = 1.0
//! ```

use super::error::{deserialize_at, ScenarioError};
use crate::line::LineConfig;
use crate::observe::ModelKind;

/// Keys of `[model]` owned by the scenario layer (removed before the model's config is parsed).
pub const SCENARIO_KEYS: [&str; 3] = ["kind", "models", "nodes"];

/// The model kinds a scenario can name.
pub const KINDS: [&str; 1] = ["line"];

/// A parsed and validated model configuration.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelConfig {
    /// The line of cells (thesis Chapters 2–3).
    Line(Box<LineConfig>),
    /// A growing line with cell division: `kind = "line"` plus a `division = { rule = … }`
    /// table (thesis §3.3.2; [`crate::events::run_proliferation`]).
    Proliferating(Box<crate::events::ProliferationConfig>),
}

impl ModelConfig {
    /// The `kind` string.
    pub fn kind(&self) -> &'static str {
        match self {
            ModelConfig::Line(_) | ModelConfig::Proliferating(_) => "line",
        }
    }

    /// The configuration as JSON (for `summary.json` `"parameters"`).
    pub fn to_json(&self) -> serde_json::Value {
        match self {
            ModelConfig::Line(c) => serde_json::to_value(c).unwrap_or(serde_json::Value::Null),
            ModelConfig::Proliferating(c) => {
                serde_json::to_value(c).unwrap_or(serde_json::Value::Null)
            }
        }
    }
}

/// What `[model]` says.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSection {
    /// The model's configuration.
    pub config: ModelConfig,
    /// Discretisations to run, in order.
    pub models: Vec<ModelKind>,
    /// Continuum grid size (`None`: the model's default).
    pub nodes: Option<usize>,
}

/// Parses and validates `[model]`. Errors name `model.<key>`.
pub fn parse_model(table: &toml::Table) -> Result<ModelSection, ScenarioError> {
    let mut rest = table.clone();
    let kind = match rest.remove("kind") {
        Some(toml::Value::String(s)) => s,
        Some(other) => {
            return Err(ScenarioError::key(
                "model.kind",
                format!(
                    "expected a string, found a {}; valid: {}",
                    other.type_str(),
                    KINDS.join(", ")
                ),
            ))
        }
        None => {
            return Err(ScenarioError::key(
                "model.kind",
                format!("missing; valid: {}", KINDS.join(", ")),
            ))
        }
    };
    let models = match rest.remove("models") {
        None => vec![ModelKind::Discrete, ModelKind::Continuum],
        Some(v) => parse_models(&v)?,
    };
    let nodes = match rest.remove("nodes") {
        None => None,
        Some(toml::Value::Integer(n)) if n >= 2 && n <= 100_000_000 => Some(n as usize),
        Some(v) => {
            return Err(ScenarioError::key(
                "model.nodes",
                format!("= {v} must be an integer in 2..=100000000"),
            ))
        }
    };
    let config = match kind.as_str() {
        "line" if rest.contains_key("division") => {
            let cfg = crate::events::ProliferationConfig::from_table(&rest)
                .and_then(|c| c.validate().map(|_| c))
                .map_err(|e| ScenarioError::key(field_key(&e), e))?;
            ModelConfig::Proliferating(Box::new(cfg))
        }
        "line" => {
            let cfg: LineConfig = deserialize_at("model", toml::Value::Table(rest))?;
            cfg.validate().map_err(line_error)?;
            ModelConfig::Line(Box::new(cfg))
        }
        other => {
            return Err(ScenarioError::key(
                "model.kind",
                format!("unknown model kind `{other}`; valid: {}", KINDS.join(", ")),
            ))
        }
    };
    Ok(ModelSection {
        config,
        models,
        nodes,
    })
}

fn parse_models(v: &toml::Value) -> Result<Vec<ModelKind>, ScenarioError> {
    let bad = |m: String| ScenarioError::key("model.models", m);
    let items = v.as_array().ok_or_else(|| {
        bad(format!(
            "expected a list such as [\"discrete\", \"continuum\"], found a {}",
            v.type_str()
        ))
    })?;
    if items.is_empty() {
        return Err(bad(
            "needs at least one of \"discrete\", \"continuum\"".into()
        ));
    }
    let mut out = Vec::new();
    for item in items {
        let m = match item.as_str() {
            Some("discrete") => ModelKind::Discrete,
            Some("continuum") => ModelKind::Continuum,
            _ => {
                return Err(bad(format!(
                    "unknown model {item}; valid: \"discrete\", \"continuum\""
                )))
            }
        };
        if out.contains(&m) {
            return Err(bad(format!("{item} is listed twice")));
        }
        out.push(m);
    }
    Ok(out)
}

/// A line validation error as a key error under `model.`.
fn line_error(e: crate::line::LineError) -> ScenarioError {
    use crate::line::LineError;
    match e {
        LineError::Invalid { key, value, range } => ScenarioError::key(
            format!("model.{key}"),
            format!("= {value} is invalid: must be {range}"),
        ),
        LineError::Field(msg) => {
            let key: String = msg
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '.')
                .collect();
            let key = if key.is_empty() {
                "model".into()
            } else {
                format!("model.{key}")
            };
            ScenarioError::key(key, msg)
        }
        other => ScenarioError::key(field_key(&other.to_string()), other.to_string()),
    }
}

/// The first back-quoted key in a message, under `model.` (falls back to `model`).
fn field_key(message: &str) -> String {
    message
        .split('`')
        .nth(1)
        .filter(|k| !k.is_empty() && !k.contains(' '))
        .map(|k| format!("model.{k}"))
        .unwrap_or_else(|| "model".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<ModelSection, ScenarioError> {
        parse_model(&toml::from_str::<toml::Table>(s).unwrap())
    }

    #[test]
    fn line_defaults_run_both_models() {
        let m = parse("kind = \"line\"\ncells = 10").unwrap();
        assert_eq!(m.models, vec![ModelKind::Discrete, ModelKind::Continuum]);
        assert_eq!(m.nodes, None);
        let ModelConfig::Line(cfg) = &m.config else {
            panic!("a line")
        };
        assert_eq!(cfg.cells, 10);
    }

    #[test]
    fn errors_name_the_model_key() {
        let key = |s: &str| parse(s).unwrap_err().key_name().map(str::to_string);
        assert_eq!(key("cells = 10").as_deref(), Some("model.kind"));
        assert_eq!(key("kind = \"blob\"").as_deref(), Some("model.kind"));
        assert_eq!(
            key("kind = \"line\"\nkay = 1").as_deref(),
            Some("model.kay")
        );
        assert_eq!(
            key("kind = \"line\"\ncells = \"ten\"").as_deref(),
            Some("model.cells")
        );
        assert_eq!(
            key("kind = \"line\"\ncells = 0").as_deref(),
            Some("model.cells")
        );
        assert_eq!(
            key("kind = \"line\"\nk1 = 1.2").as_deref(),
            Some("model.k1")
        );
        assert_eq!(
            key("kind = \"line\"\nmu = -1.0").as_deref(),
            Some("model.mu")
        );
        assert_eq!(
            key("kind = \"line\"\nnodes = 1").as_deref(),
            Some("model.nodes")
        );
        assert_eq!(
            key("kind = \"line\"\nmodels = []").as_deref(),
            Some("model.models")
        );
        assert_eq!(
            key("kind = \"line\"\nmodels = [\"pde\"]").as_deref(),
            Some("model.models")
        );
    }
}
