//! Serde configurations of the Chapter 4 runs, with range-checked validation whose errors name
//! the key and its valid range. Defaults are docs/model.md's (§0.3, §5.6): `N = M = 10`,
//! `γ₀ = β₀ = 1`, `K_th = 1` (boundary-form `K = ½`), `m = 0`, `k₁ = 0.1`, exponential ramp,
//! free top; shear `F_A = 1`.
//!
//! Each config carries a `law` ([`AnyEnergy`], default neo-Hookean `μ = 1`); the run functions
//! take the law as a separate generic argument so that any [`crate::StrainEnergy`] (also
//! user-written ones) can be used: pass `&cfg.law` for the configured one.
//!
//! ```
//! use celltissue::sheet::SheetConfig;
//! let cfg: SheetConfig = toml::from_str("cells_x = 20\ntop = \"periodic\"").unwrap();
//! assert_eq!(cfg.drag(), 0.5);
//! assert!(cfg.validate().is_ok());
//! assert!(toml::from_str::<SheetConfig>("cellz = 3").is_err());
//! ```

use super::ramp::Ramp;
use super::shear::ShearParams;
use super::uniaxial::{SheetGrowth, SheetParams};
use crate::cell::growth_laws::GrowthSpec;
use crate::cell::{Field, ViscosityModel};
use crate::energy::{AnyEnergy, NeoHookean};
use crate::substrate::FreeEndDrag;
use serde::{Deserialize, Serialize};

/// The side `y = w₀` of the sheet.
///
/// ```
/// use celltissue::sheet::{SheetConfig, TopBoundary};
/// let cfg: SheetConfig = toml::from_str("top = \"periodic\"")?;
/// assert_eq!(cfg.top, TopBoundary::Periodic);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TopBoundary {
    /// Zero traction, `K κ ẏ_b(j,M) = −H L σ₂₂` ((4.34)–(4.37)).
    #[default]
    Free,
    /// Periodic in y, `y_b(j,M) = y_b(j,0) + w₀` ((4.38)).
    Periodic,
}

/// The side `x = l` of the sheet.
///
/// ```
/// use celltissue::sheet::{RightEdge, SheetConfig};
/// let cfg: SheetConfig = toml::from_str("right = \"free\"\ngrowth = { law = \"tanh\" }")?;
/// assert_eq!(cfg.right, RightEdge::Free);
/// assert!(cfg.validate().is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RightEdge {
    /// `x_b(N, k) = l(t)`, the ramp of `k1` and `ramp` (the thesis's Chapter 4).
    #[default]
    Prescribed,
    /// Zero traction, `K κ ẋ_b(N,k) = −H W σ₁₁` (a growing sheet; `k1` and `ramp` unused).
    Free,
}

/// The in-plane directions in which a growing sheet's cells grow.
///
/// ```
/// use celltissue::sheet::GrowthDirections;
/// assert!(GrowthDirections::Both.grows(0) && GrowthDirections::Both.grows(1));
/// assert!(GrowthDirections::X.grows(0) && !GrowthDirections::X.grows(1));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GrowthDirections {
    /// `ġ₁ = G(σ₁₁)` and `ġ₂ = G(σ₂₂)`.
    #[default]
    Both,
    /// Along x only (`g₂ = 1`): with a periodic side the rows are lines of cells.
    X,
    /// Along y only (`g₁ = 1`).
    Y,
}

impl GrowthDirections {
    /// Whether direction `i` (0 = x, 1 = y) grows.
    ///
    /// ```
    /// use celltissue::sheet::GrowthDirections;
    /// assert!(GrowthDirections::X.grows(0) && !GrowthDirections::X.grows(1));
    /// assert!(GrowthDirections::Both.grows(1));
    /// ```
    pub fn grows(self, i: usize) -> bool {
        matches!(
            (self, i),
            (GrowthDirections::Both, _) | (GrowthDirections::X, 0) | (GrowthDirections::Y, 1)
        )
    }
}

