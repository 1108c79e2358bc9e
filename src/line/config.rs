//! [`LineConfig`]: the line section of a scenario file (serde, unknown keys rejected), with the
//! thesis defaults of docs/model.md §0.3, [`LineConfig::validate`] (errors name the key and its valid
//! range), and the translation into the builders' [`LineParams`].
//!
//! ```
//! use celltissue::line::LineConfig;
//! let cfg: LineConfig = toml::from_str(r#"
//!     cells = 100
//!     K = 0.01
//!     mu = { type = "gaussian", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }
//! "#).unwrap();
//! assert!(cfg.validate().is_ok());
//! let bad: LineConfig = toml::from_str("k1 = 1.5").unwrap();
//! assert!(bad.validate().unwrap_err().to_string().contains("k1"));
//! assert!(toml::from_str::<LineConfig>("kay = 1").is_err());
//! ```

use super::build::LineParams;
use super::LineError;
use crate::boundary::{Ramp, RampKind, RightEnd};
use crate::cell::{Active, Field, Sampling, ViscosityModel};
use crate::energy::{AnyEnergy, NeoHookean};
use crate::substrate::{DragForm, FreeEndDrag, WidthRule};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The right-end condition named in a scenario.
///
/// ```
/// use celltissue::line::config::RightEndKind;
/// use celltissue::line::LineConfig;
/// let cfg: LineConfig = toml::from_str("cells = 12\nright_end = \"periodic\"\nK = 1")?;
/// assert_eq!(cfg.right_end, RightEndKind::Periodic); // a ring of 12 cells
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RightEndKind {
    /// `x_N = l(t)` by the ramp.
    #[default]
    Prescribed,
    /// Free end with applied force `force`.
    Free,
    /// Ring.
    Periodic,
}

/// The continuum discretisation.
///
/// ```
/// use celltissue::line::config::ContinuumScheme;
/// use celltissue::line::LineConfig;
/// let cfg: LineConfig = toml::from_str("continuum_scheme = \"thesis\"")?;
/// assert_eq!(cfg.continuum_scheme, ContinuumScheme::Thesis);
/// assert_eq!(LineConfig::default().continuum_scheme, ContinuumScheme::Conservative);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContinuumScheme {
    /// Conservative scheme, `n` segments (docs/model.md §3.3a; recommended).
    #[default]
    Conservative,
    /// The thesis's finite-difference scheme, `n` nodes (§3.3b; reproduction mode, no growth,
    /// prescribed end).
    Thesis,
}

/// The growth law by name (`growth = { law = "tanh", sigma0 = 0.1 }`; absent = no growth).
pub type GrowthConfig = crate::cell::GrowthSpec;

