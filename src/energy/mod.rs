//! Strain energies (docs/model.md §1): the [`StrainEnergy`] trait — a user writes only
//! `W(λ₁, λ₂, λ₃)`, generic over the scalar — and the responses the cell arrays need, derived by
//! forward-mode AD (hand-written closed forms may override them for speed):
//!
//! * [`LineResponse`]: plane-strain cell of the line (§1.2), `σ_el(a)`, `dσ_el/da`, `p_el(a)`;
//! * [`SheetResponse`]: quasi-3D uniaxial sheet cell (§1.4), `σ₁₁, σ₂₂, p` and the 2×2 tangent;
//! * [`ShearResponse`]: simple-shear cell (§1.5), `τ(T)` and `dτ/dT`.
//!
//! The AD plumbing lives in [`ad`]; its functions are public so a law with hand-written
//! overrides can still be checked against AD. Every response is allocation-free: one nested-dual
//! evaluation of `W` for the line ([`num_dual::Dual2`]`<`[`num_dual::Dual64`]`>`), one
//! [`num_dual::Dual2SVec64`]`<3>` evaluation for the sheet, one [`num_dual::Dual2_64`] for shear.
//!
//! ```
//! use celltissue::{NeoHookean, StrainEnergy};
//! let law = NeoHookean::new(1.0).unwrap();
//! let r = law.line(1.0);
//! assert_eq!(r.sigma, 0.0);
//! assert!((r.dsigma - 4.0).abs() < 1e-14); // dσ_el/da(1) = 4μ
//! ```

pub mod ad;
mod any;
mod error;
mod expression;
mod gent;
mod hgo;
mod mooney_rivlin;
mod neo_hookean;
mod ogden;
pub mod registry;
mod scaled;
#[cfg(test)]
mod tests;

pub use any::{AnyEnergy, LawVisitor};
pub use error::EnergyError;
pub use expression::{Expression, ExpressionError};
pub use gent::Gent;
pub use hgo::Hgo;
pub use mooney_rivlin::MooneyRivlin;
pub use neo_hookean::NeoHookean;
pub use ogden::Ogden;
pub use scaled::Scaled;

use num_dual::DualNum;

/// Plane-strain response of a line cell at axial stretch `a` (deformation `diag(a, 1/a, 1)`,
/// `σ₂₂ = 0`), docs/model.md §1.2.
///
/// ```
/// use celltissue::{NeoHookean, StrainEnergy};
/// let r = NeoHookean::new(2.0).unwrap().line(2.0);
/// assert!((r.sigma - 2.0 * (4.0 - 0.25)).abs() < 1e-12); // μ(a² − a⁻²)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineResponse {
    /// Axial elastic Cauchy stress `σ_el(a) = a·Ŵ'(a)` (tension positive).
    pub sigma: f64,
    /// Tangent `dσ_el/da`.
    pub dsigma: f64,
    /// Elastic pressure `p_el = a₂·W₂` at `(a, 1/a, 1)`.
    pub pressure: f64,
    /// `dp_el/da`.
    pub dpressure: f64,
}

/// Quasi-3D sheet-cell response at `(λ₁, λ₂)`, `λ₃ = 1/(λ₁λ₂)`, `σ₃₃ = 0` (docs/model.md §1.4).
///
/// ```
/// use celltissue::{NeoHookean, StrainEnergy};
/// let r = NeoHookean::new(1.0).unwrap().sheet(1.0, 1.0);
/// assert!((r.tangent[0][0] - 4.0).abs() < 1e-14 && (r.tangent[0][1] - 2.0).abs() < 1e-14);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetResponse {
    /// `σ₁₁ = λ₁ ∂₁Ŵ`.
    pub s11: f64,
    /// `σ₂₂ = λ₂ ∂₂Ŵ`.
    pub s22: f64,
    /// Pressure `p = λ₃ W₃`.
    pub pressure: f64,
    /// Tangent `∂σᵢᵢ/∂λₖ`, row `i` (0: σ₁₁, 1: σ₂₂), column `k`.
    pub tangent: [[f64; 2]; 2],
}

