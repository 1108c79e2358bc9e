//! TR-BDF2 as an L-stable ESDIRK in residual form, with its embedded third-order error estimate
//! (Hosea & Shampine, "Analysis and implementation of TR-BDF2", Appl. Numer. Math. 20 (1996)
//! 21–37; Bank et al. 1985 for the original scheme).
//!
//! With `γ = 2 − √2`, `d = γ/2` and `w = √2/4` the Butcher tableau is
//!
//! ```text
//!   0 |  0   0   0
//!   γ |  d   d   0          b  = ( w,         w,          d   )  (order 2, stiffly accurate)
//!   1 |  w   w   d          b̂ = ((1−w)/3, (3w+1)/3,   d/3 )  (order 3, embedded)
//! ```
//!
//! The first stage is explicit and reuses `ẏ_n` (FSAL: `ẏ_{n+1}` is the last stage derivative),
//! so a restart after an event costs nothing beyond the consistent `ẏ`. The implicit stages are
//! solved in residual form: with `z_i = y_n + h Σ_{j<i} a_ij k_j`,
//!
//! ```text
//!   F(t_n + c_i h, Y_i, (Y_i − z_i)/(d h)) = 0,
//! ```
//!
//! by Newton with the iteration matrix `E = ∂F/∂y + (1/(d h))·∂F/∂ẏ`, the same for both
//! implicit stages: one factorisation per step, reused across steps while `h` is unchanged and
//! Newton converges well. `∂F/∂y` and `∂F/∂ẏ` are stored separately (two
//! [`System::jacobian`] calls per refresh, at `c = 0` and `c = 1/(d h)`), so a change of `h` costs
//! one refactorisation but no new Jacobian; the Jacobian is refreshed only when Newton converges
//! slowly or fails.
//!
//! Error estimate: `est = h Σ (b_i − b̂_i) k_i`, filtered as in Hosea & Shampine (and Hairer's
//! RADAU5) through the iteration matrix, `δ = E⁻¹ (∂F/∂ẏ · est)/(d h)` (for an ODE this is
//! `(I − d h J)⁻¹ est`), which keeps the estimate bounded for stiff components. Step-size
//! control: `h_new = h · min(5, max(0.2, 0.9 · err^(−1/3)))`, no increase right after a
//! rejection. Dense output: cubic Hermite interpolation of `(y, ẏ)` at both ends of the step.
//!
//! With [`crate::Options::fixed_step`] set, steps are exactly of that size without error control
//! (observed order 2).
//!
//! ```
//! use integrators::Method;
//! use integrators::methods::esdirk::Esdirk;
//! assert_eq!(Esdirk::new().name(), "esdirk");
//! ```

use crate::error::SolverError;
use crate::linalg::{LinearSolver, Matrix};
use crate::method::Method;
use crate::methods::one_step::{self, Attempt};
use crate::methods::radau::{
    classify, classify_factor, error_weights, newton_weights, worst, Fail,
};
use crate::system::{StepFailure, System};

/// Newton contraction above which the Jacobian is refreshed for the next step.
const THETA_REFRESH: f64 = 0.3;
/// TR-BDF2 in ESDIRK form (see the [module documentation](self)).
///
/// ```
/// use integrators::Method;
/// let m = integrators::methods::esdirk::Esdirk::new();
/// assert_eq!(m.name(), "esdirk");
/// ```
pub struct Esdirk {
    started: bool,
    /// Restarts after events ([`one_step::Resume`]).
    resume: one_step::Resume,
    n: usize,
    t: f64,
    t_prev: f64,
    h: f64,
    h_old: f64,
    y: Vec<f64>,
    yp: Vec<f64>,
    y_prev: Vec<f64>,
    yp_prev: Vec<f64>,
    // stage work
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    y2: Vec<f64>,
    y3: Vec<f64>,
    zs: Vec<f64>,
    r: Vec<f64>,
    wt: Vec<f64>,
    ewt: Vec<f64>,
    tmp: Vec<f64>,
    // Jacobians and factorisation
    j0: Option<Matrix>,
    j1: Option<Matrix>,
    e: Option<Matrix>,
    lu: Option<LinearSolver>,
    jac_valid: bool,
    jac_fresh: bool,
    lu_h: f64,
    // controller state
    reject: bool,
    eta: f64,
    theta_max: f64,
}