/// Which form of the shear column to integrate.
///
/// ```
/// use celltissue::sheet::{ShearConfig, ShearForm};
/// let cfg: ShearConfig = toml::from_str("form = \"cell_centre\"")?; // the thesis's form
/// assert_eq!(cfg.form, ShearForm::CellCentre);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShearForm {
    /// Canonical edge form (docs/model.md §4.4).
    #[default]
    Edge,
    /// The thesis's cell-centre form (4.85)–(4.98), discrete only (docs/model.md §4.5).
    CellCentre,
}

/// A configuration value outside its valid range.
///
/// ```
/// use celltissue::sheet::SheetConfig;
/// let e = SheetConfig { k1: 1.5, ..Default::default() }.validate().unwrap_err();
/// assert_eq!((e.key.as_str(), e.value.as_str()), ("k1", "1.5"));
/// assert_eq!(e.to_string(), "k1 = 1.5: must be in (-1, 1)");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {expected}")]
pub struct ConfigError {
    /// The offending key.
    pub key: String,
    /// Its value, as text.
    pub value: String,
    /// The valid range or rule.
    pub expected: String,
}

fn need(ok: bool, key: &str, value: impl ToString, expected: &str) -> Result<(), ConfigError> {
    if ok {
        Ok(())
    } else {
        Err(ConfigError {
            key: key.into(),
            value: value.to_string(),
            expected: expected.into(),
        })
    }
}

fn pos(key: &str, v: f64) -> Result<(), ConfigError> {
    need(
        v > 0.0 && v.is_finite(),
        key,
        v,
        "must be positive and finite",
    )
}

fn drag_from(k_th: Option<f64>, drag: Option<f64>) -> f64 {
    match (drag, k_th) {
        (Some(k), _) => k,
        (None, Some(kt)) => 0.5 * kt,
        (None, None) => 0.5,
    }
}

fn check_drag(k_th: Option<f64>, drag: Option<f64>, allow_zero: bool) -> Result<(), ConfigError> {
    need(
        !(k_th.is_some() && drag.is_some()),
        "drag",
        drag.unwrap_or_default(),
        "give either k_th (thesis Ch. 4 drag) or drag (boundary form K = k_th/2), not both",
    )?;
    for (key, v) in [("k_th", k_th), ("drag", drag)] {
        if let Some(v) = v {
            if allow_zero {
                need(v >= 0.0 && v.is_finite(), key, v, "must be >= 0 and finite")?;
            } else {
                pos(key, v)?;
            }
        }
    }
    Ok(())
}