/// Simple-shear response at amount of shear `T = tan θ` (docs/model.md §1.5).
///
/// ```
/// use celltissue::{NeoHookean, StrainEnergy};
/// let r = NeoHookean::new(3.0).unwrap().shear(0.5);
/// assert!((r.tau - 1.5).abs() < 1e-14 && (r.dtau - 3.0).abs() < 1e-14); // τ = μT
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearResponse {
    /// Shear stress `τ = dŴ/dT`.
    pub tau: f64,
    /// `dτ/dT`.
    pub dtau: f64,
}

/// Whether the stretches `l` lie in `law`'s domain ([`StrainEnergy::admissible`]), as a bool
/// for the cell loops. The error is moved out in its own branch: where `admissible` is the
/// `Ok(())` default, nothing is left to drop and the test folds to `true`. (Dropping the
/// whole `Result` after `.is_ok()` called its drop glue once per cell wherever the glue was
/// compiled apart from the loop, which also kept the loop off vector lanes: the blocked line
/// residual took twice its instructions.)
///
/// ```
/// use celltissue::energy::{in_domain, Gent};
/// use celltissue::NeoHookean;
/// assert!(in_domain(&NeoHookean::new(1.0)?, [10.0, 0.1, 1.0]));
/// let gent = Gent::new(1.0, 2.0)?;
/// assert!(in_domain(&gent, [1.1, 1.0 / 1.1, 1.0]) && !in_domain(&gent, [3.0, 1.0 / 3.0, 1.0]));
/// # Ok::<(), celltissue::energy::EnergyError>(())
/// ```
#[inline(always)]
pub fn in_domain<E: StrainEnergy + ?Sized>(law: &E, l: [f64; 3]) -> bool {
    match law.admissible(l) {
        Ok(()) => true,
        Err(e) => {
            drop(e);
            false
        }
    }
}

/// An incompressible hyperelastic law given by its strain energy `W(λ₁, λ₂, λ₃)` in the principal
/// stretches (for fibre laws: the stretches along the cell axes).
///
/// Implement [`energy`](StrainEnergy::energy) generically over `D: DualNum<Primitive = f64>` and
/// [`shear_modulus`](StrainEnergy::shear_modulus); the responses used by the cell arrays are then
/// derived by forward-mode AD ([`ad`]). Override them with closed forms if you want speed; tests
/// check they agree with AD.
///
/// ```
/// use celltissue::StrainEnergy;
/// use num_dual::DualNum;
///
/// /// Yeoh-type law W = C₁(I₁−3) + C₂(I₁−3)², μ = 2C₁.
/// struct Yeoh { c1: f64, c2: f64 }
/// impl StrainEnergy for Yeoh {
///     fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
///         let j1 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] - 3.0;
///         j1 * self.c1 + j1 * j1 * self.c2
///     }
///     fn shear_modulus(&self) -> f64 { 2.0 * self.c1 }
/// }
/// let law = Yeoh { c1: 0.5, c2: 0.1 };
/// assert!((law.line(1.0).dsigma - 4.0 * law.shear_modulus()).abs() < 1e-12);
/// assert!((law.shear(0.0).dtau - law.shear_modulus()).abs() < 1e-12);
/// ```
pub trait StrainEnergy: Send + Sync {
    /// `W(λ₁, λ₂, λ₃)`, generic over the scalar so AD can differentiate it.
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D;

    /// Small-strain shear modulus `μ` (so `dσ_el/da(1) = 4μ` in the line).
    fn shear_modulus(&self) -> f64;

    /// Whether the principal stretches `l` lie in the law's domain: `Ok` by default; a law
    /// whose energy is finite only on part of the stretches (a locking law such as
    /// [`Gent`]) returns [`EnergyError::OutsideDomain`] naming the law and the violated bound.
    /// The cell arrays check every cell with it before evaluating a response, so a state past
    /// the lock is a named, recoverable error (the step is retried), never NaN.
    #[inline(always)]
    fn admissible(&self, _l: [f64; 3]) -> Result<(), EnergyError> {
        Ok(())
    }

    /// Plane-strain line response at axial stretch `a > 0` (AD by default, [`ad::line`]).
    #[inline]
    fn line(&self, a: f64) -> LineResponse {
        ad::line(self, a)
    }

