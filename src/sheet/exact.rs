//! Exact solutions for Chapter 4 (docs/model.md §4.3, §4.6).
//!
//! * [`sheet_free_steady`] / [`sheet_periodic_steady`] — the steady states of the uniaxial sheet
//!   (uniform law): `λ₁ = 1 − k₁` in every cell (`σ₁₁` uniform and monotone in `λ₁`); free top:
//!   `σ₂₂(λ₁, λ₂) = 0` fixes `λ₂` (for neo-Hookean `λ₂ = λ₃ = (1 − k₁)^{−1/2}`); periodic:
//!   `λ₂ ≡ 1`.
//! * [`shear_series`] — the continuum series solution of the shear column;
//!   [`shear_series_viscous`] with Kelvin–Voigt cells.
//! * [`ShearDiscreteExact`] — the exact solution of the discrete edge form (neo-Hookean, linear),
//!   elastic or Kelvin–Voigt ([`ShearDiscreteExact::with_viscosity`]).

use crate::energy::StrainEnergy;
use std::f64::consts::PI;

/// A homogeneous sheet state.
///
/// ```
/// use celltissue::sheet::exact::sheet_periodic_steady;
/// // a periodic sheet 10 % shorter: λ₂ = 1 (held by periodicity), λ₃ = 1/0.9
/// let s = sheet_periodic_steady(&celltissue::NeoHookean::new(1.0).unwrap(), 0.1).unwrap();
/// assert!((s.stretch[0] - 0.9).abs() < 1e-12 && (s.stretch[1] - 1.0).abs() < 1e-12);
/// assert!((s.pressure - 1.0 / 0.81).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetSteady {
    /// `λ₁, λ₂, λ₃`.
    pub stretch: [f64; 3],
    /// Pressure `p = λ₃W₃`.
    pub pressure: f64,
    /// `σ₁₁` (uniform).
    pub s11: f64,
    /// `σ₂₂` (zero for a free top).
    pub s22: f64,
}

/// Why an exact solution could not be computed.
///
/// ```
/// use celltissue::sheet::exact::{sheet_free_steady, ExactError};
/// use celltissue::Gent;
/// // a Gent cell locks at I₁ − 3 = J_m: halved in length, the free top's root
/// // λ₂ = λ₃ = √2 has I₁ − 3 = 1.25 > J_m = 0.5, so no admissible state exists
/// let e = sheet_free_steady(&Gent::new(1.0, 0.5)?, 0.5).unwrap_err();
/// assert!(matches!(e, ExactError::Inadmissible { .. }), "{e}");
/// // a quarter shorter it is admissible: I₁ − 3 = 0.56 + 2/0.75 − 3 = 0.23
/// assert!(sheet_free_steady(&Gent::new(1.0, 0.5)?, 0.25).is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExactError {
    /// Newton's method for `σ₂₂(λ₁, λ₂) = 0` did not converge.
    #[error("no root of sigma22(lambda1 = {lambda1}, lambda2) = 0 found")]
    NoRoot {
        /// The given `λ₁`.
        lambda1: f64,
    },
    /// The state is outside the law's domain (a locking law past its lock): no admissible
    /// steady state exists.
    #[error("the steady stretches {stretch:?} are outside the law's domain: {reason}")]
    Inadmissible {
        /// The stretches `λ₁, λ₂, λ₃`.
        stretch: [f64; 3],
        /// The law's reason.
        reason: String,
    },
}

/// The homogeneous state at `(λ₁, λ₂)`, if the law admits it.
fn steady(law: &impl StrainEnergy, l1: f64, l2: f64) -> Result<SheetSteady, ExactError> {
    let stretch = [l1, l2, 1.0 / (l1 * l2)];
    law.admissible(stretch)
        .map_err(|e| ExactError::Inadmissible {
            stretch,
            reason: e.to_string(),
        })?;
    let r = law.sheet(l1, l2);
    Ok(SheetSteady {
        stretch,
        pressure: r.pressure,
        s11: r.s11,
        s22: r.s22,
    })
}

