//! `[sweep]`: which parameter values a scenario runs, as a list of [`SweepPoint`]s.
//!
//! Three forms, documented in `models/README.md`:
//!
//! * one parameter: `parameter = "K"`, `values = [...]`, optional `labels`;
//! * a grid product: `grid = [{ parameter, values, labels }, …]`, every combination, the first
//!   parameter varying slowest;
//! * zipped lists: `zip = [{ parameter, values, labels }, …]`, lists of equal length whose
//!   `i`-th values run together. Given with `grid`, the zipped group is one more axis of the
//!   product (its last).
//!
//! ```
//! use celltissue::scenario::sweep::{expand, SweepSection};
//! let s: SweepSection = toml::from_str(r#"
//!     grid = [{ parameter = "k1", values = [0.1, 0.3] },
//!             { parameter = "drag_exponent", values = [0, 1] }]
//! "#).unwrap();
//! let points = expand(&s).unwrap();
//! let labels: Vec<String> = points.iter().map(|p| p.assignment()).collect();
//! assert_eq!(labels, ["k1=0.1 drag_exponent=0", "k1=0.1 drag_exponent=1",
//!                     "k1=0.3 drag_exponent=0", "k1=0.3 drag_exponent=1"]);
//! ```

use super::error::ScenarioError;
use super::load::format_number;
use super::overrides::parse_path;
use serde::Deserialize;

/// Most runs one sweep may expand to (every point is validated before anything runs).
pub const MAX_SWEEP_POINTS: usize = 100_000;

/// The `[sweep]` table as written.
///
/// ```
/// use celltissue::scenario::sweep::{expand, SweepSection};
/// let s: SweepSection = toml::from_str("parameter = \"K\"\nvalues = [0.01, 1]").unwrap();
/// let points = expand(&s).unwrap();
/// assert_eq!(points.len(), 2);
/// assert_eq!((points[0].name.as_str(), points[0].value), ("K", Some(0.01)));
/// ```
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// One-parameter form: dotted key, relative to `[model]` (`"K"`, `"active.beta"`) or from
    /// the root (`"solver.rtol"`, `"model.eta"`).
    #[serde(default)]
    pub parameter: Option<String>,
    /// One-parameter form: the values (numbers, or any TOML value such as a field table).
    #[serde(default)]
    pub values: Option<Vec<toml::Value>>,
    /// One-parameter form: names for the values in labels and legends (default: the values).
    #[serde(default)]
    pub labels: Option<Vec<String>>,
    /// Grid product: every combination of these parameters' values.
    #[serde(default)]
    pub grid: Option<Vec<SweepAxis>>,
    /// Zipped lists: the `i`-th values of these parameters run together.
    #[serde(default)]
    pub zip: Option<Vec<SweepAxis>>,
    /// Realisations of a stochastic model: the seed key runs through `realisations`
    /// consecutive values, as the product's last (fastest) axis; the outputs add the
    /// ensemble's statistics ([`crate::output::ensemble`]).
    #[serde(default)]
    pub ensemble: Option<EnsembleSpec>,
}

/// `ensemble = { realisations = 32 }`: the seeded runs of one parameter set.
///
/// ```
/// use celltissue::scenario::sweep::{expand, SweepSection};
/// let s: SweepSection = toml::from_str("ensemble = { realisations = 3, first_seed = 7 }")
///     .unwrap();
/// let labels: Vec<String> = expand(&s).unwrap().iter().map(|p| p.assignment()).collect();
/// assert_eq!(labels, ["division.seed=7", "division.seed=8", "division.seed=9"]);
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleSpec {
    /// The seed's dotted key (default `"division.seed"`, the stochastic division rule's).
    #[serde(default = "default_seed_key")]
    pub parameter: String,
    /// Number of realisations, 2 to [`MAX_SWEEP_POINTS`].
    pub realisations: usize,
    /// The first seed (default 0); realisation `i` has seed `first_seed + i`.
    #[serde(default)]
    pub first_seed: u32,
}

fn default_seed_key() -> String {
    "division.seed".into()
}

