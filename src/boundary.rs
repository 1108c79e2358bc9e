//! Boundary conditions of the line (docs/model.md §2.6): the left end is a wall `x₀ = 0` (or, on a
//! ring, free); the right end is one of [`RightEnd`]: prescribed length `l(t)` (a [`Ramp`]:
//! exponential (2.80), polynomial (2.81), constant, or any closure giving `l` and `l̇`), free with
//! an optional applied force `F_ext(t)`, or periodic (`x_N = x₀ + l₀`).

use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::Arc;

/// A user-supplied function of time returning `(value, d value/dt)`.
pub type TimeFn = Arc<dyn Fn(f64) -> (f64, f64) + Send + Sync>;

/// A prescribed length `l(t)` with its rate `l̇(t)`.
///
/// ```
/// use celltissue::boundary::Ramp;
/// let r = Ramp::Exponential { l0: 100.0, k1: 0.1, t_ramp: 1.0 };
/// let (l, ld) = r.eval(0.0);
/// assert_eq!(l, 100.0);
/// assert!((ld + 10.0).abs() < 1e-12);
/// let p = Ramp::Polynomial { l0: 100.0, k1: 0.1, t_ramp: 1.0 };
/// assert!((p.eval(2.0).0 - 90.0).abs() < 1e-12);
/// ```
#[derive(Clone)]
pub enum Ramp {
    /// `l = l₀(1 − k₁ + k₁ e^{−t/t_ramp})` (2.80).
    Exponential {
        /// Initial length.
        l0: f64,
        /// Fractional shortening.
        k1: f64,
        /// Ramp time.
        t_ramp: f64,
    },
    /// `l = l₀(1 − k₁ s(t/t_ramp))`, `s(τ) = 3τ² − 2τ³` for `τ ≤ 1`, 1 after (2.81).
    Polynomial {
        /// Initial length.
        l0: f64,
        /// Fractional shortening.
        k1: f64,
        /// Ramp time.
        t_ramp: f64,
    },
    /// Fixed length.
    Constant(f64),
    /// Any `t ↦ (l, l̇)`.
    Custom(TimeFn),
}

impl fmt::Debug for Ramp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ramp::Exponential { l0, k1, t_ramp } => {
                write!(f, "Exponential {{ l0: {l0}, k1: {k1}, t_ramp: {t_ramp} }}")
            }
            Ramp::Polynomial { l0, k1, t_ramp } => {
                write!(f, "Polynomial {{ l0: {l0}, k1: {k1}, t_ramp: {t_ramp} }}")
            }
            Ramp::Constant(l) => write!(f, "Constant({l})"),
            Ramp::Custom(_) => write!(f, "Custom"),
        }
    }
}

impl Ramp {
    /// Times where `l` is not smooth (the polynomial ramp's end, where `l̈` jumps). Integrators
    /// must not step across them: [`crate::line::run::integrate`] restarts there.
    ///
    /// ```
    /// use celltissue::boundary::Ramp;
    /// let poly = Ramp::Polynomial { l0: 10.0, k1: 0.1, t_ramp: 2.0 };
    /// assert_eq!(poly.breakpoints(), [2.0]); // l̈ jumps where the ramp ends
    /// assert!(Ramp::Exponential { l0: 10.0, k1: 0.1, t_ramp: 2.0 }.breakpoints().is_empty());
    /// ```
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            Ramp::Polynomial { t_ramp, .. } => vec![*t_ramp],
            _ => Vec::new(),
        }
    }

    /// `(l(t), l̇(t))`.
    ///
    /// ```
    /// use celltissue::boundary::Ramp;
    /// // (2.80): l = l₀(1 − k₁ + k₁e^{−t/t_r}), l̇ = −l₀k₁e^{−t/t_r}/t_r
    /// let (l, v) = Ramp::Exponential { l0: 10.0, k1: 0.1, t_ramp: 1.0 }.eval(0.0);
    /// assert_eq!((l, v), (10.0, -1.0));
    /// assert_eq!(Ramp::Constant(7.0).eval(3.0), (7.0, 0.0));
    /// ```
    #[inline]
    pub fn eval(&self, t: f64) -> (f64, f64) {
        match self {
            Ramp::Exponential { l0, k1, t_ramp } => {
                let e = (-t / t_ramp).exp();
                (l0 * (1.0 - k1 + k1 * e), -l0 * k1 * e / t_ramp)
            }
            Ramp::Polynomial { l0, k1, t_ramp } => {
                let tau = t / t_ramp;
                if tau >= 1.0 {
                    (l0 * (1.0 - k1), 0.0)
                } else if tau <= 0.0 {
                    (*l0, 0.0)
                } else {
                    let s = 3.0 * tau * tau - 2.0 * tau * tau * tau;
                    let ds = (6.0 * tau - 6.0 * tau * tau) / t_ramp;
                    (l0 * (1.0 - k1 * s), -l0 * k1 * ds)
                }
            }
            Ramp::Constant(l) => (*l, 0.0),
            Ramp::Custom(f) => f(t),
        }
    }
}

