//! Solver options: tolerances, step limits, Jacobian reuse, error norm, the choice of
//! linear solver ([`LinearSolverChoice`]) and of parallelism ([`Parallelism`]); invalid
//! values are an [`OptionsError`] naming the field and its valid range.

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
    /// Settings of the BDF method only ([`BdfOptions`]); a solve with another method and
    /// non-default BDF settings is an `InvalidInput` error naming the setting.
    pub bdf: BdfOptions,
    /// Exclude algebraic components from the local error test (as IDA's `suppressalg`).
    pub suppress_algebraic: bool,
    /// Event location tolerance on t: absolute, scaled by the solve's time scale when its
    /// times stay below 1 ([`crate::solver::event_tolerance`]).
    pub event_tol: f64,
    /// Use a finite-difference Jacobian even if the problem provides exact ones.
    pub force_fd_jacobian: bool,
    /// Maximum Newton iterations per nonlinear solve.
    pub max_newton_iters: usize,
    /// Fixed-step mode (for order-of-accuracy studies): when `Some(h)`, every method takes
    /// steps of exactly `h` (the last one shortened to land on the stop time) and skips the
    /// local error test. `None` (default): adaptive steps.
    pub fixed_step: Option<f64>,
    /// How weighted error vectors are measured in the local error test and the Newton
    /// convergence test of every method (default: RMS).
    pub norm: ErrorNorm,
    /// How the Newton systems are solved (default: [`LinearSolverChoice::Direct`]).
    pub linear_solver: LinearSolverChoice,
    /// Whether the solve splits its vector passes (default [`Parallelism::Serial`] —
    /// parallelism is passed in, never global). The problem is told through
    /// [`crate::Problem::set_threads`] (celltissue's line splits its residual sweep). Results
    /// do not depend on it beyond the summation order of norms.
    pub parallel: Parallelism,
    /// Whether every step that would pass an output time ends at it, so that the output is
    /// the step's own solution rather than dense output (default `None`: for the methods whose
    /// dense output the error test does not control, [`crate::Method::dense_output_controlled`],
    /// i.e. all but BDF). Measured on a stiff cell cluster near its quasi-static limit
    /// (celltissue's Fig 2.8 line at drag 1e-5, rtol 1e-6): Radau IIA's stretch at an
    /// interpolated output erred by 73·rtol, at a step's end by 0.02·rtol.
    pub land_on_outputs: Option<bool>,
    /// Whether an output of a problem that reads rates ([`crate::Problem::outputs_read_rates`])
    /// keeps the interpolated `ẏ` instead of one solved from its state (default `false`).
    /// Interpolated rates save about three residuals and solves per output and are not
    /// error-controlled: a viscous line's pressure erred by 13·rtol at rtol 1e-6 through
    /// them, 2.5·rtol with solved rates, and the solved rates took a 10⁵-cell viscous line
    /// with 101 outputs from about 1.35 s to 1.7 s.
    pub interpolate_rates: bool,
}

/// How a solve may use a second worker: BDF's vector passes (predictor, weights, error
/// norms), the tridiagonal factorisation and solve and the condensed band's are split in two
/// halves run by [`rayon::join`] — on the rayon pool the solve runs in, so no thread is
/// started per pass. A solve called outside every rayon pool makes its thread worker 0 of a
/// two-thread pool kept for that thread's lifetime (one more OS thread); a solve inside a pool
/// (a caller's [`install`](rayon::ThreadPool::install)) uses that pool.
///
/// ```
/// use integrators::{Options, Parallelism};
/// let o = Options { parallel: Parallelism::from_threads(2)?, ..Default::default() };
/// assert!(o.parallel.splits(1 << 18) && !o.parallel.splits(1000));
/// // a lower threshold, e.g. on a machine with idle cores:
/// let p = Parallelism::Halves { min_len: 1 << 12 };
/// assert!(p.splits(1 << 12) && p.threads() == 2);
/// assert!(Parallelism::from_threads(3).is_err()); // only two-way splits exist
/// # Ok::<(), integrators::OptionsError>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parallelism {
    /// Every pass on the calling thread.
    #[default]
    Serial,
    /// Passes over at least `min_len` (≥ 2) components run in two halves.
    Halves {
        /// Smallest pass length that is split ([`Parallelism::DEFAULT_MIN_LEN`] by default).
        min_len: usize,
    },
}

