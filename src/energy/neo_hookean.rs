//! Neo-Hookean law (thesis (2.6), docs/model.md §1.3), with closed-form responses.

use super::error::{positive, EnergyError};
use super::{LineResponse, ShearResponse, SheetResponse, StrainEnergy};
use num_dual::DualNum;
use serde::{Deserialize, Serialize};

/// Incompressible neo-Hookean law `W = μ/2 (λ₁² + λ₂² + λ₃² − 3)`.
///
/// Parameter: shear modulus `mu > 0` (also the small-strain shear modulus). Responses are
/// hand-written closed forms (docs/model.md §1.3–§1.5), tested against AD:
/// line `σ_el = μ(a² − a⁻²)`, `dσ_el/da = 2μ(a + a⁻³)`, `p_el = μa⁻²`;
/// sheet `σ₁₁ = μ(λ₁² − λ₃²)`, `σ₂₂ = μ(λ₂² − λ₃²)`, `p = μλ₃²`; shear `τ = μT`.
///
/// ```
/// use celltissue::{NeoHookean, StrainEnergy};
/// let law = NeoHookean::new(1.0)?;
/// assert!((law.line(2.0).sigma - 3.75).abs() < 1e-14);
/// assert!(NeoHookean::new(0.0).is_err());
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "NeoHookeanParams")]
pub struct NeoHookean {
    mu: f64,
}

/// Unvalidated serde form of [`NeoHookean`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NeoHookeanParams {
    mu: f64,
}

impl TryFrom<NeoHookeanParams> for NeoHookean {
    type Error = EnergyError;
    fn try_from(p: NeoHookeanParams) -> Result<Self, EnergyError> {
        Self::new(p.mu)
    }
}

impl NeoHookean {
    /// Neo-Hookean law with shear modulus `mu` (finite, `> 0`).
    ///
    /// ```
    /// use celltissue::NeoHookean;
    /// assert_eq!(NeoHookean::new(-1.0).unwrap_err().to_string(), "mu = -1 must be finite and > 0");
    /// ```
    pub fn new(mu: f64) -> Result<Self, EnergyError> {
        Ok(Self {
            mu: positive("mu", mu)?,
        })
    }

    /// The shear modulus `μ`.
    ///
    /// ```
    /// assert_eq!(celltissue::NeoHookean::new(2.5).unwrap().mu(), 2.5);
    /// ```
    pub fn mu(&self) -> f64 {
        self.mu
    }
}

impl StrainEnergy for NeoHookean {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0) * (0.5 * self.mu)
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        self.mu
    }

    #[inline]
    fn line(&self, a: f64) -> LineResponse {
        let mu = self.mu;
        let ia2 = 1.0 / (a * a);
        LineResponse {
            sigma: mu * (a * a - ia2),
            dsigma: 2.0 * mu * (a + ia2 / a),
            pressure: mu * ia2,
            dpressure: -2.0 * mu * ia2 / a,
        }
    }

    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        let mu = self.mu;
        let l3 = 1.0 / (l1 * l2);
        let l3s = l3 * l3;
        SheetResponse {
            s11: mu * (l1 * l1 - l3s),
            s22: mu * (l2 * l2 - l3s),
            pressure: mu * l3s,
            tangent: [
                [2.0 * mu * (l1 + l3s / l1), 2.0 * mu * l3s / l2],
                [2.0 * mu * l3s / l1, 2.0 * mu * (l2 + l3s / l2)],
            ],
        }
    }

    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        ShearResponse {
            tau: self.mu * t,
            dtau: self.mu,
        }
    }
}
