//! The first step after a resizing event ([`Method::resume`]): backward Euler over `h` and over
//! two halves, the halves accepted when their step-doubled error estimate, measured in cell
//! units through the error map, passes; up to `DOUBLING_TRIES` Newton failures and
//! `DOUBLING_ERROR_TRIES` error-test failures (more while the estimate falls at about the
//! halves' order, `CONVERGING_ORDER`) before the ordinary error test takes over.

use super::*;

impl Bdf {
    /// The first step after a [`Method::resume`]: backward Euler over `h` and over two halves
    /// of it; the halves are the accepted steps, and `‖y_halves − y_full‖` (weighted) is their
    /// error estimate (at order 1 the full step's error is twice the halves', so the
    /// difference estimates the halves' error). Unlike the predictor difference it needs no
    /// smoothness before the step, so a kink at the event costs nothing once its transient
    /// is shorter than `h/2`. On rejection `h` shrinks by the usual factor (the Newton
    /// matrices are kept: `α` changes by a refactorisation), after the first rejection to at
    /// most [`RESUME_GROWTH`] times the first step the previous resume accepted; after
    /// [`DOUBLING_TRIES`] failed attempts, or [`DOUBLING_ERROR_TRIES`] failed error tests
    /// whose estimate has stopped falling at [`CONVERGING_ORDER`], the ordinary step (error
    /// test against the restart's `ẏ`) takes over. On success the history is the post-event
    /// nodes `t + h, t + h/2, t`, from which the ordinary steps go on.
    pub(super) fn step_doubled(
        &mut self,
        sys: &mut System<'_>,
        t_stop: f64,
    ) -> Result<(), SolverError> {
        let opts = sys.opts;
        self.ensure_work(sys);
        let t0 = self.t;
        let mut h = self.h;
        let mut nef = 0usize;
        let mut ncf = 0usize;
        // the last failed error test's step and estimate, to read the estimate's order
        let mut last_error: Option<(f64, f64)> = None;
        let mut full = sys.take_vec();
        loop {
            let h_floor = opts.h_min.max(1e-14 * t0.abs());
            let remaining = t_stop - t0;
            let (h_try, t_new) = if h >= remaining * (1.0 - 1e-12) {
                (remaining, t_stop)
            } else {
                (h, t0 + h)
            };
            let t_half = t0 + 0.5 * h_try;
            // the full step, then the first half (both from the double node at t0)
            let mut outcome = self.be_solve(sys, t_new);
            if outcome.is_ok() {
                full.copy_from_slice(&self.ycur);
                outcome = self.be_solve(sys, t_half);
            }
            let mut half_pushed = false;
            if outcome.is_ok() {
                self.push_accepted(sys, t_half);
                half_pushed = true;
                outcome = self.be_solve(sys, t_new);
            }
            let fail = match outcome {
                Ok(()) => None,
                Err(NewtonFail::Fatal(mut e)) => {
                    e.t = t0;
                    return Err(e);
                }
                Err(NewtonFail::NoConvergence(c)) => {
                    self.jac_valid = false;
                    sys.stats.newton_failures += 1;
                    Some((0.25, LastFailure::Newton(c)))
                }
                Err(NewtonFail::Recoverable(r, c)) => Some((0.25, LastFailure::Recoverable(r, c))),
            };
            let err = if fail.is_none() {
                let w = self.ewt();
                let map = sys.error_map();
                if map.is_empty() {
                    let d = self
                        .ycur
                        .iter()
                        .zip(&full)
                        .zip(w)
                        .map(|((a, b), w)| (a - b) * w);
                    match opts.norm {
                        ErrorNorm::Max => d.fold(0.0f64, |m, x| {
                            if x.is_nan() || m.is_nan() {
                                f64::NAN
                            } else {
                                m.max(x.abs())
                            }
                        }),
                        ErrorNorm::Rms => {
                            (d.map(|x| x * x).sum::<f64>() / self.n.max(1) as f64).sqrt()
                        }
                    }
                } else {
                    // the estimate is an error vector like any other: measured as cell-level
                    // quantities (differences with the partner, end rows), so a shift common to
                    // a whole run of boundaries — the far side of a dividing cell moving with
                    // its extra growth — is no error of any cell (`full` is reused for it)
                    for (f, a) in full.iter_mut().zip(&self.ycur) {
                        *f = a - *f;
                    }
                    map_norm(map, &full, w, opts.norm, self.parallel)
                }
            } else {
                f64::NAN
            };
            let factor = match &fail {
                Some((f, _)) => {
                    ncf += 1;
                    Some(*f)
                }
                // (NaN fails)
                None if err.is_nan() || err > 1.0 => {
                    nef += 1;
                    sys.stats.error_test_failures += 1;
                    let r = 0.9 * (2.0 * err).powf(-0.5);
                    Some(if r.is_finite() {
                        r.clamp(0.1, 0.9)
                    } else {
                        0.25
                    })
                }
                None => None,
            };
            if let Some(f) = factor {
                log::debug!(
                    "BDF step-doubled first step after an event rejected at t = {t0:e}, \
                     h = {h_try:e}: {}",
                    if fail.is_some() {
                        "Newton failed".to_string()
                    } else {
                        format!("error estimate {err:.3e} (tolerance 1)")
                    }
                );
                // (the error test compares two solutions; no single unknown is named)
                let (cause, component) = match &fail {
                    Some((_, last)) => last.cause(),
                    None => LastFailure::ErrorTest(None).cause(),
                };
                sys.reject_step(t0, h_try, cause, component);
                if half_pushed {
                    self.pop_accepted(sys, t0);
                }
                h = h_try * f;
                // after the first failure, straight to about where the last resume succeeded
                if nef + ncf == 1 && self.resume_h > 0.0 {
                    h = h.min(RESUME_GROWTH * self.resume_h);
                }
                // an estimate falling at about the halves' order (2) has found the transient
                // shorter than the step: go on doubling, cut by that observed order
                let converging = match (fail.is_none(), last_error) {
                    (true, Some((h_prev, e_prev))) => {
                        let p = (e_prev / err).ln() / (h_prev / h_try).ln();
                        (p >= CONVERGING_ORDER && p.is_finite())
                            .then(|| h_try * (0.5 / err).powf(1.0 / p).clamp(0.1, 0.9))
                    }
                    _ => None,
                };
                if fail.is_none() {
                    last_error = Some((h_try, err));
                }
                let out_of_tries = nef >= DOUBLING_ERROR_TRIES && converging.is_none();
                if let (true, Some(h_conv)) = (nef >= DOUBLING_ERROR_TRIES, converging) {
                    h = h_conv;
                }
                if out_of_tries || nef + ncf >= DOUBLING_TRIES || h < h_floor {
                    // the transient is not shorter than the step: resolve it with the
                    // ordinary error test from the same restart node
                    sys.give_vec(full);
                    self.doubling = false;
                    self.h = h.max(h_floor);
                    return self.step_once(sys, t_stop);
                }
                continue;
            }
            self.push_accepted(sys, t_new);
            sys.give_vec(full);
            // the restart's double node carried the pre-event ẏ, which the kink made stale:
            // keep t0 as a plain node
            let len = self.times.len();
            if len >= 2 && self.times[len - 1] == self.times[len - 2] {
                self.times.pop_back();
                if let Some(v) = self.vals.pop_back() {
                    sys.give_vec(v);
                }
            }
            self.doubling = false;
            self.k = 1;
            // dense output (and so event location) over the whole [t0, t0 + h]: the quadratic
            // through the three post-event nodes
            self.t_prev = t0;
            self.k_last = 2;
            self.steps_at_order = 2;
            // the halves' error was `err` at step h/2; aim at 0.5 for the next step, at most
            // doubling the full step
            let r = (0.5 / (err + 1e-4)).sqrt();
            self.h = (0.5 * h_try * r.clamp(1.0, 4.0)).min(opts.h_max);
            if nef > 0 || ncf > 0 {
                self.h = self.h.min(0.5 * h_try);
            }
            return Ok(());
        }
    }

