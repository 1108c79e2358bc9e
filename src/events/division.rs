//! Division rules: when does a cell divide? A [`DivisionRule`] is an event function of one
//! cell's state that crosses zero *upwards* when the cell should divide; the integrator locates
//! the crossing on its dense output (docs/model.md §2.8).
//!
//! * [`AreaDoubling`] (default, thesis §3.1.8): `A/A₀ − r = g g₂ − r`, `r = 2`;
//! * [`AgeRule`]: `t − t_birth − T` (fixed cycle time);
//! * [`RandomThreshold`]: `g g₂ − θ_j` with a per-cell threshold drawn **at birth** from
//!   `θ ~ Uniform[r − w, r + w]` by a seeded [`SplitMix64`] generator (draws happen in event
//!   order — daughter with the lower index first — so a run is reproducible from its seed).

use super::rules::RuleSpec;
use crate::registry::{positive, ParamError, Params};
use serde::{Deserialize, Serialize};

/// What a rule sees of one cell: its growth and age, and (for rules whose
/// [`DivisionRule::needs_mechanics`] is `true`) its geometry and mechanics at the current
/// state. Mechanical fields are `NaN` for rules that do not ask for them.
///
/// ```
/// use celltissue::events::{CellView, DivisionRule, SurfaceToVolume};
/// // a surface-to-volume rule reads the cell's geometry
/// let rule = SurfaceToVolume { critical: 3.5 };
/// assert!(rule.needs_mechanics());
/// // a 2 × 1 cell: perimeter 6, area 2, ratio 3 below the critical 3.5: it divides
/// let c = CellView { length: 2.0, width: 1.0, area: 2.0, ..CellView::growth_only(2.0, 1.0, f64::NAN) };
/// assert_eq!(c.surface_to_volume(), 3.0);
/// assert!(rule.event(&c) > 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellView {
    /// Area ratio `A/A₀ = g·g₂`.
    pub area_ratio: f64,
    /// Time since the cell was born (since `t = 0` for the initial cells).
    pub age: f64,
    /// The cell's threshold drawn at birth ([`DivisionRule::draw_threshold`]; `NaN` if unused).
    pub threshold: f64,
    /// Current length `x_j − x_{j−1}`.
    pub length: f64,
    /// Current width `W = γ₀ g₂/α` (incompressible cell).
    pub width: f64,
    /// Current area `length·width` (`= A₀ g g₂`).
    pub area: f64,
    /// Axial stress `σ` (elastic, viscous and active parts).
    pub stress: f64,
    /// Elastic pressure `μ p(α)`.
    pub pressure: f64,
    /// Centre position `½(x_{j−1} + x_j)`.
    pub position: f64,
    /// Lengths of the left and right neighbours (`NaN` at an end of the line).
    pub neighbour_lengths: [f64; 2],
}

impl CellView {
    /// A view with growth and age only (mechanical fields `NaN`).
    ///
    /// ```
    /// use celltissue::events::CellView;
    /// let c = CellView::growth_only(1.5, 2.0, f64::NAN);
    /// assert_eq!(c.area_ratio, 1.5);
    /// assert!(c.length.is_nan());
    /// ```
    pub fn growth_only(area_ratio: f64, age: f64, threshold: f64) -> Self {
        Self {
            area_ratio,
            age,
            threshold,
            length: f64::NAN,
            width: f64::NAN,
            area: f64::NAN,
            stress: f64::NAN,
            pressure: f64::NAN,
            position: f64::NAN,
            neighbour_lengths: [f64::NAN; 2],
        }
    }

    /// Perimeter over area of the cell's 2D shape, `2(1/length + 1/width)`.
    ///
    /// ```
    /// use celltissue::events::CellView;
    /// let square = CellView { length: 1.0, width: 1.0, ..CellView::growth_only(1.0, 1.0, f64::NAN) };
    /// assert_eq!(square.surface_to_volume(), 4.0); // perimeter 4 over area 1
    /// ```
    pub fn surface_to_volume(&self) -> f64 {
        2.0 * (1.0 / self.length + 1.0 / self.width)
    }
}

