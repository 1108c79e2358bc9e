//! The driver: consistent initialisation, stepping, output at requested times, event location
//! and actions (stop / modify / resize), statistics and errors with the partial solution.
//!
//! # Flow of a solve
//!
//! 1. Validate the options, `y0` (length, finiteness) and the output times (finite, sorted,
//!    `≥ t0`, non-empty); errors are [`ErrorKind::InvalidInput`].
//! 2. Build the per-dimension cache, compute a consistent `ẏ0` (and algebraic `y0`) with
//!    [`System::consistent_init`], start the method.
//! 3. Step towards the last output time. Before the first step and every
//!    [`ROUNDOFF_CHECK_EVERY`] steps the tolerances are held against the round-off of the
//!    state ([`System::roundoff_ratio`]): above [`ROUNDOFF_LIMIT`] the solve stops with
//!    [`ErrorKind::TooMuchAccuracy`] instead of creeping on with steps that only noise limits.
//!    After each accepted step `[t_prev, t]`, event functions
//!    are evaluated at `t` and compared with their values at the previous accepted point; the
//!    earliest sign change is located on the method's dense output by an Illinois-safeguarded
//!    secant iteration to [`Options::event_tol`] (scaled down for a solve on times below 1,
//!    see [`event_tolerance`]). Outputs in `(t_prev, t]` come from the dense output.
//! 4. At a located event `t*`, outputs before `t*` are emitted, the problem's
//!    [`Problem::handle_event`] is called with the interpolated state, and the action is applied.
//!
//! # Event conventions
//!
//! * A function *fires* when it changes sign between two points, including a change to exactly
//!   zero from a nonzero value. A function that is exactly zero at the earlier point does not fire
//!   when it leaves zero.
//! * The located time `t*` is the right end of the final bracket, so the functions whose root
//!   lies in it already have their post-crossing sign (or are zero) at `t*`. Functions whose
//!   roots lie within `event_tol` of each other fire together (indices in increasing order):
//!   those whose root lies in `(t*, t* + event_tol]` fire with the event too, still on their
//!   pre-crossing side at `t*`.
//! * After an event, each fired function that is zero or still has its post-crossing sign at the
//!   (possibly modified) state is treated as exactly zero until it moves away from zero, so the
//!   same root never fires twice (a bouncing ball left at height `-1e-15` does not bounce again
//!   immediately); so is each function fired ahead of its root, which would otherwise cross just
//!   after the event. A function reset to its pre-crossing side fires normally at its next
//!   crossing.
//! * [`EventAction::Continue`]: the step is kept and the rest of it is searched for further
//!   events; changes the handler made to `y` are ignored.
//! * [`EventAction::Modified`] / [`EventAction::Resized`]: the step after `t*` is discarded, the
//!   cache is rebuilt (resize), `ẏ` is made consistent at `t*`, and the method restarts at `t*`
//!   from [`Problem::restart_derivative`] (default: the consistent `ẏ`) with the last step size
//!   as a hint. (A fresh starting-step estimate at every division restart was measured worse on
//!   a proliferating line: its second-derivative probe sees the sub-step transient of the new
//!   cell boundary and starts far too small; the pre-event step is the better guess.)
//! * [`EventAction::Stop`]: the solve ends successfully at `t*`; `(t*, y, ẏ)` (after the handler)
//!   is appended to the outputs (once, even if `t*` is also a requested output time).
//!
//! **Outputs at an event time** (requested times within `event_tol` before `t*`, or equal to it)
//! are emitted *after* the event is handled (right-continuous convention): they report the
//! modified / resized state and its consistent `ẏ` (labelled with the requested time). For a
//! `Stop` they are replaced by the stop entry.

use std::cell::RefCell;

use crate::error::{ErrorKind, SolveFailure, SolverError};
use crate::method::{Method, MethodChoice};
use crate::observer::{AcceptedStep, Observer, Outputs};
use crate::options::Options;
use crate::problem::{EventAction, Problem, ResidualError};
use crate::stats::Stats;
use crate::system::{System, SystemCache};

mod events;
use events::{eval_events, fires, locate, mask_fired, Located};

/// Round-off over tolerance ([`System::roundoff_ratio`]) above which a solve stops with
/// [`ErrorKind::TooMuchAccuracy`]. Measured on a line of 4 000 cells pushed to λ = 0.026
/// (stretch tolerances at the crushed cell against its boundaries' round-off): ratio 0.016
/// (rtol 1e-9) took 58 670 steps, as the rtol^(−1/5) of the order-5 formula predicts from rtol
/// 1e-6; 0.16 (rtol 3e-10) took 130 738, 1.7 times the prediction; 0.27 (rtol 1.8e-10) took
/// 431 422, 5.8 times; 0.47 (rtol 1e-10) had not reached 0.4 of the time span after 10⁶ steps.
/// Past the limit the cost explodes while the accuracy bought stays at round-off.
pub const ROUNDOFF_LIMIT: f64 = 0.25;