    /// Backward Euler from the newest history node (predictor of order 1) to `t_new`; the
    /// solution is left in `ycur`/`ẏcur`.
    pub(super) fn be_solve(&mut self, sys: &mut System<'_>, t_new: f64) -> Result<(), NewtonFail> {
        self.k = 1;
        self.predict(sys, 2, t_new);
        let alpha = self.alpha(1, t_new);
        self.jac_current = false;
        let mut outcome = self.newton(sys, t_new, alpha);
        if let Err(NewtonFail::NoConvergence(_)) = outcome {
            if !self.jac_current {
                self.jac_valid = false;
                self.predict(sys, 2, t_new);
                outcome = self.newton(sys, t_new, alpha);
            }
        }
        outcome
    }

    /// Moves the Newton solution at `t_new` into the history as an accepted step.
    pub(super) fn push_accepted(&mut self, sys: &mut System<'_>, t_new: f64) {
        self.t_prev = self.t;
        self.t = t_new;
        let buf = if self.times.len() >= MAX_NODES {
            self.times.pop_back();
            self.vals.pop_back().expect("history")
        } else {
            sys.take_vec()
        };
        let y_new = std::mem::replace(&mut self.ycur, buf);
        std::mem::swap(&mut self.yp, &mut self.ypcur);
        self.times.push_front(t_new);
        self.vals.push_front(y_new);
        self.k_last = 1;
        self.accepted += 1;
        self.steps_since_jac += 1;
        self.steps_since_start += 1;
    }

    /// Undoes [`push_accepted`](Bdf::push_accepted) back to the restart node at `t0` (whose
    /// derivative is `ẏ0`).
    pub(super) fn pop_accepted(&mut self, sys: &mut System<'_>, t0: f64) {
        self.times.pop_front();
        if let Some(v) = self.vals.pop_front() {
            sys.give_vec(v);
        }
        self.t = t0;
        self.t_prev = t0;
        self.yp.copy_from_slice(&self.yp0);
        self.accepted -= 1;
        self.steps_since_jac = self.steps_since_jac.saturating_sub(1);
        self.steps_since_start = self.steps_since_start.saturating_sub(1);
    }
}
