//! Solver options: tolerances, step limits, Jacobian reuse, error norm and the choice of
//! linear solver ([`LinearSolverChoice`]).

/// Options shared by every method.
///
/// ```
/// let o = integrators::Options { rtol: 1e-8, ..Default::default() };
/// assert!(o.validate().is_ok());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Relative tolerance (> 0).
    pub rtol: f64,
    /// Absolute tolerance for every component unless the problem gives per-component ones (> 0).
    pub atol: f64,
    /// Initial step size; `None` = estimated.
    pub h0: Option<f64>,
    /// Largest step size.
    pub h_max: f64,
    /// Smallest step size before failing with `StepSizeTooSmall`.
    pub h_min: f64,
    /// Maximum number of steps.
    pub max_steps: usize,
    /// Maximum BDF order (1..=5).
    pub max_order: usize,
    /// Exclude algebraic components from the local error test (as IDA's `suppressalg`).
    pub suppress_algebraic: bool,
    /// Event location tolerance on t (absolute).
    pub event_tol: f64,
    /// Use a finite-difference Jacobian even if the problem provides exact ones.
    pub force_fd_jacobian: bool,
    /// Maximum Newton iterations per nonlinear solve.
    pub max_newton_iters: usize,
    /// Fixed-step mode (for order-of-accuracy studies): when `Some(h)`, the one-step methods
    /// (ESDIRK, Radau IIA, Dormand–Prince) take steps of exactly `h` (the last one shortened to
    /// land on the stop time) and skip the local error test. `None` (default): adaptive steps.
    pub fixed_step: Option<f64>,
    /// BDF only: use exactly this order (reached as soon as the history allows after each
    /// start) instead of selecting it; step-size control stays on. `None` (default): variable
    /// order up to [`Options::max_order`]. Used for tolerance-sweep order studies of the BDF.
    pub fixed_order: Option<usize>,
    /// How weighted error vectors are measured in the local error test and the Newton
    /// convergence test of every method (default: RMS).
    pub norm: ErrorNorm,
    /// How the Newton systems are solved (default: [`LinearSolverChoice::Direct`]).
    pub linear_solver: LinearSolverChoice,
    /// Threads a solve may use (≥ 1; default 1 — parallelism is passed in, never global).
    /// With 2 or more, problems of at least [`crate::System::PARALLEL_MIN`] unknowns split
    /// BDF's vector passes and the tridiagonal solve in two halves on two threads, and the
    /// problem is told through [`crate::Problem::set_threads`] (celltissue's line splits its
    /// residual sweep). Only two-way splits exist, so values above 2 act as 2. Results do not
    /// depend on it beyond the summation order of norms.
    pub threads: usize,
}

/// How the linear systems of the Newton iterations are solved.
///
/// `Iterative` applies to problems with a [`crate::Pattern::Sparse`] Jacobian pattern; dense
/// and banded patterns (and Radau's complex-pair system) always use their direct LU.
///
/// ```
/// use integrators::{IterativeSettings, LinearSolverChoice, Options};
/// let o = Options {
///     linear_solver: LinearSolverChoice::Iterative(IterativeSettings::default()),
///     ..Default::default()
/// };
/// assert!(o.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LinearSolverChoice {
    /// Direct LU by pattern (dense, banded, sparse with symbolic reuse).
    #[default]
    Direct,
    /// Sparse patterns: ILU(0)-preconditioned BiCGStab (see [`IterativeSettings`]); the
    /// "factorisation" is the preconditioner, each solve iterates until the Newton iteration
    /// that asked for it has what it needs (or to `rtol`).
    Iterative(IterativeSettings),
}

