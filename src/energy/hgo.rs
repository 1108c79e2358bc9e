//! Holzapfel–Gasser–Ogden law with one fibre family (thesis (1.11), docs/model.md §1.3, §7).

use super::error::{finite, non_negative, positive, EnergyError};
use super::{ShearResponse, StrainEnergy};
use num_dual::{Dual2_64, Dual64, DualNum};
use serde::{Deserialize, Serialize};

/// Holzapfel–Gasser–Ogden (HGO) law, one fibre family at angle `θ` to the line, in the
/// substrate plane:
///
/// `W = c/2 (I₁ − 3) + k₁/(2k₂) [exp(k₂E²) − 1] 𝟙[E > 0]`, `E = I₄ − 1`,
/// `I₄ = λ₁² cos²θ + λ₂² sin²θ` with `λ₁, λ₂` the stretches along the cell's axes (the line
/// and the sheet deform along them). Simple shear turns the principal axes, so
/// [`StrainEnergy::shear`] and [`StrainEnergy::shear_pressure`] follow the fibre through the
/// deformation gradient instead (docs/model.md §1.5).
///
/// * Fibres act only in tension: the fibre term is exactly zero for `I₄ ≤ 1`.
/// * The prefactor is the standard `k₁/(2k₂)`; the thesis's (1.11) writes `k₁/k₂`, so
///   thesis `k₁` = this `k₁/2` (docs/model.md §7). For `k2 = 0` the fibre term is its limit
///   `k₁E²/2`.
/// * Parameters: `c > 0`, `k1 ≥ 0`, `k2 ≥ 0`, `theta` finite (radians).
/// * Small-strain shear modulus `μ = c` (fibre-inactive side). On the tensile side the line
///   tangent jumps: `dσ_el/da(1⁺) = 4c + 4k₁cos²2θ`; the energy is `C¹` at `I₄ = 1`.
///
/// Responses by AD.
///
/// ```
/// use celltissue::{Hgo, StrainEnergy};
/// let law = Hgo::new(1.0, 0.5, 2.0, 0.0)?; // fibres along the line
/// assert_eq!(law.line(0.8).sigma, 1.0 * (0.64 - 1.0 / 0.64)); // compression: matrix only
/// assert!(law.line(1.2).sigma > 1.2f64.powi(2) - 1.2f64.powi(-2)); // tension: fibres stiffen
/// # Ok::<(), celltissue::EnergyError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "HgoParams")]
pub struct Hgo {
    c: f64,
    k1: f64,
    k2: f64,
    theta: f64,
    #[serde(skip)]
    cos2: f64,
    #[serde(skip)]
    sin2: f64,
    #[serde(skip)]
    sin_cos: f64,
}

/// Unvalidated serde form of [`Hgo`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HgoParams {
    c: f64,
    k1: f64,
    k2: f64,
    theta: f64,
}

impl TryFrom<HgoParams> for Hgo {
    type Error = EnergyError;
    fn try_from(p: HgoParams) -> Result<Self, EnergyError> {
        Self::new(p.c, p.k1, p.k2, p.theta)
    }
}

impl Hgo {
    /// HGO law with matrix modulus `c > 0`, fibre stiffness `k1 ≥ 0`, fibre exponent `k2 ≥ 0`
    /// and fibre angle `theta` (radians, to the line axis).
    ///
    /// ```
    /// use celltissue::Hgo;
    /// assert_eq!(Hgo::new(1.0, -0.1, 1.0, 0.0).unwrap_err().to_string(),
    ///            "k1 = -0.1 must be finite and >= 0");
    /// ```
    pub fn new(c: f64, k1: f64, k2: f64, theta: f64) -> Result<Self, EnergyError> {
        let c = positive("c", c)?;
        let k1 = non_negative("k1", k1)?;
        let k2 = non_negative("k2", k2)?;
        let theta = finite("theta", theta)?;
        let (s, co) = theta.sin_cos();
        Ok(Self {
            c,
            k1,
            k2,
            theta,
            cos2: co * co,
            sin2: s * s,
            sin_cos: s * co,
        })
    }

    /// `(c, k1, k2, theta)`.
    ///
    /// ```
    /// assert_eq!(celltissue::Hgo::new(1.0, 0.5, 2.0, 0.3).unwrap().params(), (1.0, 0.5, 2.0, 0.3));
    /// ```
    pub fn params(&self) -> (f64, f64, f64, f64) {
        (self.c, self.k1, self.k2, self.theta)
    }

