//! The scalar type the model residuals are generic over: `f64` for plain evaluation, and
//! `Dual64` (forward-mode AD) for exact directional derivatives, from which the integrators build
//! banded/sparse Jacobians by column colouring (a handful of seeds, independent of N).
//!
//! Constitutive functions evaluated in `f64` with a known derivative (e.g. `σ_el(α)` and its
//! tangent from a [`crate::StrainEnergy`]) enter a generic residual through [`Scalar::lift`], so the
//! energy's own AD (nested duals) never has to run inside the residual's AD.

use num_dual::{Dual64, DualNum};

/// A real scalar for residual evaluation: `f64` or a first-order dual number.
///
/// ```
/// use celltissue::Scalar;
/// use num_dual::Dual64;
/// // d/dx sin(x) at x = 0.5 via lift, with x carrying derivative 1
/// let x = Dual64::new(0.5, 1.0);
/// let s = x.lift(0.5f64.sin(), 0.5f64.cos());
/// assert!((s.eps - 0.5f64.cos()).abs() < 1e-15);
/// ```
pub trait Scalar: DualNum<Primitive = f64> + Copy + Send + Sync {
    /// Applies a scalar function whose value `f` and derivative `df` at `self.re()` are known.
    fn lift(self, f: f64, df: f64) -> Self;
    /// The derivative part (0 for `f64`).
    fn eps_part(&self) -> f64;
}

impl Scalar for f64 {
    #[inline]
    fn lift(self, f: f64, _df: f64) -> Self {
        f
    }
    #[inline]
    fn eps_part(&self) -> f64 {
        0.0
    }
}

impl Scalar for Dual64 {
    #[inline]
    fn lift(self, f: f64, df: f64) -> Self {
        Dual64::new(f, self.eps * df)
    }
    #[inline]
    fn eps_part(&self) -> f64 {
        self.eps
    }
}