/// One swept parameter of a `grid` or `zip`.
///
/// ```
/// use celltissue::scenario::sweep::SweepSection;
/// let sw: SweepSection = toml::from_str(
///     r#"zip = [{ parameter = "K", values = [0.1, 1.0], labels = ["weak", "strong"] },
///               { parameter = "eta", values = [0, 2] }]"#)?;
/// let axes = sw.zip.unwrap();
/// assert_eq!((axes[0].parameter.as_str(), axes[1].values.len()), ("K", 2));
/// assert_eq!(axes[0].labels.as_deref(), Some(&["weak".to_string(), "strong".to_string()][..]));
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepAxis {
    /// Dotted key (as [`SweepSection::parameter`]).
    pub parameter: String,
    /// The values.
    pub values: Vec<toml::Value>,
    /// Names for the values (default: the values themselves).
    #[serde(default)]
    pub labels: Option<Vec<String>>,
}

/// One swept parameter's value at a sweep point.
///
/// ```
/// use celltissue::scenario::sweep::{expand, SweepSection};
/// let sw: SweepSection = toml::from_str("parameter = \"division.ratio\"\nvalues = [1.5, 2]")?;
/// let part = &expand(&sw)?[1].parts[0];
/// assert_eq!((part.key.as_str(), part.name.as_str(), part.label.as_str()), ("model.division.ratio", "division.ratio", "2"));
/// assert_eq!((part.value, part.origin.as_str()), (Some(2.0), "sweep.values[1]"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPart {
    /// Full dotted key (`"model.K"`).
    pub key: String,
    /// Short name for labels: the key below its section (`"K"`, `"rtol"`, `"mu.amplitude"`).
    pub name: String,
    /// The value as shown in labels (`"0.01"`, `"1e-5"`, or the given label).
    pub label: String,
    /// The numeric value, if it is a number.
    pub value: Option<f64>,
    /// The value as TOML.
    pub raw: toml::Value,
    /// Where the value is written, e.g. `sweep.values[2]` or `sweep.grid[0].values[1]`.
    pub origin: String,
}

/// One point of a sweep: one value of every swept parameter.
///
/// ```
/// use celltissue::scenario::sweep::{expand, SweepSection};
/// let s: SweepSection = toml::from_str(
///     "zip = [{ parameter = \"k1\", values = [0.1, 0.2] }, { parameter = \"m\", values = [0, 1] }]",
/// ).unwrap();
/// let p = &expand(&s).unwrap()[1];
/// assert_eq!(p.assignment(), "k1=0.2 m=1");
/// assert_eq!(p.parts[0].key, "model.k1");
/// assert_eq!(p.value, None); // several parameters: no single numeric value
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// Short parameter name (`"K"`; several joined by commas: `"k1,drag_exponent"`).
    pub name: String,
    /// The value as shown in labels (several joined by commas: `"0.1,0"`).
    pub label: String,
    /// The numeric value of a one-parameter sweep (used on sweep-plot axes); `None` for a
    /// non-numeric value or several parameters.
    pub value: Option<f64>,
    /// The value as TOML (one parameter), or a table of the values by key (several).
    pub raw: toml::Value,
    /// Every swept parameter's value, in declaration order.
    pub parts: Vec<SweepPart>,
}