impl Parallelism {
    /// Default split threshold, 2¹⁵ components (a pass of about 0.05 ms). The solving thread
    /// runs as a worker of its own two-thread pool, so a split costs a push to its own queue
    /// and, if the other worker is slow to take the half, the solving thread runs it itself;
    /// below about 3·10⁴ unknowns the split measured no faster (BENCHMARKS.md, "Two threads
    /// below 10⁶ unknowns").
    pub const DEFAULT_MIN_LEN: usize = 1 << 15;

    /// From a thread count: 1 → [`Parallelism::Serial`], 2 → [`Parallelism::Halves`] at
    /// [`Parallelism::DEFAULT_MIN_LEN`]; anything else is an error (passes split in two
    /// halves at most, so more threads would be silently unused).
    ///
    /// ```
    /// use integrators::Parallelism;
    /// assert_eq!(Parallelism::from_threads(1).unwrap(), Parallelism::Serial);
    /// assert!(Parallelism::from_threads(4).is_err()); // passes split in two halves at most
    /// ```
    pub fn from_threads(threads: usize) -> Result<Self, OptionsError> {
        match threads {
            1 => Ok(Parallelism::Serial),
            2 => Ok(Parallelism::Halves {
                min_len: Self::DEFAULT_MIN_LEN,
            }),
            _ => Err(OptionsError::Threads(threads)),
        }
    }

    /// Workers a pass may use: 1 or 2.
    ///
    /// ```
    /// use integrators::Parallelism;
    /// assert_eq!(Parallelism::from_threads(2).unwrap().threads(), 2);
    /// ```
    pub fn threads(self) -> usize {
        match self {
            Parallelism::Serial => 1,
            Parallelism::Halves { .. } => 2,
        }
    }

    /// Whether a pass over `n` components is split.
    ///
    /// ```
    /// use integrators::Parallelism;
    /// let p = Parallelism::Halves { min_len: 1000 };
    /// assert!(p.splits(1000) && !p.splits(999) && !Parallelism::Serial.splits(1 << 30));
    /// ```
    pub fn splits(self, n: usize) -> bool {
        match self {
            Parallelism::Serial => false,
            Parallelism::Halves { min_len } => n >= min_len,
        }
    }
}

/// An option outside its valid range: the message names the field and the range.
///
/// ```
/// use integrators::Options;
/// let bad = Options { rtol: -1.0, ..Default::default() };
/// let e = bad.validate().unwrap_err();
/// assert!(e.to_string().starts_with("rtol = -1 must be"), "{e}");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OptionsError {
    /// A field outside its range.
    #[error("{field} = {value} must be {range}")]
    OutOfRange {
        /// Field name (`linear_solver.rtol` for nested ones).
        field: &'static str,
        /// The value given, formatted.
        value: String,
        /// The valid range, in words.
        range: String,
    },
    /// An unknown name for an enumerated option.
    #[error("{field} = {value:?} must be {valid}")]
    UnknownName {
        /// Field name.
        field: &'static str,
        /// The name given.
        value: String,
        /// The valid names.
        valid: &'static str,
    },
    /// A thread count other than 1 or 2.
    #[error("threads = {0} must be 1 or 2 (passes are split in two halves at most)")]
    Threads(usize),
    /// A setting of one method given for another.
    #[error("{field} = {value} applies to method {applies_to} only, not {method}")]
    NotForMethod {
        /// The setting.
        field: &'static str,
        /// Its value, formatted.
        value: String,
        /// The method it belongs to.
        applies_to: &'static str,
        /// The method chosen.
        method: &'static str,
    },
}

fn out_of_range(
    field: &'static str,
    value: impl std::fmt::Display,
    range: impl Into<String>,
) -> OptionsError {
    OptionsError::OutOfRange {
        field,
        value: value.to_string(),
        range: range.into(),
    }
}

