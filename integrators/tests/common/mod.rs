//! Canonical test problems shared by the integration tests (and the heat bench, which includes
//! this file by path).
#![allow(dead_code)]

use integrators::adapters::OdeProblem;
use integrators::linalg::Matrix;
use integrators::{EventAction, Options, Pattern, Problem, ResidualError};

/// Robertson's chemical kinetics as an ODE (Hairer & Wanner II, §IV.1; test set "ROBER").
pub struct Robertson {
    /// Provide the exact Jacobian.
    pub exact_jacobian: bool,
}

impl OdeProblem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
        f[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        f[2] = 3e7 * y[1] * y[1];
        f[1] = -f[0] - f[2];
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut Matrix) -> Result<bool, ResidualError> {
        if !self.exact_jacobian {
            return Ok(false);
        }
        jac.add(0, 0, -0.04);
        jac.add(0, 1, 1e4 * y[2]);
        jac.add(0, 2, 1e4 * y[1]);
        jac.add(2, 1, 6e7 * y[1]);
        jac.add(1, 0, 0.04);
        jac.add(1, 1, -1e4 * y[2] - 6e7 * y[1]);
        jac.add(1, 2, -1e4 * y[1]);
        Ok(true)
    }
    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![1e-8, 1e-14, 1e-8])
    }
}

/// Robertson as the index-1 DAE of the IDA example: two kinetic equations and the conservation
/// law `y1 + y2 + y3 = 1` as an algebraic equation for `y3`.
pub struct RobertsonDae;

impl Problem for RobertsonDae {
    fn dim(&self) -> usize {
        3
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = -0.04 * y[0] + 1e4 * y[1] * y[2] - yp[0];
        r[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1] - yp[1];
        r[2] = y[0] + y[1] + y[2] - 1.0;
        Ok(())
    }
    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![1e-8, 1e-14, 1e-8])
    }
    fn algebraic(&self) -> Vec<bool> {
        vec![false, false, true]
    }
}

/// Van der Pol in the unscaled form `y1' = y2, y2' = μ(1 − y1²)y2 − y1`, with an event on
/// `y1 = 0` that just counts crossings (Continue).
pub struct VanDerPol {
    pub mu: f64,
    /// Times at which y1 crossed zero.
    pub crossings: Vec<f64>,
}

impl OdeProblem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
        f[0] = y[1];
        f[1] = self.mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut Matrix) -> Result<bool, ResidualError> {
        jac.add(0, 1, 1.0);
        jac.add(1, 0, -2.0 * self.mu * y[0] * y[1] - 1.0);
        jac.add(1, 1, self.mu * (1.0 - y[0] * y[0]));
        Ok(true)
    }
    fn num_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn handle_event(
        &mut self,
        t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        self.crossings.push(t);
        Ok(EventAction::Continue)
    }
}

/// Van der Pol in the scaled form of the test set ("VDPOL", ε = 1e-6 ⇔ μ = 1000):
/// `y1' = y2, y2' = ((1 − y1²)y2 − y1)/ε`, `y(0) = (2, 0)`, `t ∈ [0, 2]`.
pub struct VanDerPolScaled {
    pub eps: f64,
}

impl OdeProblem for VanDerPolScaled {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
        f[0] = y[1];
        f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.eps;
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut Matrix) -> Result<bool, ResidualError> {
        jac.add(0, 1, 1.0);
        jac.add(1, 0, (-2.0 * y[0] * y[1] - 1.0) / self.eps);
        jac.add(1, 1, (1.0 - y[0] * y[0]) / self.eps);
        Ok(true)
    }
}

/// 1D heat equation `u_t = u_xx` on (0, 1), `u(0) = u(1) = 0`, second-order central
/// differences on `n` interior points (`Δx = 1/(n+1)`), tridiagonal (banded 1/1) pattern.
/// Exact PDE solution for `u(x, 0) = sin(πx)`: `e^{−π² t} sin(πx)`.
pub struct Heat {
    pub n: usize,
    pub exact_jacobian: bool,
}

