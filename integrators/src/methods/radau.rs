//! Radau IIA of order 5 (three stages, stiffly accurate, L-stable) for residual-form DAEs
//! `F(t, y, ẏ) = 0`: explicit ODEs, constant or state-dependent mass matrices `M(t, y)·ẏ = f` and
//! index-1 DAEs.
//!
//! The implementation follows Hairer & Wanner, *Solving Ordinary Differential Equations II*,
//! 2nd ed., Springer 1996, §IV.8, and their Fortran code RADAU5 (constants, simplified Newton
//! with the eigen-decomposition of `A⁻¹`, error estimate, Gustafsson step-size control,
//! Jacobian reuse), rewritten for the residual form:
//!
//! * unknowns `Z_i = Y_i − y_n` (`i = 1..3`), stage derivatives `Ẏ = h⁻¹ (A⁻¹ ⊗ I) Z`, stage
//!   equations `F(t_n + c_i h, y_n + Z_i, Ẏ_i) = 0`;
//! * simplified Newton with `J0 = ∂F/∂y` and `J1 = ∂F/∂ẏ` frozen at the start of the step; the
//!   Newton matrix `I ⊗ J0 + h⁻¹ A⁻¹ ⊗ J1` is block-diagonalised by `T⁻¹ A⁻¹ T = diag(γ̂, [[α̂, −β̂],
//!   [β̂, α̂]])` into a real `n × n` system `J0 + (γ̂/h) J1` (the problem's own pattern) and a complex
//!   one `J0 + ((α̂ + iβ̂)/h) J1` solved in real `2n` form through
//!   [`crate::linalg::complex_pair_pattern`] (a banded problem stays banded);
//! * `J0` and `J1` are obtained from two [`System::jacobian`] evaluations, at `c = 0` and at
//!   `c = γ̂/h` (so `J1 = (J(γ̂/h) − J0)·h/γ̂`, well scaled for stiff problems): a Jacobian
//!   refresh therefore counts **two** Jacobian evaluations in [`crate::Stats`];
//! * the error estimate is RADAU5's `err = (J0 + (γ̂/h) J1)⁻¹ J1 (ẏ_n + h⁻¹ Σ dd_i Z_i)` (for an
//!   ODE `J1 = I` and `J1 ẏ_n = f(t_n, y_n)`, which is exactly Hairer's formula), with the second
//!   "filtered" estimate `(J0 + (γ̂/h)J1)⁻¹ [J1 (ẏ_n + h⁻¹ Σ dd_i Z_i) − F(t_n, y_n + err, ẏ_n)]` after a
//!   rejection or on the first step;
//! * as in RADAU5 the error is measured against the internal tolerance
//!   `rtol' = 0.1·rtol^(2/3)`, `atol' = atol·rtol'/rtol`, but no looser than `10·rtol`
//!   (below rtol 1e-6). The estimate is of an embedded 3rd-order solution; RADAU5's calibration
//!   makes the order-5 solution's error, ∝ h⁶ against the estimate's h⁴, track `rtol`. Where the
//!   stiff components reduce the order (the stage order is 3) the error tracks the estimate
//!   instead, and grew like rtol^(2/3): on a softening shear column 1.2, 2.5, 12.5, 9.9 and
//!   19.8·rtol at rtol 1e-6 to 1e-10, against at most 1.5·rtol with the bound (1.2–2.2× the
//!   steps at rtol 1e-7 to 1e-10);
//! * dense output (`y` and `ẏ`) is the collocation polynomial of the last step, which also
//!   provides the Newton starting values of the next step; a first step or a retry, which has
//!   no such polynomial, starts from `Z_i = c_i h ẏ_n` (stage rates `ẏ_n`) instead of RADAU5's
//!   `Z = 0`, which is an O(1) distance in rate from `ẏ_n` for problems nonlinear in `ẏ`.
//!
//! With [`crate::Options::fixed_step`] set, steps are exactly of that size and no error estimate is
//! computed (used to measure the order of accuracy, 5 on ODEs; the stage order is 3, so stiff or
//! algebraic components may show order reduction).
//!
//! ```
//! use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
//! /// 2ẏ = -y (a constant "mass matrix" 2)
//! struct Decay;
//! impl Problem for Decay {
//!     fn dim(&self) -> usize { 1 }
//!     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
//!         -> Result<(), ResidualError> { r[0] = 2.0 * yp[0] + y[0]; Ok(()) }
//! }
//! let sol = Solver::new(MethodKind::Radau, Options { rtol: 1e-8, atol: 1e-10, ..Default::default() })
//!     .solve(&mut Decay, 0.0, &[1.0], &[2.0])
//!     .unwrap();
//! assert!((sol.y[0][0] - (-1.0f64).exp()).abs() < 1e-7);
//! ```

