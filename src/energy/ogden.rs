//! Ogden law (thesis (1.10), docs/model.md §1.3, §1.4).

use super::error::{finite, EnergyError};
use super::StrainEnergy;
use num_dual::DualNum;
use serde::{Deserialize, Serialize};

/// Incompressible Ogden law `W = Σₚ μₚ/αₚ (λ₁^αₚ + λ₂^αₚ + λ₃^αₚ − 3)` with any number of terms.
///
/// Parameters: `terms = [(μ₁, α₁), …]`, non-empty, finite, `μₚαₚ > 0` for every term.
/// Small-strain shear modulus `μ = ½ Σ μₚαₚ`. One term with `α = 2` is neo-Hookean.
/// Line: `σ_el = Σ μₚ(a^αₚ − a^−αₚ)`. Responses by AD.
///
/// ```
/// use celltissue::{Ogden, StrainEnergy};
/// let law = Ogden::new(vec![(0.6, 3.0), (-0.1, -2.0)])?;
/// assert!((law.shear_modulus() - 1.0).abs() < 1e-15);
/// assert!((law.line(1.0).dsigma - 4.0).abs() < 1e-12);
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "OgdenParams")]
pub struct Ogden {
    terms: Vec<(f64, f64)>,
}

/// Unvalidated serde form of [`Ogden`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OgdenParams {
    terms: Vec<(f64, f64)>,
}

impl TryFrom<OgdenParams> for Ogden {
    type Error = EnergyError;
    fn try_from(p: OgdenParams) -> Result<Self, EnergyError> {
        Self::new(p.terms)
    }
}

impl Ogden {
    /// Ogden law from `(μₚ, αₚ)` pairs; errors name the offending term.
    ///
    /// ```
    /// use celltissue::Ogden;
    /// assert_eq!(Ogden::new(vec![(1.0, 2.0), (1.0, -1.0)]).unwrap_err().to_string(),
    ///            "terms[1].mu_p*alpha_p = -1 must be > 0");
    /// assert_eq!(Ogden::new(vec![(0.3, -1.5)]).unwrap_err().to_string(),
    ///            "terms[0].mu_p*alpha_p = -0.45 must be > 0");
    /// assert!(Ogden::new(vec![]).is_err());
    /// ```
    pub fn new(terms: Vec<(f64, f64)>) -> Result<Self, EnergyError> {
        if terms.is_empty() {
            return Err(EnergyError::EmptyOgden);
        }
        for (p, &(mu, alpha)) in terms.iter().enumerate() {
            finite(&format!("terms[{p}].mu_p"), mu)?;
            finite(&format!("terms[{p}].alpha_p"), alpha)?;
            if mu * alpha <= 0.0 {
                // the product to 12 significant digits: 0.3·(−1.5) reads −0.45, not the
                // product's binary rounding −0.44999999999999996
                let product = format!("{:.11e}", mu * alpha)
                    .parse::<f64>()
                    .unwrap_or(mu * alpha);
                return Err(EnergyError::out_of_range(
                    format!("terms[{p}].mu_p*alpha_p"),
                    product,
                    "> 0",
                ));
            }
        }
        Ok(Self { terms })
    }

    /// The `(μₚ, αₚ)` pairs.
    ///
    /// ```
    /// assert_eq!(celltissue::Ogden::new(vec![(1.0, 2.0)]).unwrap().terms(), &[(1.0, 2.0)]);
    /// ```
    pub fn terms(&self) -> &[(f64, f64)] {
        &self.terms
    }
}

impl StrainEnergy for Ogden {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let mut w = D::from(0.0);
        for &(mu, alpha) in &self.terms {
            let s = l[0].powf(alpha) + l[1].powf(alpha) + l[2].powf(alpha) - 3.0;
            w += s * (mu / alpha);
        }
        w
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        0.5 * self.terms.iter().map(|&(m, a)| m * a).sum::<f64>()
    }
}