/// The ratio [`ErrorKind::TooMuchAccuracy`] advises reaching: rtol 3e-10 in the measurement
/// of [`ROUNDOFF_LIMIT`], the tightest that cost less than twice the predicted steps.
pub const ROUNDOFF_ADVISED: f64 = 0.02;

/// Accepted steps between two round-off checks (each a pass over the state, so that it costs
/// a few per cent of one pass per step).
pub const ROUNDOFF_CHECK_EVERY: usize = 32;

/// One handled event.
///
/// ```
/// use integrators::{EventAction, EventRecord};
/// let e = EventRecord { t: 1.5, fired: vec![0], action: EventAction::Stop, dim_after: 2 };
/// assert_eq!((e.fired.as_slice(), &e.action), (&[0][..], &EventAction::Stop));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct EventRecord {
    /// Located event time.
    pub t: f64,
    /// Indices of the event functions that changed sign.
    pub fired: Vec<usize>,
    /// What the problem did.
    pub action: EventAction,
    /// Problem dimension after the action.
    pub dim_after: usize,
}

/// Output of a solve.
///
/// ```
/// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> { r[0] = yp[0] + y[0]; Ok(()) }
/// }
/// let sol = Solver::new(MethodKind::Bdf, Options::default()).solve(&mut Decay, 0.0, &[1.0], &[0.5, 1.0])?;
/// assert_eq!(sol.t, [0.5, 1.0]);
/// assert_eq!((sol.t_last, sol.y_last.len()), (1.0, 1));
/// assert!(sol.events.is_empty() && sol.stats.steps > 0);
/// # Ok::<(), integrators::SolveFailure>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solution {
    /// Output times reached (the requested ones, plus the stop time of a `Stop` event).
    pub t: Vec<f64>,
    /// States at `t` (lengths may differ across resizes).
    pub y: Vec<Vec<f64>>,
    /// Derivatives at `t`.
    pub yp: Vec<Vec<f64>>,
    /// Events handled, in time order.
    pub events: Vec<EventRecord>,
    /// Work counters.
    pub stats: Stats,
    /// Last accepted time.
    pub t_last: f64,
    /// Last accepted state.
    pub y_last: Vec<f64>,
}

/// Where the solver gets its method from.
enum MethodSource {
    Kind(MethodChoice),
    Boxed(RefCell<Box<dyn Method>>),
}

/// The integration driver: a method plus options.
///
/// ```
/// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
/// /// ẏ = -y
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> { r[0] = yp[0] + y[0]; Ok(()) }
/// }
/// let solver = Solver::new(MethodKind::Bdf, Options { rtol: 1e-8, atol: 1e-10, ..Default::default() });
/// let sol = solver.solve(&mut Decay, 0.0, &[1.0], &[1.0, 2.0]).unwrap();
/// assert!((sol.y[1][0] - (-2.0f64).exp()).abs() < 1e-6);
/// ```
pub struct Solver {
    opts: Options,
    source: MethodSource,
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("method", &self.method_name())
            .field("opts", &self.opts)
            .finish()
    }
}