impl Default for Esdirk {
    fn default() -> Self {
        Self::new()
    }
}

/// TR-BDF2 constants.
struct Tab {
    gamma: f64,
    d: f64,
    w: f64,
    /// `b − b̂`.
    e: [f64; 3],
}

fn tab() -> Tab {
    let s2 = 2f64.sqrt();
    let gamma = 2.0 - s2;
    let d = gamma / 2.0;
    let w = s2 / 4.0;
    Tab {
        gamma,
        d,
        w,
        e: [w - (1.0 - w) / 3.0, w - (3.0 * w + 1.0) / 3.0, d - d / 3.0],
    }
}

impl Esdirk {
    /// A fresh TR-BDF2 integrator (call [`Method::start`] before stepping).
    ///
    /// ```
    /// use integrators::Method;
    /// let m = integrators::methods::esdirk::Esdirk::new();
    /// assert_eq!(m.name(), "esdirk");
    /// ```
    pub fn new() -> Self {
        Self {
            started: false,
            resume: Default::default(),
            n: 0,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            h_old: 0.0,
            y: Vec::new(),
            yp: Vec::new(),
            y_prev: Vec::new(),
            yp_prev: Vec::new(),
            k1: Vec::new(),
            k2: Vec::new(),
            k3: Vec::new(),
            y2: Vec::new(),
            y3: Vec::new(),
            zs: Vec::new(),
            r: Vec::new(),
            wt: Vec::new(),
            ewt: Vec::new(),
            tmp: Vec::new(),
            j0: None,
            j1: None,
            e: None,
            lu: None,
            jac_valid: false,
            jac_fresh: false,
            lu_h: f64::NAN,
            reject: false,
            eta: 1.0,
            theta_max: 0.0,
        }
    }

    fn eval_jacobian(&mut self, sys: &mut System<'_>, h: f64) -> Result<(), StepFailure> {
        let c = 1.0 / (tab().d * h);
        let j0 = self.j0.as_mut().expect("workspace");
        sys.jacobian(self.t, &self.y, &self.yp, 0.0, j0)?;
        let e = self.e.as_mut().expect("workspace");
        sys.jacobian(self.t, &self.y, &self.yp, c, e)?;
        let j1 = self.j1.as_mut().expect("workspace");
        j1.set_zero();
        j1.axpby(0.0, 1.0 / c, e);
        j1.axpby(1.0, -1.0 / c, self.j0.as_ref().expect("workspace"));
        self.jac_valid = true;
        self.jac_fresh = true;
        self.lu_h = f64::NAN;
        Ok(())
    }

    fn factorise(&mut self, sys: &mut System<'_>, h: f64) -> Result<(), StepFailure> {
        let c = 1.0 / (tab().d * h);
        let e = self.e.as_mut().expect("workspace");
        e.set_zero();
        e.axpby(0.0, 1.0, self.j0.as_ref().expect("workspace"));
        e.axpby(1.0, c, self.j1.as_ref().expect("workspace"));
        self.lu_h = f64::NAN;
        sys.factor(self.lu.as_mut().expect("workspace"), e)?;
        self.lu_h = h;
        Ok(())
    }

