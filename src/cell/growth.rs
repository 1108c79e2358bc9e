//! Stress-controlled axial growth laws `ġ = G(σ)` (docs/model.md §2.7): the [`GrowthLaw`] trait and
//! the thesis's tanh law [`TanhGrowth`]. The line's residual evaluates `G` in `f64` with its
//! derivative and lifts it into the AD scalar, so any law with a derivative plugs in.

use serde::{Deserialize, Serialize};

/// A growth law: rate `ġ = G(σ)` of the axial growth stretch as a function of the cell's full
/// axial stress `σ` (elastic + viscous + active).
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
}

/// `ġ = ½ G_m (1 + tanh(σ/σ₀))` (3.15), canonical `σ₀ = 0.1`, `G_m = 1`.
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

impl GrowthLaw for TanhGrowth {
    #[inline]
    fn rate(&self, sigma: f64) -> (f64, f64) {
        let th = (sigma / self.sigma0).tanh();
        (
            0.5 * self.gm * (1.0 + th),
            0.5 * self.gm * (1.0 - th * th) / self.sigma0,
        )
    }
}