/// The line of cells as configured in a scenario. Every key has the thesis default.
///
/// ```
/// use celltissue::line::LineConfig;
/// let cfg: LineConfig = toml::from_str("cells = 50\nK = 0.1\nright_end = \"free\"\ngrowth = { sigma0 = 0.1 }")?;
/// assert!(cfg.validate().is_ok());
/// assert_eq!(cfg.n_cells(), 50);
/// let bad: LineConfig = toml::from_str("cells = 50\nK = -1")?;
/// assert!(bad.validate().unwrap_err().to_string().contains("K"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LineConfig {
    /// Number of cells `N` (≥ 1).
    pub cells: usize,
    /// Reference length of every cell (> 0).
    pub cell_length: f64,
    /// Optional per-cell reference lengths (overrides `cells` and `cell_length`).
    pub ref_lengths: Option<Vec<f64>>,
    /// Fractional shortening `k₁` of the prescribed end (< 1).
    pub k1: f64,
    /// Ramp time (> 0).
    pub t_ramp: f64,
    /// Ramp shape: `"exponential"` (2.80) or `"polynomial"` (2.81).
    pub ramp: RampKind,
    /// Substrate drag per boundary `K(X)` (≥ 0).
    #[serde(rename = "K")]
    pub k: Field,
    /// Drag–area exponent `m` (any real).
    pub m: f64,
    /// Viscosity `η(X)` (≥ 0, including the factor 2).
    pub eta: Field,
    /// Shear-modulus scale `μ(X)` (> 0) multiplying the law's energy.
    pub mu: Field,
    /// Where fields are sampled: `"centres"` (default) or `"integer_points"`.
    pub sampling: Sampling,
    /// Aspect ratio `γ₀` (> 0).
    pub gamma0: f64,
    /// Lateral growth stretch `g₂` (> 0).
    pub g2: f64,
    /// `"boundary"` (B, canonical) or `"centre"` (C, thesis code).
    pub drag_form: DragForm,
    /// A continuum grid's free-end drag: `"segment"` (default) or `"cells"` ([`FreeEndDrag`];
    /// read only with a free right end and the boundary drag form).
    pub free_end_drag: FreeEndDrag,
    /// Shared width: `"mean"` or `"min"`.
    pub width: WidthRule,
    /// `"prescribed"`, `"free"` or `"periodic"`.
    pub right_end: RightEndKind,
    /// Constant applied force on a free right end.
    pub force: f64,
    /// Pin `x₀ = 0` on a ring (required when `K = 0`).
    pub gauge: bool,
    /// Active stress `{ beta, omega }` (absent = none; thesis: `beta = -1`, `omega = 1/l₀`).
    pub active: Option<Active>,
    /// Active amplitude field `A(X)` (used with `active`).
    pub active_amplitude: Field,
    /// Growth law `{ law = "tanh", sigma0, gm }` (`law` defaults to `tanh`; any name in
    /// [`crate::cell::growth_laws`]; absent = no growth).
    pub growth: Option<GrowthConfig>,
    /// The strain energy, e.g. `law = { law = "neo_hookean", mu = 1 }` (any [`AnyEnergy`];
    /// scaled per cell by `mu`).
    pub law: AnyEnergy,
    /// Continuum discretisation used when the continuum model is run.
    pub continuum_scheme: ContinuumScheme,
    /// Viscosity model `{ model = "kelvin_voigt", eta }`, `{ model = "maxwell", mu_m, eta_m }`
    /// or `{ model = "standard_linear_solid", mu_m, eta_m }` (absent: Kelvin–Voigt with `eta`).
    pub viscosity: Option<ViscosityModel>,
    /// External pressure `p_e(X)` on the cells' lateral faces (any finite number or field;
    /// docs/model.md §8.2).
    pub external_pressure: Field,
}

impl Default for LineConfig {
    fn default() -> Self {
        Self {
            cells: 100,
            cell_length: 1.0,
            ref_lengths: None,
            k1: 0.1,
            t_ramp: 1.0,
            ramp: RampKind::Exponential,
            k: Field::Constant(1.0),
            m: 0.0,
            eta: Field::Constant(0.0),
            mu: Field::Constant(1.0),
            sampling: Sampling::Centres,
            gamma0: 1.0,
            g2: 1.0,
            drag_form: DragForm::Boundary,
            free_end_drag: FreeEndDrag::Segment,
            width: WidthRule::Mean,
            right_end: RightEndKind::Prescribed,
            force: 0.0,
            gauge: false,
            active: None,
            active_amplitude: Field::Constant(1.0),
            growth: None,
            law: AnyEnergy::NeoHookean(NeoHookean::new(1.0).expect("valid")),
            continuum_scheme: ContinuumScheme::Conservative,
            viscosity: None,
            external_pressure: Field::Constant(0.0),
        }
    }
}

/// Shortest cell length accepted (reference lengths in `[1e-100, 1e100]`: a line of up to 10⁸
/// such cells has a finite length whose square is finite).
pub const MIN_CELL_LENGTH: f64 = 1e-100;
/// Longest cell length accepted (see [`MIN_CELL_LENGTH`]).
pub const MAX_CELL_LENGTH: f64 = 1e100;

fn finite_pos(key: &str, v: f64) -> Result<(), LineError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(LineError::invalid(key, v, "finite and > 0"))
    }
}

impl LineConfig {
    /// Number of cells (from `ref_lengths` if given).
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("ref_lengths = [1.0, 2.0, 0.5]")?;
    /// assert_eq!((cfg.n_cells(), cfg.lengths(), cfg.l0()), (3, vec![1.0, 2.0, 0.5], 3.5));
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn n_cells(&self) -> usize {
        self.ref_lengths.as_ref().map_or(self.cells, |v| v.len())
    }

    /// Whether all cells have one reference length (`cell_length`, or a `ref_lengths` list of
    /// equal entries).
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("ref_lengths = [1.0, 2.0]")?;
    /// assert!(!cfg.equal_cells() && LineConfig::default().equal_cells());
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn equal_cells(&self) -> bool {
        self.ref_lengths
            .as_ref()
            .is_none_or(|v| v.windows(2).all(|w| w[0] == w[1]))
    }