    /// Newton for one implicit stage: solves `F(ts, Y, (Y − zs)/(d h)) = 0` for `Y` (in/out:
    /// `ys` holds the predictor), leaving the stage derivative in `k`.
    #[allow(clippy::too_many_arguments)]
    fn solve_stage(
        &mut self,
        sys: &mut System<'_>,
        ts: f64,
        h: f64,
        stage: usize,
        fnewt: f64,
        fixed: bool,
    ) -> Result<Result<(), Attempt>, SolverError> {
        let n = self.n;
        // In fixed-step mode the step cannot be reduced: iterate while contracting.
        let nit = if fixed {
            sys.opts.max_newton_iters.max(30)
        } else {
            sys.opts.max_newton_iters
        };
        let dh = tab().d * h;
        let mut ys = std::mem::take(if stage == 2 {
            &mut self.y2
        } else {
            &mut self.y3
        });
        let mut k = std::mem::take(if stage == 2 {
            &mut self.k2
        } else {
            &mut self.k3
        });
        let mut newt = 0usize;
        let mut dynold = 0.0f64;
        self.eta = self.eta.max(f64::EPSILON).powf(0.8);
        let result = loop {
            if newt >= nit {
                break Ok(Err(self.newton_fail(sys, 0.5 * h)));
            }
            for l in 0..n {
                k[l] = (ys[l] - self.zs[l]) / dh;
            }
            if let Err(f) = sys.residual(ts, &ys, &k, &mut self.r) {
                match classify(f) {
                    Ok(fail) => {
                        sys.stats.newton_failures += 1;
                        self.reject = true;
                        if !self.jac_fresh {
                            self.jac_valid = false;
                        }
                        break Ok(Err(Attempt::Rejected(fail, 0.5 * h)));
                    }
                    Err(e) => break Err(e),
                }
            }
            for v in self.r.iter_mut() {
                *v = -*v;
            }
            sys.solve(self.lu.as_ref().expect("workspace"), &mut self.r);
            newt += 1;
            sys.stats.newton_iterations += 1;
            for (a, b) in ys.iter_mut().zip(&self.r) {
                *a += b;
            }
            let dyno = sys.norm(&self.r, &self.wt);
            if !dyno.is_finite() {
                break Ok(Err(self.newton_fail(sys, 0.5 * h)));
            }
            if newt > 1 {
                let theta = dyno / dynold;
                self.theta_max = self.theta_max.max(theta);
                if theta >= 0.99 && sys.below_roundoff(dyno) {
                    // no longer contracting, but within the rounding of the state: converged as
                    // far as the state resolves (`System::below_roundoff`), not diverging
                    for l in 0..n {
                        k[l] = (ys[l] - self.zs[l]) / dh;
                    }
                    break Ok(Ok(()));
                }
                if theta >= 0.99 {
                    break Ok(Err(self.newton_fail(sys, 0.5 * h)));
                }
                self.eta = theta / (1.0 - theta);
                let pred = self.eta * dyno * theta.powi((nit - newt) as i32) / fnewt;
                if !fixed && newt < nit && pred >= 1.0 {
                    let q = pred.clamp(1e-4, 20.0);
                    let hhfac = 0.8 * q.powf(-1.0 / (3.0 + (nit - newt) as f64));
                    break Ok(Err(self.newton_fail(sys, hhfac * h)));
                }
            }
            if self.eta * dyno <= fnewt {
                for l in 0..n {
                    k[l] = (ys[l] - self.zs[l]) / dh;
                }
                break Ok(Ok(()));
            }
            dynold = dyno.max(f64::EPSILON);
        };
        if stage == 2 {
            self.y2 = ys;
            self.k2 = k;
        } else {
            self.y3 = ys;
            self.k3 = k;
        }
        result
    }

    fn newton_fail(&mut self, sys: &mut System<'_>, h_new: f64) -> Attempt {
        sys.stats.newton_failures += 1;
        self.reject = true;
        if !self.jac_fresh {
            self.jac_valid = false;
        }
        self.eta = 1.0;
        let comp = worst(&self.r, &self.wt);
        Attempt::Rejected(Fail::Newton { component: comp }, h_new)
    }