use crate::error::{ErrorKind, SolverError};
use crate::linalg::{complex_pair_pattern, fill_complex_pair, LinearSolver, Matrix};
use crate::method::Method;
use crate::methods::one_step::{self, Attempt};
use crate::options::ErrorNorm;
use crate::system::{StepFailure, System};

mod constants;
use constants::Consts;

/// Safety factor of the step-size controller (RADAU5 `SAFE`).
const SAFE: f64 = 0.9;
/// `h_new/h ≥ 1/FACL` (RADAU5 `WORK(8)`).
const FACL: f64 = 5.0;
/// `h_new/h ≤ 1/FACR` (RADAU5 `WORK(9)`).
const FACR: f64 = 0.125;
/// Newton contraction below which the Jacobian is kept for the next step (RADAU5 `WORK(3)`).
const THET: f64 = 0.001;
/// Keep the step size (and the factorisations) when `QUOT1 ≤ h_new/h ≤ QUOT2`.
const QUOT1: f64 = 1.0;
const QUOT2: f64 = 1.2;
/// The ratio of successive Newton corrections from which an iteration whose corrections are
/// within the state's round-off counts as stalled on that round-off. Corrections there are
/// noise and their ratio scatters about 1: a quasi-static line restarting at a breakpoint at
/// rtol 1e-10 had two corrections at 1.05 times its positions' round-off, in a ratio of 0.965
/// in one build and 0.989 in another.
const STALLED: f64 = 0.9;

/// Why an attempt was rejected (kept to build the final error if retries run out).
#[derive(Clone, Debug)]
pub(crate) enum Fail {
    /// Local error test failed.
    ErrorTest { component: Option<usize> },
    /// Newton diverged, converged too slowly or produced non-finite values.
    Newton { component: Option<usize> },
    /// The residual reported a recoverable error (or a non-finite value).
    Residual {
        reason: crate::error::RecoverableCause,
        component: Option<usize>,
    },
    /// Zero pivot.
    Singular { column: usize },
}

impl Fail {
    /// The cause and unknown reported to the observer for a rejected attempt.
    pub(crate) fn cause(&self) -> (crate::observer::RejectCause, Option<usize>) {
        use crate::observer::RejectCause;
        match self {
            Fail::ErrorTest { component } => (RejectCause::ErrorTest, *component),
            Fail::Newton { component } => (RejectCause::Newton, *component),
            Fail::Residual { reason, component } => {
                (RejectCause::Recoverable(reason.clone()), *component)
            }
            Fail::Singular { column } => (
                RejectCause::Recoverable(crate::RecoverableCause::SingularMatrix {
                    column: *column,
                }),
                Some(*column),
            ),
        }
    }

    /// The error to report when the step size can no longer be reduced.
    pub(crate) fn into_error(self, t: f64, h: f64, too_small: bool) -> SolverError {
        match self {
            Fail::Singular { column } => {
                SolverError::new(ErrorKind::SingularMatrix { column }, t, Some(column))
            }
            Fail::Residual { reason, component } => SolverError::new(reason.into(), t, component),
            Fail::Newton { component } if !too_small => {
                SolverError::new(ErrorKind::NewtonFailure, t, component)
            }
            Fail::ErrorTest { component } | Fail::Newton { component } => {
                SolverError::new(ErrorKind::StepSizeTooSmall { h }, t, component)
            }
        }
    }
}

/// Weights `1/(rtol·|y_i| + atol_i)` for all components (algebraic ones included: used for
/// Newton convergence, where algebraic unknowns must converge too).
pub(crate) fn newton_weights(sys: &System<'_>, y: &[f64], w: &mut [f64]) {
    sys.newton_weights(y, w);
}

