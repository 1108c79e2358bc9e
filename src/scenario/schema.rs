//! The sections of a scenario file as serde types (every table rejects unknown keys). The
//! `[model]` table is kept raw here: its `kind` selects the model's own config type
//! (see [`super::model`]), which owns and validates the rest of the keys.

use super::error::ScenarioError;
use crate::settings::SolveSettings;
use integrators::{ErrorNorm, IterativeSettings, LinearSolverChoice, MethodChoice};
use serde::{Deserialize, Serialize};

/// The file's top level as written (before sweep expansion and model parsing).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScenario {
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
    pub sweep: Option<super::sweep::SweepSection>,
    /// `[plots]` (optional).
    #[serde(default)]
    pub plots: PlotSettings,
}

/// `[solver]`: integrator and tolerances.
///
/// ```
/// use celltissue::scenario::schema::SolverSection;
/// let s: SolverSection = toml::from_str("method = \"radau\"\nrtol = 1e-8")?;
/// let settings = s.validate()?;
/// assert_eq!((settings.method.name(), settings.rtol), ("radau", 1e-8));
/// let bad: SolverSection = toml::from_str("rtol = 2")?;
/// assert_eq!(bad.validate().unwrap_err().key_name(), Some("solver.rtol"));
/// // a BDF-only key
/// let bound: SolverSection = toml::from_str("newton_alpha_bound = true")?;
/// assert!(bound.validate()?.newton_alpha_bound);
/// let radau: SolverSection = toml::from_str("method = \"radau\"\nnewton_alpha_bound = true")?;
/// assert_eq!(radau.validate().unwrap_err().key_name(), Some("solver.newton_alpha_bound"));
/// let order: SolverSection = toml::from_str("max_order = 2")?;
/// assert_eq!(order.validate()?.max_order, 2);
/// let six: SolverSection = toml::from_str("max_order = 6")?;
/// assert_eq!(six.validate().unwrap_err().key_name(), Some("solver.max_order"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
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
    /// Linear solver of the Newton iterations: `"direct"` (default: banded or sparse LU) or
    /// `"iterative"` (ILU(0)-preconditioned BiCGStab; sheet models only).
    pub linear_solver: String,
    /// Iterative solver: relative preconditioned residual at which every solve stops, in (0, 1).
    pub krylov_rtol: f64,
    /// Iterative solver: most BiCGStab iterations per solve, ≥ 1.
    pub krylov_max_iters: usize,
    /// Iterative solver: fraction of the Newton tolerance the linear error may reach, in
    /// [0, 1); 0 keeps only `krylov_rtol`.
    pub newton_factor: f64,
    /// Threads a run may use, 1 or 2 (default 1; 2 splits the passes of lines with ≥ 2¹⁵ cells).
    pub threads: usize,
    /// BDF only: steps after which the Newton matrices are refreshed even though Newton
    /// converges, 1 to 10⁶ (default 50).
    pub jacobian_age: Option<usize>,
    /// BDF only: whether the first Newton iteration after a change of the step's `α` assumes
    /// at least the convergence rate that change implies (default false: IDA's test).
    pub newton_alpha_bound: bool,
    /// BDF only: the highest order it may select, 1 to 5 (default 5).
    pub max_order: Option<usize>,
    /// Most steps a run may take before it stops, saying so, 1 to 10¹² (default 10⁶).
    pub max_steps: Option<u64>,
    /// Whether steps end at every output time instead of interpolating (default: for every
    /// method but BDF, whose dense output is error-controlled).
    pub land_on_outputs: Option<bool>,
    /// Whether outputs that read rates keep the interpolated ones (default false: solved from
    /// each output's state).
    pub interpolate_rates: bool,
    /// Whether each run is repeated at a tenfold tighter `rtol` and `atol` and compared with
    /// it at the profile and series times (default false).
    pub accuracy_check: bool,
}

/// Largest `solver.max_steps` (10¹²): beyond any run that could finish.
const MAX_STEPS_LIMIT: u64 = 1_000_000_000_000;

