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
//!
//! Sheets and shear columns also take `energy = { law = "neo_hookean", mu = 1.0 }` (any
//! [`AnyEnergy`]; default neo-Hookean, μ = 1); a sheet's `nodes` is `[n, m]`.

use super::error::{deserialize_at, ScenarioError};
use crate::energy::AnyEnergy;
use crate::line::LineConfig;
use crate::observe::ModelKind;
use crate::sheet::{ShearConfig, SheetConfig};

/// Keys of `[model]` owned by the scenario layer (removed before the model's config is parsed).
pub const SCENARIO_KEYS: [&str; 4] = ["kind", "models", "nodes", "energy"];

/// The model kinds a scenario can name.
pub const KINDS: [&str; 3] = ["line", "sheet", "shear"];

/// A parsed and validated model configuration.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelConfig {
    /// The line of cells (thesis Chapters 2–3).
    Line(Box<LineConfig>),
    /// A growing line with cell division: `kind = "line"` plus a `division = { rule = … }`
    /// table (thesis §3.3.2; [`crate::events::run_proliferation`]).
    Proliferating(Box<crate::events::ProliferationConfig>),
    /// The uniaxial sheet (thesis Chapter 4.2) and its strain energy.
    Sheet(Box<SheetConfig>, AnyEnergy),
    /// The simple-shear column (thesis Chapter 4.3) and its strain energy.
    Shear(Box<ShearConfig>, AnyEnergy),
}

impl ModelConfig {
    /// The `kind` string.
    pub fn kind(&self) -> &'static str {
        match self {
            ModelConfig::Line(_) | ModelConfig::Proliferating(_) => "line",
            ModelConfig::Sheet(..) => "sheet",
            ModelConfig::Shear(..) => "shear",
        }
    }

    /// The configuration as JSON (for `summary.json` `"parameters"`).
    pub fn to_json(&self) -> serde_json::Value {
        let (v, energy) = match self {
            ModelConfig::Line(c) => (serde_json::to_value(c), None),
            ModelConfig::Proliferating(c) => (serde_json::to_value(c), None),
            ModelConfig::Sheet(c, e) => (serde_json::to_value(c), Some(e)),
            ModelConfig::Shear(c, e) => (serde_json::to_value(c), Some(e)),
        };
        let mut v = v.unwrap_or(serde_json::Value::Null);
        if let (serde_json::Value::Object(m), Some(e)) = (&mut v, energy) {
            m.insert("energy".into(), serde_json::to_value(e).unwrap_or_default());
        }
        v
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
    /// Continuum grid of a sheet, `[n, m]` (`None`: the model's default).
    pub grid: Option<(usize, usize)>,
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
    let node_count = |v: &toml::Value| match v {
        toml::Value::Integer(n) if (1..=100_000_000).contains(n) => Some(*n as usize),
        _ => None,
    };
    let (mut nodes, mut grid) = (None, None);
    match rest.remove("nodes") {
        None => {}
        Some(v) if kind == "sheet" => {
            let g = v
                .as_array()
                .filter(|a| a.len() == 2)
                .and_then(|a| Some((node_count(&a[0])?, node_count(&a[1])?)));
            grid = Some(g.ok_or_else(|| {
                ScenarioError::key(
                    "model.nodes",
                    format!("= {v} must be [n, m] with integers n, m >= 1 (continuum grid)"),
                )
            })?);
        }
        Some(v) => {
            nodes = Some(node_count(&v).ok_or_else(|| {
                ScenarioError::key(
                    "model.nodes",
                    format!("= {v} must be an integer in 1..=100000000"),
                )
            })?);
        }
    }
    let energy = match rest.remove("energy") {
        None if kind != "line" => Some(default_energy()),
        None => None,
        Some(_) if kind == "line" => {
            return Err(ScenarioError::key(
                "model.energy",
                "the line takes its strain energy from `law` (LineConfig); `energy` is for sheet and shear",
            ))
        }
        Some(v) => Some(deserialize_at::<AnyEnergy>("model.energy", v)?),
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
        "sheet" => {
            let cfg: SheetConfig = deserialize_at("model", toml::Value::Table(rest))?;
            cfg.validate().map_err(sheet_error)?;
            ModelConfig::Sheet(Box::new(cfg), energy.unwrap_or_else(default_energy))
        }
        "shear" => {
            let cfg: ShearConfig = deserialize_at("model", toml::Value::Table(rest))?;
            cfg.validate().map_err(sheet_error)?;
            ModelConfig::Shear(Box::new(cfg), energy.unwrap_or_else(default_energy))
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
        grid,
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

/// Neo-Hookean with μ = 1, the thesis's cell law.
fn default_energy() -> AnyEnergy {
    AnyEnergy::NeoHookean(crate::energy::NeoHookean::new(1.0).expect("mu = 1 is valid"))
}

/// A sheet/shear validation error as a key error under `model.`.
fn sheet_error(e: crate::sheet::ConfigError) -> ScenarioError {
    ScenarioError::key(
        format!("model.{}", e.key),
        format!("= {} is invalid: {}", e.value, e.expected),
    )
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
    fn sheet_and_shear_parse_with_default_energy() {
        let m = parse("kind = \"sheet\"\ncells_x = 4\ncells_y = 3\nnodes = [8, 6]").unwrap();
        assert_eq!(m.grid, Some((8, 6)));
        assert!(matches!(m.config, ModelConfig::Sheet(..)));
        let m = parse("kind = \"shear\"\ncells = 5\nnodes = 20\nenergy = { law = \"mooney_rivlin\", c1 = 0.3, c2 = 0.2 }").unwrap();
        assert_eq!(m.nodes, Some(20));
        assert_eq!(m.config.kind(), "shear");
        assert_eq!(m.config.to_json()["energy"]["law"], "mooney_rivlin");
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
            key("kind = \"line\"\nnodes = 0").as_deref(),
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
        assert_eq!(
            key("kind = \"sheet\"\nnodes = 4").as_deref(),
            Some("model.nodes")
        );
        assert_eq!(
            key("kind = \"sheet\"\ncells_x = 0").as_deref(),
            Some("model.cells_x")
        );
        assert_eq!(
            key("kind = \"shear\"\nenergy = { law = \"neo_hookean\", mu = -1.0 }").as_deref(),
            Some("model.energy")
        );
        assert_eq!(
            key("kind = \"line\"\nenergy = { law = \"neo_hookean\" }").as_deref(),
            Some("model.energy")
        );
    }
}
