//! What the driver reports while it integrates: the [`Observer`] trait (outputs, accepted steps,
//! rejected steps with their cause and worst unknown, handled events) and the records it is
//! handed. [`crate::Solver::solve_observed`] takes one; [`crate::Solver::solve_with`] wraps a
//! plain output closure in [`Outputs`].
//!
//! Methods report a rejected attempt through [`crate::System::reject_step`]; the driver
//! passes each on after the method's step returns (also when the step fails, so an observer
//! sees the rejections that led to a failure), then the accepted step, then events and
//! outputs in time order.

use crate::error::RecoverableCause;
use crate::solver::EventRecord;

/// Receives what happens during a solve. Every method has a default that does nothing:
/// implement the ones you need.
///
/// ```
/// use integrators::observer::{AcceptedStep, Observer, RejectedStep};
/// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
/// /// ẏ = −1000 (y − cos t): stiff, so the first steps are rejected a few times
/// struct Stiff;
/// impl Problem for Stiff {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> { r[0] = yp[0] + 1000.0 * (y[0] - t.cos()); Ok(()) }
/// }
/// /// The step sizes taken and the times of rejected attempts.
/// #[derive(Default)]
/// struct StepLog { h: Vec<f64>, rejected: Vec<f64> }
/// impl<P> Observer<P> for StepLog {
///     fn accepted(&mut self, _: &P, step: &AcceptedStep, _y: &[f64]) {
///         self.h.push(step.t - step.t_prev);
///     }
///     fn rejected(&mut self, _: &P, step: &RejectedStep) { self.rejected.push(step.t); }
/// }
/// let mut log = StepLog::default();
/// let solver = Solver::new(MethodKind::Bdf, Options::default());
/// let sol = solver.solve_observed(&mut Stiff, 0.0, &[2.0], &[1.0], &mut log).unwrap();
/// assert_eq!(log.h.len(), sol.stats.steps);
/// assert_eq!(log.rejected.len(), sol.stats.rejected_steps);
/// assert!((log.h.iter().sum::<f64>() - 1.0).abs() < 1e-12);
/// ```
pub trait Observer<P: ?Sized> {
    /// A requested output time `t` reached, with the state and its derivative there.
    fn output(&mut self, _problem: &P, _t: f64, _y: &[f64], _yp: &[f64]) {}

    /// A step accepted, with the state at its end (`step.t`).
    fn accepted(&mut self, _problem: &P, _step: &AcceptedStep, _y: &[f64]) {}

    /// An attempted step rejected (it is retried with a smaller step).
    fn rejected(&mut self, _problem: &P, _step: &RejectedStep) {}

    /// An event handled (the problem has acted on it; for a resize `y` has the new length).
    fn event(&mut self, _problem: &P, _event: &EventRecord, _y: &[f64]) {}
}

impl<P: ?Sized, O: Observer<P> + ?Sized> Observer<P> for &mut O {
    fn output(&mut self, problem: &P, t: f64, y: &[f64], yp: &[f64]) {
        (**self).output(problem, t, y, yp);
    }
    fn accepted(&mut self, problem: &P, step: &AcceptedStep, y: &[f64]) {
        (**self).accepted(problem, step, y);
    }
    fn rejected(&mut self, problem: &P, step: &RejectedStep) {
        (**self).rejected(problem, step);
    }
    fn event(&mut self, problem: &P, event: &EventRecord, y: &[f64]) {
        (**self).event(problem, event, y);
    }
}

/// An observer of outputs only, from a closure `(problem, t, y, ẏ)`.
///
/// ```
/// use integrators::observer::{Observer, Outputs};
/// let mut seen = Vec::new();
/// let mut o = Outputs(|_: &(), t: f64, _: &[f64], _: &[f64]| seen.push(t));
/// o.output(&(), 0.5, &[], &[]);
/// assert_eq!(seen, [0.5]);
/// ```
pub struct Outputs<F>(pub F);

impl<P: ?Sized, F: FnMut(&P, f64, &[f64], &[f64])> Observer<P> for Outputs<F> {
    fn output(&mut self, problem: &P, t: f64, y: &[f64], yp: &[f64]) {
        (self.0)(problem, t, y, yp);
    }
}

/// An accepted step from `t_prev` to `t`.
///
/// ```
/// use integrators::observer::AcceptedStep;
/// let s = AcceptedStep { t_prev: 0.5, t: 0.75, substeps: 1 };
/// assert_eq!(s.t - s.t_prev, 0.25); // the step size taken
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcceptedStep {
    /// Start of the step.
    pub t_prev: f64,
    /// End of the step.
    pub t: f64,
    /// Accepted steps it counts for in [`crate::Stats::steps`]: 1, or 2 for BDF's step-doubled
    /// restart after an event (two half steps reported as one).
    pub substeps: usize,
}

/// A rejected step attempt: from where, how long, why, and the unknown that decided it.
///
/// ```
/// use integrators::observer::{RejectCause, RejectedStep};
/// use integrators::RecoverableCause;
/// let r = RejectedStep {
///     t: 1.0,
///     h: 0.1,
///     cause: RejectCause::Recoverable(RecoverableCause::Rejected("cell 4 collapsed".into())),
///     component: Some(7),
/// };
/// assert_eq!(r.to_string(), "cell 4 collapsed (step from t = 1 with h = 1.0e-1, unknown 7)");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RejectedStep {
    /// Start of the attempted step.
    pub t: f64,
    /// Its size.
    pub h: f64,
    /// Why it was rejected.
    pub cause: RejectCause,
    /// The unknown with the largest weighted error (error test), the slowest to converge
    /// (Newton), or the one the problem or the factorisation named; `None` if not known.
    pub component: Option<usize>,
}

impl std::fmt::Display for RejectedStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} (step from t = {} with h = {:.1e}",
            self.cause, self.t, self.h
        )?;
        if let Some(c) = self.component {
            write!(f, ", unknown {c}")?;
        }
        f.write_str(")")
    }
}

/// Why an attempted step was rejected.
///
/// ```
/// use integrators::observer::RejectCause;
/// assert_eq!(RejectCause::ErrorTest.to_string(), "local error test failed");
/// assert_eq!(RejectCause::Newton.to_string(), "Newton iteration did not converge");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RejectCause {
    /// The local error estimate exceeded the tolerance.
    #[error("local error test failed")]
    ErrorTest,
    /// Newton's iteration diverged or converged too slowly.
    #[error("Newton iteration did not converge")]
    Newton,
    /// The problem rejected a state, a residual was not finite, or a factorisation met a zero
    /// pivot.
    #[error("{0}")]
    Recoverable(RecoverableCause),
}