/// A division rule: an event function that crosses zero upwards when a cell should divide.
///
/// ```
/// use celltissue::events::{AreaDoubling, CellView, DivisionRule};
/// let rule = AreaDoubling::default();
/// let cell = CellView::growth_only(1.5, 1.0, f64::NAN);
/// assert_eq!(rule.event(&cell), -0.5); // divides when g g₂ reaches 2
/// ```
pub trait DivisionRule: Send + Sync {
    /// Event value for a cell (negative before division, crosses zero upwards at division).
    fn event(&self, cell: &CellView) -> f64;

    /// [`event`](DivisionRule::event) of several cells at once, `out[i]` for `cells[i]`.
    /// The dividing line evaluates its cells in chunks through this method, so the rule's
    /// own `event` is inlined into the loop rather than called through the trait object cell
    /// by cell (that call and its view had cost 60 instructions per cell at every step).
    /// The default is that loop; override it only to do better.
    ///
    /// ```
    /// use celltissue::events::{AreaDoubling, CellView, DivisionRule};
    /// let rule: Box<dyn DivisionRule> = Box::new(AreaDoubling::default());
    /// let cells = [CellView::growth_only(1.5, 0.0, f64::NAN), CellView::growth_only(2.5, 0.0, f64::NAN)];
    /// let mut out = [0.0; 2];
    /// rule.event_batch(&cells, &mut out);
    /// assert_eq!(out, [rule.event(&cells[0]), rule.event(&cells[1])]);
    /// ```
    fn event_batch(&self, cells: &[CellView], out: &mut [f64]) {
        for (c, o) in cells.iter().zip(out) {
            *o = self.event(c);
        }
    }

    /// Per-cell threshold drawn when a cell is born (default: none, `NaN`).
    fn draw_threshold(&self, _rng: &mut SplitMix64) -> f64 {
        f64::NAN
    }

    /// Short name for logs.
    fn name(&self) -> String;

    /// Whether [`event`](DivisionRule::event) reads the geometry and mechanics of
    /// [`CellView`] (default `false`: they are then not computed, and are `NaN`).
    fn needs_mechanics(&self) -> bool {
        false
    }

    /// Checks the rule's parameters when a scenario builds it by name (default: nothing to
    /// check); the error names the parameter and its valid range.
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }

    /// Seed of the generator that [`draw_threshold`](DivisionRule::draw_threshold) draws from
    /// (default 0, for rules that draw nothing).
    fn seed(&self) -> u64 {
        0
    }
}

/// A shared rule is a rule (what a parsed [`DivisionConfig`] holds).
impl<R: DivisionRule + ?Sized> DivisionRule for std::sync::Arc<R> {
    fn event(&self, cell: &CellView) -> f64 {
        (**self).event(cell)
    }
    fn event_batch(&self, cells: &[CellView], out: &mut [f64]) {
        (**self).event_batch(cells, out)
    }
    fn draw_threshold(&self, rng: &mut SplitMix64) -> f64 {
        (**self).draw_threshold(rng)
    }
    fn name(&self) -> String {
        (**self).name()
    }
    fn needs_mechanics(&self) -> bool {
        (**self).needs_mechanics()
    }
    fn check(&self) -> Result<(), ParamError> {
        (**self).check()
    }
    fn seed(&self) -> u64 {
        (**self).seed()
    }
}

/// Division when the cell's perimeter-to-area ratio `2(1/ℓ + 1/W)` falls to `critical`
/// (thesis Ch. 5: a cell divides when its surface can no longer supply its volume). Unlike the
/// area rule it sees the shape: a cell compressed along the line (small `ℓ`, large `W`) keeps
/// a larger ratio and divides later than a stretched one of the same area.
///
/// ```
/// use celltissue::events::{CellView, DivisionRule, SurfaceToVolume};
/// let rule = SurfaceToVolume { critical: 3.0 };
/// let mut c = CellView::growth_only(2.0, 0.0, f64::NAN);
/// (c.length, c.width) = (2.0, 1.0); // P/A = 2(1/2 + 1) = 3
/// assert_eq!(rule.event(&c), 0.0);
/// (c.length, c.width) = (1.0, 2.0); // same area, same ratio (a square of side √2 has 2.83)
/// assert_eq!(rule.event(&c), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceToVolume {
    /// Perimeter-to-area ratio at division, > 0 (in 1/length; unit cells start at 4).
    pub critical: f64,
}

