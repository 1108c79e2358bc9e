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

    /// [`lift`](Self::lift) of a function known as its value alone (`value(x)`) and as value
    /// with derivative (`both(x)`), at `x = self.re()`: `f64` calls only `value`, so a residual
    /// evaluated in `f64` never computes the derivative it would drop; a dual number calls
    /// `both`.
    ///
    /// ```
    /// use celltissue::Scalar;
    /// use num_dual::Dual64;
    /// let sin = |x: f64| x.sin();
    /// let sin_cos = |x: f64| (x.sin(), x.cos());
    /// assert_eq!(0.5f64.lift_fn(sin, sin_cos), 0.5f64.sin());
    /// let d = Dual64::new(0.5, 2.0).lift_fn(sin, sin_cos);
    /// assert_eq!((d.re, d.eps), (0.5f64.sin(), 2.0 * 0.5f64.cos()));
    /// ```
    #[inline(always)]
    fn lift_fn(
        self,
        _value: impl FnOnce(f64) -> f64,
        both: impl FnOnce(f64) -> (f64, f64),
    ) -> Self {
        let (f, df) = both(self.re());
        self.lift(f, df)
    }

    /// The values as `f64`s when the scalar is `f64` itself (`None` for dual numbers): lets a
    /// sweep written generically take an `f64`-only fast path.
    ///
    /// ```
    /// use celltissue::Scalar;
    /// use num_dual::Dual64;
    /// assert_eq!(f64::as_f64s(&[1.0, 2.0]), Some(&[1.0, 2.0][..]));
    /// assert!(Dual64::as_f64s(&[Dual64::new(1.0, 0.0)]).is_none());
    /// ```
    #[inline(always)]
    fn as_f64s(xs: &[Self]) -> Option<&[f64]> {
        let _ = xs;
        None
    }

    /// [`as_f64s`](Self::as_f64s) for a slice written to.
    #[inline(always)]
    fn as_f64s_mut(xs: &mut [Self]) -> Option<&mut [f64]> {
        let _ = xs;
        None
    }
}

impl Scalar for f64 {
    #[inline(always)]
    fn as_f64s(xs: &[Self]) -> Option<&[f64]> {
        Some(xs)
    }
    #[inline(always)]
    fn as_f64s_mut(xs: &mut [Self]) -> Option<&mut [f64]> {
        Some(xs)
    }
    #[inline]
    fn lift(self, f: f64, _df: f64) -> Self {
        f
    }
    #[inline]
    fn eps_part(&self) -> f64 {
        0.0
    }
    #[inline(always)]
    fn lift_fn(
        self,
        value: impl FnOnce(f64) -> f64,
        _both: impl FnOnce(f64) -> (f64, f64),
    ) -> Self {
        value(self)
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
