//! Mooney–Rivlin law (docs/model.md §1.3, §1.4).

use super::error::{non_negative, positive, EnergyError};
use super::StrainEnergy;
use num_dual::DualNum;
use serde::{Deserialize, Serialize};

/// Incompressible Mooney–Rivlin law `W = C₁(I₁ − 3) + C₂(I₂ − 3)`, `I₁ = Σλᵢ²`,
/// `I₂ = Σ_{i<k} λᵢ²λₖ²`.
///
/// Parameters `c1 ≥ 0`, `c2 ≥ 0` with `c1 + c2 > 0`; small-strain shear modulus
/// `μ = 2(C₁ + C₂)`. In the plane-strain line `I₁ = I₂`, so the line response equals neo-Hookean
/// with that `μ`; in the sheet it differs:
/// `σ₁₁ = 2(λ₁² − λ₃²)(C₁ + C₂λ₂²)`. Responses by AD.
///
/// ```
/// use celltissue::{MooneyRivlin, NeoHookean, StrainEnergy};
/// let mr = MooneyRivlin::new(0.3, 0.2)?;
/// let nh = NeoHookean::new(1.0)?;
/// assert!((mr.line(1.7).sigma - nh.line(1.7).sigma).abs() < 1e-12);
/// // at λ₂ = 1 the two coincide (C₁ + C₂λ₂² = μ/2); off it they differ
/// assert!((mr.sheet(1.7, 1.0).s11 - nh.sheet(1.7, 1.0).s11).abs() < 1e-12);
/// assert!((mr.sheet(1.7, 0.8).s11 - nh.sheet(1.7, 0.8).s11).abs() > 1e-3);
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MooneyRivlinParams")]
pub struct MooneyRivlin {
    c1: f64,
    c2: f64,
}

/// Unvalidated serde form of [`MooneyRivlin`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MooneyRivlinParams {
    c1: f64,
    c2: f64,
}

impl TryFrom<MooneyRivlinParams> for MooneyRivlin {
    type Error = EnergyError;
    fn try_from(p: MooneyRivlinParams) -> Result<Self, EnergyError> {
        Self::new(p.c1, p.c2)
    }
}

impl MooneyRivlin {
    /// Mooney–Rivlin law; `c1, c2` finite and `≥ 0`, `c1 + c2 > 0`.
    ///
    /// ```
    /// use celltissue::MooneyRivlin;
    /// assert_eq!(MooneyRivlin::new(1.0, -0.1).unwrap_err().to_string(),
    ///            "c2 = -0.1 must be finite and >= 0");
    /// assert_eq!(MooneyRivlin::new(0.0, 0.0).unwrap_err().to_string(),
    ///            "c1 + c2 = 0 must be finite and > 0");
    /// ```
    pub fn new(c1: f64, c2: f64) -> Result<Self, EnergyError> {
        let c1 = non_negative("c1", c1)?;
        let c2 = non_negative("c2", c2)?;
        positive("c1 + c2", c1 + c2)?;
        Ok(Self { c1, c2 })
    }

    /// `(C₁, C₂)`.
    ///
    /// ```
    /// assert_eq!(celltissue::MooneyRivlin::new(0.3, 0.2).unwrap().params(), (0.3, 0.2));
    /// ```
    pub fn params(&self) -> (f64, f64) {
        (self.c1, self.c2)
    }
}

impl StrainEnergy for MooneyRivlin {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let (s1, s2, s3) = (l[0] * l[0], l[1] * l[1], l[2] * l[2]);
        let i1 = s1 + s2 + s3;
        let i2 = s1 * s2 + s2 * s3 + s3 * s1;
        (i1 - 3.0) * self.c1 + (i2 - 3.0) * self.c2
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        2.0 * (self.c1 + self.c2)
    }
}
