//! A law with its energy multiplied by a positive factor (heterogeneous moduli).

use super::error::{positive, EnergyError};
use super::{LineResponse, ShearResponse, SheetResponse, StrainEnergy};
use num_dual::DualNum;

/// `W = factor · W_inner`: used for heterogeneous moduli `μ(X) = factor × base μ`. All
/// responses (stresses, pressures, tangents, `shear_modulus`) scale linearly, and the inner
/// law's own (possibly closed-form) responses are reused.
///
/// ```
/// use celltissue::{NeoHookean, Scaled, StrainEnergy};
/// let base = NeoHookean::new(1.0)?;
/// let stiff = Scaled::new(base, 3.0)?;
/// assert_eq!(stiff.shear_modulus(), 3.0);
/// assert_eq!(stiff.line(1.5).sigma, 3.0 * base.line(1.5).sigma);
/// assert!(Scaled::new(base, 0.0).is_err());
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scaled<E> {
    /// The base law.
    pub inner: E,
    /// The positive multiplier.
    pub factor: f64,
}

impl<E: StrainEnergy> Scaled<E> {
    /// Scales `inner` by `factor` (finite, `> 0`).
    ///
    /// ```
    /// use celltissue::{NeoHookean, Scaled};
    /// let err = Scaled::new(NeoHookean::new(1.0).unwrap(), -2.0).unwrap_err();
    /// assert_eq!(err.to_string(), "factor = -2 must be finite and > 0");
    /// ```
    pub fn new(inner: E, factor: f64) -> Result<Self, EnergyError> {
        Ok(Self {
            inner,
            factor: positive("factor", factor)?,
        })
    }
}

impl<E: StrainEnergy> StrainEnergy for Scaled<E> {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        self.inner.energy(l) * self.factor
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        self.factor * self.inner.shear_modulus()
    }

    #[inline(always)]
    fn admissible(&self, l: [f64; 3]) -> Result<(), super::EnergyError> {
        self.inner.admissible(l)
    }

    #[inline]
    fn line(&self, a: f64) -> LineResponse {
        let r = self.inner.line(a);
        let f = self.factor;
        LineResponse {
            sigma: f * r.sigma,
            dsigma: f * r.dsigma,
            pressure: f * r.pressure,
            dpressure: f * r.dpressure,
        }
    }

    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        let r = self.inner.sheet(l1, l2);
        let f = self.factor;
        let t = r.tangent;
        SheetResponse {
            s11: f * r.s11,
            s22: f * r.s22,
            pressure: f * r.pressure,
            tangent: [[f * t[0][0], f * t[0][1]], [f * t[1][0], f * t[1][1]]],
        }
    }

    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        let r = self.inner.shear(t);
        ShearResponse {
            tau: self.factor * r.tau,
            dtau: self.factor * r.dtau,
        }
    }

    #[inline]
    fn shear_pressure(&self, t: f64) -> f64 {
        self.factor * self.inner.shear_pressure(t)
    }

    fn shear_is_exact(&self) -> bool {
        self.inner.shear_is_exact()
    }
}