/// Error weights `1/(rtol·|y_i| + atol_i)`, zero for algebraic components when
/// `opts.suppress_algebraic` (same as [`System::error_weights`], computed here).
pub(crate) fn error_weights(sys: &System<'_>, y: &[f64], w: &mut [f64]) {
    sys.error_weights(y, w);
}

/// Component with the largest `|v_i w_i|`.
pub(crate) fn worst(v: &[f64], w: &[f64]) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, (a, b)) in v.iter().zip(w).enumerate() {
        let x = (a * b).abs();
        let x = if x.is_nan() { f64::INFINITY } else { x };
        if best.is_none_or(|(_, m)| x > m) {
            best = Some((i, x));
        }
    }
    best.map(|(i, _)| i)
}

/// Whether `h` is below the minimum step or round-off level at `t`.
pub(crate) fn step_too_small(h: f64, t: f64, h_min: f64) -> bool {
    h.is_nan() || h <= h_min || h <= 16.0 * f64::EPSILON * t.abs().max(f64::MIN_POSITIVE)
}

/// Converts a recoverable [`StepFailure`] from a residual/Jacobian call into a [`Fail`], or
/// passes a fatal one through.
pub(crate) fn classify(f: StepFailure) -> Result<Fail, SolverError> {
    match f {
        StepFailure::Recoverable { reason, component } => Ok(Fail::Residual { reason, component }),
        StepFailure::Fatal(e) => Err(e),
    }
}

/// Converts a failed factorisation into a [`Fail`].
pub(crate) fn classify_factor(f: StepFailure, n: usize) -> Result<Fail, SolverError> {
    match f {
        StepFailure::Recoverable { component, .. } => Ok(Fail::Singular {
            column: component.unwrap_or(0).min(n.saturating_sub(1)),
        }),
        StepFailure::Fatal(e) => Err(e),
    }
}

/// Newton iteration limit: `Options::max_newton_iters`, but at least RADAU5's default of 7
/// (the option's default, 4, is tuned for BDF's one-stage corrector); in fixed-step mode, where
/// the step cannot be reduced, at least 30 (iteration stops on divergence).
pub(crate) fn newton_iters(opt: usize, fixed: bool) -> usize {
    if fixed {
        opt.max(30)
    } else {
        opt.max(7)
    }
}

/// Radau IIA, order 5, variable step (see the [module documentation](self)).
///
/// ```
/// use integrators::Method;
/// use integrators::methods::radau::Radau5;
/// let m = Radau5::new();
/// assert_eq!(m.name(), "radau");
/// ```
pub struct Radau5 {
    k: Consts,
    started: bool,
    /// Restarts after events ([`one_step::Resume`]).
    resume: one_step::Resume,
    n: usize,
    t: f64,
    t_prev: f64,
    /// Step size to try next.
    h: f64,
    /// Size of the last accepted step.
    h_old: f64,
    y: Vec<f64>,
    yp: Vec<f64>,
    /// Collocation polynomial of the last accepted step (divided differences, RADAU5 `CONT`).
    cont: Vec<f64>,
    has_cont: bool,
    // Newton work
    z: Vec<f64>,
    w: Vec<f64>,
    dw: Vec<f64>,
    g: Vec<f64>,
    ys: Vec<f64>,
    yps: Vec<f64>,
    cplx: Vec<f64>,
    wt: Vec<f64>,
    ewt: Vec<f64>,
    tmp: Vec<f64>,
    tmp2: Vec<f64>,
    // Jacobians and factorisations
    j0: Option<Matrix>,
    j1: Option<Matrix>,
    e1: Option<Matrix>,
    e2: Option<Matrix>,
    lu1: Option<LinearSolver>,
    lu2: Option<LinearSolver>,
    jac_valid: bool,
    jac_fresh: bool,
    lu_h: f64,
    // controller state
    first: bool,
    reject: bool,
    faccon: f64,
    /// Step size at which `faccon` was last measured.
    h_faccon: f64,
    theta: f64,
    h_acc: f64,
    err_acc: f64,
    n_accept: usize,
}