impl DivisionRule for SurfaceToVolume {
    fn event(&self, c: &CellView) -> f64 {
        self.critical - c.surface_to_volume()
    }
    fn name(&self) -> String {
        format!("surface to volume {}", self.critical)
    }
    fn needs_mechanics(&self) -> bool {
        true
    }
    fn check(&self) -> Result<(), ParamError> {
        positive("critical", self.critical)
    }
}

/// Division when the footprint area reaches `ratio` times its reference value (default 2).
///
/// ```
/// use celltissue::events::{AreaDoubling, CellView, DivisionRule};
/// let rule = AreaDoubling::default();
/// // the event function changes sign when A/A₀ crosses 2
/// assert!(rule.event(&CellView::growth_only(1.9, 0.0, f64::NAN)) < 0.0);
/// assert!(rule.event(&CellView::growth_only(2.1, 0.0, f64::NAN)) > 0.0);
/// assert!(AreaDoubling { ratio: 1.0 }.check().is_err()); // must be > 1
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AreaDoubling {
    /// Area ratio at division, > 1 (default 2).
    #[serde(default = "two")]
    pub ratio: f64,
}

fn two() -> f64 {
    2.0
}

impl Default for AreaDoubling {
    fn default() -> Self {
        Self { ratio: 2.0 }
    }
}

impl DivisionRule for AreaDoubling {
    fn event(&self, c: &CellView) -> f64 {
        c.area_ratio - self.ratio
    }
    fn name(&self) -> String {
        format!("area ratio {}", self.ratio)
    }
    fn check(&self) -> Result<(), ParamError> {
        match self.ratio > 1.0 && self.ratio.is_finite() {
            true => Ok(()),
            false => Err(ParamError::range("ratio", self.ratio, "finite and > 1")),
        }
    }
}

/// Division at a fixed age `period` after birth (cell-cycle clock; independent of growth).
///
/// Daughters still get half the parent's *grown* length `L₀g/2`, so a cell that divides
/// before `g = 2` produces daughters with a smaller reference length than its own.
///
/// ```
/// use celltissue::events::{AgeRule, CellView, DivisionRule};
/// let rule = AgeRule { period: 3.0 };
/// // the age decides, whatever the growth
/// assert!(rule.event(&CellView::growth_only(1.0, 3.5, f64::NAN)) > 0.0);
/// assert!(rule.event(&CellView::growth_only(5.0, 2.5, f64::NAN)) < 0.0);
/// assert_eq!(rule.name(), "age 3");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AgeRule {
    /// Cycle time `T > 0`.
    pub period: f64,
}

impl DivisionRule for AgeRule {
    fn event(&self, c: &CellView) -> f64 {
        c.age - self.period
    }
    fn name(&self) -> String {
        format!("age {}", self.period)
    }
    fn check(&self) -> Result<(), ParamError> {
        positive("period", self.period)
    }
}

/// Stochastic area threshold: cell `j` divides when `g g₂` reaches `θ_j`, with
/// `θ_j ~ Uniform[mean − spread, mean + spread]` drawn at its birth (initial cells at `t = 0`).
/// Requires `mean − spread > 1` so that a daughter (`g = 1`) never starts past its threshold.
///
/// ```
/// use celltissue::events::{DivisionRule, RandomThreshold, SplitMix64};
/// let rule = RandomThreshold { mean: 2.0, spread: 0.2, seed: 7 };
/// let mut rng = SplitMix64::new(rule.seed());
/// let draws: Vec<f64> = (0..1000).map(|_| rule.draw_threshold(&mut rng)).collect();
/// assert!(draws.iter().all(|&d| (1.8..=2.2).contains(&d)));
/// let mean = draws.iter().sum::<f64>() / 1000.0;
/// assert!((mean - 2.0).abs() < 0.01);
/// // the same seed draws the same thresholds
/// let mut again = SplitMix64::new(7);
/// assert_eq!(rule.draw_threshold(&mut again), draws[0]);
/// assert!(RandomThreshold { mean: 1.1, spread: 0.2, seed: 0 }.check().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomThreshold {
    /// Mean threshold (default 2).
    #[serde(default = "two")]
    pub mean: f64,
    /// Half-width of the uniform distribution (≥ 0).
    pub spread: f64,
    /// RNG seed.
    #[serde(default)]
    pub seed: u64,
}

