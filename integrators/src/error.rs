//! Typed solver errors. Every failure says when (`t`), where (the worst component, if known) and
//! why; [`SolveFailure`] also carries everything computed before the failure.

use crate::solver::Solution;

/// What went wrong.
///
/// ```
/// use integrators::ErrorKind;
/// assert_eq!(ErrorKind::SingularMatrix { column: 3 }.to_string(), "singular iteration matrix (zero pivot in column 3)");
/// assert_eq!(ErrorKind::StepSizeTooSmall { h: 1e-14 }.to_string(), "step size 1e-14 too small");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The step size fell below `Options::h_min` (or round-off level) while the error test or
    /// Newton kept failing.
    #[error("step size {h:e} too small")]
    StepSizeTooSmall {
        /// The step size at failure.
        h: f64,
    },
    /// Newton's method did not converge even after Jacobian refresh and step reductions.
    #[error("Newton iteration failed to converge")]
    NewtonFailure,
    /// The iteration matrix could not be factorised (zero pivot).
    #[error("singular iteration matrix (zero pivot in column {column})")]
    SingularMatrix {
        /// Column of the zero pivot.
        column: usize,
    },
    /// A residual, Jacobian or state value was NaN or infinite.
    #[error("non-finite value")]
    NonFinite,
    /// The problem's residual rejected the trial states (`ResidualError::Recoverable`) at every
    /// retry of a step, down to the smallest step; the problem's own reason is kept.
    #[error("the problem rejected the state at every retry: {0}")]
    Rejected(String),
    /// More than `Options::max_steps` steps.
    #[error("maximum number of steps (max_steps = {0}) exceeded")]
    TooManySteps(usize),
    /// The tolerances ask for more accuracy than the stored state resolves: at the reported
    /// component the round-off of its tested quantity is `ratio` of its tolerance
    /// ([`crate::ErrorMap::roundoff_ratio`]), above [`crate::solver::ROUNDOFF_LIMIT`]. Its error
    /// test would measure rounding noise and the steps shrink without end (a line of 4 000
    /// cells crushed to λ = 0.026 at rtol 1e-10 took 10⁶ steps for 0.4 time units).
    #[error(
        "tolerance too close to round-off: the round-off of this component's tested quantity is \
         {} of its tolerance (its error test would measure rounding noise); raise rtol \
         and atol at least {}-fold",
        short_number((ratio * 100.0).round() / 100.0),
        short_number((ratio / crate::solver::ROUNDOFF_ADVISED).ceil())
    )]
    TooMuchAccuracy {
        /// Round-off of the component's tested quantity over its tolerance.
        ratio: f64,
    },
    /// The iteration matrix held a NaN or infinite entry (the problem's derivatives
    /// overflowed), at every retry of a step.
    #[error("non-finite iteration matrix entry {value} in row {row}, column {column} (the problem's derivatives overflowed)")]
    NonFiniteMatrix {
        /// Row (equation) of the entry.
        row: usize,
        /// Column (unknown) of the entry.
        column: usize,
        /// The entry.
        value: f64,
    },
    /// The solve's [`crate::interrupt::Interrupt`] was raised (e.g. by SIGINT or a Python
    /// `KeyboardInterrupt`); the steps taken before it are kept.
    #[error("interrupted")]
    Interrupted,
    /// The problem's residual reported a fatal error.
    #[error("residual error: {0}")]
    Residual(String),
    /// Consistent initial ẏ (or algebraic y) could not be found.
    #[error("consistent initialisation failed: {0}")]
    Initialisation(String),
    /// An explicit method's steps are held at its stability limit (the problem is stiff here;
    /// see [`crate::method::StabilityLimit`]) and the rest of the span at the current step
    /// would take more than `Options::max_steps` steps: the solve stops now rather than creep
    /// towards that limit.
    #[error(
        "the problem is stiff here: the explicit method's step is held at its stability limit \
         (h·ρ = {h_rho:.2}, ρ the problem's fastest rate), and the rest of the span at that step \
         would take about {projected_steps:.1e} steps, beyond max_steps = {max_steps}; use an \
         implicit method (bdf, esdirk or radau)"
    )]
    Stiff {
        /// `h·ρ` at the method's last stiffness test.
        h_rho: f64,
        /// Steps taken plus the rest of the span over the current step.
        projected_steps: f64,
        /// `Options::max_steps`.
        max_steps: usize,
    },
    /// The method cannot handle this problem (e.g. Dormand–Prince with algebraic components).
    #[error("method not applicable: {0}")]
    NotApplicable(String),
    /// Invalid input (dimensions, tolerances, output times).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The problem's [`crate::ErrorMap`] does not fit it.
    #[error("invalid error map: {0}")]
    ErrorMap(#[from] crate::ErrorMapError),
}