/// Configuration of a uniaxial sheet run (docs/model.md §4.1–4.3).
///
/// ```
/// use celltissue::sheet::SheetConfig;
/// let cfg: SheetConfig = toml::from_str("cells_x = 20\ncells_y = 5\ndrag = 0.1")?;
/// assert_eq!((cfg.cells_x, cfg.drag()), (20, 0.1));
/// assert!(cfg.validate().is_ok());
/// assert!(SheetConfig { cells_y: 0, ..cfg }.validate().is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SheetConfig {
    /// Cells in x, `N >= 1` (default 10).
    pub cells_x: usize,
    /// Rows of cells, `M >= 1` (default 10).
    pub cells_y: usize,
    /// Planar aspect ratio `γ₀ > 0` (default 1).
    pub gamma0: f64,
    /// Height aspect ratio `β₀ > 0` (default 1).
    pub beta0: f64,
    /// Thesis Chapter 4 drag `K_th >= 0` (default 1); the boundary form uses `K = K_th/2`.
    pub k_th: Option<f64>,
    /// Boundary-form drag `K >= 0` directly (exclusive with `k_th`).
    pub drag: Option<f64>,
    /// Drag–area exponent `m >= 0` in `κ = (λ₁λ₂)^m` (thesis: 0 or 1).
    pub drag_exponent: f64,
    /// Fractional shortening `k₁ ∈ (−1, 1)` (default 0.1).
    pub k1: f64,
    /// Ramp of `l(t)` (default exponential, `t_ramp = 1`).
    pub ramp: Ramp,
    /// `"free"` (default) or `"periodic"` side.
    pub top: TopBoundary,
    /// Strain energy, e.g. `law = { law = "mooney_rivlin", c1 = 0.3, c2 = 0.2 }` (default
    /// neo-Hookean `μ = 1`).
    pub law: AnyEnergy,
    /// Viscosity `{ model = "kelvin_voigt", eta }`, `{ model = "maxwell", mu_m, eta_m }` or
    /// `{ model = "standard_linear_solid", mu_m, eta_m }` (absent: elastic cells, as in the
    /// thesis; docs/viscoelasticity.md).
    pub viscosity: Option<ViscosityModel>,
    /// External pressure `p_e(X)` on the cells' upper faces (any finite number or field of `X`,
    /// constant along `Y`; docs/external_pressure.md).
    pub external_pressure: Field,
    /// `"prescribed"` (default: the ramp) or `"free"` side `x = l`.
    pub right: RightEdge,
    /// Growth law `{ law = "tanh", sigma0, gm }` of each cell's in-plane reference lengths
    /// (absent = no growth; docs/sheet_growth.md).
    pub growth: Option<GrowthSpec>,
    /// Which in-plane directions grow: `"both"` (default), `"x"` or `"y"`.
    pub growth_directions: GrowthDirections,
    /// A continuum grid's drag on its free edges: `"segment"` (default) or `"cells"`
    /// ([`FreeEndDrag`]; read only with a free top or a free side).
    pub free_end_drag: FreeEndDrag,
}

fn default_law() -> AnyEnergy {
    AnyEnergy::NeoHookean(NeoHookean::new(1.0).expect("valid modulus"))
}

impl Default for SheetConfig {
    fn default() -> Self {
        Self {
            cells_x: 10,
            cells_y: 10,
            gamma0: 1.0,
            beta0: 1.0,
            k_th: None,
            drag: None,
            drag_exponent: 0.0,
            k1: 0.1,
            ramp: Ramp::default(),
            top: TopBoundary::Free,
            law: default_law(),
            viscosity: None,
            external_pressure: Field::Constant(0.0),
            right: RightEdge::Prescribed,
            growth: None,
            growth_directions: GrowthDirections::Both,
            free_end_drag: FreeEndDrag::Segment,
        }
    }
}

impl SheetConfig {
    /// Boundary-form drag `K` (`k_th/2`, or `drag`, default ½).
    ///
    /// ```
    /// use celltissue::sheet::SheetConfig;
    /// let thesis: SheetConfig = toml::from_str("k_th = 1.0")?;
    /// assert_eq!(thesis.drag(), 0.5); // the boundary form K = K_th/2
    /// assert_eq!(SheetConfig::default().drag(), 0.5);
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn drag(&self) -> f64 {
        drag_from(self.k_th, self.drag)
    }

    /// Checks every key; the error names the key and its valid range.
    ///
    /// ```
    /// use celltissue::sheet::SheetConfig;
    /// let cfg: SheetConfig = toml::from_str("k1 = 1.5")?;
    /// assert_eq!(cfg.validate().unwrap_err().key, "k1");
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn validate(&self) -> Result<(), ConfigError> {
        need(self.cells_x >= 1, "cells_x", self.cells_x, "must be >= 1")?;
        need(self.cells_y >= 1, "cells_y", self.cells_y, "must be >= 1")?;
        pos("gamma0", self.gamma0)?;
        pos("beta0", self.beta0)?;
        check_drag(self.k_th, self.drag, true)?;
        need(
            self.drag_exponent >= 0.0 && self.drag_exponent.is_finite(),
            "drag_exponent",
            self.drag_exponent,
            "must be >= 0 and finite (thesis: 0 or 1)",
        )?;
        need(
            self.k1 > -1.0 && self.k1 < 1.0,
            "k1",
            self.k1,
            "must be in (-1, 1)",
        )?;
        pos("ramp.t_ramp", self.ramp.t_ramp())?;
        need(
            !(self.top == TopBoundary::Periodic && self.drag() == 0.0),
            "k_th",
            self.drag() * 2.0,
            "must be > 0 with a periodic side (rigid y-translation is a null mode)",
        )?;
        self.validate_viscosity_and_pressure()
    }