    /// Fibre invariant `I₄ = λ₁² cos²θ + λ₂² sin²θ`.
    ///
    /// ```
    /// let law = celltissue::Hgo::new(1.0, 0.5, 2.0, 0.0).unwrap();
    /// assert_eq!(law.i4(2.0, 0.5), 4.0);
    /// ```
    pub fn i4<D: DualNum<Primitive = f64> + Copy>(&self, l1: D, l2: D) -> D {
        l1 * l1 * self.cos2 + l2 * l2 * self.sin2
    }

    /// Fibre energy `k₁/(2k₂)[exp(k₂E²) − 1]` for `E = I₄ − 1 > 0`, exactly zero otherwise.
    ///
    /// ```
    /// use celltissue::Hgo;
    /// let law = Hgo::new(1.0, 0.5, 2.0, 0.0).unwrap();
    /// assert_eq!(law.fibre_energy(0.9), 0.0);
    /// assert_eq!(law.fibre_energy(1.0), 0.0);
    /// assert!(law.fibre_energy(1.1) > 0.0);
    /// ```
    pub fn fibre_energy<D: DualNum<Primitive = f64> + Copy>(&self, i4: D) -> D {
        let e = i4 - 1.0;
        if e <= 0.0 || self.k1 == 0.0 {
            return D::from(0.0);
        }
        let e2 = e * e;
        if self.k2 == 0.0 {
            e2 * (0.5 * self.k1)
        } else {
            (e2 * self.k2).exp_m1() * (self.k1 / (2.0 * self.k2))
        }
    }
}

impl StrainEnergy for Hgo {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let i1 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
        (i1 - 3.0) * (0.5 * self.c) + self.fibre_energy(self.i4(l[0], l[1]))
    }

    #[inline]
    fn shear_modulus(&self) -> f64 {
        self.c
    }

    /// Simple shear `F = [[1, T, 0], [0, 1, 0], [0, 0, 1]]` turns the fibre `a = (cos θ, sin θ)`
    /// into `Fa = (cos θ + T sin θ, sin θ)`, so `I₄ = 1 + 2T sin θ cos θ + T² sin²θ` and
    /// `I₁ = 3 + T²`: `Ŵ(T) = cT²/2 + Ψ(I₄(T))`, `τ = dŴ/dT` (the principal stretches alone
    /// cannot say where the fibre points; docs/model.md §1.5).
    ///
    /// ```
    /// use celltissue::{Hgo, StrainEnergy};
    /// let law = Hgo::new(0.5, 1.0, 1.0, 0.5)?;
    /// let (t, th) = (0.4_f64, 0.5_f64);
    /// let e = 2.0 * t * th.sin() * th.cos() + (t * th.sin()).powi(2); // I₄ − 1
    /// let dedt = 2.0 * th.sin() * th.cos() + 2.0 * t * th.sin().powi(2);
    /// let tau = 0.5 * t + 1.0 * e * (e * e).exp() * dedt; // cT + Ψ'(I₄) dI₄/dT
    /// assert!((law.shear(t).tau - tau).abs() < 1e-14);
    /// // fibres pointing the other way are compressed at first: the matrix alone
    /// assert_eq!(Hgo::new(0.5, 1.0, 1.0, -0.5)?.shear(0.1).tau, 0.5 * 0.1);
    /// # Ok::<(), celltissue::EnergyError>(())
    /// ```
    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        let t = Dual2_64::from_re(t).derivative();
        let i4 = t * (2.0 * self.sin_cos) + t * t * self.sin2 + 1.0;
        let w = t * t * (0.5 * self.c) + self.fibre_energy(i4);
        ShearResponse {
            tau: w.v1,
            dtau: w.v2,
        }
    }

    /// `p = ∂W/∂F₂₂` at the shear (the extra stress `(F S Fᵀ)₂₂ = S₂₂` that `σ₂₂ = 0` balances):
    /// `c + 2Ψ'(I₄) sin²θ`.
    ///
    /// ```
    /// use celltissue::{Hgo, StrainEnergy};
    /// assert_eq!(Hgo::new(0.5, 1.0, 1.0, 0.0)?.shear_pressure(0.7), 0.5); // fibre along x₁: unstretched
    /// assert!(Hgo::new(0.5, 1.0, 1.0, 0.5)?.shear_pressure(0.7) > 0.5);
    /// # Ok::<(), celltissue::EnergyError>(())
    /// ```
    #[inline]
    fn shear_pressure(&self, t: f64) -> f64 {
        let i4 = Dual64::from_re(1.0 + 2.0 * t * self.sin_cos + t * t * self.sin2).derivative();
        self.c + 2.0 * self.fibre_energy(i4).eps * self.sin2
    }

    /// `true`: [`shear`](Self::shear) and [`shear_pressure`](Self::shear_pressure) follow the
    /// fibre through the shear.
    fn shear_is_exact(&self) -> bool {
        true
    }
}
