//! Gent's limiting-chain law (Gent 1996): a locking material for the constitutive extension
//! points (docs/model.md §1, §8): its energy is finite only for `I₁ − 3 < J_m`, and it rejects
//! states outside that domain by name ([`StrainEnergy::admissible`]).

use super::error::{positive, EnergyError};
use super::StrainEnergy;
use num_dual::DualNum;
use serde::{Deserialize, Serialize};

/// Incompressible Gent law `W = −(μ J_m / 2) ln(1 − (I₁ − 3)/J_m)`, `I₁ = λ₁² + λ₂² + λ₃²`.
///
/// Parameters: small-strain shear modulus `mu > 0` and locking parameter `jm > 0` (neo-Hookean
/// as `J_m → ∞`). The stress diverges as `I₁ − 3 → J_m`; on the line (`I₁ − 3 = (a − 1/a)²`)
/// the cell locks at `|a − 1/a| = √J_m`. Responses come from AD.
///
/// ```
/// use celltissue::{Gent, StrainEnergy};
/// let law = Gent::new(1.0, 0.5)?;
/// assert!((law.line(1.0).dsigma - 4.0).abs() < 1e-12);
/// // a = 1.5 is past the lock (a − 1/a = 0.83 > √0.5): a named error, not NaN
/// let e = law.admissible([1.5, 1.0 / 1.5, 1.0]).unwrap_err();
/// assert!(e.to_string().contains("gent"));
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "GentParams")]
pub struct Gent {
    mu: f64,
    jm: f64,
}

/// Unvalidated serde form of [`Gent`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GentParams {
    mu: f64,
    jm: f64,
}

impl TryFrom<GentParams> for Gent {
    type Error = EnergyError;
    fn try_from(p: GentParams) -> Result<Self, EnergyError> {
        Self::new(p.mu, p.jm)
    }
}

impl Gent {
    /// Gent law with shear modulus `mu` and locking parameter `jm` (both finite and `> 0`).
    ///
    /// ```
    /// use celltissue::Gent;
    /// assert_eq!(Gent::new(1.0, 0.0).unwrap_err().to_string(), "jm = 0 must be finite and > 0");
    /// ```
    pub fn new(mu: f64, jm: f64) -> Result<Self, EnergyError> {
        Ok(Self {
            mu: positive("mu", mu)?,
            jm: positive("jm", jm)?,
        })
    }

    /// The locking parameter `J_m`.
    ///
    /// ```
    /// assert_eq!(celltissue::Gent::new(1.0, 30.0)?.jm(), 30.0);
    /// # Ok::<(), celltissue::EnergyError>(())
    /// ```
    pub fn jm(&self) -> f64 {
        self.jm
    }
}

impl StrainEnergy for Gent {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let i1m3 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
        (-(i1m3 / self.jm) + 1.0).ln() * (-0.5 * self.mu * self.jm)
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        self.mu
    }

    fn admissible(&self, l: [f64; 3]) -> Result<(), EnergyError> {
        let i1m3 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
        if i1m3 < self.jm && i1m3.is_finite() {
            Ok(())
        } else {
            Err(EnergyError::OutsideDomain {
                law: "gent",
                reason: format!(
                    "I1 - 3 = {i1m3:.6e} at stretches ({:.6e}, {:.6e}, {:.6e}) must be < jm = {} (the chains lock)",
                    l[0], l[1], l[2], self.jm
                ),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_stress_matches_the_closed_form_and_diverges_at_the_lock() {
        let law = Gent::new(1.3, 0.5).unwrap();
        for a in [0.8, 1.0, 1.2, 1.4] {
            // σ = a Ŵ'(a) with Ŵ = −(μJ/2) ln(1 − (a − 1/a)²/J):
            // σ = μ (a² − a⁻²) / (1 − (a − 1/a)²/J)
            let x = (a - 1.0 / a) * (a - 1.0 / a) / 0.5;
            let closed = 1.3 * (a * a - 1.0 / (a * a)) / (1.0 - x);
            let r = law.line(a);
            assert!(
                (r.sigma - closed).abs() < 1e-12 * closed.abs().max(1.0),
                "{a}"
            );
        }
        let lock = (0.5f64.sqrt() + (0.5 + 4.0f64).sqrt()) / 2.0;
        assert!(law.line(lock * (1.0 - 1e-9)).sigma > 1e6);
        assert!(law
            .admissible([lock * (1.0 + 1e-9), 1.0 / lock, 1.0])
            .is_err());
        assert!(law
            .admissible([lock * (1.0 - 1e-9), 1.0 / lock, 1.0])
            .is_ok());
    }
}