impl SweepPoint {
    /// `"K=0.01"`, or `"k1=0.1 drag_exponent=0"` for several parameters (used in run labels).
    ///
    /// ```
    /// use celltissue::scenario::sweep::{expand, SweepSection};
    /// let sw: SweepSection = toml::from_str(r#"zip = [{ parameter = "K", values = [0.01] }, { parameter = "eta", values = [2] }]"#)?;
    /// assert_eq!(expand(&sw)?[0].assignment(), "K=0.01 eta=2");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn assignment(&self) -> String {
        self.parts
            .iter()
            .map(|p| format!("{}={}", p.name, p.label))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// The full key of a sweep parameter: relative to `[model]` unless it starts with a section.
///
/// ```
/// use celltissue::scenario::sweep::sweep_key;
/// assert_eq!(sweep_key("sweep.parameter", "K").unwrap(), ["model", "K"]);
/// assert_eq!(sweep_key("sweep.parameter", "solver.rtol").unwrap(), ["solver", "rtol"]);
/// assert!(sweep_key("sweep.parameter", "a..b").is_err());
/// ```
pub fn sweep_key(at: &str, parameter: &str) -> Result<Vec<String>, ScenarioError> {
    let parts = parse_path(parameter).ok_or_else(|| {
        ScenarioError::key(
            at,
            format!("`{parameter}` is not a dotted key such as \"K\" or \"model.eta\""),
        )
    })?;
    Ok(match parts[0].as_str() {
        "model" | "solver" | "output" | "plots" => parts,
        _ => std::iter::once("model".to_string()).chain(parts).collect(),
    })
}

/// The ensemble's seed key (full dotted key), if the sweep has an ensemble.
///
/// ```
/// use celltissue::scenario::sweep::{ensemble_key, SweepSection};
/// let sw: SweepSection = toml::from_str("ensemble = { realisations = 4 }")?;
/// assert_eq!(ensemble_key(&sw)?.as_deref(), Some("model.division.seed"));
/// let plain: SweepSection = toml::from_str("parameter = \"K\"\nvalues = [1]")?;
/// assert_eq!(ensemble_key(&plain)?, None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn ensemble_key(sw: &SweepSection) -> Result<Option<String>, ScenarioError> {
    match &sw.ensemble {
        None => Ok(None),
        Some(e) => Ok(Some(
            sweep_key("sweep.ensemble.parameter", &e.parameter)?.join("."),
        )),
    }
}

/// The full keys a sweep sets (empty without a sweep), e.g. `["model.K"]`.
///
/// ```
/// use celltissue::scenario::sweep::{swept_keys, SweepSection};
/// let s: SweepSection = toml::from_str("grid = [{ parameter = \"K\", values = [1] }, \
///     { parameter = \"solver.rtol\", values = [1e-6] }]").unwrap();
/// assert_eq!(swept_keys(&s).unwrap(), ["model.K", "solver.rtol"]);
/// assert!(swept_keys(&SweepSection::default()).unwrap().is_empty());
/// ```
pub fn swept_keys(sw: &SweepSection) -> Result<Vec<String>, ScenarioError> {
    Ok(axes(sw)?
        .into_iter()
        .flat_map(|dim| dim.into_iter().map(|a| a.key))
        .collect())
}

/// A parameter ready to expand.
struct Axis {
    key: String,
    name: String,
    at: String,
    values: Vec<toml::Value>,
    labels: Option<Vec<String>>,
}