impl Default for SolverSection {
    fn default() -> Self {
        Self {
            method: "bdf".into(),
            rtol: 1e-6,
            atol: 1e-8,
            norm: "max".into(),
            linear_solver: "direct".into(),
            krylov_rtol: IterativeSettings::default().rtol,
            krylov_max_iters: IterativeSettings::default().max_iters,
            newton_factor: IterativeSettings::default().newton_factor,
            threads: 1,
            jacobian_age: None,
            newton_alpha_bound: false,
            max_order: None,
            max_steps: None,
            land_on_outputs: None,
            interpolate_rates: false,
            accuracy_check: false,
        }
    }
}

impl SolverSection {
    /// Checks the method name and tolerance ranges.
    ///
    /// ```
    /// use celltissue::scenario::schema::SolverSection;
    /// let s: SolverSection = toml::from_str("method = \"radau\"\nrtol = 1e-8")?;
    /// assert_eq!(s.validate()?.rtol, 1e-8);
    /// let bad: SolverSection = toml::from_str("method = \"euler\"")?;
    /// assert!(bad.validate().is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn validate(&self) -> Result<SolveSettings, ScenarioError> {
        // built-in names and the methods registered with `integrators::method::register`
        let method: MethodChoice =
            self.method
                .parse()
                .map_err(|e: integrators::method::MethodError| {
                    ScenarioError::key("solver.method", e.to_string())
                })?;
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
        let norm = ErrorNorm::parse(&self.norm)
            .map_err(|e| ScenarioError::key("solver.norm", e.to_string()))?;
        let linear_solver = match self.linear_solver.as_str() {
            "direct" => LinearSolverChoice::Direct,
            "iterative" => {
                if !(self.krylov_rtol > 0.0 && self.krylov_rtol < 1.0) {
                    return Err(ScenarioError::key(
                        "solver.krylov_rtol",
                        format!("= {} must be in (0, 1)", self.krylov_rtol),
                    ));
                }
                if self.krylov_max_iters == 0 {
                    return Err(ScenarioError::key(
                        "solver.krylov_max_iters",
                        "= 0 must be at least 1".to_string(),
                    ));
                }
                if !(self.newton_factor >= 0.0 && self.newton_factor < 1.0) {
                    return Err(ScenarioError::key(
                        "solver.newton_factor",
                        format!("= {} must be in [0, 1)", self.newton_factor),
                    ));
                }
                LinearSolverChoice::Iterative(IterativeSettings {
                    rtol: self.krylov_rtol,
                    max_iters: self.krylov_max_iters,
                    newton_factor: self.newton_factor,
                })
            }
            other => {
                return Err(ScenarioError::key(
                    "solver.linear_solver",
                    format!("= \"{other}\" must be \"direct\" or \"iterative\""),
                ))
            }
        };
        if integrators::Parallelism::from_threads(self.threads).is_err() {
            return Err(ScenarioError::key(
                "solver.threads",
                format!(
                    "= {} must be 1 or 2 (passes are split in two halves at most)",
                    self.threads
                ),
            ));
        }
        let bdf = |key: &str, value: Option<usize>, default: usize, max: usize, unit: &str| {
            bdf_count(key, value, default, max, unit, method.name())
        };
        let jacobian_age = bdf(
            "solver.jacobian_age",
            self.jacobian_age,
            SolveSettings::default().jacobian_age,
            1_000_000,
            "steps",
        )?;
        if self.newton_alpha_bound && method.name() != "bdf" {
            return Err(bdf_only("solver.newton_alpha_bound", method.name()));
        }
        let max_order = bdf(
            "solver.max_order",
            self.max_order,
            SolveSettings::default().max_order,
            5,
            "BDF's orders",
        )?;
        let max_steps = match self.max_steps {
            None => SolveSettings::default().max_steps,
            Some(m) if !(1..=MAX_STEPS_LIMIT).contains(&m) => {
                return Err(ScenarioError::key(
                    "solver.max_steps",
                    format!("= {m} must be from 1 to 10^12 (steps)"),
                ))
            }
            Some(m) => usize::try_from(m).unwrap_or(usize::MAX),
        };
        Ok(SolveSettings {
            method,
            rtol: self.rtol,
            atol: self.atol,
            norm,
            linear_solver,
            threads: self.threads,
            jacobian_age,
            newton_alpha_bound: self.newton_alpha_bound,
            max_order,
            max_steps,
            land_on_outputs: self.land_on_outputs,
            interpolate_rates: self.interpolate_rates,
            accuracy_check: self.accuracy_check,
        })
    }
}