/// Settings of the iterative linear solver ([`LinearSolverChoice::Iterative`]).
///
/// A solve starts from `x = 0` and stops at the first of two tests on the preconditioned
/// residual `r̂ = M⁻¹(b − A x)` (`M` the ILU(0) preconditioner; `r̂` estimates the error of `x`):
///
/// * **Newton-aware (default rule)**: when the method passes its Newton tolerance (the BDF
///   method does: its Newton weights, its norm and its tolerance ε = 0.33, see
///   [`crate::linalg::LinearTolerance`]), the solve stops once `‖r̂‖_w ≤ newton_factor · ε` —
///   the inexact-Newton rule of SUNDIALS IDA/CVODE (`eplifac`). The linear error is then a
///   small fraction of what the Newton convergence test tolerates, whatever `rtol` says.
/// * **relative residual**: `‖r̂‖₂ ≤ rtol · ‖M⁻¹b‖₂`. This is the only rule for solves without
///   a Newton tolerance (ESDIRK, Radau IIA, direct calls of
///   [`crate::linalg::LinearSolver::solve_in_place`]) and an upper bound on the work of any
///   solve. `newton_factor = 0` makes it the only rule everywhere (the behaviour before the
///   Newton-aware rule existed).
///
/// ```
/// use integrators::IterativeSettings;
/// let s = IterativeSettings::default();
/// assert_eq!((s.rtol, s.max_iters, s.newton_factor), (1e-8, 200, 0.01));
/// // a fixed relative residual for every solve instead of the Newton-aware rule:
/// let fixed = IterativeSettings { rtol: 1e-10, newton_factor: 0.0, ..s };
/// assert_eq!(fixed.max_iters, 200);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterativeSettings {
    /// Relative preconditioned residual `‖M⁻¹(b − A x)‖₂ / ‖M⁻¹b‖₂` at which a solve always
    /// stops, in (0, 1).
    pub rtol: f64,
    /// Most BiCGStab iterations per solve (≥ 1); a solve that does not converge makes the
    /// Newton iteration fail, and the step is retried smaller.
    pub max_iters: usize,
    /// Fraction of the Newton tolerance the linear error may reach (SUNDIALS' `eplifac`), in
    /// [0, 1); 0 disables the Newton-aware stopping rule.
    ///
    /// The default, 0.01, is tighter than SUNDIALS' 0.05: the preconditioned residual
    /// underestimates the error by the conditioning of `M⁻¹A` (6–14× on a grid operator in the
    /// unit tests), and with the max norm that noise reaches the BDF error estimate — on the
    /// 500 × 500 macroscale sheet (measured during development, see BENCHMARKS.md) 0.05 took
    /// 84 steps against 71 with exact solves, 0.01 took 72 at nearly the same Krylov work
    /// (573 against 538 iterations).
    pub newton_factor: f64,
}

impl Default for IterativeSettings {
    /// `rtol = 1e-8`, `max_iters = 200`, `newton_factor = 0.01`.
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            max_iters: 200,
            newton_factor: 0.01,
        }
    }
}

/// Norm of a weighted error vector `(v_i·w_i)`.
///
/// ```
/// use integrators::{ErrorNorm, Options};
/// let o = Options { norm: ErrorNorm::Max, ..Default::default() };
/// assert_eq!(o.norm.of(&[3.0, 4.0], &[1.0, 1.0]), 4.0);
/// assert!((ErrorNorm::Rms.of(&[3.0, 4.0], &[1.0, 1.0]) - 12.5f64.sqrt()).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ErrorNorm {
    /// Root mean square `sqrt(mean((v_i·w_i)²))`, as IDA, DASSL, SciPy and Hairer's codes.
    #[default]
    Rms,
    /// Maximum `max |v_i·w_i|`. The RMS norm dilutes an error confined to a few of `n`
    /// components by `√n`; on a spatially extended problem whose dynamics are localised (a
    /// boundary layer at a moving end of a line of `N` cells) that lets large local errors
    /// pass the error test as `N` grows and the step count climbs. The max norm keeps the
    /// per-component error controlled and the step count independent of `N`.
    Max,
}