/// Settings of the BDF method ([`crate::MethodKind::Bdf`]), ignored by no other method: a
/// solve with another method rejects non-default values ([`Options::check_method`]).
///
/// ```
/// use integrators::{BdfOptions, MethodKind, Options};
/// let o = Options { bdf: BdfOptions { fixed_order: Some(2), ..Default::default() }, ..Default::default() };
/// assert!(o.check_method(MethodKind::Bdf.into()).is_ok());
/// assert_eq!(
///     o.check_method(MethodKind::Radau.into()).unwrap_err().to_string(),
///     "bdf.fixed_order = 2 applies to method bdf only, not radau"
/// );
/// let bound = Options { bdf: BdfOptions { newton_alpha_bound: true, ..Default::default() }, ..Default::default() };
/// assert_eq!(
///     bound.check_method(MethodKind::Esdirk.into()).unwrap_err().to_string(),
///     "bdf.newton_alpha_bound = true applies to method bdf only, not esdirk"
/// );
/// // the Newton matrices must be refreshed at some age
/// let stale = BdfOptions { max_jacobian_age: 0, ..Default::default() };
/// assert!(Options { bdf: stale, ..Default::default() }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BdfOptions {
    /// Maximum order (1..=5; default 5).
    pub max_order: usize,
    /// Use exactly this order (reached as soon as the history allows after each start)
    /// instead of selecting it; step-size control stays on. `None` (default): variable order
    /// up to `max_order`. Used for tolerance-sweep order studies.
    pub fixed_order: Option<usize>,
    /// Steps after which the Newton matrices are refreshed even though Newton converges
    /// (≥ 1; default 50). A slow Newton iteration refreshes them sooner whatever this is; a
    /// larger age saves Jacobian evaluations on problems whose Jacobian drifts slowly, and
    /// leaves the accuracy alone (Newton still converges to the same test).
    pub max_jacobian_age: usize,
    /// Whether the first Newton iteration of a step whose `α` differs from the factored one
    /// is tested with at least the convergence rate that difference implies (default `false`:
    /// IDA's test, with the rate estimate of earlier iterations alone).
    ///
    /// The matrix `∂F/∂y + α_f ∂F/∂ẏ` is reused while `r = α/α_f` stays within 25 % of 1,
    /// and the correction is scaled by `2/(1 + r)`. A linear mode whose two parts are both
    /// dissipative then keeps a fraction between 0 and `ρ_α = |r − 1|/(1 + r)` of its error per
    /// iteration, the largest where one part dominates. The rate estimate carried from earlier
    /// steps was measured before `α` moved and can be far smaller, so the first correction may
    /// pass the test while leaving an error of the order of the tolerance in the modes the
    /// stiffness dominates. With this set, that test takes the larger of the two rates, and
    /// such a step iterates once more. On a long quasi-static line, whose cell-scale modes are
    /// just those a cell-unit error norm weighs most, it saves a sixth to a third of the steps
    /// (the macroscale line of 10⁶ and 10⁵ cells).
    pub newton_alpha_bound: bool,
}

impl Default for BdfOptions {
    /// `max_order = 5`, variable order, Jacobians refreshed at least every 50 steps, IDA's
    /// Newton test.
    fn default() -> Self {
        Self {
            max_order: 5,
            fixed_order: None,
            max_jacobian_age: 50,
            newton_alpha_bound: false,
        }
    }
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
    ///
    /// ```
    /// use integrators::ErrorNorm;
    /// let (v, w) = ([3.0, 4.0], [1.0, 1.0]);
    /// assert_eq!(ErrorNorm::Max.of(&v, &w), 4.0);
    /// assert!((ErrorNorm::Rms.of(&v, &w) - 12.5f64.sqrt()).abs() < 1e-15);
    /// ```
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
    ///
    /// ```
    /// use integrators::ErrorNorm;
    /// assert_eq!(ErrorNorm::parse("max"), Ok(ErrorNorm::Max));
    /// assert_eq!(
    ///     ErrorNorm::parse("l2").unwrap_err().to_string(),
    ///     r#"norm = "l2" must be "rms" or "max""#
    /// );
    /// ```
    pub fn parse(s: &str) -> Result<Self, OptionsError> {
        match s {
            "rms" => Ok(ErrorNorm::Rms),
            "max" => Ok(ErrorNorm::Max),
            other => Err(OptionsError::UnknownName {
                field: "norm",
                value: other.to_string(),
                valid: "\"rms\" or \"max\"",
            }),
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
            bdf: BdfOptions::default(),
            suppress_algebraic: true,
            event_tol: 1e-12,
            force_fd_jacobian: false,
            max_newton_iters: 4,
            fixed_step: None,
            norm: ErrorNorm::Rms,
            linear_solver: LinearSolverChoice::Direct,
            parallel: Parallelism::Serial,
            land_on_outputs: None,
            interpolate_rates: false,
        }
    }
}