/// A BDF-only count key (`value`, `default` when absent), from 1 to `max` (`unit` names what
/// it counts), set with method `method`.
fn bdf_count(
    key: &str,
    value: Option<usize>,
    default: usize,
    max: usize,
    unit: &str,
    method: &str,
) -> Result<usize, ScenarioError> {
    match value {
        None => Ok(default),
        Some(v) if !(1..=max).contains(&v) => Err(ScenarioError::key(
            key,
            format!("= {v} must be from 1 to {max} ({unit})"),
        )),
        Some(_) if method != "bdf" => Err(bdf_only(key, method)),
        Some(v) => Ok(v),
    }
}

/// The error for a BDF-only `[solver]` key set with another method.
fn bdf_only(key: &str, method: &str) -> ScenarioError {
    ScenarioError::key(
        key,
        format!(
            "applies to method \"bdf\" only, not \"{method}\" (remove it from [solver], or \
             --unset {key}, to run another method)"
        ),
    )
}

/// `[output]`: when to record.
///
/// ```
/// use celltissue::scenario::schema::OutputSection;
/// use celltissue::scenario::times::parse_times;
/// let o: OutputSection = toml::from_str("series = { start = 0, stop = 10, count = 11 }\nprofiles = [10]")?;
/// assert_eq!(parse_times("output.series", &o.series)?.len(), 11);
/// assert!(o.profiles.is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Times of the scalar series: a list or `{ start, stop, count, spacing, zero }`.
    pub series: toml::Value,
    /// Times of the profiles (default: none).
    #[serde(default)]
    pub profiles: Option<toml::Value>,
}

/// An axis scale.
///
/// ```
/// use celltissue::scenario::schema::Scale;
/// #[derive(serde::Deserialize)]
/// struct Axes { time_axis: Scale }
/// let a: Axes = toml::from_str("time_axis = \"log\"")?;
/// assert_eq!(a.time_axis, Scale::Log);
/// assert_eq!(Scale::default(), Scale::Linear);
/// # Ok::<(), toml::de::Error>(())
/// ```
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
///
/// ```
/// use celltissue::scenario::schema::{PlotSettings, ProfileAxis};
/// let p: PlotSettings = toml::from_str("profile_axis = \"current\"")?;
/// assert_eq!(p.profile_axis, ProfileAxis::Current);
/// assert_eq!(PlotSettings::default().profile_axis, ProfileAxis::Reference); // against X
/// # Ok::<(), toml::de::Error>(())
/// ```
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
///
/// ```
/// use celltissue::scenario::schema::{PlotSettings, ProfileAxis, Scale};
/// let p: PlotSettings = toml::from_str("time_axis = \"log\"\nprofile_axis = \"current\"\nsweep_profiles = [10]")?;
/// assert_eq!((p.time_axis, p.profile_axis, p.sweep_profiles), (Scale::Log, ProfileAxis::Current, vec![10.0]));
/// assert!(toml::from_str::<PlotSettings>("time_axis = \"ln\"").is_err());
/// # Ok::<(), toml::de::Error>(())
/// ```
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
    /// Also plot each cell's stretch (tan θ for a shear column) against `t` through the
    /// profile times, one curve per cell or continuum segment (Fig 4.6c); at most
    /// [`crate::output::figures::MAX_HISTORIES`] curves per run (every k-th cell beyond).
    pub histories: bool,
    /// Profile times (each one of `output.profiles`) at which the profiles of every swept
    /// value are also drawn on one plot, colour = swept value (Fig 3.1b: `α` at `t = 10` for
    /// several `K`); needs a `[sweep]`. Empty (default): none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sweep_profiles: Vec<f64>,
}