impl Solver {
    /// A solver using a built-in ([`crate::MethodKind`]) or registered method
    /// ([`MethodChoice`]); a fresh method object per solve.
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Solver};
    /// let s = Solver::new(MethodKind::Esdirk, Options::default());
    /// assert_eq!(s.method_name(), "esdirk");
    /// ```
    pub fn new(method: impl Into<MethodChoice>, opts: Options) -> Self {
        Self {
            opts,
            source: MethodSource::Kind(method.into()),
        }
    }

    /// A solver using the caller's own [`Method`] implementation. The method object is reused
    /// (restarted with [`Method::start`]) by every solve; a solve started from inside the
    /// observer of another solve with the same `Solver` fails with `InvalidInput`.
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
    /// /// ẏ = −y in residual form.
    /// struct Decay;
    /// impl Problem for Decay {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    ///         r[0] = yp[0] + y[0];
    ///         Ok(())
    ///     }
    /// }
    /// // the caller's own method object (here a built-in one), reused by every solve
    /// let s = Solver::with_method(integrators::methods::build(MethodKind::Radau), Options::default());
    /// let sol = s.solve(&mut Decay, 0.0, &[1.0], &[1.0]).unwrap();
    /// assert!((sol.y[0][0] - (-1.0f64).exp()).abs() < 1e-5);
    /// ```
    pub fn with_method(method: Box<dyn Method>, opts: Options) -> Self {
        Self {
            opts,
            source: MethodSource::Boxed(RefCell::new(method)),
        }
    }

    /// The options.
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Solver};
    /// let s = Solver::new(MethodKind::Bdf, Options { rtol: 1e-9, ..Default::default() });
    /// assert_eq!(s.options().rtol, 1e-9);
    /// ```
    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// Name of the method (`"bdf"`, …, or the custom method's name).
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Solver};
    /// assert_eq!(Solver::new(MethodKind::Dopri, Options::default()).method_name(), "dopri");
    /// ```
    pub fn method_name(&self) -> &'static str {
        match &self.source {
            MethodSource::Kind(k) => k.name(),
            MethodSource::Boxed(m) => m.try_borrow().map(|m| m.name()).unwrap_or("custom"),
        }
    }

    /// Integrates `problem` from `(t0, y0)` and returns the state at every time of `t_out`
    /// (sorted, `≥ t0`; the last one is the end of the integration).
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
    /// /// ẏ = −y in residual form.
    /// struct Decay;
    /// impl Problem for Decay {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    ///         r[0] = yp[0] + y[0];
    ///         Ok(())
    ///     }
    /// }
    /// let opts = Options { rtol: 1e-8, atol: 1e-10, ..Default::default() };
    /// let sol = Solver::new(MethodKind::Bdf, opts).solve(&mut Decay, 0.0, &[1.0], &[0.5, 2.0]).unwrap();
    /// assert_eq!(sol.t, [0.5, 2.0]);
    /// assert!((sol.y[1][0] - (-2.0f64).exp()).abs() < 1e-6);
    /// ```
    pub fn solve<P: Problem>(
        &self,
        problem: &mut P,
        t0: f64,
        y0: &[f64],
        t_out: &[f64],
    ) -> Result<Solution, SolveFailure> {
        self.solve_with(problem, t0, y0, t_out, |_, _, _, _| {})
    }

    /// As [`solve`](Solver::solve), calling `observer(problem, t, y, ẏ)` at every output (after
    /// it is stored) — the place to record model observables such as the number of cells after
    /// resizes.
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
    /// /// ẏ = −y in residual form.
    /// struct Decay;
    /// impl Problem for Decay {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    ///         r[0] = yp[0] + y[0];
    ///         Ok(())
    ///     }
    /// }
    /// let mut seen = Vec::new();
    /// Solver::new(MethodKind::Bdf, Options::default())
    ///     .solve_with(&mut Decay, 0.0, &[1.0], &[0.5, 1.0], |_, t, y, _| seen.push((t, y[0])))
    ///     .unwrap();
    /// assert_eq!(seen.len(), 2);
    /// ```
    pub fn solve_with<P, O>(
        &self,
        problem: &mut P,
        t0: f64,
        y0: &[f64],
        t_out: &[f64],
        observer: O,
    ) -> Result<Solution, SolveFailure>
    where
        P: Problem,
        O: FnMut(&P, f64, &[f64], &[f64]),
    {
        self.solve_observed(problem, t0, y0, t_out, Outputs(observer))
    }

    /// As [`solve`](Solver::solve), reporting outputs, accepted and rejected steps and events
    /// to `observer` as they happen (see [`Observer`] for an example).
    ///
    /// ```
    /// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
    /// /// ẏ = −y in residual form.
    /// struct Decay;
    /// impl Problem for Decay {
    ///     fn dim(&self) -> usize { 1 }
    ///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
    ///         r[0] = yp[0] + y[0];
    ///         Ok(())
    ///     }
    /// }
    /// use integrators::observer::{AcceptedStep, Observer};
    /// struct Count(usize);
    /// impl<P> Observer<P> for Count {
    ///     fn accepted(&mut self, _: &P, _: &AcceptedStep, _: &[f64]) { self.0 += 1; }
    /// }
    /// let mut count = Count(0);
    /// let sol = Solver::new(MethodKind::Bdf, Options::default())
    ///     .solve_observed(&mut Decay, 0.0, &[1.0], &[1.0], &mut count)
    ///     .unwrap();
    /// assert_eq!(count.0, sol.stats.steps);
    /// ```
    pub fn solve_observed<P, O>(
        &self,
        problem: &mut P,
        t0: f64,
        y0: &[f64],
        t_out: &[f64],
        observer: O,
    ) -> Result<Solution, SolveFailure>
    where
        P: Problem,
        O: Observer<P>,
    {
        match &self.source {
            MethodSource::Kind(k) => {
                let mut m = k.build();
                run(&self.opts, m.as_mut(), problem, t0, y0, t_out, observer)
            }
            MethodSource::Boxed(cell) => match cell.try_borrow_mut() {
                Ok(mut m) => run(&self.opts, m.as_mut(), problem, t0, y0, t_out, observer),
                Err(_) => Err(SolveFailure {
                    error: SolverError::new(
                        ErrorKind::InvalidInput("solver already in use by another solve".into()),
                        t0,
                        None,
                    ),
                    partial: Box::default(),
                }),
            },
        }
    }
}

