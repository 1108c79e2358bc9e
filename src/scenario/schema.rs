//! The sections of a scenario file as serde types (every table rejects unknown keys). The
//! `[model]` table is kept raw here: its `kind` selects the model's own config type
//! (see [`super::model`]), which owns and validates the rest of the keys.

use super::error::ScenarioError;
use integrators::{ErrorNorm, MethodKind};
use serde::{Deserialize, Serialize};

/// The file's top level as written (before sweep expansion and model parsing).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScenario {
    /// Short name; becomes `"scenario"` in `summary.json`.
    pub name: String,
    /// One line saying what the scenario runs (shown by `celltissue list`).
    #[serde(default)]
    pub description: String,
    /// The thesis figure it reproduces, e.g. `"2.5"`.
    #[serde(default)]
    pub figure: Option<String>,
    /// `[solver]`.
    #[serde(default)]
    pub solver: SolverSection,
    /// `[output]`.
    pub output: OutputSection,
    /// `[model]`, parsed by [`super::model::parse_model`].
    pub model: toml::Table,
    /// `[sweep]` (optional).
    #[serde(default)]
    pub sweep: Option<SweepSection>,
    /// `[plots]` (optional).
    #[serde(default)]
    pub plots: PlotSettings,
}

/// `[solver]`: integrator and tolerances.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSection {
    /// `"bdf"` (default), `"esdirk"`, `"radau"` or `"dopri"`.
    pub method: String,
    /// Relative tolerance, in (0, 1).
    pub rtol: f64,
    /// Absolute tolerance in cell units, > 0.
    pub atol: f64,
    /// Error norm: `"max"` (default for cell arrays) or `"rms"`.
    pub norm: String,
}

impl Default for SolverSection {
    fn default() -> Self {
        Self {
            method: "bdf".into(),
            rtol: 1e-6,
            atol: 1e-8,
            norm: "max".into(),
        }
    }
}

/// The validated solver choice.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolverChoice {
    /// Method.
    #[serde(serialize_with = "method_name")]
    pub method: MethodKind,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (cell units).
    pub atol: f64,
    /// Error norm of the local error and Newton tests.
    #[serde(serialize_with = "norm_name")]
    pub norm: ErrorNorm,
}

fn norm_name<S: serde::Serializer>(n: &ErrorNorm, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(match n {
        ErrorNorm::Rms => "rms",
        ErrorNorm::Max => "max",
    })
}

fn method_name<S: serde::Serializer>(m: &MethodKind, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(m.name())
}

impl SolverSection {
    /// Checks the method name and tolerance ranges.
    pub fn validate(&self) -> Result<SolverChoice, ScenarioError> {
        let method: MethodKind = self
            .method
            .parse()
            .map_err(|e: String| ScenarioError::key("solver.method", e))?;
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(ScenarioError::key(
                "solver.rtol",
                format!("= {} must be in (0, 1)", self.rtol),
            ));
        }
        if !(self.atol > 0.0 && self.atol.is_finite()) {
            return Err(ScenarioError::key(
                "solver.atol",
                format!("= {} must be finite and > 0", self.atol),
            ));
        }
        let norm =
            ErrorNorm::parse(&self.norm).map_err(|e| ScenarioError::key("solver.norm", e))?;
        Ok(SolverChoice {
            method,
            rtol: self.rtol,
            atol: self.atol,
            norm,
        })
    }
}

/// `[output]`: when to record.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Times of the scalar series: a list or `{ start, stop, count, spacing, zero }`.
    pub series: toml::Value,
    /// Times of the profiles (default: none).
    #[serde(default)]
    pub profiles: Option<toml::Value>,
}

/// `[sweep]`: one parameter, several values; every model runs once per value.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// Dotted key, relative to `[model]` (`"K"`, `"active.beta"`) or from the root
    /// (`"solver.rtol"`, `"model.eta"`).
    pub parameter: String,
    /// The values (numbers, or any TOML value such as a field table).
    pub values: Vec<toml::Value>,
    /// Names for the values in labels and legends (default: the values themselves).
    #[serde(default)]
    pub labels: Option<Vec<String>>,
}

/// An axis scale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    /// Linear.
    #[default]
    Linear,
    /// Logarithmic (non-positive values are left out).
    Log,
}

/// Which position profiles are plotted against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileAxis {
    /// The reference position `X` (initial cell centre).
    #[default]
    Reference,
    /// The current position `x`.
    Current,
}

/// `[plots]`: how the PNGs look (all keys optional).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlotSettings {
    /// Horizontal axis of profile plots: `"reference"` (X, default) or `"current"` (x).
    pub profile_axis: ProfileAxis,
    /// Time axis of series plots: `"linear"` (default) or `"log"`.
    pub time_axis: Scale,
    /// Horizontal axis of sweep plots (extremes vs the swept value): `"linear"` or `"log"`.
    pub sweep_axis: Scale,
    /// Also plot the current position x against X, with the uniform-strain line
    /// `x = (l(t)/l₀)·X` dashed (Fig 2.6).
    pub position: bool,
    /// Also draw cell rectangles coloured by pressure at each profile time (Fig 2.10e).
    pub rectangles: bool,
}