impl DivisionRule for RandomThreshold {
    fn event(&self, c: &CellView) -> f64 {
        c.area_ratio - c.threshold
    }
    fn draw_threshold(&self, rng: &mut SplitMix64) -> f64 {
        self.mean + self.spread * (2.0 * rng.next_f64() - 1.0)
    }
    fn name(&self) -> String {
        format!(
            "random area U[{}, {}]",
            self.mean - self.spread,
            self.mean + self.spread
        )
    }
    fn check(&self) -> Result<(), ParamError> {
        if !(self.spread >= 0.0 && self.spread.is_finite()) {
            return Err(ParamError::range("spread", self.spread, "finite and >= 0"));
        }
        if !(self.mean - self.spread > 1.0 && self.mean.is_finite()) {
            return Err(ParamError::range(
                "mean",
                self.mean,
                "finite with mean - spread > 1",
            ));
        }
        Ok(())
    }
    fn seed(&self) -> u64 {
        self.seed
    }
}

/// The `division` table of a scenario: the rule by name with its parameters
/// (`{ rule = "area", ratio = 2 }`, `{ rule = "age", period = 2 }`,
/// `{ rule = "random_area", mean = 2, spread = 0.2, seed = 1 }`,
/// `{ rule = "surface_to_volume", critical = 3 }` or any rule registered with
/// [`super::rules::register`]), plus an optional cap `max_cells` (no division once `N` reaches
/// it). The rule is built, and its parameters checked, when the table is parsed.
///
/// ```
/// use celltissue::events::DivisionConfig;
/// let c: DivisionConfig = toml::from_str("rule = \"age\"\nperiod = 2.5").unwrap();
/// assert!(c.validate().is_ok());
/// assert_eq!(c.rule.name(), "age");
/// let e = toml::from_str::<DivisionConfig>("rule = \"area\"\nratio = 0.5").unwrap_err();
/// assert!(e.message().starts_with("`ratio` = 0.5: must be finite and > 1"), "{e}");
/// let e = toml::from_str::<DivisionConfig>("rule = \"size\"").unwrap_err();
/// assert!(e.message().starts_with("`rule` = \"size\": not a registered division rule (age, area,"));
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DivisionConfig {
    /// The rule.
    #[serde(flatten)]
    pub rule: RuleSpec,
    /// Stop dividing once the line has this many cells (default [`DEFAULT_MAX_CELLS`]; every
    /// run ends: a rule that fires too often, e.g. `period = 1e-300` or `ratio = 1.0001`, stops
    /// at the cap instead of dividing forever).
    #[serde(default = "default_max_cells")]
    pub max_cells: Option<usize>,
    /// Run the proliferating continuum (`models = ["continuum"]`) on the cell-number grid
    /// ([`crate::proliferation::CellGrid`]) instead of the density continuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cell_grid: Option<CellGridConfig>,
    /// Divisions due within this time after an event are brought forward to it (default 0:
    /// each at its own time; [`crate::events::Dividing::batch_within`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub batch_within: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The range of [`DivisionConfig::batch_within`] (and [`crate::events::Dividing::batch_within`]):
/// finite and ≥ 0.
pub(crate) fn check_batch_within(w: f64) -> Result<(), ParamError> {
    if w >= 0.0 && w.is_finite() {
        Ok(())
    } else {
        Err(ParamError::range("batch_within", w, "finite and >= 0"))
    }
}

/// The `division.cell_grid` table: the proliferating continuum on segments of `cells / nodes`
/// whole cells that split as cells do; with `merge_below`, segments growing at less than that
/// fraction of the unstressed rate merge in pairs, and with `merge_stress_within`, segments
/// whose stresses differ by at most that fraction of the growth law's stress scale, up to
/// `merge_max` cells, once `merge_batch` pairs qualify ([`crate::proliferation::Coarsening`]).
///
/// ```
/// use celltissue::events::DivisionConfig;
/// let v: toml::Value = toml::from_str("rule = \"area\"\ncell_grid = { merge_below = 1e-3 }")?;
/// let g = DivisionConfig::from_value(v)?.cell_grid.unwrap();
/// assert_eq!((g.merge_below, g.merge_max, g.merge_batch), (Some(1e-3), 64, 8));
/// let v: toml::Value = toml::from_str("rule = \"area\"\ncell_grid = { merge_max = 3 }")?;
/// assert_eq!(DivisionConfig::from_value(v).unwrap_err().key(), "cell_grid.merge_max");
/// // in-phase merging: neighbours within 1e-3 of the growth law's stress scale
/// let v: toml::Value =
///     toml::from_str("rule = \"area\"\ncell_grid = { merge_stress_within = 1e-3 }")?;
/// let g = DivisionConfig::from_value(v)?.cell_grid.unwrap();
/// assert_eq!(g.coarsening().unwrap().stress_within, Some(1e-3));
/// let v: toml::Value =
///     toml::from_str("rule = \"area\"\ncell_grid = { merge_stress_within = 2 }")?;
/// let e = DivisionConfig::from_value(v).unwrap_err();
/// assert_eq!(e.key(), "cell_grid.merge_stress_within");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CellGridConfig {
    /// Merge segments growing below this fraction of `G(0)` (none: not for slow growth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merge_below: Option<f64>,
    /// Merge neighbouring segments whose stresses differ by at most this fraction of the
    /// growth law's stress scale `G(0)/G′(0)` (none: never for that reason).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merge_stress_within: Option<f64>,
    /// Largest merged segment, in cells (a power of two, ≥ 2; default 64).
    pub merge_max: usize,
    /// Pairs that must qualify before they merge (≥ 1; default 8).
    pub merge_batch: usize,
}

