//! Starting step size shared by every method: Hairer–Wanner's `HINIT` (Solving ODEs I, §II.4)
//! carried over to residual form, where `ẏ` at a trial point comes from a consistent
//! initialisation instead of a right-hand-side call.
//!
//! The first-derivative estimate alone (`h = 0.01·‖y‖/‖ẏ‖`) cannot see forcing that starts from
//! rest: a line of cells whose end begins to move at `t₀` has `ẏ(t₀) = 0` everywhere, and a
//! step sized from `ẏ` alone (or from a fraction of the output interval) can drive the end cell
//! to collapse inside the first step. The second-derivative estimate `‖ẏ(t₀+h₀) − ẏ(t₀)‖/h₀`
//! sees it, at the cost of one consistent initialisation per (re)start.

use crate::system::System;

impl System<'_> {
    /// Starting step for a method of order `order` from a consistent `(t0, y0, yp0)`, at most
    /// `span` (the distance to the next stop) and within `[h_min, h_max]`.
    ///
    /// `h₀ = 0.01·‖y₀‖/‖ẏ₀‖` (`10⁻⁶·span` when either norm is negligible); then
    /// `ẏ₁` is made consistent at `(t₀ + h₀, y₀ + h₀ẏ₀)` and
    /// `h₁ = (0.01/max(‖ẏ₀‖, ‖ẏ₁ − ẏ₀‖/h₀))^{1/(order+1)}`; the result is `min(100·h₀, h₁)`.
    /// All norms are weighted RMS norms (as in Hairer's code, whatever [`crate::Options::norm`]
    /// is) of the error weights at `y₀` over the differential components. If the trial point cannot be made consistent, `h₀` is returned. With
    /// `unit_mass` (the caller knows `∂F/∂ẏ = I`, as for an explicit ODE) `ẏ₁ − ẏ₀` is
    /// `−F(t₀ + h₀, y₁, ẏ₀)`, one residual call and no factorisation.
    ///
    /// ```
    /// use integrators::adapters::{Ode, OdeProblem};
    /// use integrators::{MethodKind, Options, ResidualError, Solver};
    /// // ẏ = 1 − y from rest (ẏ(0) = 1, ÿ(0) = −1): the solver sizes its own first step
    /// struct Relax;
    /// impl OdeProblem for Relax {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) -> Result<(), ResidualError> {
    ///         f[0] = 1.0 - y[0];
    ///         Ok(())
    ///     }
    /// }
    /// let sol = Solver::new(MethodKind::Bdf, Options::default())
    ///     .solve(&mut Ode(Relax), 0.0, &[0.0], &[1.0])
    ///     .unwrap();
    /// assert!((sol.y[0][0] - (1.0 - (-1.0f64).exp())).abs() < 1e-5);
    /// ```
    pub fn initial_step(
        &mut self,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        span: f64,
        order: usize,
        unit_mass: bool,
    ) -> f64 {
        if self.dim() == 0 {
            return clamp_step(span, span, self.opts);
        }
        // scratch from the system's spares (see `Spares`); every entry is written before use
        let mut w = self.take_vec();
        let mut y1 = self.take_vec();
        let mut yp1 = self.take_vec();
        let scratch = [&mut w, &mut y1, &mut yp1];
        let h1 = self.initial_step_with(t0, y0, yp0, span, order, unit_mass, scratch);
        for v in [w, y1, yp1] {
            self.give_vec(v);
        }
        h1
    }

    /// [`initial_step`](Self::initial_step) with its scratch (`n ≥ 1`).
    #[allow(clippy::too_many_arguments)]
    fn initial_step_with(
        &mut self,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        span: f64,
        order: usize,
        unit_mass: bool,
        [w, y1, yp1]: [&mut Vec<f64>; 3],
    ) -> f64 {
        let clamp = |h: f64, opts: &crate::Options| clamp_step(h, span, opts);
        self.error_weights(y0, w);
        for (wi, &alg) in w.iter_mut().zip(&self.cache.algebraic) {
            if alg {
                *wi = 0.0;
            }
        }
        // RMS, as Hairer's HINIT, whatever `Options::norm` is: measured, the max norm here made
        // the line's 10⁶-cell macroscale run fail late, the RMS start
        // costs fig2_6's continuum a few rejected first tries
        // (where the squares overflow, as with the rates 1e150 of a drag far below the
        // stiffness, the max norm: within √n of the RMS one, and finite)
        let norm = |sys: &Self, v: &[f64]| {
            let rms = sys.norm_with(crate::ErrorNorm::Rms, v, w);
            if rms == f64::INFINITY {
                sys.norm_with(crate::ErrorNorm::Max, v, w)
            } else {
                rms
            }
        };
        let d0 = norm(self, y0);
        let d1 = norm(self, yp0);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 || !d1.is_finite() {
            1e-6 * span
        } else {
            0.01 * d0 / d1
        };
        let mut h0 = clamp(h0, self.opts);
        // The probe `y₀ + h₀·ẏ₀` at `t₀ + h₀` must be a state the problem accepts: with a
        // moving prescribed end and `ẏ₀ ≈ 0` (nothing has moved yet), an `h₀` of the whole span
        // (what `0.01·d₀/d₁` gives when `d₁` is rounding noise) carries the end past its
        // neighbour and the trial initialisation fails. A failed probe is not an answer: it
        // says `h₀` is far beyond the problem's time scale, so shrink it and probe again.
        // (as many shrinks as it takes down to the step floor: a span of 1e50 over a problem
        // whose time scale is 1 starts at h₀ = 1e44, and eight shrinks left it at 1e28,
        // untested, which the method then cut by 0.25 per failure until it gave up at t₀)
        let floor = self.opts.h_min.max(1e-14 * t0.abs()).max(f64::MIN_POSITIVE);
        let mut probed = false;
        for _ in 0..PROBE_TRIES {
            if self.probe(t0, y0, yp0, h0, unit_mass, y1, yp1) {
                probed = true;
                break;
            }
            if h0 <= floor {
                break;
            }
            // (at most the time in which `ẏ₀` moves `y` by one tolerance: with rates of 1e200
            // the fixed shrink alone never reached a probe the problem could evaluate)
            let one_tolerance = if d1 > 0.0 { 1.0 / d1 } else { f64::INFINITY };
            h0 = clamp((h0 * PROBE_SHRINK).min(one_tolerance), self.opts);
        }
        if !probed {
            return h0;
        }
        let change = norm(self, yp1);
        let d2 = change / h0;
        let dmax = d1.max(d2);
        let exponent = 1.0 / (order as f64 + 1.0);
        let h1 = if dmax == f64::INFINITY && change.is_finite() && d1.is_finite() {
            // ‖ẏ₁ − ẏ₀‖/h₀ overflowed though both are finite: a derivative that changes
            // within a time far below h₀, so h₁ is far below it too (in logarithms)
            let ln_dmax = d1.ln().max(change.ln() - h0.ln());
            (exponent * (0.01f64.ln() - ln_dmax)).exp()
        } else if dmax <= 1e-15 || !dmax.is_finite() {
            (h0 * 1e-3).max(1e-6 * span)
        } else {
            (0.01 / dmax).powf(exponent)
        };
        clamp((100.0 * h0).min(h1), self.opts)
    }
}