impl ErrorNorm {
    /// The norm of `(v_i·w_i)` (0 for empty vectors; NaN propagates).
    pub fn of(self, v: &[f64], w: &[f64]) -> f64 {
        debug_assert_eq!(v.len(), w.len(), "norm: length mismatch");
        if v.is_empty() {
            return 0.0;
        }
        match self {
            ErrorNorm::Rms => {
                let s: f64 = v.iter().zip(w).map(|(a, b)| (a * b) * (a * b)).sum();
                (s / v.len() as f64).sqrt()
            }
            ErrorNorm::Max => v.iter().zip(w).fold(0.0, |m: f64, (a, b)| {
                let x = (a * b).abs();
                if x.is_nan() || m.is_nan() {
                    f64::NAN
                } else {
                    m.max(x)
                }
            }),
        }
    }

    /// Parses `"rms"` or `"max"`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "rms" => Ok(ErrorNorm::Rms),
            "max" => Ok(ErrorNorm::Max),
            other => Err(format!("norm = {other:?} must be \"rms\" or \"max\"")),
        }
    }
}

impl Default for Options {
    fn default() -> Self {
        Self {
            rtol: 1e-6,
            atol: 1e-8,
            h0: None,
            h_max: f64::INFINITY,
            h_min: 0.0,
            max_steps: 1_000_000,
            max_order: 5,
            suppress_algebraic: true,
            event_tol: 1e-12,
            force_fd_jacobian: false,
            max_newton_iters: 4,
            fixed_step: None,
            fixed_order: None,
            norm: ErrorNorm::Rms,
            linear_solver: LinearSolverChoice::Direct,
            threads: 1,
        }
    }
}

impl Options {
    /// Checks ranges; the error names the field and its valid range.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(format!("rtol = {} must be in (0, 1)", self.rtol));
        }
        if !(self.atol > 0.0 && self.atol.is_finite()) {
            return Err(format!("atol = {} must be positive and finite", self.atol));
        }
        if let Some(h0) = self.h0 {
            if !(h0 > 0.0 && h0.is_finite()) {
                return Err(format!("h0 = {h0} must be positive and finite"));
            }
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(format!("h_max = {} must be positive", self.h_max));
        }
        if !(self.h_min >= 0.0 && self.h_min < self.h_max) {
            return Err(format!("h_min = {} must be in [0, h_max)", self.h_min));
        }
        if !(1..=5).contains(&self.max_order) {
            return Err(format!("max_order = {} must be in 1..=5", self.max_order));
        }
        if self.max_newton_iters == 0 {
            return Err("max_newton_iters must be at least 1".into());
        }
        if let Some(h) = self.fixed_step {
            if !(h > 0.0 && h.is_finite()) {
                return Err(format!("fixed_step = {h} must be positive and finite"));
            }
        }
        if let Some(k) = self.fixed_order {
            if !(1..=self.max_order).contains(&k) {
                return Err(format!(
                    "fixed_order = {k} must be in 1..=max_order ({})",
                    self.max_order
                ));
            }
        }
        if let LinearSolverChoice::Iterative(it) = self.linear_solver {
            if !(it.rtol > 0.0 && it.rtol < 1.0) {
                return Err(format!(
                    "linear_solver.rtol = {} must be in (0, 1)",
                    it.rtol
                ));
            }
            if it.max_iters == 0 {
                return Err("linear_solver.max_iters must be at least 1".into());
            }
            if !(it.newton_factor >= 0.0 && it.newton_factor < 1.0) {
                return Err(format!(
                    "linear_solver.newton_factor = {} must be in [0, 1)",
                    it.newton_factor
                ));
            }
        }
        if self.threads == 0 {
            return Err("threads = 0 must be at least 1".into());
        }
        if self.event_tol.is_nan() || self.event_tol <= 0.0 {
            return Err(format!("event_tol = {} must be positive", self.event_tol));
        }
        Ok(())
    }
}