    /// Checks `viscosity` and `external_pressure` (finite at every cell centre of the discrete
    /// sheet).
    fn validate_viscosity_and_pressure(&self) -> Result<(), ConfigError> {
        if let Some(v) = &self.viscosity {
            v.branch().map_err(|e| ConfigError {
                key: format!("viscosity.{}", e.key),
                value: e.value.to_string(),
                expected: format!("must be {}", e.range),
            })?;
        }
        need(
            self.growth.is_some() || self.growth_directions == GrowthDirections::Both,
            "growth_directions",
            format!("{:?}", self.growth_directions).to_lowercase(),
            "needs growth (add growth = { law = \"tanh\", sigma0 = 0.1 })",
        )?;
        need(
            self.free_end_drag == FreeEndDrag::Segment
                || self.top == TopBoundary::Free
                || self.right == RightEdge::Free,
            "free_end_drag",
            "\"cells\"",
            "is read only on a free edge (a free top or a free side), and this sheet has a periodic side and a prescribed one: leave it out",
        )?;
        need(
            self.growth.is_some() || self.right == RightEdge::Prescribed,
            "right",
            "\"free\"",
            "without growth nothing drives a free sheet; add growth = { law = \"tanh\" } or use \"prescribed\"",
        )?;
        let centres: Vec<f64> = (0..self.cells_x).map(|j| j as f64 + 0.5).collect();
        let p_ext = self.external_pressure.sample(&centres, self.cells_x as f64);
        if let Some(bad) = p_ext.iter().find(|v| !v.is_finite()) {
            return Err(ConfigError {
                key: "external_pressure".into(),
                value: bad.to_string(),
                expected: "must be finite at every cell".into(),
            });
        }
        Ok(())
    }

    /// The model parameters.
    ///
    /// ```
    /// use celltissue::sheet::SheetConfig;
    /// let cfg: SheetConfig = toml::from_str("cells_x = 4\nviscosity = { model = \"kelvin_voigt\", eta = 0.3 }")?;
    /// let p = cfg.params();
    /// assert_eq!((p.cells_x, p.eta, p.branch), (4, 0.3, None));
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn params(&self) -> SheetParams {
        SheetParams {
            cells_x: self.cells_x,
            cells_y: self.cells_y,
            gamma0: self.gamma0,
            beta0: self.beta0,
            drag: self.drag(),
            drag_exponent: self.drag_exponent,
            k1: self.k1,
            ramp: self.ramp,
            top: self.top,
            branch: self.viscosity.and_then(|v| v.branch().ok().flatten()),
            eta: match self.viscosity {
                Some(ViscosityModel::KelvinVoigt { eta }) => eta,
                _ => 0.0,
            },
            external_pressure: self.external_pressure.clone(),
            right: self.right,
            growth: self.growth.as_ref().map(|g| SheetGrowth {
                law: g.law().clone(),
                directions: self.growth_directions,
            }),
            free_end_drag: self.free_end_drag,
        }
    }
}