impl Options {
    /// Rejects settings that belong to another method than `method` (today: non-default
    /// [`BdfOptions`] with a method other than BDF), naming the setting.
    ///
    /// ```
    /// use integrators::{BdfOptions, MethodChoice, MethodKind, Options};
    /// // a BDF-only setting with another method is refused, naming it
    /// let o = Options { bdf: BdfOptions { max_order: 2, ..Default::default() }, ..Default::default() };
    /// assert!(o.check_method(MethodChoice::Builtin(MethodKind::Bdf)).is_ok());
    /// assert!(o.check_method(MethodChoice::Builtin(MethodKind::Radau)).is_err());
    /// ```
    pub fn check_method(&self, method: crate::MethodChoice) -> Result<(), OptionsError> {
        self.check_method_name(method.name())
    }

    /// As [`check_method`](Self::check_method), by the method's name.
    pub(crate) fn check_method_name(&self, method: &'static str) -> Result<(), OptionsError> {
        if method == "bdf" {
            return Ok(());
        }
        let d = BdfOptions::default();
        let bad = if self.bdf.max_order != d.max_order {
            Some(("bdf.max_order", self.bdf.max_order.to_string()))
        } else if self.bdf.newton_alpha_bound {
            Some(("bdf.newton_alpha_bound", "true".to_string()))
        } else {
            self.bdf
                .fixed_order
                .map(|k| ("bdf.fixed_order", k.to_string()))
        };
        match bad {
            Some((field, value)) => Err(OptionsError::NotForMethod {
                field,
                value,
                applies_to: "bdf",
                method,
            }),
            None => Ok(()),
        }
    }

    /// Checks ranges; the error names the field and its valid range.
    ///
    /// ```
    /// let o = integrators::Options { rtol: 2.0, ..Default::default() };
    /// assert_eq!(o.validate().unwrap_err().to_string(), "rtol = 2 must be in (0, 1)");
    /// ```
    pub fn validate(&self) -> Result<(), OptionsError> {
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(out_of_range("rtol", self.rtol, "in (0, 1)"));
        }
        if !(self.atol > 0.0 && self.atol.is_finite()) {
            return Err(out_of_range("atol", self.atol, "positive and finite"));
        }
        if let Some(h0) = self.h0 {
            if !(h0 > 0.0 && h0.is_finite()) {
                return Err(out_of_range("h0", h0, "positive and finite"));
            }
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(out_of_range("h_max", self.h_max, "positive"));
        }
        if !(self.h_min >= 0.0 && self.h_min < self.h_max) {
            return Err(out_of_range("h_min", self.h_min, "in [0, h_max)"));
        }
        if !(1..=5).contains(&self.bdf.max_order) {
            return Err(out_of_range(
                "bdf.max_order",
                self.bdf.max_order,
                "in 1..=5",
            ));
        }
        if self.bdf.max_jacobian_age == 0 {
            return Err(out_of_range("bdf.max_jacobian_age", 0, "at least 1"));
        }
        if self.max_newton_iters == 0 {
            return Err(out_of_range("max_newton_iters", 0, "at least 1"));
        }
        if self.max_steps == 0 {
            return Err(out_of_range("max_steps", 0, "at least 1"));
        }
        if let Some(h) = self.fixed_step {
            if !(h > 0.0 && h.is_finite()) {
                return Err(out_of_range("fixed_step", h, "positive and finite"));
            }
        }
        if let Some(k) = self.bdf.fixed_order {
            if !(1..=self.bdf.max_order).contains(&k) {
                return Err(out_of_range(
                    "bdf.fixed_order",
                    k,
                    format!("in 1..=bdf.max_order ({})", self.bdf.max_order),
                ));
            }
        }
        if let LinearSolverChoice::Iterative(it) = self.linear_solver {
            if !(it.rtol > 0.0 && it.rtol < 1.0) {
                return Err(out_of_range("linear_solver.rtol", it.rtol, "in (0, 1)"));
            }
            if it.max_iters == 0 {
                return Err(out_of_range("linear_solver.max_iters", 0, "at least 1"));
            }
            if !(it.newton_factor >= 0.0 && it.newton_factor < 1.0) {
                return Err(out_of_range(
                    "linear_solver.newton_factor",
                    it.newton_factor,
                    "in [0, 1)",
                ));
            }
        }
        if let Parallelism::Halves { min_len } = self.parallel {
            if min_len < 2 {
                return Err(out_of_range("parallel.min_len", min_len, "at least 2"));
            }
        }
        if self.event_tol.is_nan() || self.event_tol <= 0.0 {
            return Err(out_of_range("event_tol", self.event_tol, "positive"));
        }
        Ok(())
    }
}
