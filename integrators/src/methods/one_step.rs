//! The step loop shared by the one-step methods (ESDIRK, Radau IIA, Dormand–Prince): plan the
//! step (estimating the starting step on the first call after a start), clip it to the stop
//! time, attempt it, and on rejection retry with the method's proposed step until it succeeds,
//! falls below the round-off floor, or fails too often in a row. Two rules bound the proposal:
//! from the second error-test failure in a row it is at most
//! [`REPEATED_ERROR_FAILURE_CAP`] of the rejected step, and a restart's first rejection
//! retries at most [`RESUME_GROWTH`] times the first step the previous restart accepted.
//!
//! A method supplies only [`OneStep::attempt`] (one step of size `h`, with its own error test
//! and step proposal) and a few accessors; [`step`] is its `Method::step`.

use crate::error::{ErrorKind, SolverError};
use crate::methods::radau::{step_too_small, Fail};
use crate::system::System;

/// Consecutive rejected attempts after which a step gives up.
pub(crate) const MAX_CONSECUTIVE_FAILURES: usize = 60;

/// The largest retry step, as a fraction of the rejected one, from the second error-test
/// failure in a row (ARKODE's `etamxf` after `small_nef` failures). A transient far faster
/// than the step (the daughters' relaxation after a division under drag) gives an error
/// estimate that hardly falls with `h` until `h` reaches its time scale, so the method's own
/// proposal, `0.9·err^(−1/(q+1))` with `err` just above 1, shrinks the step by about 0.9 per
/// try: ESDIRK on a dividing line at K = 1e-5 failed 60 times in a row from h = 1.1e-2 down
/// to 3e-6 and stopped. With the cap the same retries span a factor 0.3 each.
pub(crate) const REPEATED_ERROR_FAILURE_CAP: f64 = 0.3;

/// After the first rejection of a restart, the retry is at most this multiple of the first
/// step the previous restart accepted (BDF's `RESUME_GROWTH`): the restarts of one solve
/// follow alike events (the divisions of a line), so their transients ask for alike steps.
pub(crate) const RESUME_GROWTH: f64 = 2.0;

/// A one-step method's memory of its restarts after events: whether the first step after a
/// restart is still to be accepted, and the first step the last restart accepted.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Resume {
    pending: bool,
    first_h: f64,
}

impl Resume {
    /// At a start: a start of a method already started is a restart after an event.
    pub(crate) fn on_start(&mut self, was_started: bool) {
        self.pending = was_started;
    }
}

/// Outcome of one step attempt.
pub(crate) enum Attempt {
    /// The step was taken; the method has advanced its state and proposed the next `h`.
    Accepted,
    /// The step was rejected for this reason; retry with this step size.
    Rejected(Fail, f64),
}

/// What the shared loop needs from a one-step method.
pub(crate) trait OneStep {
    /// Whether [`crate::Method::start`] has been called.
    fn started(&self) -> bool;
    /// Current time.
    fn time(&self) -> f64;
    /// Current `(y, ẏ)` (copied for the starting-step estimate, once per start).
    fn state(&self) -> (Vec<f64>, Vec<f64>);
    /// Step size to try next (NaN: estimate it, as after a start without a step hint).
    fn planned_h(&self) -> f64;
    /// Sets the step size to try next (also the method's "previous step" after a start).
    fn set_h(&mut self, h: f64, after_start: bool);
    /// The method's memory of its restarts ([`Resume`]).
    fn resume(&mut self) -> &mut Resume;
    /// Order of the local error estimate minus one, for the starting-step estimate.
    fn start_order(&self) -> usize;
    /// Whether `∂F/∂ẏ` is known to be the identity.
    fn unit_mass(&self) -> bool {
        false
    }
    /// One attempt from the current time to `t_new = t + h` (`fixed`: no error test).
    fn attempt(
        &mut self,
        sys: &mut System<'_>,
        h: f64,
        fixed: bool,
        t_new: f64,
    ) -> Result<Attempt, SolverError>;
}

/// Implements [`OneStep`] for a method struct with the fields `started`, `t`, `y`, `yp`, `h`
/// and `resume` (plus `h_old`, reset at a start, when `h_old: true`), forwarding `attempt` to
/// the type's inherent `attempt` and answering `unit_mass` with the given expression of `self`.
macro_rules! impl_one_step {
    ($ty:ident, order: $order:expr, h_old: $h_old:tt, unit_mass: |$s:ident| $unit:expr) => {
        impl $crate::methods::one_step::OneStep for $ty {
            fn started(&self) -> bool {
                self.started
            }
            fn time(&self) -> f64 {
                self.t
            }
            fn state(&self) -> (Vec<f64>, Vec<f64>) {
                (self.y.clone(), self.yp.clone())
            }
            fn planned_h(&self) -> f64 {
                self.h
            }
            fn set_h(&mut self, h: f64, after_start: bool) {
                self.h = h;
                $crate::methods::one_step::impl_one_step!(@h_old $h_old, self, h, after_start);
            }
            fn start_order(&self) -> usize {
                $order
            }
            fn resume(&mut self) -> &mut $crate::methods::one_step::Resume {
                &mut self.resume
            }
            fn unit_mass(&self) -> bool {
                let $s = self;
                $unit
            }
            fn attempt(
                &mut self,
                sys: &mut $crate::system::System<'_>,
                h: f64,
                fixed: bool,
                t_new: f64,
            ) -> Result<$crate::methods::one_step::Attempt, $crate::error::SolverError> {
                $ty::attempt(self, sys, h, fixed, t_new)
            }
        }
    };
    (@h_old true, $self:ident, $h:ident, $after:ident) => {
        if $after {
            $self.h_old = $h;
        }
    };
    (@h_old false, $self:ident, $h:ident, $after:ident) => {
        let _ = ($h, $after);
    };
}
pub(crate) use impl_one_step;