/// The state of one run, bundled so that failures can return everything computed so far.
struct Run<'o, O> {
    t_out: &'o [f64],
    next_out: usize,
    sol: Solution,
    stats: Stats,
    cache: SystemCache,
    observer: O,
    ybuf: Vec<f64>,
    ypbuf: Vec<f64>,
    /// The event handling's state vectors (`y` and `ẏ` at the event, `y` and `ẏ` after it),
    /// kept across events: a problem that grows at each event (a dividing line) then extends
    /// them in place instead of receiving fresh vectors of its old size.
    event_bufs: [Vec<f64>; 4],
    /// The factorised `∂F/∂ẏ` of the last output whose rates were solved from its state
    /// ([`System::rates_from_state`]) and its dimension, kept for the next output.
    rates_lu: Option<(usize, crate::linalg::LinearSolver)>,
}

impl<O> Run<'_, O> {
    /// Records `y` as the last accepted state ([`Solution::y_last`]).
    fn keep_last(&mut self, y: &[f64]) {
        self.sol.y_last.clear();
        self.sol.y_last.extend_from_slice(y);
    }

    fn fail(self, kind: ErrorKind, t: f64, component: Option<usize>) -> SolveFailure {
        self.fail_err(SolverError::new(kind, t, component))
    }

    fn fail_err(mut self, error: SolverError) -> SolveFailure {
        log::warn!(
            "solve failed: {error} (after {} steps, {} rejected)",
            self.stats.steps,
            self.stats.rejected_steps
        );
        self.sol.stats = self.stats;
        SolveFailure {
            error,
            partial: Box::new(self.sol),
        }
    }
}

