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
//! Every kind takes its strain energy from its config's `law` key, e.g.
//! `law = { law = "neo_hookean", mu = 1.0 }` (any [`AnyEnergy`]; default neo-Hookean, μ = 1);
//! `energy` is rejected, naming `law`. A sheet's `nodes` is `[n, m]`.

use super::error::{deserialize_at, ScenarioError};
use super::limits;
use crate::energy::AnyEnergy;
use crate::line::LineConfig;
use crate::observe::ModelKind;
use crate::sheet::{ShearConfig, SheetConfig};

/// Keys of `[model]` owned by the scenario layer (removed before the model's config is parsed).
pub const SCENARIO_KEYS: [&str; 3] = ["kind", "models", "nodes"];

/// The model kinds a scenario can name.
pub const KINDS: [&str; 3] = ["line", "sheet", "shear"];

/// The built-in kinds and the registered modes ([`crate::modes::register`]), for messages.
fn valid_kinds() -> String {
    let mut kinds: Vec<String> = KINDS.iter().map(|k| k.to_string()).collect();
    kinds.extend(crate::modes::names());
    kinds.join(", ")
}

/// A parsed and validated model configuration.
///
/// ```
/// use celltissue::scenario::{model::parse_model, ModelConfig};
/// let t: toml::Table = toml::from_str("kind = \"line\"\nright_end = \"free\"\n\
///     growth = { sigma0 = 0.1 }\ndivision = { rule = \"area\" }")?;
/// // a line with a division table is a proliferating line
/// assert!(matches!(parse_model(&t)?.config, ModelConfig::Proliferating(_)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelConfig {
    /// The line of cells (thesis Chapters 2–3).
    Line(Box<LineConfig>),
    /// A growing line with cell division: `kind = "line"` plus a `division = { rule = … }`
    /// table (thesis §3.3.2; [`crate::events::run_proliferation`]).
    Proliferating(Box<crate::events::ProliferationConfig>),
    /// The uniaxial sheet (thesis Chapter 4.2) and its strain energy (the config's `law`).
    Sheet(Box<SheetConfig>, AnyEnergy),
    /// The simple-shear column (thesis Chapter 4.3) and its strain energy (the config's `law`).
    Shear(Box<ShearConfig>, AnyEnergy),
    /// A deformation mode a program registered ([`crate::modes::register`]).
    Mode(Box<crate::modes::ModeSpec>),
}

impl ModelConfig {
    /// Whether the model's outputs read rates (Kelvin–Voigt cells: η given and not 0), which
    /// `solver.interpolate_rates` is about; `None` for a registered mode, which the scenario
    /// cannot see into.
    ///
    /// ```
    /// use celltissue::scenario::model::parse_model;
    /// let line = |extra: &str| -> Result<Option<bool>, Box<dyn std::error::Error>> {
    ///     let t: toml::Table = toml::from_str(&format!("kind = \"line\"\ncells = 4\n{extra}"))?;
    ///     Ok(parse_model(&t)?.config.outputs_read_rates())
    /// };
    /// assert_eq!(line("")?, Some(false));
    /// assert_eq!(line("eta = 0.5")?, Some(true));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn outputs_read_rates(&self) -> Option<bool> {
        use crate::cell::ViscosityModel;
        let kelvin_voigt = |v: &Option<ViscosityModel>| matches!(v, Some(ViscosityModel::KelvinVoigt { eta }) if *eta != 0.0);
        let line =
            |c: &LineConfig| !matches!(c.kv_eta(), crate::cell::Field::Constant(e) if e == 0.0);
        match self {
            ModelConfig::Line(c) => Some(line(c)),
            ModelConfig::Proliferating(c) => Some(line(&c.line)),
            ModelConfig::Sheet(c, _) => Some(kelvin_voigt(&c.viscosity)),
            ModelConfig::Shear(c, _) => Some(kelvin_voigt(&c.viscosity)),
            ModelConfig::Mode(_) => None,
        }
    }

    /// The `kind` string.
    ///
    /// ```
    /// use celltissue::scenario::model::parse_model;
    /// let t: toml::Table = toml::from_str("kind = \"shear\"\ncells = 4")?;
    /// let m = parse_model(&t)?;
    /// assert_eq!(m.config.kind(), "shear");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn kind(&self) -> &str {
        match self {
            ModelConfig::Line(_) | ModelConfig::Proliferating(_) => "line",
            ModelConfig::Sheet(..) => "sheet",
            ModelConfig::Shear(..) => "shear",
            ModelConfig::Mode(m) => m.name(),
        }
    }

    /// The configuration as JSON (for `summary.json` `"parameters"`).
    ///
    /// ```
    /// use celltissue::scenario::model::parse_model;
    /// let t: toml::Table = toml::from_str("kind = \"shear\"\ncells = 4")?;
    /// let m = parse_model(&t)?;
    /// let j = m.config.to_json();
    /// assert_eq!(j["cells"], 4);
    /// assert!(j.get("law").is_some()); // the law, once
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn to_json(&self) -> serde_json::Value {
        // the law is the config's own `law` key (the `AnyEnergy` beside a sheet/shear config is
        // a copy of it), so it appears once
        let v = match self {
            ModelConfig::Line(c) => serde_json::to_value(c),
            ModelConfig::Proliferating(c) => serde_json::to_value(c),
            ModelConfig::Sheet(c, _) => serde_json::to_value(c),
            ModelConfig::Shear(c, _) => serde_json::to_value(c),
            ModelConfig::Mode(m) => Ok(serde_json::Value::Object(m.params().clone())),
        };
        v.unwrap_or(serde_json::Value::Null)
    }
}