/// One accepted step of `m` towards `t_stop` (never past it).
pub(crate) fn step<M: OneStep>(
    m: &mut M,
    sys: &mut System<'_>,
    t_stop: f64,
) -> Result<usize, SolverError> {
    super::check_step_request(m.started(), m.time(), t_stop)?;
    if m.planned_h().is_nan() {
        let (y, yp) = m.state();
        let h = sys.initial_step(
            m.time(),
            &y,
            &yp,
            t_stop - m.time(),
            m.start_order(),
            m.unit_mass(),
        );
        m.set_h(h, true);
    }
    let fixed = sys.opts.fixed_step;
    let mut failures = 0usize;
    let mut error_failures = 0usize;
    loop {
        let t = m.time();
        let remaining = t_stop - t;
        let planned = match fixed {
            Some(hf) => hf,
            None => m.planned_h().min(sys.opts.h_max),
        };
        let (h, t_new, clipped) = if planned * (1.0 + 1e-4) >= remaining {
            (remaining, t_stop, true)
        } else {
            (planned, t + planned, false)
        };
        if fixed.is_none() && !clipped && step_too_small(h, t, sys.opts.h_min) {
            return Err(SolverError::new(ErrorKind::StepSizeTooSmall { h }, t, None));
        }
        match m.attempt(sys, h, fixed.is_some(), t_new)? {
            Attempt::Accepted => {
                let resume = m.resume();
                if resume.pending {
                    resume.pending = false;
                    resume.first_h = h;
                }
                if clipped && fixed.is_none() {
                    // a step shortened to land on the stop must not shrink the next one
                    let next = m.planned_h().max(planned.min(sys.opts.h_max));
                    m.set_h(next, false);
                }
                return Ok(1);
            }
            Attempt::Rejected(fail, mut h_new) => {
                if matches!(fail, Fail::ErrorTest { .. }) && fixed.is_none() {
                    error_failures += 1;
                    if error_failures >= 2 {
                        h_new = h_new.min(REPEATED_ERROR_FAILURE_CAP * h);
                    }
                } else {
                    error_failures = 0;
                }
                // a restart's first rejection: straight to about where the last one succeeded
                let resume = *m.resume();
                if failures == 0 && resume.pending && resume.first_h > 0.0 && fixed.is_none() {
                    h_new = h_new.min(RESUME_GROWTH * resume.first_h);
                }
                log::debug!(
                    "{} step rejected at t = {t:e}, h = {h:e}: {fail:?}; retrying with h = {h_new:e}",
                    std::any::type_name::<M>().rsplit("::").next().unwrap_or("one-step")
                );
                let (cause, component) = fail.cause();
                sys.reject_step(t, h, cause, component);
                failures += 1;
                if fixed.is_some() {
                    return Err(fail.into_error(t, h, false));
                }
                if failures >= MAX_CONSECUTIVE_FAILURES {
                    return Err(fail.into_error(t, h_new, false));
                }
                if step_too_small(h_new, t, sys.opts.h_min) {
                    return Err(fail.into_error(t, h_new, true));
                }
                m.set_h(h_new, false);
            }
        }
    }
}

/// The step to try first after a start: the caller's hint or `Options::h0` (capped at `h_max`),
/// else NaN — estimated by [`step`] at the first call, when the distance to the stop is known.
pub(crate) fn start_h(hint: Option<f64>, opts: &crate::Options) -> f64 {
    match hint.or(opts.h0).filter(|v| *v > 0.0 && v.is_finite()) {
        Some(v) => v.min(opts.h_max),
        None => f64::NAN,
    }
}

/// Shared precondition of `start`: `y` and `ẏ` have the problem's length and are finite.
pub(crate) fn check_start(n: usize, t: f64, y: &[f64], yp: &[f64]) -> Result<(), SolverError> {
    if y.len() != n || yp.len() != n {
        return Err(SolverError::new(
            ErrorKind::InvalidInput(format!(
                "state length {} / derivative length {} differ from dim() = {n}",
                y.len(),
                yp.len()
            )),
            t,
            None,
        ));
    }
    if !t.is_finite() || y.iter().chain(yp).any(|v| !v.is_finite()) {
        return Err(SolverError::new(ErrorKind::NonFinite, t, None));
    }
    Ok(())
}