impl<O> Run<'_, O> {
    fn push<P: Problem>(&mut self, p: &P, t: f64, y: &[f64], yp: &[f64])
    where
        O: Observer<P>,
    {
        self.sol.t.push(t);
        self.sol.y.push(y.to_vec());
        self.sol.yp.push(yp.to_vec());
        self.observer.output(p, t, y, yp);
    }

    /// Passes the rejected attempts the method recorded to the observer.
    fn report_rejections<P: Problem>(&mut self, p: &P)
    where
        O: Observer<P>,
    {
        for r in self.cache.rejected.drain(..) {
            self.observer.rejected(p, &r);
        }
    }

    /// Emits outputs with `t_out < limit` (or `≤` if `inclusive`) from the method's dense output.
    ///
    /// For problems with algebraic components the state (interpolated, or the step's own at a
    /// step's end) is projected back onto the constraints: [`System::consistent_init`] at the
    /// output time recomputes the algebraic components (and a consistent `ẏ`) from the
    /// differential ones. Without this, algebraic outputs carry the interpolation error of a
    /// component that is not error-controlled when [`Options::suppress_algebraic`] is set, and
    /// a step's end the Newton iterate's distance from the constraints. (Counted in the
    /// statistics; if the projection fails the unprojected values are kept.) A problem whose
    /// outputs read `ẏ` ([`Problem::outputs_read_rates`]) is projected the same way: its
    /// differential components are kept and `ẏ` solved from them (unless
    /// [`Options::interpolate_rates`]).
    fn emit_interp<P: Problem>(
        &mut self,
        p: &mut P,
        opts: &Options,
        m: &dyn Method,
        limit: f64,
        inclusive: bool,
    ) where
        O: Observer<P>,
    {
        while self.next_out < self.t_out.len() {
            let to = self.t_out[self.next_out];
            if to < limit || (inclusive && to == limit) {
                let n = m.y().len();
                self.ybuf.resize(n, 0.0);
                self.ypbuf.resize(n, 0.0);
                if to == m.t() {
                    self.ybuf.copy_from_slice(m.y());
                    self.ypbuf.copy_from_slice(m.yp());
                } else {
                    m.interpolate(to, &mut self.ybuf, &mut self.ypbuf);
                }
                // also at a step's own end: its algebraic components are a Newton iterate,
                // accepted by a convergence test and not error-controlled, so they can sit
                // farther from the constraints than the differential ones' accuracy
                let rates = self.cache.outputs_read_rates && !opts.interpolate_rates;
                let algebraic = self.cache.algebraic.iter().any(|&a| a);
                if rates && !algebraic {
                    // (a failure leaves the interpolated ẏ, as a failed projection does)
                    let mut sys = System::new(p, opts, &mut self.stats, &mut self.cache);
                    let h = m.t() - m.t_prev();
                    let _ = sys.rates_from_state(
                        to,
                        &self.ybuf,
                        &mut self.ypbuf,
                        &mut self.rates_lu,
                        h,
                    );
                } else if rates || algebraic {
                    let (y0, yp0) = (self.ybuf.clone(), self.ypbuf.clone());
                    let mut sys = System::new(p, opts, &mut self.stats, &mut self.cache);
                    if sys
                        .consistent_init(to, &mut self.ybuf, &mut self.ypbuf)
                        .is_err()
                    {
                        self.ybuf = y0;
                        self.ypbuf = yp0;
                    }
                }
                let (yb, ypb) = (
                    std::mem::take(&mut self.ybuf),
                    std::mem::take(&mut self.ypbuf),
                );
                self.push(p, to, &yb, &ypb);
                self.ybuf = yb;
                self.ypbuf = ypb;
                self.next_out += 1;
            } else {
                break;
            }
        }
    }

    /// Emits outputs at exactly `t` (and any earlier ones) with the given state.
    fn emit_at<P: Problem>(&mut self, p: &P, t: f64, y: &[f64], yp: &[f64])
    where
        O: Observer<P>,
    {
        while self.next_out < self.t_out.len() && self.t_out[self.next_out] <= t {
            let to = self.t_out[self.next_out];
            self.push(p, to, y, yp);
            self.next_out += 1;
        }
    }
}

/// The event tolerance of a solve from `t0` to `t_end`: [`Options::event_tol`] times the
/// solve's time scale `max(|t₀|, |t_end|)` when that is below 1, else `event_tol` itself.
/// An absolute tolerance of 1e-12 meant nothing to a problem posed on times of 1e-100 (a
/// dividing line at that scale divided at the ends of steps, 600·rtol off); scaled, the
/// same problem divides at the same relative times. Solves reaching times of 1 or more keep
/// the absolute tolerance (and, far beyond, the secant's floor `4ε|t|` takes over).
///
/// ```
/// use integrators::solver::event_tolerance;
/// assert_eq!(event_tolerance(1e-12, 0.0, 18.0), 1e-12);
/// assert_eq!(event_tolerance(1e-12, 0.0, 0.5), 0.5e-12);
/// assert!((event_tolerance(1e-12, 0.0, 3e-100) / 3e-112 - 1.0).abs() < 1e-15);
/// ```
pub fn event_tolerance(event_tol: f64, t0: f64, t_end: f64) -> f64 {
    event_tol * t0.abs().max(t_end.abs()).min(1.0)
}

fn residual_error_kind(e: ResidualError) -> ErrorKind {
    ErrorKind::Residual(format!("event handler: {e}"))
}