/// The ramp shape named in a scenario.
///
/// ```
/// use celltissue::boundary::RampKind;
/// use celltissue::line::LineConfig;
/// let cfg: LineConfig = toml::from_str("ramp = \"polynomial\"\nk1 = 0.1")?;
/// assert_eq!(cfg.ramp, RampKind::Polynomial);
/// // (2.81) reaches l = (1 − k₁) l₀ at t_ramp and stays there
/// let (l, v) = cfg.ramp().eval(5.0);
/// assert!((l - 90.0).abs() < 1e-12 && v.abs() < 1e-12);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RampKind {
    /// (2.80).
    #[default]
    Exponential,
    /// (2.81).
    Polynomial,
}

/// The right-end condition (the left end is a wall except on a ring).
///
/// ```
/// use celltissue::boundary::{Ramp, RightEnd};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::NeoHookean;
/// let mut p = LineParams::unit_cells(10);
/// p.right = RightEnd::Prescribed(Ramp::Constant(9.0)); // held 10 % short
/// let held = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// p.right = RightEnd::Free(None); // free: one more unknown, the end's position
/// let free = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// assert_eq!(free.initial_state().len(), held.initial_state().len() + 1);
/// ```
#[derive(Clone)]
pub enum RightEnd {
    /// `x_N = l(t)`; the holding force `W_N σ_N` is reported.
    Prescribed(Ramp),
    /// Boundary `N` moves by drag against `F_ext(t) − W_N σ_N` (`None`: no applied force).
    Free(Option<TimeFn>),
    /// Ring: `x_N ≡ x₀ + l₀`, `x₀` free. With `gauge`, `x₀ = 0` is pinned (needed when `K = 0`).
    Periodic {
        /// Pin `x₀ = 0`.
        gauge: bool,
    },
}

impl fmt::Debug for RightEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RightEnd::Prescribed(r) => write!(f, "Prescribed({r:?})"),
            RightEnd::Free(force) => write!(
                f,
                "Free({})",
                if force.is_some() { "F_ext" } else { "no force" }
            ),
            RightEnd::Periodic { gauge } => write!(f, "Periodic {{ gauge: {gauge} }}"),
        }
    }
}

impl RightEnd {
    /// Whether the line is a ring.
    ///
    /// ```
    /// use celltissue::boundary::{Ramp, RightEnd};
    /// assert!(RightEnd::Periodic { gauge: false }.is_periodic());
    /// assert!(!RightEnd::Prescribed(Ramp::Constant(1.0)).is_periodic());
    /// ```
    pub fn is_periodic(&self) -> bool {
        matches!(self, RightEnd::Periodic { .. })
    }
    /// Whether boundary `N` is an unknown.
    ///
    /// ```
    /// use celltissue::boundary::{Ramp, RightEnd};
    /// assert!(RightEnd::Free(None).is_free());
    /// assert!(!RightEnd::Prescribed(Ramp::Constant(1.0)).is_free());
    /// ```
    pub fn is_free(&self) -> bool {
        matches!(self, RightEnd::Free(_))
    }
}