/// The sweep's dimensions: each a list of parameters of equal length that vary together.
fn axes(sw: &SweepSection) -> Result<Vec<Vec<Axis>>, ScenarioError> {
    let single = sw.parameter.is_some() || sw.values.is_some() || sw.labels.is_some();
    let multi = sw.grid.is_some() || sw.zip.is_some();
    if single && multi {
        return Err(ScenarioError::key(
            "sweep",
            "give either `parameter`/`values` (one parameter) or `grid`/`zip` (several), not both",
        ));
    }
    let axis = |at: String, a: &SweepAxis| -> Result<Axis, ScenarioError> {
        let key = sweep_key(&format!("{at}.parameter"), &a.parameter)?;
        Ok(Axis {
            // the key below its section: `K`, `rtol`, and `mu.amplitude`, not `amplitude`
            // (which K, η and the active stress have as well)
            name: key[1..].join("."),
            key: key.join("."),
            at,
            values: a.values.clone(),
            labels: a.labels.clone(),
        })
    };
    let mut dims: Vec<Vec<Axis>> = Vec::new();
    if single {
        let parameter = sw
            .parameter
            .as_deref()
            .ok_or_else(|| ScenarioError::key("sweep.parameter", "missing: the swept key"))?;
        let values = sw
            .values
            .clone()
            .ok_or_else(|| ScenarioError::key("sweep.values", "missing: the swept values"))?;
        let a = SweepAxis {
            parameter: parameter.to_string(),
            values,
            labels: sw.labels.clone(),
        };
        let mut ax = axis("sweep".into(), &a)?;
        ax.at = "sweep".into();
        dims.push(vec![ax]);
    }
    for (i, a) in sw.grid.iter().flatten().enumerate() {
        dims.push(vec![axis(format!("sweep.grid[{i}]"), a)?]);
    }
    if let Some(zip) = &sw.zip {
        if zip.is_empty() {
            return Err(ScenarioError::key(
                "sweep.zip",
                "needs at least one parameter",
            ));
        }
        let group = zip
            .iter()
            .enumerate()
            .map(|(i, a)| axis(format!("sweep.zip[{i}]"), a))
            .collect::<Result<Vec<_>, _>>()?;
        let n = group[0].values.len();
        if let Some(a) = group.iter().find(|a| a.values.len() != n) {
            return Err(ScenarioError::key(
                format!("{}.values", a.at),
                format!(
                    "has {} values but {}.values has {n}; zipped lists run their i-th values \
                     together and need equal lengths (use `grid` for every combination)",
                    a.values.len(),
                    group[0].at
                ),
            ));
        }
        dims.push(group);
    }
    if let Some(e) = &sw.ensemble {
        if !(2..=MAX_SWEEP_POINTS).contains(&e.realisations) {
            return Err(ScenarioError::key(
                "sweep.ensemble.realisations",
                format!(
                    "= {} must be from 2 to {MAX_SWEEP_POINTS} (an ensemble has several realisations)",
                    e.realisations
                ),
            ));
        }
        let seeds =
            (0..e.realisations as i64).map(|i| toml::Value::Integer(e.first_seed as i64 + i));
        let a = SweepAxis {
            parameter: e.parameter.clone(),
            values: seeds.collect(),
            labels: None,
        };
        dims.push(vec![axis("sweep.ensemble".into(), &a)?]);
    }
    if sw.grid.as_ref().is_some_and(Vec::is_empty) {
        return Err(ScenarioError::key(
            "sweep.grid",
            "needs at least one parameter",
        ));
    }
    // no key swept twice, and none inside another (`mu` and `mu.width`)
    let all: Vec<&Axis> = dims.iter().flatten().collect();
    for (i, a) in all.iter().enumerate() {
        for b in &all[..i] {
            let inside = |x: &str, y: &str| x == y || x.starts_with(&format!("{y}."));
            if inside(&a.key, &b.key) || inside(&b.key, &a.key) {
                return Err(ScenarioError::key(
                    format!("{}.parameter", a.at),
                    format!(
                        "`{}` is also swept by {}.parameter (`{}`); sweep each key once",
                        a.key, b.at, b.key
                    ),
                ));
            }
        }
    }
    Ok(dims)
}

/// Expands a sweep into its points (first grid axis slowest). Errors name the `[sweep]` key.
///
/// ```
/// use celltissue::scenario::sweep::{expand, SweepSection};
/// let sw: SweepSection = toml::from_str(r#"
///     grid = [{ parameter = "k1", values = [0.01, 0.1] },
///             { parameter = "drag_exponent", values = [0, 1] }]"#)?;
/// let labels: Vec<String> = expand(&sw)?.iter().map(|p| p.label.clone()).collect();
/// assert_eq!(labels, ["0.01,0", "0.01,1", "0.1,0", "0.1,1"]); // first axis slowest
/// assert_eq!(expand(&sw)?[0].parts[0].key, "model.k1");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn expand(sw: &SweepSection) -> Result<Vec<SweepPoint>, ScenarioError> {
    let dims = axes(sw)?;
    // each dimension as a list of value tuples
    let mut columns: Vec<Vec<Vec<SweepPart>>> = Vec::new();
    for dim in &dims {
        let n = dim[0].values.len();
        let mut rows: Vec<Vec<SweepPart>> = vec![Vec::new(); n];
        for a in dim {
            for (i, part) in parts(a)?.into_iter().enumerate() {
                rows[i].push(part);
            }
        }
        columns.push(rows);
    }
    let total = columns
        .iter()
        .try_fold(1usize, |acc, c| acc.checked_mul(c.len()))
        .filter(|n| *n <= MAX_SWEEP_POINTS);
    let Some(total) = total else {
        return Err(ScenarioError::key(
            "sweep",
            format!(
                "expands to more than {MAX_SWEEP_POINTS} parameter sets ({}); split it into \
                 several scenarios",
                columns
                    .iter()
                    .map(|c| c.len().to_string())
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
        ));
    };
    let mut points = Vec::with_capacity(total);
    for k in 0..total {
        // mixed-radix digits of k, last dimension fastest
        let mut rem = k;
        let mut idx = vec![0; columns.len()];
        for (d, c) in columns.iter().enumerate().rev() {
            idx[d] = rem % c.len();
            rem /= c.len();
        }
        let parts: Vec<SweepPart> = columns
            .iter()
            .zip(&idx)
            .flat_map(|(c, &i)| c[i].iter().cloned())
            .collect();
        points.push(point(parts));
    }
    let mut seen = std::collections::HashSet::new();
    for p in &points {
        if !seen.insert(p.assignment()) {
            return Err(ScenarioError::key(
                "sweep.labels",
                format!(
                    "`{}` appears twice; every run needs its own label (give distinct values \
                     or labels)",
                    p.assignment()
                ),
            ));
        }
    }
    Ok(points)
}

