//! Cell viscosity (docs/model.md §2.3, §8.3; derivation in docs/viscoelasticity.md): the
//! scenario's [`ViscosityModel`] and the finite-strain Maxwell branch [`MaxwellBranch`], a
//! [`ViscousBranch`] with one internal variable per cell.
//!
//! * Kelvin–Voigt (the thesis): `σ += η α̇ (1 + α⁻²)`, no internal variable (the line's `eta`);
//!   in the sheet, `η α̇ᵢ` in each principal direction ([`kelvin_voigt_sheet`]).
//! * Maxwell branch: multiplicative split `α = a_e a_v` of the cell's elastic stretch, branch
//!   energy of the cell law's family with modulus `μ_m` at `a_e`, flow rule
//!   `ȧ_v / a_v = σ_m(a_e) / η_m`. The internal variable `a_v` is an unknown of the residual
//!   (row `ȧ_v − a_v σ_m / η_m`), like growth's `g`.
//! * Standard linear solid: the cell's elastic law plus a Maxwell branch; Maxwell: the branch
//!   alone (the cell's own law then carries no stress).
//!
//! Small-strain limit: `σ_m' + σ_m/τ = 4μ_m ε'` with `τ = η_m/(4μ_m)`.

use crate::energy::StrainEnergy;
use crate::scalar::Scalar;
use serde::{Deserialize, Serialize};

/// A viscous branch of a cell carrying internal variables (one per cell on the line): what a
/// cell array needs to put it in its residual. Implemented by [`MaxwellBranch`].
///
/// ```
/// use celltissue::cell::{MaxwellBranch, ViscousBranch};
/// use celltissue::NeoHookean;
/// let b = MaxwellBranch::standard_linear_solid(0.5, 2.0).unwrap();
/// let law = NeoHookean::new(1.0).unwrap();
/// // relaxed branch (a_v = α): no stress, no flow
/// assert_eq!(b.stress(&law, 1.2f64, 1.2), 0.0);
/// assert_eq!(b.rate(1.2f64, 0.0), 0.0);
/// assert_eq!(b.initial(), 1.0);
/// ```
pub trait ViscousBranch: Send + Sync {
    /// Value of the internal variable in the undeformed, unstressed cell.
    fn initial(&self) -> f64;
    /// Branch stress at the cell's elastic stretch `α` and internal variable `q`, for the
    /// cell's strain-energy family `law` (unscaled: the branch sets its own modulus).
    fn stress<S: Scalar, E: StrainEnergy>(&self, law: &E, alpha: S, q: S) -> S;
    /// Evolution rate `q̇` given `q` and the branch stress.
    fn rate<S: Scalar>(&self, q: S, sigma_branch: S) -> S;
    /// Whether the cell's own elastic law acts in parallel with the branch.
    fn keeps_elastic(&self) -> bool;
    /// Whether the internal variable `q` is admissible (finite and, for a stretch, > 0).
    fn admissible(&self, q: f64) -> bool;
    /// The quasi-3D sheet cell's flow rule (docs/viscoelasticity.md, "The sheet"): rates
    /// `(q̇₁, q̇₂)` of its two in-plane internal variables given `q` and the branch's in-plane
    /// stresses `(σ₁₁, σ₂₂)` (its `σ₃₃` is 0).
    fn sheet_rate<S: Scalar>(&self, q: [S; 2], sigma_branch: [S; 2]) -> [S; 2];
}

/// A finite-strain Maxwell branch (modulus `μ_m`, viscosity `η_m`), in parallel with the
/// cell's elastic law ([`standard_linear_solid`](Self::standard_linear_solid)) or alone
/// ([`maxwell`](Self::maxwell)). Internal variable: the viscous stretch `a_v` (1 at rest).
///
/// ```
/// use celltissue::cell::MaxwellBranch;
/// let b = MaxwellBranch::maxwell(1.0, 4.0).unwrap();
/// assert_eq!(b.relaxation_time(), 1.0); // τ = η_m / (4 μ_m)
/// assert!(MaxwellBranch::maxwell(0.0, 1.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaxwellBranch {
    /// Branch modulus `μ_m` (the branch's small-strain shear modulus).
    pub mu_m: f64,
    /// Branch viscosity `η_m`.
    pub eta_m: f64,
    /// `true`: standard linear solid (cell law + branch); `false`: Maxwell (branch alone).
    pub elastic: bool,
}