/// Steady state of the free-top sheet at final shortening `k₁`: `λ₁ = 1 − k₁`, `λ₂` from
/// `σ₂₂ = 0` by a safeguarded Newton iteration.
///
/// ```
/// use celltissue::sheet::exact::sheet_free_steady;
/// use celltissue::NeoHookean;
/// let s = sheet_free_steady(&NeoHookean::new(1.0).unwrap(), 0.1).unwrap();
/// assert!((s.stretch[1] - 0.9f64.powf(-0.5)).abs() < 1e-12);
/// assert!((s.pressure - 1.0 / 0.9).abs() < 1e-12);
/// ```
pub fn sheet_free_steady(law: &impl StrainEnergy, k1: f64) -> Result<SheetSteady, ExactError> {
    let l1 = 1.0 - k1;
    let mut l2 = l1.powf(-0.5);
    for _ in 0..100 {
        let r = law.sheet(l1, l2);
        let d = r.tangent[1][1];
        if !(d.is_finite() && d != 0.0) {
            break;
        }
        let mut step = r.s22 / d;
        // keep λ₂ positive
        while l2 - step <= 0.0 {
            step *= 0.5;
        }
        l2 -= step;
        if step.abs() <= 1e-15 * l2 {
            return steady(law, l1, l2);
        }
    }
    let s = steady(law, l1, l2)?;
    if s.s22.abs() < 1e-13 {
        Ok(s)
    } else {
        Err(ExactError::NoRoot { lambda1: l1 })
    }
}

/// Steady state of the sheet with a periodic side: `λ₁ = 1 − k₁`, `λ₂ = 1` (an error if the law
/// does not admit it).
///
/// ```
/// use celltissue::sheet::exact::sheet_periodic_steady;
/// let s = sheet_periodic_steady(&celltissue::NeoHookean::new(1.0)?, 0.5)?;
/// assert_eq!(s.stretch[0], 0.5);
/// assert!((s.stretch[2] - 2.0).abs() < 1e-12 && (s.pressure - 4.0).abs() < 1e-12); // λ₃ = 2, p = 4
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sheet_periodic_steady(law: &impl StrainEnergy, k1: f64) -> Result<SheetSteady, ExactError> {
    steady(law, 1.0 - k1, 1.0)
}

/// Continuum series solution of the shear column (docs/model.md §4.6), uniform `μ`:
/// returns `(x(y, t), tan θ = x_y(y, t))` for `K x_t = β₀γ₀μ x_yy` on `(0, w)`, `x(0) = 0`,
/// `β₀μ x_y(w) = F_A`, `x(y, 0) = 0`, with `s = F_A/(β₀μ)` and `D = β₀γ₀μ/K`. Pass `w = w₀ = Mγ₀`
/// for the continuum, or `w_eff = (M + ½)γ₀` to mimic the discrete column's lumped top drag.
/// `terms` modes are summed (the `x` series converges like `j⁻³`; `tan θ` like `j⁻²` only at
/// `t = 0`).
///
/// ```
/// use celltissue::sheet::exact::shear_series;
/// let (x, tan) = shear_series(1.0, 2.0, 10.0, 10.0, 1e6, 50);
/// assert!((x - 10.0).abs() < 1e-9 && (tan - 1.0).abs() < 1e-9);
/// ```
pub fn shear_series(s: f64, d: f64, w: f64, y: f64, t: f64, terms: usize) -> (f64, f64) {
    shear_series_viscous(s, d, 0.0, w, y, t, terms)
}

/// [`shear_series`] for Kelvin–Voigt cells, `τ = μ x_y + (η/2) x_yt`:
/// `K x_t = β₀γ₀ (μ x_yy + (η/2) x_yyt)`. The top condition `β₀τ(w) = F_A` and the modes
/// `sin(k_j y)`, `k_j = (2j+1)π/(2w)`, are the elastic ones; mode `j` decays at
/// `D k_j²/(1 + E k_j²)` with `E = β₀γ₀η/(2K)`, so the fast modes are held back to the rate
/// `D/E = 2μ/η` (the line's `1/t_k`). `E = 0` is the elastic column.
///
/// ```
/// use celltissue::sheet::exact::{shear_series, shear_series_viscous};
/// // viscosity slows the approach to the steady shear s·y …
/// let (elastic, _) = shear_series(1.0, 2.0, 10.0, 10.0, 5.0, 400);
/// let (viscous, _) = shear_series_viscous(1.0, 2.0, 3.0, 10.0, 10.0, 5.0, 400);
/// assert!(viscous < elastic && elastic < 10.0);
/// // … but not the steady state itself
/// let (late, _) = shear_series_viscous(1.0, 2.0, 3.0, 10.0, 10.0, 1e6, 400);
/// assert!((late - 10.0).abs() < 1e-9);
/// ```
pub fn shear_series_viscous(
    s: f64,
    d: f64,
    e: f64,
    w: f64,
    y: f64,
    t: f64,
    terms: usize,
) -> (f64, f64) {
    let mut x = s * y;
    let mut tan = s;
    for j in 0..terms {
        let kj = (2 * j + 1) as f64 * PI / (2.0 * w);
        let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
        let k2 = kj * kj;
        let decay = (-d * k2 / (1.0 + e * k2) * t).exp();
        x -= 2.0 * s / w * sign / k2 * (kj * y).sin() * decay;
        tan -= 2.0 * s / w * sign / kj * (kj * y).cos() * decay;
    }
    (x, tan)
}