/// What `[model]` says.
///
/// ```
/// use celltissue::observe::ModelKind;
/// use celltissue::scenario::model::parse_model;
/// let t: toml::Table = toml::from_str("kind = \"line\"\ncells = 10\nmodels = [\"continuum\"]\nnodes = 40")?;
/// let m = parse_model(&t)?;
/// assert_eq!((m.models.as_slice(), m.nodes, m.grid), (&[ModelKind::Continuum][..], Some(40), None));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
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
///
/// ```
/// use celltissue::scenario::model::parse_model;
/// let t: toml::Table = toml::from_str("kind = \"sheet\"\ncells_x = 4\ncells_y = 2\nnodes = [8, 4]")?;
/// let m = parse_model(&t)?;
/// assert_eq!(m.grid, Some((8, 4)));
/// let bad: toml::Table = toml::from_str("kind = \"line\"\nK = -1")?;
/// assert_eq!(parse_model(&bad).unwrap_err().key_name(), Some("model.K"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
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
                    valid_kinds()
                ),
            ))
        }
        None => {
            return Err(ScenarioError::key(
                "model.kind",
                format!("missing; valid: {}", valid_kinds()),
            ))
        }
    };
    let models = match rest.remove("models") {
        None => vec![ModelKind::Discrete, ModelKind::Continuum],
        Some(v) => parse_models(&v)?,
    };
    // a whole number written as a float (`nodes = 2e2`) counts as well, as for every integer key
    let node_count = |v: &toml::Value| match v {
        toml::Value::Integer(n) if (1..=100_000_000).contains(n) => Some(*n as usize),
        toml::Value::Float(x) if x.fract() == 0.0 && (1.0..=1e8).contains(x) => Some(*x as usize),
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
                    format!("= {v} must be an integer from 1 to 100000000"),
                )
            })?);
        }
    }
    if rest.contains_key("energy") {
        // one key for the strain energy of every model kind: `law` (the models' own field)
        return Err(ScenarioError::key(
            "model.energy",
            "is not a key: the strain energy of every model kind is `model.law`, e.g. \
             law = { law = \"neo_hookean\", mu = 1 }",
        ));
    }
    let config = match kind.as_str() {
        "line" if rest.contains_key("division") => {
            let mut division_rest = rest.clone();
            let division = division_rest
                .remove("division")
                .unwrap_or_else(|| toml::Value::Table(toml::Table::new()));
            let division: crate::events::DivisionConfig =
                deserialize_at("model.division", division)?;
            let line: LineConfig = deserialize_at("model", toml::Value::Table(division_rest))?;
            check_end_keys(&written(&rest), &line)?;
            check_line_size(
                &line,
                models
                    .contains(&ModelKind::Continuum)
                    .then_some(nodes)
                    .flatten(),
            )?;
            if let Some(m) = division.max_cells {
                limits::check_cells(
                    "model.division.max_cells",
                    m as f64,
                    limits::LINE_BYTES_PER_CELL,
                    limits::MAX_LINE_CELLS,
                )?;
            }
            line.validate().map_err(line_error)?;
            if models.contains(&ModelKind::Continuum) {
                check_continuum_grid(&line, nodes)?;
                let (cells, n) = (line.n_cells(), nodes.unwrap_or(line.n_cells()));
                if division.cell_grid.is_some() && (n == 0 || !cells.is_multiple_of(n)) {
                    return Err(ScenarioError::key(
                        "model.nodes",
                        format!(
                            "{n}: the cell-number grid (division.cell_grid) needs a whole \
                             number of cells per segment, so nodes must divide cells = {cells}"
                        ),
                    ));
                }
                if division.batch_within > 0.0 {
                    return Err(ScenarioError::key(
                        "model.division.batch_within",
                        format!(
                            "{}: bringing divisions forward applies to the discrete line \
                             only; the continuum models divide each segment at its own time \
                             (run them with batch_within = 0, or set models = [\"discrete\"])",
                            division.batch_within
                        ),
                    ));
                }
                if division.cell_grid.is_none() && division.area_ratio().is_none() {
                    return Err(ScenarioError::key(
                        "model.division.rule",
                        "the density continuum (model \"continuum\" without \
                         division.cell_grid) supports only rule = \"area\"; add \
                         cell_grid = {} to the division table for other rules",
                    ));
                }
            }
            let cfg = crate::events::ProliferationConfig { line, division };
            let continuum = models.contains(&ModelKind::Continuum);
            cfg.validate()
                .and_then(|()| {
                    if continuum {
                        cfg.validate_continuum()
                    } else {
                        Ok(())
                    }
                })
                .map_err(|e| match e {
                    crate::events::ProliferationError::Line(e) => line_error(e),
                    other => {
                        ScenarioError::key(model_key(other.key().as_deref()), other.to_string())
                    }
                })?;
            ModelConfig::Proliferating(Box::new(cfg))
        }
        "line" => {
            let given = written(&rest);
            let cfg: LineConfig = deserialize_at("model", toml::Value::Table(rest))?;
            check_end_keys(&given, &cfg)?;
            check_line_size(
                &cfg,
                models
                    .contains(&ModelKind::Continuum)
                    .then_some(nodes)
                    .flatten(),
            )?;
            cfg.validate().map_err(line_error)?;
            if models.contains(&ModelKind::Continuum) {
                check_continuum_grid(&cfg, nodes)?;
            }
            ModelConfig::Line(Box::new(cfg))
        }
        "sheet" => {
            let given = written(&rest);
            let cfg: SheetConfig = deserialize_at("model", toml::Value::Table(rest))?;
            check_sheet_end_keys(&given, &cfg)?;
            limits::check_cells(
                "model.cells_x",
                cfg.cells_x as f64 * cfg.cells_y as f64,
                limits::SHEET_BYTES_PER_CELL,
                limits::MAX_SHEET_CELLS,
            )
            .map_err(|e| e.with_note("cells_x · cells_y counts"))?;
            if models.contains(&ModelKind::Continuum) {
                // the continuum's default grid is (2 cells_x, 2 cells_y)
                let (n, m) =
                    grid.unwrap_or((2 * cfg.cells_x.min(1 << 40), 2 * cfg.cells_y.min(1 << 40)));
                limits::check_cells(
                    "model.nodes",
                    n as f64 * m as f64,
                    limits::SHEET_BYTES_PER_CELL,
                    limits::MAX_SHEET_CELLS,
                )
                .map_err(|e| {
                    e.with_note(
                        "n · m grid points of the continuum; default [2 cells_x, 2 cells_y]",
                    )
                })?;
            }
            cfg.validate().map_err(sheet_error)?;
            let law = cfg.law.clone();
            ModelConfig::Sheet(Box::new(cfg), law)
        }
        "shear" => {
            let cfg: ShearConfig = deserialize_at("model", toml::Value::Table(rest))?;
            let continuum = models.contains(&ModelKind::Continuum);
            if continuum && cfg.form == crate::sheet::ShearForm::CellCentre {
                return Err(ScenarioError::key(
                    "model.form",
                    "= \"cell_centre\" is discrete only; use form = \"edge\" for the \
                     continuum, or models = [\"discrete\"]",
                ));
            }
            // the continuum's default grid is 4 cells
            let grid = continuum.then(|| nodes.unwrap_or(cfg.cells.saturating_mul(4)));
            for (key, n) in [("model.cells", Some(cfg.cells)), ("model.nodes", grid)] {
                if let Some(n) = n {
                    limits::check_cells(
                        key,
                        n as f64,
                        limits::LINE_BYTES_PER_CELL,
                        limits::MAX_LINE_CELLS,
                    )?;
                }
            }
            cfg.validate().map_err(sheet_error)?;
            let law = cfg.law.clone();
            ModelConfig::Shear(Box::new(cfg), law)
        }
        other if crate::modes::names().iter().any(|n| n == other) => {
            // a registered mode: the table (with its `kind`) deserializes as the growth
            // laws' and division rules' do, errors naming `model.<key>` the same way
            let mut table = rest;
            table.insert("kind".into(), toml::Value::String(other.to_owned()));
            let spec: crate::modes::ModeSpec = deserialize_at("model", toml::Value::Table(table))?;
            ModelConfig::Mode(Box::new(spec))
        }
        other => {
            return Err(ScenarioError::key(
                "model.kind",
                format!("unknown model kind `{other}`; valid: {}", valid_kinds()),
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

/// Keys of a line that one right-end condition alone reads, with what they mean there.
const END_KEYS: [(&str, crate::line::config::RightEndKind, &str); 6] = {
    use crate::line::config::RightEndKind::{Free, Periodic, Prescribed};
    [
        ("k1", Prescribed, "the shortening of a prescribed right end"),
        (
            "t_ramp",
            Prescribed,
            "the ramp time of a prescribed right end",
        ),
        ("ramp", Prescribed, "the ramp of a prescribed right end"),
        ("force", Free, "the force on a free right end"),
        (
            "free_end_drag",
            Free,
            "the drag of a continuum grid's free-end node",
        ),
        ("gauge", Periodic, "the pin x₀ = 0 of a ring"),
    ]
};

/// The keys of [`END_KEYS`] written in `[model]` (the table itself is handed on to the
/// deserializer, and a line's may hold 10⁸ reference lengths: no copy of it).
fn written(table: &toml::Table) -> Vec<&'static str> {
    END_KEYS
        .iter()
        .map(|&(key, _, _)| key)
        .filter(|k| table.contains_key(*k))
        .collect()
}

/// Rejects a key of `[model]` (`given`: those written) that the line's right end does not read
/// ([`END_KEYS`]): it would be ignored, and a result that silently ignores a key cannot be
/// trusted.
///
/// ```
/// use celltissue::scenario::model::parse_model;
/// let t: toml::Table = toml::from_str("kind = \"line\"\nright_end = \"free\"\nK = 1\nk1 = 0.3")?;
/// let e = parse_model(&t).unwrap_err();
/// assert_eq!(e.key_name(), Some("model.k1"));
/// assert!(e.to_string().contains("prescribed right end"), "{e}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
fn check_end_keys(given: &[&str], cfg: &LineConfig) -> Result<(), ScenarioError> {
    use crate::line::config::RightEndKind;
    let name = |e| match e {
        RightEndKind::Prescribed => "prescribed",
        RightEndKind::Free => "free",
        RightEndKind::Periodic => "periodic",
    };
    for (key, end, meaning) in END_KEYS {
        if cfg.right_end != end {
            let ends = ("right_end", name(cfg.right_end), name(end));
            reject_unread(given, key, meaning, ends)?;
        }
    }
    Ok(())
}

/// The ramp keys of a sheet, read only with `right = "prescribed"`.
///
/// ```
/// use celltissue::scenario::model::parse_model;
/// let t: toml::Table = toml::from_str(
///     "kind = \"sheet\"\nright = \"free\"\ngrowth = { sigma0 = 0.1 }\nk1 = 0.3",
/// )?;
/// assert_eq!(parse_model(&t).unwrap_err().key_name(), Some("model.k1"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
fn check_sheet_end_keys(given: &[&str], cfg: &SheetConfig) -> Result<(), ScenarioError> {
    if cfg.right == crate::sheet::config::RightEdge::Free {
        let ends = ("right", "free", "prescribed");
        reject_unread(given, "k1", "the shortening of a prescribed side", ends)?;
        reject_unread(given, "ramp", "the ramp of a prescribed side", ends)?;
    }
    Ok(())
}

/// The error for `key` (with its `meaning`) written (in `given`) although the model's
/// `(end key, its value, the value that reads key)` does not read it; `Ok` if not written.
fn reject_unread(
    given: &[&str],
    key: &str,
    meaning: &str,
    (end_key, this, reads): (&str, &str, &str),
) -> Result<(), ScenarioError> {
    if !given.contains(&key) {
        return Ok(());
    }
    Err(ScenarioError::key(
        format!("model.{key}"),
        format!(
            "is {meaning}, and this model has {end_key} = \"{this}\", which does not read \
             it: remove `{key}` or set {end_key} = \"{reads}\""
        ),
    ))
}

/// Size limits of a line (cells; continuum segments when the continuum runs) and the grid-size
/// rules the continuum builders enforce, checked before anything is allocated.
fn check_line_size(cfg: &LineConfig, nodes: Option<usize>) -> Result<(), ScenarioError> {
    let cells = cfg.n_cells();
    limits::check_cells(
        "model.cells",
        cells as f64,
        limits::LINE_BYTES_PER_CELL,
        limits::MAX_LINE_CELLS,
    )?;
    if let Some(n) = nodes {
        limits::check_cells(
            "model.nodes",
            n as f64,
            limits::LINE_BYTES_PER_CELL,
            limits::MAX_LINE_CELLS,
        )?;
    }
    Ok(())
}

/// Grid-size rules of the continuum schemes (`nodes`, default `cells`): the conservative
/// scheme with a prescribed end needs 2 segments (as the discrete line needs 2 cells), the
/// thesis scheme 3 nodes.
fn check_continuum_grid(cfg: &LineConfig, nodes: Option<usize>) -> Result<(), ScenarioError> {
    use crate::line::config::{ContinuumScheme, RightEndKind};
    let (n, key) = match nodes {
        Some(n) => (n, "model.nodes"),
        None => (cfg.n_cells(), "model.nodes"),
    };
    let given = if nodes.is_some() {
        String::new()
    } else {
        format!(" (default: `cells` = {n}; set `nodes`)")
    };
    let need = match cfg.continuum_scheme {
        ContinuumScheme::Thesis => Some((3, "with continuum_scheme = \"thesis\"")),
        ContinuumScheme::Conservative
            if cfg.right_end == RightEndKind::Prescribed && cfg.growth.is_none() =>
        {
            Some((2, "for the continuum with a prescribed right end"))
        }
        ContinuumScheme::Conservative => None,
    };
    match need {
        Some((min, why)) if n < min => Err(ScenarioError::key(
            key,
            format!("= {n}{given} is invalid: must be >= {min} {why}"),
        )),
        _ => Ok(()),
    }
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
        LineError::Field(e) => ScenarioError::key(format!("model.{}", e.key), e.to_string()),
        other => ScenarioError::key(model_key(other.key()), other.to_string()),
    }
}

/// A key under `model.` (`model` itself when no single key is at fault).
fn model_key(key: Option<&str>) -> String {
    key.map_or_else(|| "model".into(), |k| format!("model.{k}"))
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
        let m = parse("kind = \"shear\"\ncells = 5\nnodes = 20\nlaw = { law = \"mooney_rivlin\", c1 = 0.3, c2 = 0.2 }").unwrap();
        assert_eq!(m.nodes, Some(20));
        assert_eq!(m.config.kind(), "shear");
        let json = m.config.to_json();
        assert_eq!(json["law"]["law"], "mooney_rivlin");
        assert!(json.get("energy").is_none(), "the law appears once: {json}");
    }

    #[test]
    fn the_configured_law_is_the_law_that_runs() {
        // the law handed to the run functions is the config's `law` (once `law` was echoed
        // while a separate `energy` key, default mu = 1, ran)
        for kind in ["sheet", "shear"] {
            let m = parse(&format!(
                "kind = \"{kind}\"\nlaw = {{ law = \"neo_hookean\", mu = 5 }}"
            ))
            .unwrap();
            let (cfg_law, run_law) = match &m.config {
                ModelConfig::Sheet(c, l) => (c.law.clone(), l.clone()),
                ModelConfig::Shear(c, l) => (c.law.clone(), l.clone()),
                _ => panic!("{kind}"),
            };
            assert_eq!(cfg_law, run_law);
            let five = AnyEnergy::NeoHookean(crate::energy::NeoHookean::new(5.0).unwrap());
            assert_eq!(run_law, five, "{kind}");
        }
        let e = parse("kind = \"sheet\"\nenergy = { law = \"neo_hookean\", mu = 5 }").unwrap_err();
        assert_eq!(e.key_name(), Some("model.energy"));
        assert!(e.to_string().contains("model.law"), "{e}");
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
            key("kind = \"shear\"\nlaw = { law = \"neo_hookean\", mu = -1.0 }").as_deref(),
            Some("model.law")
        );
        assert_eq!(
            key("kind = \"line\"\nenergy = { law = \"neo_hookean\" }").as_deref(),
            Some("model.energy")
        );
    }
}