impl Heat {
    /// Grid point `i` (0-based interior index).
    pub fn x(&self, i: usize) -> f64 {
        (i + 1) as f64 / (self.n + 1) as f64
    }
    /// The initial condition `sin(πx)`.
    pub fn initial(&self) -> Vec<f64> {
        (0..self.n)
            .map(|i| (std::f64::consts::PI * self.x(i)).sin())
            .collect()
    }
    /// Exact solution of the semi-discrete system for the `sin(πx)` initial data:
    /// `e^{−λ t} sin(πx_i)` with `λ = (4/Δx²) sin²(πΔx/2)` (the discrete Laplacian's eigenvalue).
    pub fn exact_semidiscrete(&self, t: f64, i: usize) -> f64 {
        let dx = 1.0 / (self.n + 1) as f64;
        let s = (std::f64::consts::PI * dx / 2.0).sin();
        let lam = 4.0 * s * s / (dx * dx);
        (-lam * t).exp() * (std::f64::consts::PI * self.x(i)).sin()
    }
    /// Exact PDE solution.
    pub fn exact_pde(&self, t: f64, i: usize) -> f64 {
        let pi = std::f64::consts::PI;
        (-pi * pi * t).exp() * (pi * self.x(i)).sin()
    }
}

impl OdeProblem for Heat {
    fn dim(&self) -> usize {
        self.n
    }
    fn rhs(&mut self, _t: f64, u: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
        let n = self.n;
        let inv = ((n + 1) * (n + 1)) as f64;
        for i in 0..n {
            let l = if i > 0 { u[i - 1] } else { 0.0 };
            let r = if i + 1 < n { u[i + 1] } else { 0.0 };
            f[i] = (l - 2.0 * u[i] + r) * inv;
        }
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, _u: &[f64], jac: &mut Matrix) -> Result<bool, ResidualError> {
        if !self.exact_jacobian {
            return Ok(false);
        }
        let n = self.n;
        let inv = ((n + 1) * (n + 1)) as f64;
        for i in 0..n {
            jac.add(i, i, -2.0 * inv);
            if i > 0 {
                jac.add(i, i - 1, inv);
            }
            if i + 1 < n {
                jac.add(i, i + 1, inv);
            }
        }
        Ok(true)
    }
    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 1, upper: 1 }
    }
}

/// A test problem given by its dimension and residual closure alone (dense pattern,
/// finite-difference Jacobian, no events), optionally with algebraic components: the
/// problems of single tests, without a trait impl each. Build it with [`residual_fn`].
pub struct ResidualFn<F> {
    dim: usize,
    algebraic: Option<Vec<bool>>,
    f: F,
}

/// `F(t, y, ẏ) = r` written by `f` into `r`, in `dim` unknowns.
pub fn residual_fn<F>(dim: usize, f: F) -> ResidualFn<F>
where
    F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), ResidualError>,
{
    ResidualFn {
        dim,
        algebraic: None,
        f,
    }
}

impl<F> ResidualFn<F> {
    /// Declares which components are algebraic.
    pub fn algebraic(mut self, flags: Vec<bool>) -> Self {
        self.algebraic = Some(flags);
        self
    }
}

impl<F> Problem for ResidualFn<F>
where
    F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), ResidualError>,
{
    fn dim(&self) -> usize {
        self.dim
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        (self.f)(t, y, yp, r)
    }
    fn algebraic(&self) -> Vec<bool> {
        self.algebraic
            .clone()
            .unwrap_or_else(|| vec![false; self.dim])
    }
}

/// `ẏ = −y`.
pub struct Decay;

impl Problem for Decay {
    fn dim(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] + y[0];
        Ok(())
    }
}

/// `Options` with these tolerances, everything else default.
pub fn opts(rtol: f64, atol: f64) -> Options {
    Options {
        rtol,
        atol,
        ..Default::default()
    }
}

/// [`opts`] with BDF's first Newton iteration after a change of α tested with the rate that
/// change implies ([`integrators::BdfOptions::newton_alpha_bound`]) when `bound` is set.
pub fn opts_bound(rtol: f64, atol: f64, bound: bool) -> Options {
    Options {
        bdf: integrators::BdfOptions {
            newton_alpha_bound: bound,
            ..Default::default()
        },
        ..opts(rtol, atol)
    }
}

/// The scaled Van der Pol oscillator (ε = 1e-6) from (2, 0) to t = 2 by BDF, as the test set
/// poses it.
pub fn van_der_pol_scaled_bdf(o: Options) -> integrators::Solution {
    integrators::Solver::new(integrators::MethodKind::Bdf, o)
        .solve(
            &mut integrators::adapters::Ode(VanDerPolScaled { eps: 1e-6 }),
            0.0,
            &[2.0, 0.0],
            &[2.0],
        )
        .unwrap()
}

/// Max-norm distance.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