impl Default for Radau5 {
    fn default() -> Self {
        Self::new()
    }
}

impl Radau5 {
    /// A fresh Radau IIA integrator (call [`Method::start`] before stepping).
    ///
    /// ```
    /// use integrators::Method;
    /// let m = integrators::methods::radau::Radau5::new();
    /// assert_eq!(m.name(), "radau");
    /// ```
    pub fn new() -> Self {
        Self {
            k: Consts::new(),
            started: false,
            resume: Default::default(),
            n: 0,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            h_old: 0.0,
            y: Vec::new(),
            yp: Vec::new(),
            cont: Vec::new(),
            has_cont: false,
            z: Vec::new(),
            w: Vec::new(),
            dw: Vec::new(),
            g: Vec::new(),
            ys: Vec::new(),
            yps: Vec::new(),
            cplx: Vec::new(),
            wt: Vec::new(),
            ewt: Vec::new(),
            tmp: Vec::new(),
            tmp2: Vec::new(),
            j0: None,
            j1: None,
            e1: None,
            e2: None,
            lu1: None,
            lu2: None,
            jac_valid: false,
            jac_fresh: false,
            lu_h: f64::NAN,
            first: true,
            reject: false,
            faccon: 1.0,
            h_faccon: f64::INFINITY,
            theta: THET,
            h_acc: 0.0,
            err_acc: 1e-2,
            n_accept: 0,
        }
    }

    /// Internal tolerance scaling of RADAU5: weights are multiplied by `rtol/rtol'` with
    /// `rtol' = 0.1·rtol^(2/3)`, at most `10·rtol` (the module's doc says why); returns
    /// (`factor`, `rtol'`).
    fn tol_scaling(rtol: f64) -> (f64, f64) {
        let rtol_int = (0.1 * rtol.powf(2.0 / 3.0)).min(10.0 * rtol);
        (rtol / rtol_int, rtol_int)
    }

    /// Evaluates `J0 = ∂F/∂y` and `J1 = ∂F/∂ẏ` at the current point (two Jacobian calls).
    fn eval_jacobian(&mut self, sys: &mut System<'_>, h: f64) -> Result<(), StepFailure> {
        let c = self.k.gamma / h;
        let j0 = self.j0.as_mut().expect("workspace");
        sys.jacobian(self.t, &self.y, &self.yp, 0.0, j0)?;
        let e1 = self.e1.as_mut().expect("workspace");
        sys.jacobian(self.t, &self.y, &self.yp, c, e1)?;
        let j1 = self.j1.as_mut().expect("workspace");
        j1.set_zero();
        j1.axpby(0.0, 1.0 / c, e1);
        j1.axpby(1.0, -1.0 / c, self.j0.as_ref().expect("workspace"));
        self.jac_valid = true;
        self.jac_fresh = true;
        self.lu_h = f64::NAN;
        Ok(())
    }

    /// Assembles and factorises `E1 = J0 + (γ̂/h) J1` and the complex-pair `E2` for step `h`.
    fn factorise(&mut self, sys: &mut System<'_>, h: f64) -> Result<(), StepFailure> {
        let j0 = self.j0.as_ref().expect("workspace");
        let j1 = self.j1.as_ref().expect("workspace");
        let e1 = self.e1.as_mut().expect("workspace");
        e1.set_zero();
        e1.axpby(0.0, 1.0, j0);
        e1.axpby(1.0, self.k.gamma / h, j1);
        let e2 = self.e2.as_mut().expect("workspace");
        e2.set_zero();
        fill_complex_pair(j0, j1, self.k.alpha / h, self.k.beta / h, e2);
        self.lu_h = f64::NAN;
        sys.factor(self.lu1.as_mut().expect("workspace"), e1)?;
        sys.factor(self.lu2.as_mut().expect("workspace"), e2)
            .map_err(|f| match f {
                StepFailure::Recoverable { reason, component } => StepFailure::Recoverable {
                    reason,
                    component: component.map(|c| c / 2),
                },
                other => other,
            })?;
        self.lu_h = h;
        Ok(())
    }