    /// Reference lengths of the cells.
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("cells = 3\ncell_length = 2.0")?;
    /// assert_eq!(cfg.lengths(), [2.0; 3]);
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn lengths(&self) -> Vec<f64> {
        self.ref_lengths
            .clone()
            .unwrap_or_else(|| vec![self.cell_length; self.cells])
    }

    /// `l₀`.
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("cells = 1000000\ncell_length = 0.5")?;
    /// assert_eq!(cfg.l0(), 5e5); // without building a 10⁶-vector
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn l0(&self) -> f64 {
        // no `lengths()` here: a uniform line of N cells needs no N-vector to know its length
        match &self.ref_lengths {
            Some(v) => v.iter().sum(),
            None => self.cells as f64 * self.cell_length,
        }
    }

    /// Checks every key; the error names the key and its valid range.
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("cells = 10\nK = -1.0")?;
    /// let e = cfg.validate().unwrap_err();
    /// assert!(e.to_string().contains("K"), "{e}");
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn validate(&self) -> Result<(), LineError> {
        if self.n_cells() == 0 {
            return Err(LineError::invalid("cells", 0, "an integer >= 1"));
        }
        let length_ok = |l: f64| (MIN_CELL_LENGTH..=MAX_CELL_LENGTH).contains(&l);
        if !length_ok(self.cell_length) {
            return Err(LineError::invalid(
                "cell_length",
                self.cell_length,
                "in [1e-100, 1e100] (so that the line's length and its square stay finite)",
            ));
        }
        if let Some(v) = &self.ref_lengths {
            if let Some(l) = v.iter().find(|l| !length_ok(**l)) {
                return Err(LineError::invalid(
                    "ref_lengths",
                    l,
                    "in [1e-100, 1e100] for every cell",
                ));
            }
        }
        if !(self.k1 < 1.0 && self.k1 > -1e6 && self.k1.is_finite()) {
            return Err(LineError::invalid("k1", self.k1, "finite and < 1"));
        }
        finite_pos("t_ramp", self.t_ramp)?;
        self.k.validate("K", false).map_err(LineError::Field)?;
        self.eta.validate("eta", false).map_err(LineError::Field)?;
        self.mu.validate("mu", true).map_err(LineError::Field)?;
        self.active_amplitude
            .validate("active_amplitude", false)
            .map_err(LineError::Field)?;
        if !self.m.is_finite() {
            return Err(LineError::invalid("m", self.m, "a finite real number"));
        }
        finite_pos("gamma0", self.gamma0)?;
        finite_pos("g2", self.g2)?;
        if !self.force.is_finite() {
            return Err(LineError::invalid("force", self.force, "finite"));
        }
        if let Some(a) = &self.active {
            if !a.beta.is_finite() {
                return Err(LineError::invalid("active.beta", a.beta, "finite"));
            }
            if !a.omega.is_finite() {
                return Err(LineError::invalid("active.omega", a.omega, "finite"));
            }
        }
        self.validate_viscosity_and_pressure()?;
        let periodic = self.right_end == RightEndKind::Periodic;
        if periodic && self.drag_form == DragForm::Centre {
            return Err(LineError::CentreFormPeriodic);
        }
        if self.free_end_drag == FreeEndDrag::Cells && self.drag_form == DragForm::Centre {
            return Err(LineError::Conflict {
                key: "free_end_drag",
                message: "`free_end_drag` = \"cells\" with `drag_form` = \"centre\": the centre form drags the cells' centres, not the end node, so the key would change nothing; use the boundary form or leave it out".into(),
            });
        }
        let k_zero = self.k.is_identically_zero();
        let eta_zero = self.eta.is_identically_zero();
        if periodic && k_zero && !self.gauge {
            return Err(LineError::Conflict {
                key: "K",
                message: "`K` = 0 everywhere with `right_end` = \"periodic\": rigid translation is a null mode (singular at t = 0); set K > 0 somewhere or `gauge` = true".into(),
            });
        }
        if self.right_end == RightEndKind::Free && k_zero && eta_zero && self.growth.is_none() {
            return Err(LineError::Conflict {
                key: "right_end",
                message: "`right_end` = \"free\" with `K` = 0 and `eta` = 0 and no growth: nothing drives the line (only the trivial static state); set K > 0, eta > 0 or add [growth]".into(),
            });
        }
        if self.right_end == RightEndKind::Prescribed && self.n_cells() < 2 && self.growth.is_none()
        {
            return Err(LineError::invalid(
                "cells",
                self.n_cells(),
                ">= 2 with a prescribed right end and no growth",
            ));
        }
        if self.continuum_scheme == ContinuumScheme::Thesis
            && (self.growth.is_some() || self.right_end != RightEndKind::Prescribed)
        {
            return Err(LineError::Conflict {
                key: "continuum_scheme",
                message: "`continuum_scheme` = \"thesis\" supports only a prescribed right end without growth; use \"conservative\"".into(),
            });
        }
        Ok(())
    }

