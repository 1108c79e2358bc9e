//! Stress-controlled axial growth laws `ġ = G(σ)` (docs/model.md §2.7): a law is written once,
//! generic over the scalar ([`GrowthRate`]), and its derivative comes from forward-mode AD
//! through the object-safe [`GrowthLaw`] the line holds (`Arc<dyn GrowthLaw>`); the thesis's
//! tanh law is [`TanhGrowth`]. The line's residual evaluates `(G, G')` in `f64` and lifts them
//! into its own scalar.

use crate::registry::{positive, ParamError};
use num_dual::{Dual64, DualNum};
use serde::{Deserialize, Serialize};

/// A growth law `ġ = G(σ)` written generically over the scalar: implement this and the line
/// gets `(G, dG/dσ)` by forward-mode AD ([`GrowthLaw`] is implemented for every
/// `GrowthRate`).
///
/// ```
/// use celltissue::cell::{GrowthLaw, GrowthRate};
/// use num_dual::DualNum;
/// /// Linear growth above a threshold stress, smoothed: G = softplus(σ − σ_c).
/// struct Softplus { sigma_c: f64 }
/// impl GrowthRate for Softplus {
///     fn growth_rate<D: DualNum<Primitive = f64> + Copy>(&self, sigma: D) -> D {
///         ((sigma - self.sigma_c).exp() + 1.0).ln()
///     }
/// }
/// let (g, dg) = Softplus { sigma_c: 0.0 }.rate(0.0);
/// assert!((g - 2f64.ln()).abs() < 1e-15 && (dg - 0.5).abs() < 1e-15);
/// ```
pub trait GrowthRate: Send + Sync {
    /// `G(σ)`, generic over the scalar so AD can differentiate it.
    fn growth_rate<D: DualNum<Primitive = f64> + Copy>(&self, sigma: D) -> D;

    /// Checks the law's parameters when a scenario builds it by name (default: nothing to
    /// check); the error names the parameter and its valid range.
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }
}

impl<T: GrowthRate> GrowthLaw for T {
    #[inline]
    fn rate(&self, sigma: f64) -> (f64, f64) {
        let g = self.growth_rate(Dual64::new(sigma, 1.0));
        (g.re, g.eps)
    }
    #[inline]
    fn value(&self, sigma: f64) -> f64 {
        self.growth_rate(sigma)
    }
    fn check(&self) -> Result<(), ParamError> {
        GrowthRate::check(self)
    }
}

/// A growth law as the line uses it (object-safe): rate `ġ = G(σ)` of the axial growth stretch
/// as a function of the cell's full axial stress `σ` (elastic + viscous + active), with its
/// derivative. Implemented by AD for every [`GrowthRate`]; implement it directly only for a
/// hand-written derivative.
///
/// ```
/// use celltissue::cell::{GrowthLaw, TanhGrowth};
/// let law = TanhGrowth::default(); // σ₀ = 0.1, G_m = 1
/// let (rate, _) = law.rate(0.0);
/// assert_eq!(rate, 0.5); // an unstressed cell grows at G_m/2
/// ```
pub trait GrowthLaw: Send + Sync {
    /// `(G(σ), dG/dσ)`.
    fn rate(&self, sigma: f64) -> (f64, f64);

    /// `G(σ)` alone, bitwise `rate(σ).0` (the default calls [`rate`](Self::rate)): a residual
    /// evaluated in `f64` needs no slope, so a law whose slope costs extra work (a division,
    /// an AD pass) overrides this.
    ///
    /// ```
    /// use celltissue::cell::{GrowthLaw, TanhGrowth};
    /// let law = TanhGrowth::default();
    /// assert_eq!(law.value(-0.05), law.rate(-0.05).0);
    /// ```
    #[inline]
    fn value(&self, sigma: f64) -> f64 {
        self.rate(sigma).0
    }

    /// [`value`](Self::value) of every `sigma[i]` into `out[i]` (the default calls it per
    /// entry; the slices have equal lengths). A dividing line's `f64` residual hands its
    /// growth rows to the law in blocks through this, one dynamic call per block instead of
    /// one per cell, so a law that overrides it with the same expression in an inlined loop
    /// lets the compiler overlap cells (measured on the tanh law: 6.8 ns per cell called
    /// through `&dyn GrowthLaw`, 4.9 ns in such a loop, of which `exp` 4.6 ns).
    ///
    /// ```
    /// use celltissue::cell::{GrowthLaw, TanhGrowth};
    /// let law = TanhGrowth::default();
    /// let sigma = [-0.3, 0.0, 0.05];
    /// let mut g = [0.0; 3];
    /// law.values(&sigma, &mut g);
    /// assert!(sigma.iter().zip(&g).all(|(&s, &v)| v == law.value(s)));
    /// ```
    fn values(&self, sigma: &[f64], out: &mut [f64]) {
        for (o, &s) in out.iter_mut().zip(sigma) {
            *o = self.value(s);
        }
    }

    /// Checks the law's parameters when a scenario builds it by name (default: nothing to
    /// check); the error names the parameter and its valid range.
    fn check(&self) -> Result<(), ParamError> {
        Ok(())
    }
}

/// `G(σ)` in the residual's scalar: for `f64` the law's value alone, for a dual number its
/// value and slope ([`crate::Scalar::lift_fn`]); the line's and the sheet's growth rows call
/// this.
#[inline(always)]
pub(crate) fn growth_at<S: crate::Scalar>(law: &dyn GrowthLaw, sigma: S) -> S {
    sigma.lift_fn(|s| law.value(s), |s| law.rate(s))
}

