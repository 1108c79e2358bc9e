//! Prescribed length of the sheet, `x_b(N, k) = l(t)` (docs/model.md §2.6, §4.1; (4.75) corrected to
//! `l₀(1 − k₁ + k₁e^{−t})`).

use serde::{Deserialize, Serialize};

/// Shape of the prescribed shortening `l(t) = l₀(1 − k₁ s(t))`.
///
/// ```
/// use celltissue::sheet::Ramp;
/// let r = Ramp::Exponential { t_ramp: 1.0 };
/// assert!((r.length(10.0, 0.1, 0.0) - 10.0).abs() < 1e-15);
/// assert!((r.length(10.0, 0.1, 1e9) - 9.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Ramp {
    /// `s(t) = 1 − e^{−t/t_ramp}` (2.80), the Chapter 4 default.
    Exponential {
        /// Ramp time `t_ramp > 0`.
        t_ramp: f64,
    },
    /// `s(τ) = 3τ² − 2τ³` for `τ = t/t_ramp ≤ 1`, then 1 (2.81).
    Polynomial {
        /// Ramp time `t_ramp > 0`.
        t_ramp: f64,
    },
}

impl Default for Ramp {
    fn default() -> Self {
        Ramp::Exponential { t_ramp: 1.0 }
    }
}

impl Ramp {
    /// The ramp time.
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// assert_eq!(Ramp::Polynomial { t_ramp: 3.0 }.t_ramp(), 3.0);
    /// ```
    pub fn t_ramp(&self) -> f64 {
        match *self {
            Ramp::Exponential { t_ramp } | Ramp::Polynomial { t_ramp } => t_ramp,
        }
    }

    /// Times where `l(t)` is not smooth, for the solver to restart at: the polynomial ramp's
    /// end `t_ramp`, where `l''` jumps.
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// assert_eq!(Ramp::Polynomial { t_ramp: 2.0 }.breakpoints(), vec![2.0]);
    /// assert!(Ramp::Exponential { t_ramp: 2.0 }.breakpoints().is_empty());
    /// ```
    pub fn breakpoints(&self) -> Vec<f64> {
        match *self {
            Ramp::Polynomial { t_ramp } => vec![t_ramp],
            Ramp::Exponential { .. } => Vec::new(),
        }
    }

    /// Fraction `s(t) ∈ [0, 1]` of the final shortening applied at time `t`.
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// let r = Ramp::Polynomial { t_ramp: 2.0 };
    /// assert_eq!((r.fraction(0.0), r.fraction(1.0), r.fraction(5.0)), (0.0, 0.5, 1.0));
    /// ```
    pub fn fraction(&self, t: f64) -> f64 {
        match *self {
            Ramp::Exponential { t_ramp } => 1.0 - (-t / t_ramp).exp(),
            Ramp::Polynomial { t_ramp } => {
                let tau = (t / t_ramp).clamp(0.0, 1.0);
                tau * tau * (3.0 - 2.0 * tau)
            }
        }
    }

    /// Rate `s'(t)` of the fraction (0 before the start and after a polynomial ramp ends).
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// let r = Ramp::Polynomial { t_ramp: 2.0 };
    /// let h = 1e-6;
    /// let fd = (r.fraction(0.7 + h) - r.fraction(0.7 - h)) / (2.0 * h);
    /// assert!((r.fraction_rate(0.7) - fd).abs() < 1e-9);
    /// assert_eq!(r.fraction_rate(3.0), 0.0);
    /// ```
    pub fn fraction_rate(&self, t: f64) -> f64 {
        match *self {
            Ramp::Exponential { t_ramp } => (-t / t_ramp).exp() / t_ramp,
            Ramp::Polynomial { t_ramp } => {
                let tau = t / t_ramp;
                if (0.0..=1.0).contains(&tau) {
                    6.0 * tau * (1.0 - tau) / t_ramp
                } else {
                    0.0
                }
            }
        }
    }

    /// `l(t) = l₀(1 − k₁ s(t))`.
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// let r = Ramp::Polynomial { t_ramp: 1.0 };
    /// assert_eq!((r.length(10.0, 0.1, 0.0), r.length(10.0, 0.1, 0.5), r.length(10.0, 0.1, 2.0)), (10.0, 9.5, 9.0));
    /// ```
    pub fn length(&self, l0: f64, k1: f64, t: f64) -> f64 {
        l0 * (1.0 - k1 * self.fraction(t))
    }

    /// `l'(t) = −l₀ k₁ s'(t)`.
    ///
    /// ```
    /// use celltissue::sheet::Ramp;
    /// // the exponential ramp starts at l' = −l₀k₁/t_ramp
    /// assert_eq!(Ramp::Exponential { t_ramp: 2.0 }.length_rate(10.0, 0.1, 0.0), -0.5);
    /// ```
    pub fn length_rate(&self, l0: f64, k1: f64, t: f64) -> f64 {
        -l0 * k1 * self.fraction_rate(t)
    }
}