/// An invalid viscosity parameter.
///
/// ```
/// use celltissue::cell::MaxwellBranch;
/// let e = MaxwellBranch::maxwell(0.0, 1.0).unwrap_err();
/// assert_eq!(e.key, "mu_m");
/// assert_eq!(e.to_string(), "viscosity.mu_m = 0 must be finite and > 0");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("viscosity.{key} = {value} must be {range}")]
pub struct ViscosityError {
    /// The key, e.g. `mu_m`.
    pub key: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The valid range.
    pub range: &'static str,
}

impl MaxwellBranch {
    /// Maxwell cell: the branch alone (`μ_m > 0`, `η_m > 0`, finite).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// let b = MaxwellBranch::maxwell(0.5, 1.0)?;
    /// assert!(!b.elastic); // the branch alone
    /// assert_eq!(MaxwellBranch::maxwell(1.0, -1.0).unwrap_err().key, "eta_m");
    /// # Ok::<(), celltissue::cell::ViscosityError>(())
    /// ```
    pub fn maxwell(mu_m: f64, eta_m: f64) -> Result<Self, ViscosityError> {
        Self::checked(mu_m, eta_m, false)
    }

    /// Standard linear solid: the cell's law plus the branch (`μ_m ≥ 0`, `η_m > 0`, finite;
    /// `μ_m = 0` is the elastic cell).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// // μ_m = 0 is allowed for a standard linear solid (the elastic cell), not for a Maxwell cell
    /// assert!(MaxwellBranch::standard_linear_solid(0.0, 1.0).is_ok());
    /// assert!(MaxwellBranch::maxwell(0.0, 1.0).is_err());
    /// ```
    pub fn standard_linear_solid(mu_m: f64, eta_m: f64) -> Result<Self, ViscosityError> {
        Self::checked(mu_m, eta_m, true)
    }

    fn checked(mu_m: f64, eta_m: f64, elastic: bool) -> Result<Self, ViscosityError> {
        let mu_ok = mu_m.is_finite() && if elastic { mu_m >= 0.0 } else { mu_m > 0.0 };
        if !mu_ok {
            return Err(ViscosityError {
                key: "mu_m",
                value: mu_m,
                range: if elastic {
                    "finite and >= 0"
                } else {
                    "finite and > 0"
                },
            });
        }
        if !(eta_m > 0.0 && eta_m.is_finite()) {
            return Err(ViscosityError {
                key: "eta_m",
                value: eta_m,
                range: "finite and > 0",
            });
        }
        Ok(Self {
            mu_m,
            eta_m,
            elastic,
        })
    }

    /// Small-strain relaxation time `τ = η_m / (4 μ_m)` (`E = 4μ` on the line, §1.2).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// assert_eq!(MaxwellBranch::maxwell(0.5, 2.0)?.relaxation_time(), 1.0); // η_m/(4μ_m)
    /// # Ok::<(), celltissue::cell::ViscosityError>(())
    /// ```
    pub fn relaxation_time(&self) -> f64 {
        self.eta_m / (4.0 * self.mu_m)
    }

    /// The branch's modulus relative to the cell law's own, `μ_m / μ`: the factor on the law's
    /// stresses at the elastic stretch.
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// let b = MaxwellBranch::standard_linear_solid(0.5, 2.0)?;
    /// assert_eq!(b.modulus_ratio(&celltissue::NeoHookean::new(2.0).unwrap()), 0.25);
    /// # Ok::<(), celltissue::cell::ViscosityError>(())
    /// ```
    pub fn modulus_ratio<E: StrainEnergy>(&self, law: &E) -> f64 {
        self.mu_m / law.shear_modulus()
    }

    /// Branch pressure `μ_m/μ · p_el(a_e)` at `a_e = α / a_v` (in `f64`, for observers).
    ///
    /// ```
    /// use celltissue::cell::MaxwellBranch;
    /// let law = celltissue::NeoHookean::new(1.0).unwrap();
    /// let b = MaxwellBranch::maxwell(0.5, 2.0)?;
    /// // a relaxed branch (a_v = α) keeps its rest pressure μ_m
    /// assert!((b.pressure(&law, 1.3, 1.3) - 0.5).abs() < 1e-15);
    /// # Ok::<(), celltissue::cell::ViscosityError>(())
    /// ```
    pub fn pressure<E: StrainEnergy>(&self, law: &E, alpha: f64, av: f64) -> f64 {
        self.mu_m / law.shear_modulus() * law.line(alpha / av).pressure
    }
}

