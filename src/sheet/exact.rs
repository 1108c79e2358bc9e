//! Exact solutions for Chapter 4 (docs/model.md §4.3, §4.6).
//!
//! * [`sheet_free_steady`] / [`sheet_periodic_steady`] — the steady states of the uniaxial sheet
//!   (uniform law): `λ₁ = 1 − k₁` in every cell (`σ₁₁` uniform and monotone in `λ₁`); free top:
//!   `σ₂₂(λ₁, λ₂) = 0` fixes `λ₂` (for neo-Hookean `λ₂ = λ₃ = (1 − k₁)^{−1/2}`); periodic:
//!   `λ₂ ≡ 1`.
//! * [`shear_series`] — the continuum series solution of the shear column.
//! * [`ShearDiscreteExact`] — the exact solution of the discrete edge form (neo-Hookean, linear).

use crate::energy::StrainEnergy;
use std::f64::consts::PI;

/// A homogeneous sheet state.
///
/// ```
/// use celltissue::sheet::exact::sheet_periodic_steady;
/// // a periodic sheet 10 % shorter: λ₂ = 1 (held by periodicity), λ₃ = 1/0.9
/// let s = sheet_periodic_steady(&celltissue::NeoHookean::new(1.0).unwrap(), 0.1);
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
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExactError {
    /// Newton's method for `σ₂₂(λ₁, λ₂) = 0` did not converge.
    #[error("no root of sigma22(lambda1 = {lambda1}, lambda2) = 0 found")]
    NoRoot {
        /// The given `λ₁`.
        lambda1: f64,
    },
}

fn steady(law: &impl StrainEnergy, l1: f64, l2: f64) -> SheetSteady {
    let r = law.sheet(l1, l2);
    SheetSteady {
        stretch: [l1, l2, 1.0 / (l1 * l2)],
        pressure: r.pressure,
        s11: r.s11,
        s22: r.s22,
    }
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
            return Ok(steady(law, l1, l2));
        }
    }
    let s = steady(law, l1, l2);
    if s.s22.abs() < 1e-13 {
        Ok(s)
    } else {
        Err(ExactError::NoRoot { lambda1: l1 })
    }
}

/// Steady state of the sheet with a periodic side: `λ₁ = 1 − k₁`, `λ₂ = 1`.
///
/// ```
/// use celltissue::sheet::exact::sheet_periodic_steady;
/// let s = sheet_periodic_steady(&celltissue::NeoHookean::new(1.0)?, 0.5);
/// assert_eq!(s.stretch[0], 0.5);
/// assert!((s.stretch[2] - 2.0).abs() < 1e-12 && (s.pressure - 4.0).abs() < 1e-12); // λ₃ = 2, p = 4
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sheet_periodic_steady(law: &impl StrainEnergy, k1: f64) -> SheetSteady {
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
    let mut x = s * y;
    let mut tan = s;
    for j in 0..terms {
        let kj = (2 * j + 1) as f64 * PI / (2.0 * w);
        let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
        let e = (-d * kj * kj * t).exp();
        x -= 2.0 * s / w * sign / (kj * kj) * (kj * y).sin() * e;
        tan -= 2.0 * s / w * sign / kj * (kj * y).cos() * e;
    }
    (x, tan)
}

/// Exact solution of the discrete edge form with a linear law `τ = μT` (docs/model.md §4.6):
/// `x_{e,k}(t) = δk + Σ_j b_j sin(q_j k) e^{−4c sin²(q_j/2) t}`, `q_j = (2j+1)π/(2M+1)`,
/// `c = β₀μ/(γ₀K)`, `δ = γ₀ F_A/(β₀μ)`.
///
/// ```
/// use celltissue::sheet::exact::ShearDiscreteExact;
/// let ex = ShearDiscreteExact::new(10, 1.0, 1.0, 1.0, 0.5, 1.0);
/// let x0 = ex.edges(0.0);
/// assert!(x0.iter().all(|v| v.abs() < 1e-12));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ShearDiscreteExact {
    m: usize,
    delta: f64,
    c: f64,
    q: Vec<f64>,
    b: Vec<f64>,
}

impl ShearDiscreteExact {
    /// `M` cells, `γ₀`, `β₀`, `μ`, edge drag `K`, force `F_A`.
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
        Self { m, delta, c, q, b }
    }

    /// Edge positions `x_{e,1..M}` at time `t`.
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
                            b * (q * kf).sin() * (-4.0 * self.c * (0.5 * q).sin().powi(2) * t).exp()
                        })
                        .sum::<f64>()
            })
            .collect()
    }
}