/// Probes of [`System::initial_step`] before it settles for the last `h₀` untested: enough
/// shrinks to reach any step floor from any span (200 tries span 10⁻⁴⁰⁰); the loop also stops
/// at the floor.
const PROBE_TRIES: usize = 200;
/// Factor by which a failed probe shrinks `h₀`.
const PROBE_SHRINK: f64 = 1e-2;

impl System<'_> {
    /// The initial step's probe: `y1 = y₀ + h₀·ẏ₀`, and in `yp1` the change of the derivative
    /// at `t₀ + h₀` (or `−F` for a unit mass). `false` when the problem rejects the probe.
    #[allow(clippy::too_many_arguments)]
    fn probe(
        &mut self,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        h0: f64,
        unit_mass: bool,
        y1: &mut [f64],
        yp1: &mut [f64],
    ) -> bool {
        for ((a, y), yp) in y1.iter_mut().zip(y0).zip(yp0) {
            *a = y + h0 * yp;
        }
        if unit_mass {
            if self.residual(t0 + h0, y1, yp0, yp1).is_err() {
                return false;
            }
            yp1.iter_mut().for_each(|v| *v = -*v);
        } else {
            yp1.copy_from_slice(yp0);
            if self.consistent_init(t0 + h0, y1, yp1).is_err() {
                return false;
            }
            for (a, b) in yp1.iter_mut().zip(yp0) {
                *a -= b;
            }
        }
        yp1.iter().all(|v| v.is_finite())
    }
}

/// A step size kept in `[h_min, min(span, h_max)]`; a non-finite or non-positive guess becomes
/// `10⁻⁶·span`.
fn clamp_step(h: f64, span: f64, opts: &crate::Options) -> f64 {
    let h = if h.is_finite() && h > 0.0 {
        h
    } else {
        1e-6 * span
    };
    h.min(span).min(opts.h_max).max(opts.h_min)
}