impl ViscousBranch for MaxwellBranch {
    #[inline]
    fn initial(&self) -> f64 {
        1.0
    }

    #[inline]
    fn stress<S: Scalar, E: StrainEnergy>(&self, law: &E, alpha: S, av: S) -> S {
        let ae = alpha / av;
        let s = self.modulus_ratio(law);
        let r = law.line(ae.re());
        ae.lift(s * r.sigma, s * r.dsigma)
    }

    #[inline]
    fn rate<S: Scalar>(&self, av: S, sigma_m: S) -> S {
        av * sigma_m * (1.0 / self.eta_m)
    }

    #[inline]
    fn keeps_elastic(&self) -> bool {
        self.elastic
    }

    #[inline]
    fn admissible(&self, av: f64) -> bool {
        av > 0.0 && av.is_finite()
    }

    /// Isochoric flow along the deviatoric branch stress, `ȧ_i / a_i = 2 dev(σ_m)_ii / η_m`
    /// with `σ_m,33 = 0`: `ȧ₁/a₁ = 2(2σ₁₁ − σ₂₂)/(3η_m)`, and 1 ↔ 2. At small strain both
    /// directions relax with the line's `τ = η_m/(4μ_m)`.
    #[inline]
    fn sheet_rate<S: Scalar>(&self, a: [S; 2], s: [S; 2]) -> [S; 2] {
        let c = 2.0 / (3.0 * self.eta_m);
        [
            a[0] * (s[0] * 2.0 - s[1]) * c,
            a[1] * (s[1] * 2.0 - s[0]) * c,
        ]
    }
}

/// Kelvin–Voigt stresses of a quasi-3D sheet cell (docs/viscoelasticity.md, "Kelvin–Voigt in
/// the sheet"): each principal direction carries `η α̇ᵢ`, as on the line, and the free top
/// `σ₃₃ = 0` fixes the pressure. Given the in-plane elastic stretches `α = (α₁, α₂)` and their
/// rates, returns `[σ₁₁ᵛ, σ₂₂ᵛ, pᵛ] = [η(α̇₁ − α̇₃), η(α̇₂ − α̇₃), η α̇₃]` with `α₃ = 1/(α₁α₂)`,
/// `α̇₃ = −α₃(α̇₁/α₁ + α̇₂/α₂)`.
///
/// With `α₂ ≡ 1` (plane strain) this is the line's `η α̇ (1 + α⁻²)` and `−η α̇ α⁻²`:
///
/// ```
/// use celltissue::cell::kelvin_voigt_sheet;
/// let (eta, a, rate) = (0.7, 0.8f64, 0.3);
/// let [s11, s22, p] = kelvin_voigt_sheet(eta, [a, 1.0], [rate, 0.0]);
/// assert!((s11 - eta * rate * (1.0 + a.powi(-2))).abs() < 1e-15);
/// assert!((p + eta * rate * a.powi(-2)).abs() < 1e-15);
/// assert!((s22 - (-p)).abs() < 1e-15); // σ₂₂ᵛ = η(0 − α̇₃)
/// ```
#[inline]
pub fn kelvin_voigt_sheet<S: Scalar>(eta: f64, alpha: [S; 2], rate: [S; 2]) -> [S; 3] {
    let a3 = (alpha[0] * alpha[1]).recip();
    let rate3 = -a3 * (rate[0] / alpha[0] + rate[1] / alpha[1]);
    [
        (rate[0] - rate3) * eta,
        (rate[1] - rate3) * eta,
        rate3 * eta,
    ]
}

