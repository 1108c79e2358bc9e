//! The BDF step's simplified Newton iteration: Jacobian and factorisation when they are due,
//! then iterations from the predictor with the convergence-rate test `ss·‖δ‖ ≤ 0.33` (IDA's).

use super::*;

impl Bdf {
    /// Jacobian (if needed) and factorisation for `α`, then simplified Newton from the predictor
    /// (which [`Bdf::predict`] has written into `ycur`/`ẏcur`).
    pub(super) fn newton(
        &mut self,
        sys: &mut System<'_>,
        t_new: f64,
        alpha: f64,
    ) -> Result<(), NewtonFail> {
        let n = self.n;
        self.ensure_linalg(sys);
        let mut new_fact = false;
        if !self.jac_valid || self.steps_since_jac >= sys.opts.bdf.max_jacobian_age {
            let jy = self.jy.as_mut().expect("allocated");
            let jyp = self.jyp.as_mut().expect("allocated");
            // ∂F/∂y and ∂F/∂ẏ (J(1) − J(0), with columns lost to rounding restored)
            match sys.jacobian_pair(t_new, &self.ycur, &self.ypcur, alpha, jy, jyp) {
                Ok(()) => {}
                Err(StepFailure::Recoverable { reason, component }) => {
                    self.jac_valid = false;
                    return Err(NewtonFail::Recoverable(reason, component));
                }
                Err(StepFailure::Fatal(e)) => return Err(NewtonFail::Fatal(e)),
            }
            self.jac_valid = true;
            self.jac_current = true;
            self.steps_since_jac = 0;
            new_fact = true;
        }
        if new_fact || self.c_fact == 0.0 || (alpha / self.c_fact - 1.0).abs() > 0.25 {
            // J(0) + α·∂F/∂ẏ, combined straight into the factor storage for banded patterns
            match sys.factor_combination(
                self.lin.as_mut().expect("allocated"),
                self.jy.as_ref().expect("allocated"),
                alpha,
                self.jyp.as_ref().expect("allocated"),
                self.iter.as_mut().expect("allocated"),
            ) {
                Ok(()) => {}
                Err(StepFailure::Recoverable { reason, component }) => {
                    self.c_fact = 0.0;
                    return Err(NewtonFail::Recoverable(reason, component));
                }
                Err(StepFailure::Fatal(e)) => {
                    self.c_fact = 0.0;
                    return Err(NewtonFail::Fatal(e));
                }
            }
            self.c_fact = alpha;
            self.ss = 20.0;
        }
        // The correction is scaled by 2/(1 + r), r = α/α_f, for a matrix factored at α_f. That
        // leaves the modes one part of the matrix dominates the rate ρ_α = |r − 1|/(1 + r)
        // (< 1 for r > 0); with `newton_alpha_bound` the first iteration's test assumes at least
        // that rate (`BdfOptions::newton_alpha_bound`).
        let (scale, ss_alpha) = if alpha == self.c_fact {
            (1.0, 0.0)
        } else {
            let r = alpha / self.c_fact;
            let rho = (r - 1.0).abs() / (1.0 + r);
            let ss_alpha = if sys.opts.bdf.newton_alpha_bound {
                rho / (1.0 - rho)
            } else {
                0.0
            };
            (2.0 / (1.0 + r), ss_alpha)
        };

        let mut oldnrm = 0.0;
        let maxit = sys.opts.max_newton_iters;
        let first_step = self.steps_since_start == 0;
        for m in 0..maxit {
            match sys.residual(t_new, &self.ycur, &self.ypcur, &mut self.res) {
                Ok(()) => {}
                Err(StepFailure::Recoverable { reason, component }) => {
                    return Err(NewtonFail::Recoverable(reason, component))
                }
                Err(StepFailure::Fatal(e)) => return Err(NewtonFail::Fatal(e)),
            }
            sys.stats.newton_iterations += 1;
            // δ = −scale·J⁻¹F: solving for F and negating afterwards is bitwise the same as
            // solving for −F (every rounding is sign-symmetric). The solve hands each
            // component to one fused update that stores δ in `res`, updates the iterate and,
            // without an error map, accumulates ‖δ‖; the tridiagonal solver runs it inside its
            // backward sweep. With an error map ‖δ‖ is taken in cell units afterwards. (The
            // total correction `y_new − predictor` is not accumulated here: the error test
            // recomputes it from the history in its own sweep, one stream fewer per iteration.)
            // an iterative solver stops once its error is a small fraction of EPS_NEWT in the
            // Newton norm (inexact Newton, as IDA; see `IterativeSettings`)
            let tol = LinearTolerance {
                weights: &self.nwt,
                norm: sys.opts.norm,
                target: EPS_NEWT,
            };
            let lin = self.lin.as_ref().expect("allocated");
            let (y, yp, w) = (&mut self.ycur[..n], &mut self.ypcur[..n], &self.nwt[..n]);
            let delnrm = if sys.error_map().is_empty() {
                let upd = NewtonUpdate::<true>::new(y, yp, w, scale, alpha, sys.opts.norm);
                sys.solve_map(lin, &mut self.res, Some(&tol), upd)
                    .acc
                    .finish(n)
            } else {
                let upd = NewtonUpdate::<false>::new(y, yp, w, scale, alpha, sys.opts.norm);
                sys.solve_map(lin, &mut self.res, Some(&tol), upd);
                // cell-level quantities need the partner's δ: one pass over δ (now in `res`)
                map_norm(
                    sys.error_map(),
                    &self.res,
                    &self.nwt,
                    sys.opts.norm,
                    self.parallel,
                )
            };
            if !delnrm.is_finite() {
                return Err(NewtonFail::NoConvergence(worst(&self.res, &self.nwt)));
            }
            if m == 0 {
                oldnrm = delnrm;
                if delnrm <= 1e-4 * EPS_NEWT {
                    return Ok(());
                }
                if first_step {
                    // No rate information yet and the predictor is only `y₀ + h·ẏ₀`: the
                    // first step of a (re)start is accepted only once a second iterate shows
                    // the iteration contracting. Without this, a strongly nonlinear component
                    // (a cell driven to collapse by a moving end) can make a tiny first
                    // correction that passes the test far from the solution.
                    continue;
                }
            } else {
                let rate = (delnrm / oldnrm).powf(1.0 / m as f64);
                if rate > 0.9 {
                    if sys.below_roundoff(delnrm) {
                        // the iterate is converged as far as the state resolves it
                        return Ok(());
                    }
                    return Err(NewtonFail::NoConvergence(worst(&self.res, &self.nwt)));
                }
                self.ss = rate / (1.0 - rate);
            }
            let ss = if m == 0 {
                self.ss.max(ss_alpha)
            } else {
                self.ss
            };
            if ss * delnrm <= EPS_NEWT {
                return Ok(());
            }
        }
        Err(NewtonFail::NoConvergence(worst(&self.res, &self.nwt)))
    }
}