impl Default for CellGridConfig {
    fn default() -> Self {
        Self {
            merge_below: None,
            merge_stress_within: None,
            merge_max: 64,
            merge_batch: 8,
        }
    }
}

impl CellGridConfig {
    /// Reads the `cell_grid` table, naming the innermost key on error.
    fn from_json(v: serde_json::Value) -> Result<Self, ParamError> {
        let serde_json::Value::Object(t) = v else {
            return Err(ParamError::new(
                "cell_grid",
                "must be a table such as { merge_below = 1e-3 }",
            ));
        };
        let mut cfg = Self::default();
        for (key, value) in t {
            let name = format!("cell_grid.{key}");
            match key.as_str() {
                "merge_below" | "merge_stress_within" => {
                    let x = value
                        .as_f64()
                        .ok_or_else(|| ParamError::range(&name, &value, "in (0, 1)"))?;
                    if key == "merge_below" {
                        cfg.merge_below = Some(x);
                    } else {
                        cfg.merge_stress_within = Some(x);
                    }
                }
                "merge_max" | "merge_batch" => {
                    let n = value
                        .as_u64()
                        .and_then(|n| usize::try_from(n).ok())
                        .ok_or_else(|| ParamError::range(&name, &value, "a positive integer"))?;
                    if key == "merge_max" {
                        cfg.merge_max = n;
                    } else {
                        cfg.merge_batch = n;
                    }
                }
                _ => {
                    return Err(ParamError::new(
                        &name,
                        "unknown key (cell_grid takes merge_below, merge_stress_within, merge_max, merge_batch)",
                    ))
                }
            }
        }
        cfg.check()?;
        Ok(cfg)
    }