/// Configuration of a shear-column run (docs/model.md §4.4–4.6).
///
/// ```
/// use celltissue::sheet::ShearConfig;
/// let cfg: ShearConfig = toml::from_str("cells = 20\nforce = 0.5")?;
/// assert!(cfg.validate().is_ok());
/// assert!(toml::from_str::<ShearConfig>("cels = 20").is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShearConfig {
    /// Number of cells `M >= 1` (default 10).
    pub cells: usize,
    /// Planar aspect ratio `γ₀ > 0` (default 1).
    pub gamma0: f64,
    /// Height aspect ratio `β₀ > 0` (default 1).
    pub beta0: f64,
    /// Thesis drag `K_th > 0` (default 1); edge form `K = K_th/2`.
    pub k_th: Option<f64>,
    /// Edge-form drag `K > 0` directly (exclusive with `k_th`).
    pub drag: Option<f64>,
    /// Applied shear force `F_A` (default 1).
    pub force: f64,
    /// `"edge"` (default, canonical) or `"cell_centre"` (thesis form, discrete only).
    pub form: ShearForm,
    /// Strain energy (default neo-Hookean `μ = 1`).
    pub law: AnyEnergy,
    /// Viscosity `{ model = "kelvin_voigt", eta }` (absent: elastic cells, as in the thesis;
    /// docs/viscoelasticity.md). Maxwell branches are not modelled on the column.
    pub viscosity: Option<ViscosityModel>,
}

impl Default for ShearConfig {
    fn default() -> Self {
        Self {
            cells: 10,
            gamma0: 1.0,
            beta0: 1.0,
            k_th: None,
            drag: None,
            force: 1.0,
            form: ShearForm::Edge,
            law: default_law(),
            viscosity: None,
        }
    }
}

impl ShearConfig {
    /// Edge-form drag `K`.
    ///
    /// ```
    /// use celltissue::sheet::ShearConfig;
    /// let cfg: ShearConfig = toml::from_str("drag = 0.2")?;
    /// assert_eq!(cfg.drag(), 0.2);
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn drag(&self) -> f64 {
        drag_from(self.k_th, self.drag)
    }

    /// Checks every key; the error names the key and its valid range.
    ///
    /// ```
    /// use celltissue::sheet::ShearConfig;
    /// let cfg: ShearConfig = toml::from_str("cells = 0")?;
    /// assert_eq!(cfg.validate().unwrap_err().key, "cells");
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn validate(&self) -> Result<(), ConfigError> {
        need(self.cells >= 1, "cells", self.cells, "must be >= 1")?;
        pos("gamma0", self.gamma0)?;
        pos("beta0", self.beta0)?;
        check_drag(self.k_th, self.drag, false)?;
        need(
            crate::StrainEnergy::shear_is_exact(&self.law),
            "law",
            format!("{{ law = \"{}\", … }}", self.law.name()),
            crate::sheet::shear::LAW_WITHOUT_SHEAR,
        )?;
        need(
            self.force.is_finite(),
            "force",
            self.force,
            "must be finite",
        )?;
        match self.viscosity {
            None => Ok(()),
            Some(ViscosityModel::KelvinVoigt { eta }) => need(
                eta >= 0.0 && eta.is_finite(),
                "viscosity.eta",
                eta,
                "must be finite and >= 0",
            ),
            Some(v @ (ViscosityModel::Maxwell { .. } | ViscosityModel::StandardLinearSolid { .. })) => {
                Err(ConfigError {
                    key: "viscosity.model".into(),
                    value: match v {
                        ViscosityModel::Maxwell { .. } => "\"maxwell\"".into(),
                        _ => "\"standard_linear_solid\"".into(),
                    },
                    expected: "must be \"kelvin_voigt\" (the shear column has no Maxwell or standard-linear-solid cells)".into(),
                })
            }
        }
    }

    /// The model parameters.
    ///
    /// ```
    /// use celltissue::sheet::ShearConfig;
    /// let cfg: ShearConfig = toml::from_str("cells = 5\nforce = 0.5\nk_th = 1.0")?;
    /// let p = cfg.params();
    /// assert_eq!((p.cells, p.force, p.drag, p.eta), (5, 0.5, 0.5, 0.0));
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn params(&self) -> ShearParams {
        ShearParams {
            cells: self.cells,
            gamma0: self.gamma0,
            beta0: self.beta0,
            drag: self.drag(),
            force: self.force,
            eta: match self.viscosity {
                Some(ViscosityModel::KelvinVoigt { eta }) => eta,
                _ => 0.0,
            },
        }
    }
}