    /// The registry's [`AnyEnergy`] when `self` is one (`None` for every other law): lets a
    /// hot loop pick the concrete law once ([`AnyEnergy::visit`]) instead of dispatching at
    /// every call.
    ///
    /// ```
    /// use celltissue::{AnyEnergy, NeoHookean, StrainEnergy};
    /// let law = NeoHookean::new(1.0).unwrap();
    /// assert!(law.as_any_energy().is_none());
    /// assert!(AnyEnergy::from(law).as_any_energy().is_some());
    /// ```
    #[inline(always)]
    fn as_any_energy(&self) -> Option<&AnyEnergy> {
        None
    }

    /// Sheet response at `(λ₁, λ₂)` (AD by default, [`ad::sheet`]).
    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        ad::sheet(self, l1, l2)
    }

    /// Simple-shear response at `T` (AD by default, [`ad::shear`], which reads `W` at the
    /// principal stretches: see [`shear_is_exact`](Self::shear_is_exact)).
    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        ad::shear(self, t)
    }

    /// Pressure of a simple-shear cell at `T`, from `σ₂₂ = 0` (by default [`ad::shear_pressure`],
    /// which reads `W` at the principal stretches).
    ///
    /// ```
    /// use celltissue::{NeoHookean, StrainEnergy};
    /// assert!((NeoHookean::new(1.5).unwrap().shear_pressure(0.7) - 1.5).abs() < 1e-12); // p = μ
    /// ```
    #[inline]
    fn shear_pressure(&self, t: f64) -> f64 {
        ad::shear_pressure(self, t)
    }

    /// Whether [`shear`](Self::shear) and [`shear_pressure`](Self::shear_pressure) describe
    /// this law (docs/model.md §1.5). Their defaults read `W` at the principal stretches of the
    /// shear, `W(λ₊, λ₋, 1)`, which holds for a law of the principal stretches alone. Simple
    /// shear turns the principal axes away from the cell's axes, so a law that reads its
    /// stretches along those axes (a material direction: HGO's fibres, a formula not symmetric
    /// in `l1` and `l2`) gets a wrong shear response from them: such a law overrides both with
    /// its own (as [`Hgo`] does) or answers `false`, and the shear column then refuses it. The
    /// default answers whether `W` is symmetric in its in-plane stretches
    /// ([`ad::symmetric_in_plane`]).
    ///
    /// ```
    /// use celltissue::energy::Expression;
    /// use celltissue::{Hgo, NeoHookean, StrainEnergy};
    /// assert!(NeoHookean::new(1.0)?.shear_is_exact());
    /// assert!(Hgo::new(0.5, 1.0, 1.0, 0.5)?.shear_is_exact()); // its own shear response
    /// let axial = Expression::new("mu/2*(I1 - 3) + k*(l1 - 1)^2", [("mu", 1.0), ("k", 2.0)])?;
    /// assert!(!axial.shear_is_exact());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn shear_is_exact(&self) -> bool {
        ad::symmetric_in_plane(self)
    }
}

impl<E: StrainEnergy + ?Sized> StrainEnergy for &E {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        (**self).energy(l)
    }
    #[inline]
    fn shear_modulus(&self) -> f64 {
        (**self).shear_modulus()
    }
    #[inline(always)]
    fn admissible(&self, l: [f64; 3]) -> Result<(), EnergyError> {
        (**self).admissible(l)
    }
    #[inline]
    fn line(&self, a: f64) -> LineResponse {
        (**self).line(a)
    }
    #[inline(always)]
    fn as_any_energy(&self) -> Option<&AnyEnergy> {
        (**self).as_any_energy()
    }
    #[inline]
    fn sheet(&self, l1: f64, l2: f64) -> SheetResponse {
        (**self).sheet(l1, l2)
    }
    #[inline]
    fn shear(&self, t: f64) -> ShearResponse {
        (**self).shear(t)
    }
    #[inline]
    fn shear_pressure(&self, t: f64) -> f64 {
        (**self).shear_pressure(t)
    }
    fn shear_is_exact(&self) -> bool {
        (**self).shear_is_exact()
    }
}