    /// Evaluates the collocation polynomial of the last step at `s = (t − t_n)/h_old ∈ [−1, 0]`,
    /// relative to `y_n`: writes `p(s) − y_n` into `out` (and `h·p'(s)` into `dout` if given).
    fn poly(&self, s: f64, out: &mut [f64], dout: Option<&mut [f64]>) {
        let n = self.n;
        let c1m1 = self.k.c[0] - 1.0;
        let c2m1 = self.k.c[1] - 1.0;
        let (k1, rest) = self.cont.split_at(n);
        let (k2, k3) = rest.split_at(n);
        for i in 0..n {
            let q = k2[i] + (s - c1m1) * k3[i];
            let p = k1[i] + (s - c2m1) * q;
            out[i] = s * p;
        }
        if let Some(d) = dout {
            for i in 0..n {
                let q = k2[i] + (s - c1m1) * k3[i];
                let p = k1[i] + (s - c2m1) * q;
                let dp = q + (s - c2m1) * k3[i];
                d[i] = p + s * dp;
            }
        }
    }

    /// One attempt of a step of size `h` from `(t, y)`.
    fn attempt(
        &mut self,
        sys: &mut System<'_>,
        h: f64,
        fixed: bool,
        t_new: f64,
    ) -> Result<Attempt, SolverError> {
        let n = self.n;
        let nit = newton_iters(sys.opts.max_newton_iters, fixed);
        let (wscale, rtol_int) = Self::tol_scaling(sys.opts.rtol);
        // RADAU5's FNEWT, tightened tenfold: with a state-dependent ∂F/∂ẏ (mass matrices,
        // index-1 DAEs) the simplified Newton contracts only like O(h), and the accepted
        // iteration error then dominates the global error at RADAU5's setting.
        let fnewt = (10.0 * f64::EPSILON / rtol_int).max(0.1 * 0.03f64.min(rtol_int.sqrt()));

        // Jacobian and factorisations.
        if !self.jac_valid {
            if let Err(f) = self.eval_jacobian(sys, h) {
                self.jac_valid = false;
                return Ok(Attempt::Rejected(classify(f)?, 0.5 * h));
            }
        }
        if self.lu_h != h {
            if let Err(f) = self.factorise(sys, h) {
                return Ok(Attempt::Rejected(classify_factor(f, n)?, 0.5 * h));
            }
        }

        // Weights from y_n (RADAU5's SCAL), with RADAU5's internal tolerance.
        newton_weights(sys, &self.y, &mut self.wt);
        error_weights(sys, &self.y, &mut self.ewt);
        for (a, b) in self.wt.iter_mut().zip(self.ewt.iter_mut()) {
            *a *= wscale;
            *b *= wscale;
        }

        // Starting values.
        if self.first || self.reject || !self.has_cont {
            // No usable collocation polynomial: start on the line through y_n with slope ẏ_n,
            // Z_i = c_i h ẏ_n, whose stage rates are ẏ_n exactly (A⁻¹c = 1). RADAU5's Z = 0
            // starts every stage rate at 0, an O(1) distance from ẏ_n however short the step,
            // which the simplified Newton (∂F/∂ẏ frozen at ẏ_n) crosses slowly when F is
            // nonlinear in ẏ (e.g. growth read from a viscous stress).
            for i in 0..3 {
                let ch = self.k.c[i] * h;
                for (z, yp) in self.z[i * n..(i + 1) * n].iter_mut().zip(&self.yp) {
                    *z = ch * yp;
                }
            }
        } else {
            let q = h / self.h_old;
            let mut out = std::mem::take(&mut self.tmp);
            for i in 0..3 {
                self.poly(self.k.c[i] * q, &mut out, None);
                self.z[i * n..(i + 1) * n].copy_from_slice(&out);
            }
            self.tmp = out;
        }
        // W = (T⁻¹ ⊗ I) Z
        for k in 0..3 {
            for i in 0..n {
                self.w[k * n + i] = (0..3).map(|j| self.k.ti[k][j] * self.z[j * n + i]).sum();
            }
        }

        // Simplified Newton.
        // RADAU5's predicted contraction for the first iteration, scaled up when the step grew
        // since it was measured (the contraction of the simplified Newton grows at least like
        // h, e.g. for state-dependent mass matrices).
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8) * (h / self.h_faccon).max(1.0);
        self.theta = THET;
        let mut newt = 0usize;
        let mut dynold = 0.0f64;
        let mut thqold = 0.0f64;
        loop {
            if newt >= nit {
                return Ok(self.newton_fail(sys, 0.5 * h));
            }
            // Stage derivatives and residuals.
            for i in 0..3 {
                let ti = self.t + self.k.c[i] * h;
                for l in 0..n {
                    self.ys[l] = self.y[l] + self.z[i * n + l];
                    self.yps[l] = (0..3)
                        .map(|j| self.k.a_inv[i][j] * self.z[j * n + l])
                        .sum::<f64>()
                        / h;
                }
                if let Err(f) =
                    sys.residual(ti, &self.ys, &self.yps, &mut self.g[i * n..(i + 1) * n])
                {
                    let fail = classify(f)?;
                    sys.stats.newton_failures += 1;
                    if !self.jac_fresh {
                        self.jac_valid = false;
                    }
                    return Ok(Attempt::Rejected(fail, 0.5 * h));
                }
            }
            // RHS = −(T⁻¹ ⊗ I) G
            for k in 0..3 {
                for l in 0..n {
                    self.dw[k * n + l] = -(0..3)
                        .map(|j| self.k.ti[k][j] * self.g[j * n + l])
                        .sum::<f64>();
                }
            }
            sys.solve(self.lu1.as_ref().expect("workspace"), &mut self.dw[..n]);
            for l in 0..n {
                self.cplx[2 * l] = self.dw[n + l];
                self.cplx[2 * l + 1] = self.dw[2 * n + l];
            }
            sys.solve(self.lu2.as_ref().expect("workspace"), &mut self.cplx);
            for l in 0..n {
                self.dw[n + l] = self.cplx[2 * l];
                self.dw[2 * n + l] = self.cplx[2 * l + 1];
            }
            newt += 1;
            sys.stats.newton_iterations += 1;
            let mut s = 0.0;
            if sys.error_map().is_empty() {
                for k in 0..3 {
                    for l in 0..n {
                        let v = self.dw[k * n + l] * self.wt[l];
                        s += v * v;
                    }
                }
            } else {
                // the stage corrections measured as cell-level quantities (RMS, as RADAU5)
                for k in 0..3 {
                    let r = sys.norm_with(ErrorNorm::Rms, &self.dw[k * n..(k + 1) * n], &self.wt);
                    s += r * r * n as f64;
                }
            }
            let dyno = (s / (3 * n).max(1) as f64).sqrt();
            if !dyno.is_finite() {
                return Ok(self.newton_fail(sys, 0.5 * h));
            }
            if newt > 1 && dyno >= STALLED * dynold && sys.below_roundoff(dyno) {
                // no longer contracting, but within the rounding of the state: converged as far
                // as the state resolves (`System::below_roundoff`), not diverging
                for (a, b) in self.w.iter_mut().zip(&self.dw) {
                    *a += b;
                }
                self.update_z();
                break;
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dynold;
                if fixed {
                    // No step reduction possible: iterate while contracting.
                    if thq >= 0.99 {
                        return Ok(self.newton_fail(sys, 0.5 * h));
                    }
                    self.theta = thq;
                    self.faccon = thq / (1.0 - thq);
                    self.h_faccon = h;
                    dynold = dyno.max(f64::EPSILON);
                    for (a, b) in self.w.iter_mut().zip(&self.dw) {
                        *a += b;
                    }
                    self.update_z();
                    if self.faccon * dyno <= fnewt {
                        break;
                    }
                    continue;
                }
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thqold).sqrt()
                };
                thqold = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    self.h_faccon = h;
                    let dyth =
                        self.faccon * dyno * self.theta.powi((nit - 1 - newt) as i32) / fnewt;
                    if dyth >= 1.0 {
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let hhfac = 0.8 * qnewt.powf(-1.0 / (4.0 + (nit - 1 - newt) as f64));
                        return Ok(self.newton_fail(sys, hhfac * h));
                    }
                } else {
                    return Ok(self.newton_fail(sys, 0.5 * h));
                }
            }
            dynold = dyno.max(f64::EPSILON);
            for (a, b) in self.w.iter_mut().zip(&self.dw) {
                *a += b;
            }
            self.update_z();
            if self.faccon * dyno <= fnewt {
                break;
            }
        }

        // Error estimate.
        let mut err = 0.0;
        if !fixed {
            // v = ẏ_n + h⁻¹ Σ dd_i Z_i ; rhs = J1 v
            for l in 0..n {
                self.ys[l] = self.yp[l]
                    + (0..3)
                        .map(|i| self.k.dd[i] * self.z[i * n + l])
                        .sum::<f64>()
                        / h;
            }
            let j1 = self.j1.as_ref().expect("workspace");
            j1.mul_vec(&self.ys, &mut self.tmp2);
            self.tmp.copy_from_slice(&self.tmp2);
            sys.solve(self.lu1.as_ref().expect("workspace"), &mut self.tmp);
            err = sys.norm(&self.tmp, &self.ewt).max(1e-10);
            if err >= 1.0 && (self.first || self.reject) {
                for l in 0..n {
                    self.ys[l] = self.y[l] + self.tmp[l];
                }
                match sys.residual(self.t, &self.ys, &self.yp, &mut self.yps) {
                    Ok(()) => {
                        for l in 0..n {
                            self.tmp[l] = self.tmp2[l] - self.yps[l];
                        }
                        sys.solve(self.lu1.as_ref().expect("workspace"), &mut self.tmp);
                        err = sys.norm(&self.tmp, &self.ewt).max(1e-10);
                    }
                    Err(f) => {
                        // Keep the first estimate; a domain error here only means the
                        // perturbed state is outside the model's domain.
                        classify(f)?;
                    }
                }
            }
            if !err.is_finite() {
                err = f64::INFINITY;
            }
        }

        let fac = SAFE.min(SAFE * (1 + 2 * nit) as f64 / (newt + 2 * nit) as f64);
        let mut quot = FACR.max(FACL.min(err.powf(0.25) / fac));
        let mut hnew = h / quot;

        if err < 1.0 {
            // Accept.
            self.n_accept += 1;
            if !fixed {
                if self.n_accept > 1 {
                    let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / SAFE;
                    let facgus = FACR.max(FACL.min(facgus));
                    quot = quot.max(facgus);
                    hnew = h / quot;
                }
                self.h_acc = h;
                self.err_acc = err.max(1e-2);
            }
            // Collocation polynomial (RADAU5's CONT) and the new state.
            let c1 = self.k.c[0];
            let c2 = self.k.c[1];
            let (c1m1, c2m1, c1mc2) = (c1 - 1.0, c2 - 1.0, c1 - c2);
            for l in 0..n {
                let z1 = self.z[l];
                let z2 = self.z[n + l];
                let z3 = self.z[2 * n + l];
                let k1 = (z2 - z3) / c2m1;
                let ak = (z1 - z2) / c1mc2;
                let acont3 = (ak - z1 / c1) / c2;
                let k2 = (ak - k1) / c1m1;
                self.cont[l] = k1;
                self.cont[n + l] = k2;
                self.cont[2 * n + l] = k2 - acont3;
            }
            for l in 0..n {
                self.y[l] += self.z[2 * n + l];
                self.yp[l] = (0..3)
                    .map(|j| self.k.a_inv[2][j] * self.z[j * n + l])
                    .sum::<f64>()
                    / h;
            }
            self.has_cont = true;
            self.t_prev = self.t;
            self.t = t_new;
            self.h_old = h;
            self.first = false;
            if fixed {
                self.reject = false;
                self.jac_fresh = false;
                if self.theta > THET {
                    self.jac_valid = false;
                }
                return Ok(Attempt::Accepted);
            }
            hnew = hnew.min(sys.opts.h_max);
            if self.reject {
                hnew = hnew.min(h);
            }
            self.reject = false;
            self.jac_fresh = false;
            let qt = hnew / h;
            if self.theta <= THET && (QUOT1..=QUOT2).contains(&qt) {
                self.h = h; // keep the factorisations
            } else {
                self.h = hnew;
                if self.theta > THET {
                    self.jac_valid = false;
                }
            }
            Ok(Attempt::Accepted)
        } else {
            // Reject.
            sys.stats.error_test_failures += 1;
            let comp = worst(&self.tmp, &self.ewt);
            let h_next = if self.first { 0.1 * h } else { hnew };
            self.reject = true;
            if !self.jac_fresh {
                self.jac_valid = false;
            }
            Ok(Attempt::Rejected(
                Fail::ErrorTest { component: comp },
                h_next,
            ))
        }
    }

    /// `Z = (T ⊗ I) W`.
    fn update_z(&mut self) {
        let n = self.n;
        for i in 0..3 {
            for l in 0..n {
                self.z[i * n + l] = (0..3).map(|k| self.k.t[i][k] * self.w[k * n + l]).sum();
            }
        }
    }

    /// Bookkeeping of a Newton failure; the step is retried with `h_new`.
    fn newton_fail(&mut self, sys: &mut System<'_>, h_new: f64) -> Attempt {
        sys.stats.newton_failures += 1;
        self.reject = true;
        if !self.jac_fresh {
            self.jac_valid = false;
        }
        let comp = worst(&self.dw[..self.n], &self.wt);
        Attempt::Rejected(Fail::Newton { component: comp }, h_new)
    }
}