#[allow(clippy::too_many_arguments)]
fn run<P, O>(
    opts: &Options,
    method: &mut dyn Method,
    p: &mut P,
    t0: f64,
    y0: &[f64],
    t_out: &[f64],
    observer: O,
) -> Result<Solution, SolveFailure>
where
    P: Problem,
    O: Observer<P>,
{
    let mut run = Run {
        t_out,
        next_out: 0,
        sol: Solution {
            t_last: t0,
            y_last: y0.to_vec(),
            ..Default::default()
        },
        stats: Stats::default(),
        cache: SystemCache::default(),
        observer,
        ybuf: Vec::new(),
        ypbuf: Vec::new(),
        event_bufs: Default::default(),
        rates_lu: None,
    };
    let invalid =
        |run: Run<'_, O>, msg: String| Err(run.fail(ErrorKind::InvalidInput(msg), t0, None));

    // ---- input validation
    if let Err(e) = opts
        .validate()
        .and_then(|()| opts.check_method_name(method.name()))
    {
        return invalid(run, e.to_string());
    }
    // parallelism is passed in: the problem learns how many threads it may use
    p.set_threads(opts.parallel.threads());
    if opts.parallel.threads() == 2 {
        // split passes become pushes to this thread's own queue (see `split_pool`)
        crate::split_pool::enter();
    }
    if !t0.is_finite() {
        return invalid(run, format!("t0 = {t0} is not finite"));
    }
    if t_out.is_empty() {
        return invalid(run, "t_out is empty: give at least the final time".into());
    }
    if let Some(i) = t_out.iter().position(|t| !t.is_finite()) {
        return invalid(run, format!("t_out[{i}] = {} is not finite", t_out[i]));
    }
    if let Some(i) = (1..t_out.len()).find(|&i| t_out[i] < t_out[i - 1]) {
        return invalid(run, format!("t_out is not sorted at index {i}"));
    }
    if t_out[0] < t0 {
        return invalid(
            run,
            format!(
                "t_out[0] = {} is before t0 = {t0} (backward integration is not supported)",
                t_out[0]
            ),
        );
    }
    let n = p.dim();
    if y0.len() != n {
        return invalid(
            run,
            format!(
                "y0 has length {} but the problem dimension is {n}",
                y0.len()
            ),
        );
    }
    if let Some(i) = crate::linalg::first_non_finite(y0) {
        return Err(run.fail(
            ErrorKind::InvalidInput(format!("y0[{i}] = {} is not finite", y0[i])),
            t0,
            Some(i),
        ));
    }
    if let Err(e) = run.cache.rebuild(p, opts) {
        return Err(run.fail(e, t0, None));
    }

    // ---- consistent initialisation
    let mut y = y0.to_vec();
    let mut yp = vec![0.0; n];
    {
        let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
        sys.refresh_end_weights(t0, &y);
        if let Err(e) = sys.consistent_init(t0, &mut y, &mut yp) {
            return Err(run.fail_err(e));
        }
    }
    run.sol.y_last = y.clone();
    let mut g_prev = Vec::new();
    if let Err(e) = eval_events(p, t0, &y, &mut g_prev) {
        return Err(run.fail(e, t0, None));
    }
    run.emit_at(p, t0, &y, &yp);
    let t_end = *t_out.last().expect("non-empty");
    let event_tol = event_tolerance(opts.event_tol, t0, t_end);
    if run.next_out == t_out.len() {
        run.sol.stats = run.stats;
        return Ok(run.sol);
    }
    {
        let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
        sys.refresh_end_weights(t0, &y);
        if let Err(e) = method.start(&mut sys, t0, &y, &yp, opts.h0) {
            return Err(run.fail_err(e));
        }
    }

    let land = opts
        .land_on_outputs
        .unwrap_or(!method.dense_output_controlled());
    let mut g_new = Vec::new();
    let mut unchecked = ROUNDOFF_CHECK_EVERY;
    let mut warned_stiff = false;
    let interrupt = crate::interrupt::Interrupt::current();
    loop {
        if run.stats.steps >= opts.max_steps {
            let t = method.t();
            run.keep_last(method.y());
            return Err(run.fail(ErrorKind::TooManySteps(opts.max_steps), t, None));
        }
        if interrupt.as_ref().is_some_and(|i| i.is_raised()) {
            let t = method.t();
            run.keep_last(method.y());
            return Err(run.fail(ErrorKind::Interrupted, t, None));
        }
        if unchecked >= ROUNDOFF_CHECK_EVERY {
            unchecked = 0;
            let (ratio, i) = {
                let sys = System::new(p, opts, &mut run.stats, &mut run.cache);
                sys.roundoff_ratio(method.y())
            };
            run.cache.roundoff = ratio;
            if ratio > ROUNDOFF_LIMIT {
                let t = method.t();
                run.keep_last(method.y());
                return Err(run.fail(ErrorKind::TooMuchAccuracy { ratio }, t, Some(i)));
            }
        }
        {
            let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
            // the next output after t, which the step may not pass
            let stop = if land {
                let t = method.t();
                t_out[run.next_out.min(t_out.len())..]
                    .iter()
                    .copied()
                    .find(|&o| o > t)
                    .unwrap_or(t_end)
            } else {
                t_end
            };
            sys.refresh_end_weights(method.t(), method.y());
            let stepped = method.step(&mut sys, stop);
            run.report_rejections(p);
            match stepped {
                // the driver counts steps (a method reports how many it took)
                Ok(substeps) => {
                    run.stats.steps += substeps;
                    unchecked += substeps;
                    let step = AcceptedStep {
                        t_prev: method.t_prev(),
                        t: method.t(),
                        substeps,
                    };
                    run.observer.accepted(p, &step, method.y());
                }
                Err(e) => {
                    run.sol.t_last = method.t();
                    run.sol.y_last = method.y().to_vec();
                    return Err(run.fail_err(e));
                }
            }
        }
        let t = method.t();
        run.sol.t_last = t;
        // `y_last` is copied from the method only where the run can end (here on failure,
        // before events, at the end): a copy per step is two passes over a large state
        if let Some(i) = crate::linalg::first_non_finite(method.y()) {
            run.keep_last(method.y());
            return Err(run.fail(ErrorKind::NonFinite, t, Some(i)));
        }
        // an explicit method held at its stability limit: warn once, and stop when the rest of
        // the span at this step would pass `max_steps`, the budget it would otherwise crawl to
        if let Some(limit) = method.stability_limit() {
            if !warned_stiff {
                warned_stiff = true;
                log::warn!(
                    "{}: the problem is stiff from t = {} (h·ρ = {:.2} at the stability \
                     limit): the steps are set by stability, not accuracy; an implicit method \
                     (bdf, esdirk or radau) would take far fewer",
                    method.name(),
                    crate::error::short_number(limit.since),
                    limit.h_rho
                );
            }
            let projected_steps = run.stats.steps as f64 + ((t_end - t) / method.h_next()).ceil();
            if projected_steps > opts.max_steps as f64 {
                run.keep_last(method.y());
                let kind = ErrorKind::Stiff {
                    h_rho: limit.h_rho,
                    projected_steps,
                    max_steps: opts.max_steps,
                };
                return Err(run.fail(kind, t, limit.component));
            }
        }

        // ---- events in (a, t]
        let mut a = method.t_prev();
        let mut restarted = false;
        if !g_prev.is_empty() {
            run.keep_last(method.y());
            if let Err(e) = eval_events(p, t, method.y(), &mut g_new) {
                return Err(run.fail(e, t, None));
            }
            if g_new.len() != g_prev.len() {
                return Err(run.fail(
                    ErrorKind::InvalidInput("num_events() changed without a Resized event".into()),
                    t,
                    None,
                ));
            }
            while (0..g_prev.len()).any(|i| fires(g_prev[i], g_new[i])) {
                let (mut yb, mut ypb) = (
                    std::mem::take(&mut run.ybuf),
                    std::mem::take(&mut run.ypbuf),
                );
                let located = locate(
                    p,
                    method,
                    event_tol,
                    a,
                    g_prev.clone(),
                    t,
                    g_new.clone(),
                    &mut yb,
                    &mut ypb,
                );
                run.ybuf = yb;
                run.ypbuf = ypb;
                let Located {
                    t: ts,
                    fired,
                    g: g_star,
                    post,
                    ahead,
                } = match located {
                    Ok(v) => v,
                    Err(e) => return Err(run.fail(e, t, None)),
                };
                // outputs before the event (those within event_tol of it count as at it)
                run.emit_interp(p, opts, method, ts - event_tol, false);
                let nn = method.y().len();
                let [mut ye, mut ype, mut ynew, mut ypnew] = std::mem::take(&mut run.event_bufs);
                for v in [&mut ye, &mut ype] {
                    v.clear();
                    v.resize(nn, 0.0);
                }
                if ts == t {
                    ye.copy_from_slice(method.y());
                    ype.copy_from_slice(method.yp());
                } else {
                    method.interpolate(ts, &mut ye, &mut ype);
                }
                ynew.clear();
                ynew.extend_from_slice(&ye);
                let action = match p.handle_event(ts, &fired, &mut ynew, &ype) {
                    Ok(a) => a,
                    Err(e) => {
                        run.sol.t_last = ts;
                        run.sol.y_last = ye;
                        return Err(run.fail(residual_error_kind(e), ts, None));
                    }
                };
                run.stats.events += 1;
                let dim_after = p.dim();
                log::debug!(
                    "event at t = {ts:e}: {} function(s) fired, {action:?}, dimension {nn} -> \
                     {dim_after}",
                    fired.len()
                );
                let record = EventRecord {
                    t: ts,
                    fired: fired.clone(),
                    action: action.clone(),
                    dim_after,
                };
                run.observer.event(p, &record, &ynew);
                run.sol.events.push(record);
                match action {
                    EventAction::Stop => {
                        // the stop entry (replaces a requested output at exactly ts)
                        while run.next_out < t_out.len() && t_out[run.next_out] <= ts {
                            run.next_out += 1;
                        }
                        let yp_out = if ynew.len() == ype.len() {
                            ype.clone()
                        } else {
                            vec![0.0; ynew.len()]
                        };
                        run.push(p, ts, &ynew, &yp_out);
                        run.sol.t_last = ts;
                        run.sol.y_last = ynew;
                        run.sol.stats = run.stats;
                        return Ok(run.sol);
                    }
                    EventAction::Continue => {
                        a = ts;
                        g_prev = g_star;
                        mask_fired(&mut g_prev, &fired, &post, &ahead);
                        run.event_bufs = [ye, ype, ynew, ypnew];
                        continue;
                    }
                    EventAction::Modified | EventAction::Resized => {
                        let resized = action == EventAction::Resized;
                        let expected = if resized { p.dim() } else { nn };
                        if !resized && p.dim() != nn {
                            return Err(run.fail(
                                ErrorKind::InvalidInput(format!(
                                    "event handler changed the dimension ({nn} -> {}) but returned Modified; return Resized",
                                    p.dim()
                                )),
                                ts,
                                None,
                            ));
                        }
                        if ynew.len() != expected {
                            return Err(run.fail(
                                ErrorKind::InvalidInput(format!(
                                    "event handler left y with length {} but the problem dimension is {expected}",
                                    ynew.len()
                                )),
                                ts,
                                None,
                            ));
                        }
                        if let Some(i) = crate::linalg::first_non_finite(&ynew) {
                            return Err(run.fail(ErrorKind::NonFinite, ts, Some(i)));
                        }
                        if resized {
                            run.stats.resizes += 1;
                            if let Err(e) = run.cache.rebuild(p, opts) {
                                return Err(run.fail(e, ts, None));
                            }
                        }
                        // a resize the problem can map (`Problem::map_history`): the method
                        // resumes across it (`Method::resume`) from the mapped interpolated ẏ,
                        // with no consistent initialisation
                        ypnew.clear();
                        ypnew.resize(ynew.len(), 0.0);
                        let mut resumed = false;
                        if resized && p.map_history(ts, &ype, true, &mut ypnew) {
                            let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
                            sys.refresh_end_weights(ts, &ynew);
                            match method.resume(&mut sys, ts, &ynew, &ypnew) {
                                Ok(r) => resumed = r,
                                Err(e) => return Err(run.fail_err(e)),
                            }
                        }
                        if !resumed {
                            ypnew.clear();
                            ypnew.extend_from_slice(&ype);
                            ypnew.resize(ynew.len(), 0.0);
                            let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
                            sys.refresh_end_weights(ts, &ynew);
                            if let Err(e) = sys.consistent_init(ts, &mut ynew, &mut ypnew) {
                                run.sol.t_last = ts;
                                run.sol.y_last = ynew;
                                return Err(run.fail_err(e));
                            }
                        }
                        if let Err(e) = eval_events(p, ts, &ynew, &mut g_prev) {
                            return Err(run.fail(e, ts, None));
                        }
                        mask_fired(&mut g_prev, &fired, &post, &ahead);
                        run.sol.t_last = ts;
                        run.sol.y_last.clone_from(&ynew);
                        run.emit_at(p, ts, &ynew, &ypnew);
                        if run.next_out == t_out.len() {
                            run.sol.stats = run.stats;
                            return Ok(run.sol);
                        }
                        if resumed {
                            run.event_bufs = [ye, ype, ynew, ypnew];
                            restarted = true;
                            break;
                        }
                        let hint = method.h_next();
                        let hint = if hint > 0.0 && hint.is_finite() {
                            Some(hint)
                        } else {
                            None
                        };
                        // the outputs above report the consistent ẏ; the method restarts from
                        // the problem's choice (default: the same), see
                        // `Problem::restart_derivative`
                        p.restart_derivative(ts, &ynew, &mut ypnew);
                        let started = {
                            let mut sys = System::new(p, opts, &mut run.stats, &mut run.cache);
                            sys.refresh_end_weights(ts, &ynew);
                            method.start(&mut sys, ts, &ynew, &ypnew, hint)
                        };
                        if let Err(e) = started {
                            return Err(run.fail_err(e));
                        }
                        run.event_bufs = [ye, ype, ynew, ypnew];
                        restarted = true;
                        break;
                    }
                }
            }
        }
        if restarted {
            continue;
        }
        if !g_prev.is_empty() {
            std::mem::swap(&mut g_prev, &mut g_new);
        }
        run.emit_interp(p, opts, method, t, true);
        if t >= t_end {
            run.keep_last(method.y());
            run.sol.stats = run.stats;
            return Ok(run.sol);
        }
    }
}