fn point(parts: Vec<SweepPart>) -> SweepPoint {
    if let [one] = parts.as_slice() {
        return SweepPoint {
            name: one.name.clone(),
            label: one.label.clone(),
            value: one.value,
            raw: one.raw.clone(),
            parts,
        };
    }
    let join = |f: &dyn Fn(&SweepPart) -> String| parts.iter().map(f).collect::<Vec<_>>().join(",");
    SweepPoint {
        name: join(&|p| p.name.clone()),
        label: join(&|p| p.label.clone()),
        value: None,
        raw: toml::Value::Table(
            parts
                .iter()
                .map(|p| (p.key.clone(), p.raw.clone()))
                .collect(),
        ),
        parts,
    }
}

/// The labelled values of one parameter.
fn parts(a: &Axis) -> Result<Vec<SweepPart>, ScenarioError> {
    if a.values.is_empty() {
        return Err(ScenarioError::key(
            format!("{}.values", a.at),
            "needs at least one value",
        ));
    }
    if let Some(labels) = &a.labels {
        if labels.len() != a.values.len() {
            return Err(ScenarioError::key(
                format!("{}.labels", a.at),
                format!(
                    "has {} entries but {}.values has {}; give one label per value",
                    labels.len(),
                    a.at,
                    a.values.len()
                ),
            ));
        }
        if let Some((i, _)) = labels.iter().enumerate().find(|(_, l)| !label_ok(l)) {
            return Err(ScenarioError::key(
                format!("{}.labels[{i}]", a.at),
                format!(
                    "must be 1 to {MAX_LABEL_CHARS} characters without `/`, `\\`, spaces \
                     or control characters (labels become file names)"
                ),
            ));
        }
    }
    let mut out: Vec<SweepPart> = Vec::new();
    for (i, raw) in a.values.iter().enumerate() {
        let origin = format!("{}.values[{i}]", a.at);
        let value = match raw {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(n) => Some(*n as f64),
            _ => None,
        };
        let label = match (&a.labels, raw, value) {
            (Some(l), _, _) => l[i].clone(),
            (None, toml::Value::String(s), _) if label_ok(s) => s.clone(),
            (None, toml::Value::Boolean(b), _) => b.to_string(),
            (None, _, Some(v)) => format_number(v),
            (None, _, None) => {
                return Err(ScenarioError::key(
                    format!("{}.labels", a.at),
                    format!(
                        "required: {origin} is a {} that cannot name a run (labels become \
                         file names)",
                        raw.type_str()
                    ),
                ))
            }
        };
        if out.iter().any(|p| p.label == label) {
            return Err(ScenarioError::key(
                origin,
                format!("`{label}` appears twice; every run needs its own label"),
            ));
        }
        out.push(SweepPart {
            key: a.key.clone(),
            name: a.name.clone(),
            label,
            value,
            raw: raw.clone(),
            origin,
        });
    }
    Ok(out)
}

/// Longest sweep label, in characters (file names are at most 255 bytes).
pub const MAX_LABEL_CHARS: usize = 40;