/// Why a step attempt failed in a way a smaller step may cure (the reason of a
/// [`crate::system::StepFailure::Recoverable`]).
///
/// ```
/// use integrators::{ErrorKind, RecoverableCause};
/// let c = RecoverableCause::SingularMatrix { column: 3 };
/// assert_eq!(c.to_string(), "singular iteration matrix (zero pivot in column 3)");
/// assert_eq!(ErrorKind::from(c), ErrorKind::SingularMatrix { column: 3 });
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RecoverableCause {
    /// The residual had a NaN or infinite component.
    #[error("non-finite residual component {component} ({value})")]
    NonFiniteResidual {
        /// The first non-finite component.
        component: usize,
        /// Its value.
        value: f64,
    },
    /// A factorisation met a zero pivot.
    #[error("singular iteration matrix (zero pivot in column {column})")]
    SingularMatrix {
        /// Column of the zero pivot.
        column: usize,
    },
    /// A factorisation failed on a NaN or infinite entry of the matrix.
    #[error("non-finite iteration matrix entry {value} in row {row}, column {column}")]
    NonFiniteMatrix {
        /// Row (equation) of the entry.
        row: usize,
        /// Column (unknown) of the entry.
        column: usize,
        /// The entry.
        value: f64,
    },
    /// The problem rejected the state ([`crate::ResidualError::Recoverable`]), with its reason.
    #[error("{0}")]
    Rejected(String),
}

impl From<RecoverableCause> for ErrorKind {
    /// The error of a step abandoned after recoverable failures whose last cause was this:
    /// the solver's own non-finite-residual and zero-pivot failures keep their kinds; the
    /// problem's own reason is kept verbatim as [`ErrorKind::Rejected`].
    fn from(cause: RecoverableCause) -> Self {
        match cause {
            RecoverableCause::NonFiniteResidual { .. } => ErrorKind::NonFinite,
            RecoverableCause::SingularMatrix { column } => ErrorKind::SingularMatrix { column },
            RecoverableCause::NonFiniteMatrix { row, column, value } => {
                ErrorKind::NonFiniteMatrix { row, column, value }
            }
            RecoverableCause::Rejected(reason) => ErrorKind::Rejected(reason),
        }
    }
}

/// A number as a message shows it: the shortest decimal that reads back as `v`, plainly
/// between 1e-4 and 1e9 (`2.5`), otherwise in scientific notation (`1.25e-130`,
/// where `Display` writes 130 digits).
///
/// ```
/// use integrators::error::short_number;
/// assert_eq!(short_number(2.5), "2.5");
/// assert_eq!(short_number(0.0), "0");
/// assert_eq!(short_number(19213991.25), "19213991.25");
/// assert_eq!(short_number(1.25e-130), "1.25e-130");
/// assert_eq!(short_number(-3e300), "-3e300");
/// assert_eq!(short_number(f64::INFINITY), "inf");
/// ```
pub fn short_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A solver error with its location in time and state.
///
/// ```
/// use integrators::{ErrorKind, SolverError};
/// let e = SolverError::new(ErrorKind::NewtonFailure, 2.5, Some(7));
/// assert_eq!(e.to_string(), "at t = 2.5: Newton iteration failed to converge (worst component 7)");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("at t = {}: {kind}{}", short_number(*.t), component.map(|c| format!(" (worst component {c})")).unwrap_or_default())]
pub struct SolverError {
    /// What went wrong.
    pub kind: ErrorKind,
    /// Time of failure (the start of the failing step).
    pub t: f64,
    /// Component with the largest weighted error or residual, if known.
    pub component: Option<usize>,
}

impl SolverError {
    /// Creates an error at time `t`.
    ///
    /// ```
    /// use integrators::{ErrorKind, SolverError};
    /// let e = SolverError::new(ErrorKind::NonFinite, 0.5, None);
    /// assert_eq!(e.to_string(), "at t = 0.5: non-finite value");
    /// ```
    pub fn new(kind: ErrorKind, t: f64, component: Option<usize>) -> Self {
        Self { kind, t, component }
    }
}

/// A failed solve: the error and the partial solution up to the failure.
///
/// ```
/// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> { r[0] = yp[0] + y[0]; Ok(()) }
/// }
/// let opts = Options { max_steps: 3, ..Options::default() };
/// let f = Solver::new(MethodKind::Bdf, opts).solve(&mut Decay, 0.0, &[1.0], &[100.0]).unwrap_err();
/// assert_eq!(f.partial.stats.steps, 3); // the work done before the failure is kept
/// assert!(f.to_string().contains("3"), "{f}");
/// ```
#[derive(Clone, Debug, thiserror::Error)]
#[error("{error}")]
pub struct SolveFailure {
    /// The error.
    pub error: SolverError,
    /// Output produced before the failure (outputs at requested times already passed, events,
    /// statistics, and the last accepted state).
    pub partial: Box<Solution>,
}