    /// Checks `viscosity` and `external_pressure` (errors name the inner key).
    fn validate_viscosity_and_pressure(&self) -> Result<(), LineError> {
        if let Some(v) = &self.viscosity {
            v.branch().map_err(|e| {
                LineError::invalid(&format!("viscosity.{}", e.key), e.value, e.range)
            })?;
            let eta_set = !matches!(self.eta, Field::Constant(e) if e == 0.0);
            if eta_set && matches!(v, ViscosityModel::KelvinVoigt { .. }) {
                return Err(LineError::Conflict {
                    key: "eta",
                    message:
                        "both `eta` and `viscosity` = { model = \"kelvin_voigt\" } given; set one"
                            .into(),
                });
            }
        }
        let extended = self.viscosity.is_some()
            || !matches!(self.external_pressure, Field::Constant(p) if p == 0.0);
        if extended && self.continuum_scheme == ContinuumScheme::Thesis {
            return Err(LineError::Conflict {
                key: "continuum_scheme",
                message: "`continuum_scheme` = \"thesis\" supports neither `viscosity` nor `external_pressure`; use \"conservative\"".into(),
            });
        }
        // a closure's values are checked when the line is built
        self.external_pressure
            .validate_signed("external_pressure")
            .map_err(LineError::Field)
    }

    /// The Kelvin–Voigt viscosity field: `viscosity.eta` if given, else `eta`.
    pub(crate) fn kv_eta(&self) -> Field {
        match self.viscosity {
            Some(ViscosityModel::KelvinVoigt { eta }) => Field::Constant(eta),
            _ => self.eta.clone(),
        }
    }

    /// The prescribed length `l(t)`.
    ///
    /// ```
    /// use celltissue::line::LineConfig;
    /// let cfg: LineConfig = toml::from_str("cells = 10\nk1 = 0.2")?;
    /// let (l, _) = cfg.ramp().eval(1e3); // the exponential ramp, long after
    /// assert!((l - 8.0).abs() < 1e-12);
    /// # Ok::<(), toml::de::Error>(())
    /// ```
    pub fn ramp(&self) -> Ramp {
        let l0 = self.l0();
        match self.ramp {
            RampKind::Exponential => Ramp::Exponential {
                l0,
                k1: self.k1,
                t_ramp: self.t_ramp,
            },
            RampKind::Polynomial => Ramp::Polynomial {
                l0,
                k1: self.k1,
                t_ramp: self.t_ramp,
            },
        }
    }

    /// The builders' description (validate first).
    ///
    /// ```
    /// use celltissue::line::{discrete, LineConfig};
    /// let cfg: LineConfig = toml::from_str("cells = 10\nK = 0.5\neta = 0.2")?;
    /// cfg.validate()?;
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &cfg.params(1e-8))?;
    /// assert_eq!((line.n_cells(), line.k_face()[3], line.cells().eta[2]), (10, 0.5, 0.2));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn params(&self, atol_cell: f64) -> LineParams {
        let right = match self.right_end {
            RightEndKind::Prescribed => RightEnd::Prescribed(self.ramp()),
            RightEndKind::Free => {
                if self.force != 0.0 {
                    let f = self.force;
                    RightEnd::Free(Some(Arc::new(move |_t| (f, 0.0))))
                } else {
                    RightEnd::Free(None)
                }
            }
            RightEndKind::Periodic => RightEnd::Periodic { gauge: self.gauge },
        };
        LineParams {
            ref_lengths: self.lengths(),
            mu: self.mu.clone(),
            eta: self.kv_eta(),
            k: self.k.clone(),
            active_amp: self.active_amplitude.clone(),
            sampling: self.sampling,
            m: self.m,
            g2: self.g2,
            gamma0: self.gamma0,
            width: self.width,
            form: self.drag_form,
            free_end_drag: self.free_end_drag,
            right,
            active: self.active,
            growth: self.growth.as_ref().map(|g| g.law().clone()),
            maxwell: self.viscosity.and_then(|v| v.branch().ok().flatten()),
            p_ext: self.external_pressure.clone(),
            atol_cell,
        }
    }
}