/// A label that can be part of a file name as it is.
fn label_ok(l: &str) -> bool {
    let n = l.chars().count();
    (1..=MAX_LABEL_CHARS).contains(&n)
        && !l
            .chars()
            .any(|c| c.is_control() || c.is_whitespace() || c == '/' || c == '\\')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(s: &str) -> Result<Vec<SweepPoint>, ScenarioError> {
        expand(&toml::from_str::<SweepSection>(s).unwrap())
    }

    #[test]
    fn single_parameter_form() {
        let p = sweep("parameter = \"K\"\nvalues = [1e-5, 0.01, 1]").unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!(p[0].assignment(), "K=1e-5");
        assert_eq!((p[1].name.as_str(), p[1].label.as_str()), ("K", "0.01"));
        assert_eq!(p[2].value, Some(1.0));
        assert_eq!(p[2].parts[0].origin, "sweep.values[2]");
        assert_eq!(p[2].parts[0].key, "model.K");
    }

    #[test]
    fn grid_is_the_product_first_axis_slowest() {
        let p = sweep(
            "grid = [{ parameter = \"k1\", values = [0.1, 0.3, 0.5] }, \
             { parameter = \"solver.rtol\", values = [1e-6, 1e-8] }]",
        )
        .unwrap();
        assert_eq!(p.len(), 6);
        assert_eq!(p[1].assignment(), "k1=0.1 rtol=1e-8");
        assert_eq!(p[2].assignment(), "k1=0.3 rtol=1e-6");
        assert_eq!(p[5].parts[1].origin, "sweep.grid[1].values[1]");
        assert_eq!(p[5].value, None);
        assert_eq!(
            (p[5].name.as_str(), p[5].label.as_str()),
            ("k1,rtol", "0.5,1e-8")
        );
    }

    #[test]
    fn zip_runs_values_together_and_joins_the_grid_as_one_axis() {
        let p = sweep(
            "zip = [{ parameter = \"m\", values = [0, 1] }, \
             { parameter = \"K\", values = [1e-5, 1e-2], labels = [\"low\", \"high\"] }]",
        )
        .unwrap();
        let l: Vec<String> = p.iter().map(SweepPoint::assignment).collect();
        assert_eq!(l, ["m=0 K=low", "m=1 K=high"]);
        let p = sweep(
            "grid = [{ parameter = \"k1\", values = [0.1, 0.2] }]\n\
             zip = [{ parameter = \"m\", values = [0, 1] }, { parameter = \"eta\", values = [1, 2] }]",
        )
        .unwrap();
        assert_eq!(p.len(), 4);
        assert_eq!(p[3].assignment(), "k1=0.2 m=1 eta=2");
    }

    #[test]
    fn malformed_sweeps_name_the_key() {
        let key = |s: &str| sweep(s).unwrap_err().key_name().map(str::to_string);
        assert_eq!(
            key("zip = [{ parameter = \"m\", values = [0, 1] }, { parameter = \"K\", values = [1] }]")
                .as_deref(),
            Some("sweep.zip[1].values")
        );
        assert_eq!(
            key("parameter = \"K\"\nvalues = [1]\ngrid = [{ parameter = \"m\", values = [0] }]")
                .as_deref(),
            Some("sweep")
        );
        assert_eq!(
            key("grid = [{ parameter = \"mu\", values = [1] }, { parameter = \"mu.width\", values = [0.1] }]")
                .as_deref(),
            Some("sweep.grid[1].parameter")
        );
        assert_eq!(
            key("parameter = \"K\"\nvalues = [1, 1.0]").as_deref(),
            Some("sweep.values[1]")
        );
        assert_eq!(
            key("parameter = \"K\"\nvalues = [1, 2]\nlabels = [\"a/b\", \"c\"]").as_deref(),
            Some("sweep.labels[0]")
        );
        assert_eq!(key("parameter = \"K\"").as_deref(), Some("sweep.values"));
        assert_eq!(key("values = [1]").as_deref(), Some("sweep.parameter"));
        assert_eq!(
            key("parameter = \"mu\"\nvalues = [{ type = \"constant\", value = 1 }]").as_deref(),
            Some("sweep.labels")
        );
        let big = format!(
            "grid = [{{ parameter = \"k1\", values = [{0}] }}, {{ parameter = \"m\", values = [{0}] }}]",
            (0..400).map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
        );
        assert_eq!(key(&big).as_deref(), Some("sweep"));
    }
}