one_step::impl_one_step!(Radau5, order: 3, h_old: true, unit_mass: |_m| false);

impl Method for Radau5 {
    fn name(&self) -> &'static str {
        "radau"
    }

    fn start(
        &mut self,
        sys: &mut System<'_>,
        t: f64,
        y: &[f64],
        yp: &[f64],
        h: Option<f64>,
    ) -> Result<(), SolverError> {
        let n = sys.dim();
        one_step::check_start(n, t, y, yp)?;
        let rebuild = !self.started || n != self.n || self.j0.is_none();
        self.n = n;
        self.t = t;
        self.t_prev = t;
        self.y = y.to_vec();
        self.yp = yp.to_vec();
        if rebuild || self.z.len() != 3 * n {
            self.cont = vec![0.0; 3 * n];
            self.z = vec![0.0; 3 * n];
            self.w = vec![0.0; 3 * n];
            self.dw = vec![0.0; 3 * n];
            self.g = vec![0.0; 3 * n];
            self.ys = vec![0.0; n];
            self.yps = vec![0.0; n];
            self.cplx = vec![0.0; 2 * n];
            self.wt = vec![0.0; n];
            self.ewt = vec![0.0; n];
            self.tmp = vec![0.0; n];
            self.tmp2 = vec![0.0; n];
        }
        // The pattern may have changed even at equal dimension (resize events): always rebuild
        // the matrices and solvers (symbolic analysis happens at first factorisation).
        let pat = sys.pattern().clone();
        let cpat = complex_pair_pattern(n, &pat);
        self.j0 = Some(sys.new_matrix());
        self.j1 = Some(sys.new_matrix());
        self.e1 = Some(sys.new_matrix());
        self.e2 = Some(Matrix::zeros(2 * n, &cpat));
        self.lu1 = Some(sys.new_linear_solver());
        self.lu2 = Some(LinearSolver::new(2 * n, &cpat));
        self.jac_valid = false;
        self.jac_fresh = false;
        self.lu_h = f64::NAN;
        self.has_cont = false;
        self.first = true;
        self.reject = false;
        self.faccon = 1.0;
        self.h_faccon = f64::INFINITY;
        self.theta = THET;
        self.n_accept = 0;
        self.h_acc = 0.0;
        self.err_acc = 1e-2;
        self.resume.on_start(self.started);
        self.started = true;
        self.h = one_step::start_h(h, sys.opts);
        self.h_old = self.h;
        Ok(())
    }

    super::method_accessors!(one_step);

    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        if !self.has_cont || self.t == self.t_prev {
            y.copy_from_slice(&self.y);
            yp.copy_from_slice(&self.yp);
            return;
        }
        let s = (t - self.t) / self.h_old;
        self.poly(s, y, Some(yp));
        for l in 0..self.n {
            y[l] += self.y[l];
            yp[l] /= self.h_old;
        }
    }
}

#[cfg(test)]
mod tests;
