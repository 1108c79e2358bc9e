//! Active contractile stress (2.83)–(2.84), docs/model.md §2.3:
//! `C_a,j = A_j·b_j(t)·(1 + β/2·(λ_j − 1))`, `b_j = 1 + sin(2πωt − t_R,j)`,
//! `t_R,j = 2π X_{j−1/2}/l₀` (one wavelength around the line, wave speed `ω l₀`).

use serde::{Deserialize, Serialize};

/// Parameters of the travelling active-stress wave (per-cell amplitude and phase are held by the
/// line; see [`crate::line::Cells`]).
///
/// ```
/// use celltissue::cell::Active;
/// let a = Active { beta: -1.0, omega: 0.01 };
/// // b = 1 + sin(2π·ω·t − t_R): at t = 0 and phase 0, b = 1; C_a = b(1 + β/2(λ − 1))
/// assert_eq!(a.stress(0.0, 0.0, 1.0, 1.0), 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Active {
    /// Slope `β` of the stretch dependence (thesis −1).
    #[serde(default = "default_beta")]
    pub beta: f64,
    /// Frequency `ω` (thesis `1/l₀`).
    pub omega: f64,
}

fn default_beta() -> f64 {
    -1.0
}

impl Active {
    /// `b(t) = 1 + sin(2πωt − t_R)`.
    ///
    /// ```
    /// let a = celltissue::cell::Active { beta: -1.0, omega: 0.25 };
    /// assert!((a.b(1.0, 0.0) - 2.0).abs() < 1e-15); // 1 + sin(π/2): the peak
    /// ```
    #[inline]
    pub fn b(&self, t: f64, phase: f64) -> f64 {
        1.0 + (2.0 * std::f64::consts::PI * self.omega * t - phase).sin()
    }

    /// `C_a = amplitude·b(t)·(1 + β/2·(λ − 1))` in `f64`.
    ///
    /// ```
    /// let a = celltissue::cell::Active { beta: -1.0, omega: 0.25 };
    /// // at the peak b = 2, a cell stretched to λ = 1.2 with β = −1: C_a = 2·(1 − 0.1)
    /// assert!((a.stress(1.0, 0.0, 1.0, 1.2) - 1.8).abs() < 1e-12);
    /// ```
    #[inline]
    pub fn stress(&self, t: f64, phase: f64, amplitude: f64, lambda: f64) -> f64 {
        amplitude * self.b(t, phase) * (1.0 + 0.5 * self.beta * (lambda - 1.0))
    }
}