/// The viscosity of a cell as named in a scenario:
/// `viscosity = { model = "kelvin_voigt", eta = 0.5 }`,
/// `{ model = "maxwell", mu_m = 1, eta_m = 4 }` or
/// `{ model = "standard_linear_solid", mu_m = 0.5, eta_m = 2 }`. The line's top-level `eta`
/// keeps working (a Kelvin–Voigt viscosity, also in parallel with a Maxwell branch).
///
/// ```
/// use celltissue::cell::ViscosityModel;
/// let v: ViscosityModel = toml::from_str(r#"model = "maxwell"
/// mu_m = 1.0
/// eta_m = 4.0"#).unwrap();
/// assert_eq!(v.branch().unwrap().unwrap().relaxation_time(), 1.0);
/// assert!(toml::from_str::<ViscosityModel>("model = \"maxwell\"\nmu_m = 1.0").is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum ViscosityModel {
    /// Kelvin–Voigt with viscosity `eta` (the thesis's law; same as the top-level `eta`).
    KelvinVoigt {
        /// `η ≥ 0` (including the factor 2).
        eta: f64,
    },
    /// Maxwell: the branch alone.
    Maxwell {
        /// Branch modulus `μ_m > 0`.
        mu_m: f64,
        /// Branch viscosity `η_m > 0`.
        eta_m: f64,
    },
    /// Standard linear solid: the cell's law plus a Maxwell branch.
    StandardLinearSolid {
        /// Branch modulus `μ_m ≥ 0`.
        mu_m: f64,
        /// Branch viscosity `η_m > 0`.
        eta_m: f64,
    },
}

impl ViscosityModel {
    /// The Maxwell branch of this model (`None` for Kelvin–Voigt), or the invalid key.
    ///
    /// ```
    /// use celltissue::cell::ViscosityModel;
    /// assert_eq!(ViscosityModel::KelvinVoigt { eta: 1.0 }.branch(), Ok(None)); // no internal variable
    /// let sls = ViscosityModel::StandardLinearSolid { mu_m: 0.5, eta_m: 2.0 }.branch().unwrap().unwrap();
    /// assert!(sls.elastic);
    /// assert_eq!(ViscosityModel::KelvinVoigt { eta: -1.0 }.branch().unwrap_err().key, "eta");
    /// ```
    pub fn branch(&self) -> Result<Option<MaxwellBranch>, ViscosityError> {
        match *self {
            Self::KelvinVoigt { eta } => {
                if eta >= 0.0 && eta.is_finite() {
                    Ok(None)
                } else {
                    Err(ViscosityError {
                        key: "eta",
                        value: eta,
                        range: "finite and >= 0",
                    })
                }
            }
            Self::Maxwell { mu_m, eta_m } => MaxwellBranch::maxwell(mu_m, eta_m).map(Some),
            Self::StandardLinearSolid { mu_m, eta_m } => {
                MaxwellBranch::standard_linear_solid(mu_m, eta_m).map(Some)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NeoHookean;
    use num_dual::Dual64;

    #[test]
    fn branch_stress_is_the_law_at_the_elastic_stretch_with_the_branch_modulus() {
        let law = NeoHookean::new(2.0).unwrap();
        let b = MaxwellBranch::maxwell(0.5, 1.0).unwrap();
        // a_e = 1.5 / 1.2 = 1.25; σ_m = μ_m (a_e² − a_e⁻²)
        let ae: f64 = 1.5 / 1.2;
        let s = b.stress(&law, 1.5, 1.2);
        assert!((s - 0.5 * (ae * ae - 1.0 / (ae * ae))).abs() < 1e-14);
        // derivative along α by AD of the lift agrees with a central difference
        let d = b
            .stress(&law, Dual64::new(1.5, 1.0), Dual64::new(1.2, 0.0))
            .eps;
        let h = 1e-6;
        let fd = (b.stress(&law, 1.5 + h, 1.2) - b.stress(&law, 1.5 - h, 1.2)) / (2.0 * h);
        assert!((d - fd).abs() < 1e-8, "{d} vs {fd}");
    }

    #[test]
    fn invalid_parameters_name_their_key() {
        let e = MaxwellBranch::maxwell(1.0, -1.0).unwrap_err();
        assert_eq!(e.key, "eta_m");
        assert!(e.to_string().contains("viscosity.eta_m = -1"));
        assert_eq!(
            MaxwellBranch::standard_linear_solid(f64::NAN, 1.0)
                .unwrap_err()
                .key,
            "mu_m"
        );
        assert!(MaxwellBranch::standard_linear_solid(0.0, 1.0).is_ok());
        let kv = ViscosityModel::KelvinVoigt { eta: -0.1 };
        assert_eq!(kv.branch().unwrap_err().key, "eta");
    }
}