    /// Checks the ranges (also for a table deserialized without [`DivisionConfig::from_value`]).
    fn check(&self) -> Result<(), ParamError> {
        if let Some(x) = self.merge_below.filter(|x| !(*x > 0.0 && *x < 1.0)) {
            return Err(ParamError::range("cell_grid.merge_below", x, "in (0, 1)"));
        }
        if let Some(x) = self.merge_stress_within.filter(|x| !(*x > 0.0 && *x < 1.0)) {
            return Err(ParamError::range(
                "cell_grid.merge_stress_within",
                x,
                "in (0, 1)",
            ));
        }
        let max = 1usize << 20;
        if !(self.merge_max >= 2 && self.merge_max <= max && self.merge_max.is_power_of_two()) {
            return Err(ParamError::range(
                "cell_grid.merge_max",
                self.merge_max,
                "a power of two from 2 to 2^20",
            ));
        }
        if !(1..=max).contains(&self.merge_batch) {
            return Err(ParamError::range(
                "cell_grid.merge_batch",
                self.merge_batch,
                "an integer from 1 to 2^20",
            ));
        }
        Ok(())
    }

    /// The merging rule, if any.
    ///
    /// ```
    /// use celltissue::events::CellGridConfig;
    /// assert!(CellGridConfig::default().coarsening().is_none());
    /// let c = CellGridConfig { merge_below: Some(1e-3), ..Default::default() };
    /// assert_eq!(c.coarsening().unwrap().max_cells, 64);
    /// ```
    pub fn coarsening(&self) -> Option<crate::proliferation::Coarsening> {
        (self.merge_below.is_some() || self.merge_stress_within.is_some()).then(|| {
            crate::proliferation::Coarsening {
                growth_below: self.merge_below.unwrap_or(0.0),
                stress_within: self.merge_stress_within,
                max_cells: self.merge_max,
                batch: self.merge_batch,
            }
        })
    }
}

/// Default cap on the number of cells of a dividing line: 10 000 (Fig 3.3 reaches 971 at
/// t = 18). Raise it with `division.max_cells` (up to the 10⁸-cell size limit).
pub const DEFAULT_MAX_CELLS: usize = 10_000;

fn default_max_cells() -> Option<usize> {
    Some(DEFAULT_MAX_CELLS)
}

impl Default for DivisionConfig {
    fn default() -> Self {
        Self {
            rule: RuleSpec::build("area", &Params::new())
                .expect("the built-in area rule builds from its defaults"),
            max_cells: default_max_cells(),
            cell_grid: None,
            batch_within: 0.0,
        }
    }
}

/// A division setting out of range: the key inside `division` and what is wrong.
///
/// ```
/// use celltissue::events::DivisionConfig;
/// let v: toml::Value = toml::from_str("rule = \"age\"\nperiod = -1.0").unwrap();
/// let e = DivisionConfig::from_value(v).unwrap_err();
/// assert_eq!(e.key(), "period");
/// assert!(e.to_string().starts_with("invalid `division.period`"), "{e}");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct DivisionError(pub ParamError);

impl std::fmt::Display for DivisionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0.key.as_str() {
            "" => write!(f, "invalid `division`{}", self.0.detail()),
            key => write!(f, "invalid `division.{key}`{}", self.0.detail()),
        }
    }
}

impl DivisionError {
    /// The key inside the `division` table (`ratio`, `period`, `max_cells`, …).
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// let v: toml::Value = toml::from_str("rule = \"area\"\nmax_cells = 0").unwrap();
    /// assert_eq!(DivisionConfig::from_value(v).unwrap_err().key(), "max_cells");
    /// let v: toml::Value = toml::from_str("max_cells = 10").unwrap(); // no rule named
    /// assert_eq!(DivisionConfig::from_value(v).unwrap_err().key(), "rule");
    /// ```
    pub fn key(&self) -> &str {
        &self.0.key
    }
}