/// `ġ = ½ G_m (1 + tanh(σ/σ₀))` (3.15), canonical `σ₀ = 0.1`, `G_m = 1`.
///
/// ```
/// use celltissue::cell::{GrowthLaw, TanhGrowth};
/// let g = TanhGrowth::default();
/// let (rate, slope) = g.rate(0.0);
/// assert_eq!(rate, 0.5); // half the maximum rate when unstressed
/// assert!((slope - 5.0).abs() < 1e-12); // G_m / (2σ₀)
/// assert!(g.rate(-1.0).0 < 1e-8); // compression stops growth
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TanhGrowth {
    /// Stress scale `σ₀ > 0`.
    #[serde(default = "default_sigma0")]
    pub sigma0: f64,
    /// Maximum growth rate `G_m > 0` (1 in the dimensionless model).
    #[serde(default = "default_gm")]
    pub gm: f64,
}

fn default_sigma0() -> f64 {
    0.1
}
fn default_gm() -> f64 {
    1.0
}

impl Default for TanhGrowth {
    fn default() -> Self {
        Self {
            sigma0: 0.1,
            gm: 1.0,
        }
    }
}

/// Written by hand rather than through [`GrowthRate`]'s AD: it is called for every growing cell
/// in every residual and Jacobian of a dividing line. In logistic form, `½ (1 + tanh s) =
/// 1/(1 + e^{−2s})`, with `e = e^{−2|s|} ≤ 1` (so nothing overflows) the rate is `G_m q` or
/// `G_m e q` with `q = 1/(1 + e)`, and the slope `2 G_m e q²/σ₀` has no cancellation: one `exp`
/// instead of `tanh` (an `expm1` and a division in the C library). The test below checks it
/// against AD of the tanh form.
impl TanhGrowth {
    /// `(½(1 + tanh s), e, q)` at `s = σ/σ₀` in the logistic form above (`e = e^{−2|s|}`,
    /// `q = 1/(1 + e)`), shared by the rate and its slope.
    #[inline(always)]
    fn logistic(&self, sigma: f64) -> (f64, f64, f64) {
        let s = sigma / self.sigma0;
        let e = (-2.0 * s.abs()).exp();
        let q = 1.0 / (1.0 + e);
        // (NaN takes the second branch and stays NaN)
        (if s >= 0.0 { q } else { e * q }, e, q)
    }
}

impl GrowthLaw for TanhGrowth {
    #[inline]
    fn rate(&self, sigma: f64) -> (f64, f64) {
        let (g, e, q) = self.logistic(sigma);
        (self.gm * g, 2.0 * self.gm * e * q * q / self.sigma0)
    }
    /// `rate(σ).0` by the same operations, without the slope's division (measured: the slope
    /// was a quarter of this law's cost in a dividing line's residual).
    #[inline]
    fn value(&self, sigma: f64) -> f64 {
        self.gm * self.logistic(sigma).0
    }
    /// [`value`](GrowthLaw::value)'s expression in a loop the compiler sees whole.
    fn values(&self, sigma: &[f64], out: &mut [f64]) {
        for (o, &s) in out.iter_mut().zip(sigma) {
            *o = self.gm * self.logistic(s).0;
        }
    }
    fn check(&self) -> Result<(), ParamError> {
        positive("sigma0", self.sigma0)?;
        positive("gm", self.gm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same law through AD, to check the hand-written derivative.
    struct TanhByAd(TanhGrowth);
    impl GrowthRate for TanhByAd {
        fn growth_rate<D: DualNum<Primitive = f64> + Copy>(&self, sigma: D) -> D {
            ((sigma / self.0.sigma0).tanh() + 1.0) * (0.5 * self.0.gm)
        }
    }

    #[test]
    fn the_closed_form_tanh_law_is_its_ad_value_and_slope() {
        let law = TanhGrowth {
            sigma0: 0.3,
            gm: 1.7,
        };
        for s in [-40.0, -2.0, -0.1, 0.0, 0.05, 1.0, 40.0] {
            let (g, dg) = law.rate(s);
            let (g_ad, dg_ad) = TanhByAd(law).rate(s);
            assert!((g - g_ad).abs() <= 1e-15, "{s}: {g} vs {g_ad}");
            assert!(
                (dg - dg_ad).abs() <= 1e-14 * dg_ad.abs().max(1.0),
                "{s}: {dg} vs {dg_ad}"
            );
            // and the closed form itself
            let th = (s / 0.3f64).tanh();
            assert!((g - 0.85 * (1.0 + th)).abs() < 1e-15);
        }
        // the value alone is bitwise the rate's
        for s in [
            -40.0,
            -2.0,
            -0.1,
            -1e-300,
            0.0,
            0.05,
            1.0,
            40.0,
            f64::INFINITY,
        ] {
            assert_eq!(law.value(s).to_bits(), law.rate(s).0.to_bits(), "{s}");
        }
        assert!(law.value(f64::NAN).is_nan());
        // far out it saturates without overflow, and NaN stays NaN
        assert_eq!(law.rate(-1e300), (0.0, 0.0));
        assert_eq!(law.rate(1e300), (1.7, 0.0));
        let (g, dg) = law.rate(f64::NAN);
        assert!(g.is_nan() && dg.is_nan());
    }
}
