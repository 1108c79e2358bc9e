//! One BDF step ([`Method::step`]): predictor, simplified Newton on the iteration matrix,
//! the local error test and the choice of the next order and step size, with the
//! rejection/retry logic.

use super::*;

impl Bdf {
    /// One [`Method::step`]: the accepted steps it takes are counted in `accepted`.
    pub(super) fn step_once(
        &mut self,
        sys: &mut System<'_>,
        t_stop: f64,
    ) -> Result<(), SolverError> {
        if !self.started {
            return Err(SolverError::new(
                ErrorKind::InvalidInput("BDF step before start".into()),
                self.t,
                None,
            ));
        }
        // written to reject NaN too
        if t_stop.partial_cmp(&self.t) != Some(std::cmp::Ordering::Greater) {
            return Err(SolverError::new(
                ErrorKind::InvalidInput(format!(
                    "t_stop = {} is not after t = {}",
                    crate::error::short_number(t_stop),
                    crate::error::short_number(self.t)
                )),
                self.t,
                None,
            ));
        }
        if self.doubling {
            return self.step_doubled(sys, t_stop);
        }
        let opts = sys.opts;
        if self.h_pending {
            self.h = sys.initial_step(self.t, &self.vals[0], &self.yp0, t_stop - self.t, 1, false);
            self.h_pending = false;
        }
        self.ensure_work(sys);
        let fixed = opts.fixed_step;
        if let Some(hf) = fixed {
            self.h = hf;
        }

        let mut nef = 0usize;
        let mut ncf = 0usize;
        let mut last = LastFailure::ErrorTest(None);
        let mut h = self.h;
        // the error estimate of this step's last rejected trial
        let mut last_err = f64::INFINITY;
        loop {
            let h_floor = opts.h_min.max(1e-14 * self.t.abs());
            let remaining = t_stop - self.t;
            let (h_try, t_new) = if h >= remaining * (1.0 - 1e-12) {
                (remaining, t_stop)
            } else {
                (h, self.t + h)
            };
            let k = self.k.min(self.times.len() - 1);
            self.k = k;
            let m = k + 1;
            // predictor (and the weights from the state at the start of the step)
            self.predict(sys, m, t_new);
            let alpha = self.alpha(k, t_new);
            self.jac_current = false;
            let mut outcome = self.newton(sys, t_new, alpha);
            if let Err(NewtonFail::NoConvergence(_)) = outcome {
                if !self.jac_current {
                    // stale Jacobian: refresh and retry the same step from the predictor
                    self.jac_valid = false;
                    self.predict(sys, m, t_new);
                    outcome = self.newton(sys, t_new, alpha);
                }
            }
            let fail_factor = match outcome {
                Ok(()) => None,
                Err(NewtonFail::Fatal(mut e)) => {
                    e.t = self.t;
                    return Err(e);
                }
                Err(NewtonFail::NoConvergence(c)) => {
                    // The retry is at a new t_new (and, with a moving prescribed end, a
                    // different state): a Jacobian from this failed trial can be far too stiff
                    // there, and modified Newton then takes tiny increments that pass the
                    // convergence test with an O(1) residual. Re-evaluate it.
                    self.jac_valid = false;
                    sys.stats.newton_failures += 1;
                    last = LastFailure::Newton(c);
                    Some(0.25)
                }
                Err(NewtonFail::Recoverable(reason, c)) => {
                    last = LastFailure::Recoverable(reason, c);
                    // the matrix may be bad near the failure point: a Jacobian taken at a
                    // predictor far outside the problem's domain (non-finite entries, reported
                    // as a zero pivot) would otherwise be refactored at every smaller step and
                    // fail each time (measured: the density continuum at K = 1e-5, t ≈ 4)
                    self.jac_valid = false;
                    Some(0.25)
                }
            };
            if let Some(f) = fail_factor {
                log::debug!(
                    "BDF step rejected at t = {:e}, h = {h_try:e}, order {k}: {last:?}",
                    self.t
                );
                let (cause, component) = last.cause();
                sys.reject_step(self.t, h_try, cause, component);
                ncf += 1;
                h = h_try * f;
                if fixed.is_some() || ncf >= MAX_CONV_FAILS || h < h_floor {
                    return Err(self.give_up(&last, h_try));
                }
                continue;
            }

            // local error test; the norms of the order-(k−1), (k−2) and, when an order raise
            // may be considered below, (k+1) differences come from the same sweep
            let had_failures = nef > 0 || ncf > 0;
            let may_raise = opts.bdf.fixed_order.is_none()
                && k < opts.bdf.max_order
                && self.steps_at_order + 1 > k
                && self.times.len() >= k + 2
                && !had_failures;
            // the step's own order first (the local error), then the others
            let mut orders = [k; MAX_NORMS];
            let mut no = 1;
            for (m, wanted) in [
                (k.wrapping_sub(1), k > 1),
                (k.wrapping_sub(2), k > 2),
                (k + 1, may_raise),
            ] {
                if wanted {
                    orders[no] = m;
                    no += 1;
                }
            }
            // (orders[0] = k at t_new: the predictor `predict` stored above)
            let dn = self.error_norms(&orders[..no], t_new, opts.norm, sys.error_map());
            let een = dn[0];
            let dnorm_of = |m: usize| -> f64 {
                let i = orders[1..no]
                    .iter()
                    .position(|&o| o == m)
                    .expect("order norm computed in the sweep");
                dn[1 + i]
            };
            let (err_k, terr_k) = self.estimates(k, t_new, h_try, een);
            let mut knew = k;
            let mut terr_km1 = f64::INFINITY;
            let mut err_km1 = f64::INFINITY;
            if k > 1 {
                let d1 = dnorm_of(k - 1);
                let (e1, te1) = self.estimates(k - 1, t_new, h_try, d1);
                err_km1 = e1;
                terr_km1 = te1;
                if k > 2 {
                    let d2 = dnorm_of(k - 2);
                    let (_, te2) = self.estimates(k - 2, t_new, h_try, d2);
                    if te1.max(te2) <= terr_k {
                        knew = k - 1;
                    }
                } else if te1 <= 0.5 * terr_k {
                    knew = k - 1;
                }
            }
            if let Some(fo) = opts.bdf.fixed_order {
                knew = k.min(fo);
            }

            // (NaN error estimates fail the test)
            let passed = err_k <= 1.0;
            if fixed.is_none() && !passed {
                log::debug!(
                    "BDF step rejected at t = {:e}, h = {h_try:e}, order {k}: error estimate \
                     {err_k:.3e} (tolerance 1)",
                    self.t
                );
                nef += 1;
                sys.stats.error_test_failures += 1;
                last = LastFailure::ErrorTest(self.worst_error(k, t_new));
                let (cause, component) = last.cause();
                sys.reject_step(self.t, h_try, cause, component);
                let (r, kk) = if nef == 1 || self.steps_since_start == 0 {
                    // on the first step after a (re)start the step size is a guess (or the
                    // hint from before an event): trust the estimate for large reductions
                    let e = if knew < k { err_km1 } else { err_k };
                    let r = 0.9 * (2.0 * e + 1e-4).powf(-1.0 / (knew as f64 + 1.0));
                    let lo = if self.steps_since_start == 0 {
                        1e-3
                    } else {
                        0.25
                    };
                    (r.clamp(lo, 0.9), knew)
                } else if nef == 2 {
                    (0.25, knew)
                } else {
                    (0.25, 1)
                };
                let r = if r.is_finite() { r } else { 0.25 };
                self.k = kk;
                if kk != k {
                    self.steps_at_order = 0;
                }
                h = h_try * r;
                // the first step after a (re)start goes on past MAX_ERR_FAILS while its
                // estimate keeps falling: a transient spanning many time scales (divisions
                // brought forward together on a dragged line relax diffusively; at K = 1e-8
                // the estimate fell only as h^0.25 from 1e-6 down to 1e-9) is resolved by a
                // step the usual cuts reach after more tries
                let falling = self.steps_since_start == 0 && err_k < last_err;
                last_err = err_k;
                let limit = if falling {
                    FIRST_STEP_MAX_ERR_FAILS
                } else {
                    MAX_ERR_FAILS
                };
                if nef >= limit || h < h_floor {
                    return Err(self.give_up(&last, h_try));
                }
                continue;
            }

            // accepted: choose the next order (IDA's rules)
            let mut err_new = if knew < k { err_km1 } else { err_k };
            let mut action_order = knew;
            let can_raise = opts.bdf.fixed_order.is_none()
                && knew == k
                && k < opts.bdf.max_order
                && self.steps_at_order + 1 > k
                && self.times.len() >= k + 2
                && !had_failures;
            if can_raise {
                let d = dnorm_of(k + 1);
                let (err_kp1, terr_kp1) = self.estimates(k + 1, t_new, h_try, d);
                if k == 1 {
                    if terr_kp1 < 0.5 * terr_k {
                        action_order = 2;
                        err_new = err_kp1;
                    }
                } else if terr_km1 <= terr_k.min(terr_kp1) {
                    action_order = k - 1;
                    err_new = err_km1;
                } else if terr_kp1 < terr_k {
                    action_order = k + 1;
                    err_new = err_kp1;
                }
            }
            if let Some(fo) = opts.bdf.fixed_order {
                // climb to the fixed order as soon as the history allows
                action_order = fo.min(opts.bdf.max_order).min(self.times.len());
            }

            // accept
            self.t_prev = self.t;
            self.t = t_new;
            let buf = if self.times.len() >= MAX_NODES {
                self.times.pop_back();
                self.vals.pop_back().expect("history")
            } else {
                sys.take_vec()
            };
            // the new state moves into the history (it is `y`) and `ẏ` by swapping buffers;
            // the next predictor overwrites ycur/ypcur
            let y_new = std::mem::replace(&mut self.ycur, buf);
            std::mem::swap(&mut self.yp, &mut self.ypcur);
            self.times.push_front(t_new);
            self.vals.push_front(y_new);
            self.k_last = k;
            self.accepted += 1;
            self.steps_since_jac += 1;
            self.steps_since_start += 1;
            if action_order != k {
                self.steps_at_order = 0;
            } else {
                self.steps_at_order += 1;
            }
            self.k = action_order.max(1);

            // next step size
            if fixed.is_none() {
                let r = (2.0 * err_new + 1e-4).powf(-1.0 / (self.k as f64 + 1.0));
                let mut hn = if r >= GROW_THRESHOLD {
                    r.min(2.0) * h_try
                } else if r <= 1.0 {
                    h_try * r.clamp(0.5, 0.9)
                } else {
                    h_try
                };
                if !r.is_finite() {
                    hn = h_try;
                }
                if had_failures {
                    hn = hn.min(h_try);
                }
                // don't let a step shortened to hit t_stop shrink the next one
                if t_new == t_stop && h_try < h && hn < h {
                    hn = h.min(hn.max(h_try));
                }
                self.h = hn.min(opts.h_max);
            }
            return Ok(());
        }
    }
}