impl DivisionConfig {
    /// Reads a scenario's `division` table with a typed error naming the key inside it (the
    /// rule's name or parameter, or `max_cells`) — the same result as deserializing.
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// let v: toml::Value = toml::from_str("rule = \"area\"\nratio = 0.5").unwrap();
    /// let e = DivisionConfig::from_value(v).unwrap_err();
    /// assert_eq!(e.key(), "ratio");
    /// let v: toml::Value = toml::from_str("max_cells = -3").unwrap();
    /// assert_eq!(DivisionConfig::from_value(v).unwrap_err().key(), "max_cells");
    /// ```
    pub fn from_value(v: toml::Value) -> Result<Self, DivisionError> {
        let mut table = match serde_json::to_value(&v) {
            Ok(serde_json::Value::Object(t)) => t,
            _ => {
                return Err(DivisionError(ParamError::new(
                    "",
                    format!("{v} must be a table such as {{ rule = \"area\", ratio = 2 }}"),
                )))
            }
        };
        let max_cells = match table.remove("max_cells") {
            None => default_max_cells(),
            Some(m) => Some(
                m.as_u64()
                    .and_then(|m| usize::try_from(m).ok())
                    .ok_or_else(|| {
                        DivisionError(ParamError::range("max_cells", &m, "an integer >= 1"))
                    })?,
            ),
        };
        let cell_grid = table
            .remove("cell_grid")
            .map(CellGridConfig::from_json)
            .transpose()
            .map_err(DivisionError)?;
        let batch_within = match table.remove("batch_within") {
            None => 0.0,
            Some(v) => v.as_f64().ok_or_else(|| {
                DivisionError(ParamError::range("batch_within", &v, "a number >= 0"))
            })?,
        };
        let rule = RuleSpec::from_table(table).map_err(DivisionError)?;
        let cfg = Self {
            rule,
            max_cells,
            cell_grid,
            batch_within,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks what parsing does not: `max_cells ≥ 1`, `batch_within ≥ 0` and the `cell_grid`
    /// ranges (the rule's parameters are checked when it is built).
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// let cfg = DivisionConfig { max_cells: Some(0), ..Default::default() };
    /// assert_eq!(cfg.validate().unwrap_err().key(), "max_cells");
    /// let cfg = DivisionConfig { batch_within: -1e-3, ..Default::default() };
    /// assert_eq!(cfg.validate().unwrap_err().key(), "batch_within");
    /// assert!(DivisionConfig::default().validate().is_ok());
    /// ```
    pub fn validate(&self) -> Result<(), DivisionError> {
        if let Some(g) = &self.cell_grid {
            g.check().map_err(DivisionError)?;
        }
        check_batch_within(self.batch_within).map_err(DivisionError)?;
        match self.max_cells {
            Some(0) => Err(DivisionError(ParamError::range("max_cells", 0, ">= 1"))),
            _ => Ok(()),
        }
    }

    /// The rule object.
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// let rule = DivisionConfig::default().build();
    /// assert_eq!(rule.name(), "area ratio 2"); // cells divide when their area has doubled
    /// ```
    pub fn build(&self) -> Box<dyn DivisionRule> {
        Box::new(self.rule.law().clone())
    }

    /// RNG seed of the rule (0 if it draws nothing).
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// let v: toml::Value = toml::from_str("rule = \"random_area\"\nspread = 0.2\nseed = 9").unwrap();
    /// assert_eq!(DivisionConfig::from_value(v).unwrap().seed(), 9);
    /// assert_eq!(DivisionConfig::default().seed(), 0); // the area rule draws nothing
    /// ```
    pub fn seed(&self) -> u64 {
        self.rule.law().seed()
    }

    /// The division area ratio when the rule is the area rule (the only rule the density
    /// continuum supports), `None` otherwise.
    ///
    /// ```
    /// use celltissue::events::DivisionConfig;
    /// assert_eq!(DivisionConfig::default().area_ratio(), Some(2.0));
    /// let age: toml::Value = toml::from_str("rule = \"age\"\nperiod = 1.0").unwrap();
    /// assert_eq!(DivisionConfig::from_value(age).unwrap().area_ratio(), None);
    /// ```
    pub fn area_ratio(&self) -> Option<f64> {
        match self.rule.name() {
            "area" => self.rule.params().get("ratio").and_then(|v| v.as_f64()),
            _ => None,
        }
    }
}

/// SplitMix64: a tiny, fast, seedable generator (Steele, Lea & Flood 2014), enough for
/// per-cell thresholds; the sequence is fixed for a seed on every platform.
///
/// ```
/// use celltissue::events::SplitMix64;
/// let mut a = SplitMix64::new(7);
/// let mut b = SplitMix64::new(7);
/// assert_eq!(a.next_u64(), b.next_u64());
/// let u = a.next_f64();
/// assert!((0.0..1.0).contains(&u));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator from a seed.
    ///
    /// ```
    /// use celltissue::events::SplitMix64;
    /// assert_ne!(SplitMix64::new(1).next_u64(), SplitMix64::new(2).next_u64());
    /// ```
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }
    /// Next 64 random bits.
    ///
    /// ```
    /// use celltissue::events::SplitMix64;
    /// let mut g = SplitMix64::new(0);
    /// let (a, b) = (g.next_u64(), g.next_u64());
    /// assert_ne!(a, b);
    /// ```
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)` (53 random bits).
    ///
    /// ```
    /// use celltissue::events::SplitMix64;
    /// let mut g = SplitMix64::new(42);
    /// let mean = (0..10_000).map(|_| g.next_f64()).sum::<f64>() / 1e4;
    /// assert!((mean - 0.5).abs() < 0.01);
    /// ```
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_cross_zero_upwards_at_division() {
        let c = CellView::growth_only;
        assert!(AreaDoubling::default().event(&c(1.99, 0.0, 0.0)) < 0.0);
        assert!(AreaDoubling::default().event(&c(2.01, 0.0, 0.0)) > 0.0);
        let age = AgeRule { period: 3.0 };
        assert!(age.event(&c(5.0, 2.9, 0.0)) < 0.0 && age.event(&c(1.0, 3.1, 0.0)) > 0.0);
        let r = RandomThreshold {
            mean: 2.0,
            spread: 0.25,
            seed: 3,
        };
        let mut rng = SplitMix64::new(3);
        let th: Vec<f64> = (0..1000).map(|_| r.draw_threshold(&mut rng)).collect();
        assert!(th.iter().all(|t| (1.75..=2.25).contains(t)));
        let mean = th.iter().sum::<f64>() / 1000.0;
        assert!((mean - 2.0).abs() < 0.02, "mean threshold {mean}");
        assert_eq!(r.event(&c(2.0, 0.0, 1.9)), 2.0 - 1.9);
    }

    #[test]
    fn config_parses_and_validates() {
        let c: DivisionConfig = toml::from_str("rule = \"area\"").unwrap();
        assert_eq!((c.rule.name(), c.area_ratio()), ("area", Some(2.0)));
        assert_eq!(c, DivisionConfig::default());
        let c: DivisionConfig =
            toml::from_str("rule = \"random_area\"\nspread = 0.5\nseed = 9\nmax_cells = 50")
                .unwrap();
        assert!(c.validate().is_ok());
        assert_eq!((c.seed(), c.max_cells, c.area_ratio()), (9, Some(50), None));
        let e = toml::from_str::<DivisionConfig>("rule = \"random_area\"\nspread = 1.5");
        assert!(e.unwrap_err().message().starts_with("`mean` = 2: must be"));
        assert!(toml::from_str::<DivisionConfig>("rule = \"size\"").is_err());
        let e = toml::from_str::<DivisionConfig>("max_cells = 0\nrule = \"age\"\nperiod = 1");
        let e = e.unwrap().validate().unwrap_err();
        assert_eq!(
            (e.key(), e.to_string().as_str()),
            (
                "max_cells",
                "invalid `division.max_cells` = 0: must be >= 1"
            )
        );
    }

    #[test]
    fn the_echo_holds_every_parameter_once_and_parses_back() {
        let c: DivisionConfig = toml::from_str("rule = \"random_area\"\nspread = 0.25").unwrap();
        let echo = toml::to_string(&c).unwrap();
        for key in [
            "rule = \"random_area\"",
            "mean = 2.0",
            "spread = 0.25",
            "seed = 0",
        ] {
            assert_eq!(echo.matches(key).count(), 1, "{key} in {echo}");
        }
        assert_eq!(toml::from_str::<DivisionConfig>(&echo).unwrap(), c);
    }
}