/// Exact solution of the discrete edge form with a linear law `τ = μT` (docs/model.md §4.6):
/// `x_{e,k}(t) = δk + Σ_j b_j sin(q_j k) e^{−r_j t}`, `q_j = (2j+1)π/(2M+1)`,
/// `r_j = 4c sin²(q_j/2)`, `c = β₀μ/(γ₀K)`, `δ = γ₀ F_A/(β₀μ)`. With Kelvin–Voigt cells
/// ([`with_viscosity`](Self::with_viscosity)) the modes are the same and
/// `r_j = 4c s_j²/(1 + 4v s_j²)`, `s_j = sin(q_j/2)`, `v = β₀η/(2γ₀K)`.
///
/// ```
/// use celltissue::sheet::exact::ShearDiscreteExact;
/// let ex = ShearDiscreteExact::new(10, 1.0, 1.0, 1.0, 0.5, 1.0);
/// let x0 = ex.edges(0.0);
/// assert!(x0.iter().all(|v| v.abs() < 1e-12));
/// // viscous cells lag behind the elastic ones at the top edge
/// let slow = ex.clone().with_viscosity(2.0);
/// assert!(slow.edges(1.0)[9] < ex.edges(1.0)[9]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ShearDiscreteExact {
    m: usize,
    delta: f64,
    c: f64,
    /// `β₀η/(2γ₀K)` (0 for elastic cells).
    v: f64,
    beta0: f64,
    gamma0: f64,
    drag: f64,
    q: Vec<f64>,
    b: Vec<f64>,
}

impl ShearDiscreteExact {
    /// `M` cells, `γ₀`, `β₀`, `μ`, edge drag `K`, force `F_A`.
    ///
    /// ```
    /// use celltissue::sheet::exact::ShearDiscreteExact;
    /// // M = 4, F_A = β₀μ: the column tends to tan θ = 1 in every cell, the top at x = 4
    /// let ex = ShearDiscreteExact::new(4, 1.0, 1.0, 1.0, 0.5, 1.0);
    /// let late = ex.edges(1e3);
    /// assert!((late[3] - 4.0).abs() < 1e-12);
    /// ```
    pub fn new(m: usize, gamma0: f64, beta0: f64, mu: f64, drag: f64, force: f64) -> Self {
        let delta = gamma0 * force / (beta0 * mu);
        let c = beta0 * mu / (gamma0 * drag);
        let q: Vec<f64> = (0..m)
            .map(|j| (2 * j + 1) as f64 * PI / (2 * m + 1) as f64)
            .collect();
        let b = q
            .iter()
            .map(|&qj| {
                let s: f64 = (1..=m).map(|k| k as f64 * (qj * k as f64).sin()).sum();
                -4.0 * delta / (2 * m + 1) as f64 * s
            })
            .collect();
        Self {
            m,
            delta,
            c,
            v: 0.0,
            beta0,
            gamma0,
            drag,
            q,
            b,
        }
    }

    /// The same column with Kelvin–Voigt cells of viscosity `η` (`τ = μT + (η/2)Ṫ`).
    ///
    /// ```
    /// use celltissue::sheet::exact::ShearDiscreteExact;
    /// let elastic = ShearDiscreteExact::new(4, 1.0, 1.0, 1.0, 0.5, 1.0);
    /// let viscous = elastic.clone().with_viscosity(0.0);
    /// assert_eq!(elastic.edges(2.0), viscous.edges(2.0)); // η = 0 is the elastic column
    /// ```
    pub fn with_viscosity(mut self, eta: f64) -> Self {
        self.v = self.beta0 * eta / (2.0 * self.gamma0 * self.drag);
        self
    }

    /// Edge positions `x_{e,1..M}` at time `t`.
    ///
    /// ```
    /// use celltissue::sheet::exact::ShearDiscreteExact;
    /// let ex = ShearDiscreteExact::new(3, 1.0, 1.0, 1.0, 0.5, 1.0);
    /// let x = ex.edges(1.0);
    /// assert_eq!(x.len(), 3);
    /// assert!(x.windows(2).all(|w| w[1] > w[0])); // the top moves most
    /// ```
    pub fn edges(&self, t: f64) -> Vec<f64> {
        (1..=self.m)
            .map(|k| {
                let kf = k as f64;
                self.delta * kf
                    + self
                        .q
                        .iter()
                        .zip(&self.b)
                        .map(|(&q, &b)| {
                            let s2 = (0.5 * q).sin().powi(2);
                            let rate = 4.0 * self.c * s2 / (1.0 + 4.0 * self.v * s2);
                            b * (q * kf).sin() * (-rate * t).exp()
                        })
                        .sum::<f64>()
            })
            .collect()
    }
}