    fn attempt(
        &mut self,
        sys: &mut System<'_>,
        h: f64,
        fixed: bool,
        t_new: f64,
    ) -> Result<Attempt, SolverError> {
        let n = self.n;
        let tb = tab();
        let fnewt = (10.0 * f64::EPSILON / sys.opts.rtol).max(0.03);
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
        newton_weights(sys, &self.y, &mut self.wt);
        self.theta_max = 0.0;

        // Stage 1 (explicit, FSAL).
        self.k1.copy_from_slice(&self.yp);
        // Stage 2 (trapezoidal rule to t + γh).
        for l in 0..n {
            self.zs[l] = self.y[l] + h * tb.d * self.k1[l];
            self.y2[l] = self.y[l] + tb.gamma * h * self.k1[l];
        }
        if let Err(a) = self.solve_stage(sys, self.t + tb.gamma * h, h, 2, fnewt, fixed)? {
            return Ok(a);
        }
        // Stage 3 (BDF2 to t + h). Predictor: k3 ≈ k2 + (k2 − k1)(1 − γ)/γ.
        for l in 0..n {
            self.zs[l] = self.y[l] + h * tb.w * (self.k1[l] + self.k2[l]);
            let k3p = self.k2[l] + (self.k2[l] - self.k1[l]) * (1.0 - tb.gamma) / tb.gamma;
            self.y3[l] = self.zs[l] + h * tb.d * k3p;
        }
        if let Err(a) = self.solve_stage(sys, t_new, h, 3, fnewt, fixed)? {
            return Ok(a);
        }

        let mut err = 0.0;
        if !fixed {
            // est = h Σ (b − b̂)_i k_i, filtered: δ = E⁻¹ J1 est/(d h).
            for l in 0..n {
                self.zs[l] =
                    (tb.e[0] * self.k1[l] + tb.e[1] * self.k2[l] + tb.e[2] * self.k3[l]) / tb.d;
            }
            self.j1
                .as_ref()
                .expect("workspace")
                .mul_vec(&self.zs, &mut self.tmp);
            sys.solve(self.lu.as_ref().expect("workspace"), &mut self.tmp);
            for l in 0..n {
                self.r[l] = self.y[l].abs().max(self.y3[l].abs());
            }
            error_weights(sys, &self.r, &mut self.ewt);
            err = sys.norm(&self.tmp, &self.ewt);
            if !err.is_finite() {
                err = f64::INFINITY;
            }
        }

        if err <= 1.0 {
            std::mem::swap(&mut self.y_prev, &mut self.y);
            std::mem::swap(&mut self.yp_prev, &mut self.yp);
            self.y.copy_from_slice(&self.y3);
            self.yp.copy_from_slice(&self.k3);
            self.t_prev = self.t;
            self.t = t_new;
            self.h_old = h;
            let was_reject = self.reject;
            self.reject = false;
            self.jac_fresh = false;
            if self.theta_max > THETA_REFRESH {
                self.jac_valid = false;
            }
            if !fixed {
                let mut fac = 0.9 * err.max(1e-10).powf(-1.0 / 3.0);
                fac = fac.clamp(0.2, 5.0);
                if was_reject {
                    fac = fac.min(1.0);
                }
                // Keep h (and the factorisation) for small increases.
                if self.jac_valid && (1.0..=1.2).contains(&fac) {
                    fac = 1.0;
                }
                self.h = (h * fac).min(sys.opts.h_max);
            }
            Ok(Attempt::Accepted)
        } else {
            sys.stats.error_test_failures += 1;
            self.reject = true;
            if !self.jac_fresh {
                self.jac_valid = false;
            }
            let fac = (0.9 * err.powf(-1.0 / 3.0)).clamp(0.1, 0.9);
            let comp = worst(&self.tmp, &self.ewt);
            Ok(Attempt::Rejected(
                Fail::ErrorTest { component: comp },
                h * fac,
            ))
        }
    }
}

one_step::impl_one_step!(Esdirk, order: 2, h_old: true, unit_mass: |_m| false);

impl Method for Esdirk {
    fn name(&self) -> &'static str {
        "esdirk"
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
        self.n = n;
        self.t = t;
        self.t_prev = t;
        self.y = y.to_vec();
        self.yp = yp.to_vec();
        self.y_prev = y.to_vec();
        self.yp_prev = yp.to_vec();
        for v in [
            &mut self.k1,
            &mut self.k2,
            &mut self.k3,
            &mut self.y2,
            &mut self.y3,
            &mut self.zs,
            &mut self.r,
            &mut self.wt,
            &mut self.ewt,
            &mut self.tmp,
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.j0 = Some(sys.new_matrix());
        self.j1 = Some(sys.new_matrix());
        self.e = Some(sys.new_matrix());
        self.lu = Some(sys.new_linear_solver());
        self.jac_valid = false;
        self.jac_fresh = false;
        self.lu_h = f64::NAN;
        self.reject = false;
        self.eta = 1.0;
        self.resume.on_start(self.started);
        self.started = true;
        self.h = one_step::start_h(h, sys.opts);
        self.h_old = self.h;
        Ok(())
    }

    super::method_accessors!(one_step);

    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        hermite(
            self.t_prev,
            self.t,
            (&self.y_prev, &self.yp_prev),
            (&self.y, &self.yp),
            t,
            y,
            yp,
        );
    }
}

/// Cubic Hermite interpolation of `(y, ẏ)` given both at `t0` and `t1`.
pub(crate) fn hermite(
    t0: f64,
    t1: f64,
    a: (&[f64], &[f64]),
    b: (&[f64], &[f64]),
    t: f64,
    y: &mut [f64],
    yp: &mut [f64],
) {
    let h = t1 - t0;
    if h == 0.0 {
        y.copy_from_slice(b.0);
        yp.copy_from_slice(b.1);
        return;
    }
    let s = (t - t0) / h;
    let s2 = s * s;
    let s3 = s2 * s;
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    let d00 = (6.0 * s2 - 6.0 * s) / h;
    let d10 = 3.0 * s2 - 4.0 * s + 1.0;
    let d01 = (-6.0 * s2 + 6.0 * s) / h;
    let d11 = 3.0 * s2 - 2.0 * s;
    for i in 0..y.len() {
        y[i] = h00 * a.0[i] + h10 * h * a.1[i] + h01 * b.0[i] + h11 * h * b.1[i];
        yp[i] = d00 * a.0[i] + d10 * a.1[i] + d01 * b.0[i] + d11 * b.1[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tableau_orders() {
        let tb = tab();
        let (g, d, w) = (tb.gamma, tb.d, tb.w);
        let c = [0.0, g, 1.0];
        let a = [[0.0, 0.0, 0.0], [d, d, 0.0], [w, w, d]];
        let b = [w, w, d];
        let bh = [(1.0 - w) / 3.0, (3.0 * w + 1.0) / 3.0, d / 3.0];
        for i in 0..3 {
            let rs: f64 = a[i].iter().sum();
            assert!((rs - c[i]).abs() < 1e-15);
        }
        // b: order 2
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!((b.iter().zip(&c).map(|(x, y)| x * y).sum::<f64>() - 0.5).abs() < 1e-15);
        // b̂: order 3
        assert!((bh.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!((bh.iter().zip(&c).map(|(x, y)| x * y).sum::<f64>() - 0.5).abs() < 1e-15);
        assert!((bh.iter().zip(&c).map(|(x, y)| x * y * y).sum::<f64>() - 1.0 / 3.0).abs() < 1e-15);
        let mut bac = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                bac += bh[i] * a[i][j] * c[j];
            }
        }
        assert!((bac - 1.0 / 6.0).abs() < 1e-15);
        for i in 0..3 {
            assert!((tb.e[i] - (b[i] - bh[i])).abs() < 1e-15);
        }
    }

    #[test]
    fn hermite_reproduces_cubics() {
        let f = |t: f64| 1.0 + 2.0 * t - t * t + 0.5 * t * t * t;
        let df = |t: f64| 2.0 - 2.0 * t + 1.5 * t * t;
        let (t0, t1) = (0.3, 1.1);
        let mut y = [0.0];
        let mut yp = [0.0];
        hermite(
            t0,
            t1,
            (&[f(t0)], &[df(t0)]),
            (&[f(t1)], &[df(t1)]),
            0.77,
            &mut y,
            &mut yp,
        );
        assert!((y[0] - f(0.77)).abs() < 1e-14);
        assert!((yp[0] - df(0.77)).abs() < 1e-13);
    }
}
