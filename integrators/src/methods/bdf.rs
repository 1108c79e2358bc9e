//! Variable-order (1–5), variable-step BDF in residual form — the DASSL / IDA / ode15s family.
//!
//! # Formulation
//!
//! The method keeps the last few accepted points `(t_j, y_j)` (newest first) and works with the
//! polynomials that interpolate them, so step-size changes need no re-interpolation of the
//! history (the *variable-coefficient* form of DASSL). A step of order `k` from `t_n` to
//! `t_{n+1} = t_n + h`:
//!
//! * **Predictor**: the degree-`k` polynomial through `t_n, …, t_{n-k}` evaluated (value and
//!   derivative) at `t_{n+1}` gives `y⁽⁰⁾, ẏ⁽⁰⁾`.
//! * **Corrector**: the degree-`k` polynomial through `t_{n+1}, t_n, …, t_{n+1-k}` differs from
//!   the predictor by `δ·Π(t - t_{n+1-j})/Π(t_{n+1} - t_{n+1-j})`, so with `δ = y_{n+1} - y⁽⁰⁾`
//!   the BDF derivative is `ẏ_{n+1} = ẏ⁽⁰⁾ + α·δ`, `α = Σ_{j=1..k} 1/ψ_j`,
//!   `ψ_j = t_{n+1} - t_{n+1-j}` (exactly IDA's `α_s`). The nonlinear system
//!   `F(t_{n+1}, y⁽⁰⁾+δ, ẏ⁽⁰⁾+α·δ) = 0` is solved by simplified Newton with the iteration
//!   matrix `J = ∂F/∂y + α·∂F/∂ẏ`.
//! * **Local error**: `LTE_k ≈ ‖δ‖ / (α·ψ_{k+1})` — the ratio of the BDF error constant to the
//!   predictor's on the actual (non-uniform) mesh; `1/2` for backward Euler, `2/9` for BDF2 on a
//!   uniform mesh. The step is accepted when the weighted RMS norm is `≤ 1`. The same
//!   construction with the order-`k±1` predictors gives the error estimates used for order
//!   selection (IDA's rules: lower when the lower-order estimate is not larger, raise only after
//!   `k+1` steps at the current order and when the higher-order estimate is smaller).
//! * **Start**: the history starts with the double node `(t₀, y₀, ẏ₀)` (Hermite data), so the
//!   first step is backward Euler with the Taylor predictor `y₀ + h·ẏ₀`.
//!
//! # Linear algebra reuse
//!
//! `∂F/∂y` and `∂F/∂ẏ` are stored separately (two [`System::jacobian`] evaluations at `c = 0`
//! and `c = 1`), so a change of `α` (step or order change) costs only a refactorisation, done
//! when `α` moved by more than 25% since the last one; in between, Newton corrections are scaled
//! by `2/(1 + α/α_fact)` as in IDA. The Jacobian is re-evaluated only after a Newton convergence
//! failure with a stale Jacobian, or after 50 steps.
//!
//! # Memory traffic
//!
//! For large banded systems a step is bound by passes over `n`-vectors, so the vector work is
//! fused: the iteration matrix is combined straight into the LU storage
//! ([`System::factor_combination`]); the predictor is written straight into the Newton iterate
//! (no separate predictor vectors to copy from; a retry after a Jacobian refresh recomputes it)
//! in the same block-wise pass that computes the error and Newton weights (one vector when no
//! algebraic component is suppressed); each Newton iteration is one solve whose back
//! substitution applies the update as each component is found ([`System::solve_map`]: `δ`,
//! `y`, `ẏ`, the accumulated correction — which starts as the first `δ`, no zero-fill — and the
//! norm); the local-error norm and the order-selection norms (orders `k−1`, `k−2`, `k+1`) come
//! from one block-wise sweep over the history; an accepted state moves into the history by
//! swapping buffers (the newest history vector *is* `y`). Only the order of the RMS sums in the
//! Newton norm differs from the unfused arithmetic (the tridiagonal solve produces components
//! from its middle outwards); the pinned step counts are unchanged.
//!
//! # Step control
//!
//! The suggested factor is `r = (2·err + 10⁻⁴)^{−1/(k+1)}` for the chosen order. Growth is taken
//! only when worthwhile (`r ≥ 1.5`, then by `min(r, 2)`; otherwise the step is kept), reductions
//! are to `[0.5, 0.9]×` after a successful step; after an error-test failure `[0.25, 0.9]×`
//! (then ×0.25, then ×0.25 at order 1; on the first step after a (re)start the estimate is
//! trusted down to ×10⁻³, since that step size is only a guess or a pre-event hint); after a
//! Newton failure or a recoverable residual error ×0.25. At most 10 error-test and 10
//! convergence failures per step, and never below `max(h_min, 10⁻¹⁴·|t|)`, before giving up with
//! a typed error (step size too small / Newton failure / non-finite / singular matrix, with the
//! worst component). The step never passes `t_stop` (the last one is shortened to land on it).
//!
//! With [`crate::BdfOptions::fixed_order`] the order climbs to that value as soon as the history
//! allows and stays there; with [`crate::Options::fixed_step`] every step has that size and the
//! error test is skipped (the start is still at order 1).
//!
//! The initial step (when neither a hint nor [`crate::Options::h0`] is given) is IDA's:
//! `h = min(10⁻³·(t_stop − t₀), 0.5/‖ẏ₀‖_w)`.

use std::collections::VecDeque;

use crate::error::{ErrorKind, RecoverableCause, SolverError};
use crate::error_map::{ErrorMap, NormSum};
use crate::linalg::{LinearSolver, LinearTolerance, Matrix, SolutionMap};
use crate::method::Method;
use crate::options::ErrorNorm;
use crate::pattern::Pattern;
use crate::system::{StepFailure, System};

/// Maximum number of stored history nodes (order 5 needs 6; one spare for the start's double
/// node).
const MAX_NODES: usize = 7;
/// Size of coefficient arrays (nodes + the derivative item).
const NC: usize = MAX_NODES + 1;
/// Newton convergence tolerance on the weighted norm (IDA's `epsNewt`).
const EPS_NEWT: f64 = 0.33;
/// Maximum error-test failures in one step.
const MAX_ERR_FAILS: usize = 10;
/// Maximum error-test failures of the first step after a (re)start while each failure's
/// estimate is below the previous one's (see `Bdf::step_once`).
const FIRST_STEP_MAX_ERR_FAILS: usize = 3 * MAX_ERR_FAILS;
/// Maximum Newton / recoverable failures in one step.
const MAX_CONV_FAILS: usize = 10;
/// Block length for the fused vector loops (fits L1 with a few inputs).
const BLK: usize = 256;
/// Orders whose difference norms one error sweep computes: the step's own order (the local
/// error), `k − 1`, `k − 2` and `k + 1` (order selection).
const MAX_NORMS: usize = 4;
/// Smallest worthwhile step-size increase (smaller suggested increases keep `h`).
const GROW_THRESHOLD: f64 = 1.5;
/// Failed attempts of a step-doubled first step after an event before the ordinary error
/// test takes over (see [`Bdf::step_doubled`]). Newton failures count here only: the first
/// attempt is the pre-event step, which can be far longer than Newton converges from (measured
/// on Fig 3.3's line at K = 1e-7: a step of 1.0 after a quiet stretch, three failures down to
/// 0.06, then the ordinary error test saw the daughters' relaxation, of time ≈ K, as a
/// persistent error of ≈ 1 and shrank the step to its floor at t ≈ 4.0003; with eight tries
/// the doubled step succeeds at ≈ 1.5e-5, 3.6 steps per division).
const DOUBLING_TRIES: usize = 8;
/// Failed error tests of a step-doubled first step before the ordinary error test takes
/// over: an estimate that stays large as the step shrinks is a transient to resolve (at
/// K = 1e-5 the estimate stays at 3–6 from h = 1.5e-3 down to 1.5e-6).
const DOUBLING_ERROR_TRIES: usize = 3;
/// A step-doubled first step whose error estimate falls at least at this observed order
/// between its last two failed tries goes on past [`DOUBLING_ERROR_TRIES`] (up to
/// [`DOUBLING_TRIES`]): the halves' error is `O(h²)` once the event's transient is shorter
/// than the step, so the estimate is converging and one more cut passes, whereas the
/// ordinary error test measures the jump of `ẏ` at the event and falls only as `h`.
const CONVERGING_ORDER: f64 = 1.5;
/// When the first attempt after a [`Method::resume`] fails, the retry is at most this multiple
/// of the first step accepted after the previous resume (instead of a cut by the error
/// estimate's factor, at least 0.1). Successive events of one kind (cell divisions) excite
/// alike transients, so the last one's accepted step is the best guess once the pre-event step
/// has proved too long; an event whose transient is weak still goes on at the pre-event step.
/// Measured on Fig 3.3's line (N₀ = 100, area rule, t ≤ 18 unless stated; steps, rejected
/// attempts per division and whole-run solve time, without → with): K = 1e-7: 3.72, 0.08 →
/// 3.68, 0.06; K = 1e-6: 17.2, 3.15, 7.9 s → 17.5, 2.07, 7.6 s; K = 1e-5: 36.7, 6.91, 2.1 s →
/// 36.2, 2.16, 1.8 s; K = 1e-2 to t = 1000: 60.1, 7.46, 9.0 s → 56.9, 3.31, 7.7 s. Capping the
/// first attempt itself at twice the last accepted step cut the rejections further (0.98 at
/// K = 1e-5) but cost 26 steps per division at K = 1e-6, where a weak transient then had to
/// climb back from a short step: 28 % slower there.
const RESUME_GROWTH: f64 = 2.0;

/// Why the last attempt failed (for the error reported when retries run out).
#[derive(Clone, Debug)]
enum LastFailure {
    ErrorTest(Option<usize>),
    Newton(Option<usize>),
    Recoverable(RecoverableCause, Option<usize>),
}

impl LastFailure {
    /// The cause and unknown reported to the observer for a rejected attempt.
    fn cause(&self) -> (crate::observer::RejectCause, Option<usize>) {
        use crate::observer::RejectCause;
        match self {
            LastFailure::ErrorTest(c) => (RejectCause::ErrorTest, *c),
            LastFailure::Newton(c) => (RejectCause::Newton, *c),
            LastFailure::Recoverable(r, c) => (RejectCause::Recoverable(r.clone()), *c),
        }
    }
}

/// Outcome of a failed Newton solve.
enum NewtonFail {
    /// Did not converge (rate too large or iteration limit).
    NoConvergence(Option<usize>),
    /// The residual/Jacobian/factorisation reported a recoverable failure.
    Recoverable(RecoverableCause, Option<usize>),
    /// Abort.
    Fatal(SolverError),
}

/// Variable-order, variable-step BDF (orders 1 to [`crate::BdfOptions::max_order`]) for residual
/// DAEs `F(t, y, ẏ) = 0`.
///
/// ```
/// use integrators::{Method, methods::bdf::Bdf};
/// let m = Bdf::new();
/// assert_eq!(m.name(), "bdf");
/// ```
pub struct Bdf {
    n: usize,
    pattern: Option<Pattern>,
    t: f64,
    t_prev: f64,
    /// Step size to try next.
    h: f64,
    /// Whether `h` must be estimated at the next step (needs `t_stop`).
    h_pending: bool,
    /// Order for the next step.
    k: usize,
    /// Order of the last accepted step (dense output).
    k_last: usize,
    steps_at_order: usize,
    /// Accepted steps since the last start.
    steps_since_start: usize,
    /// Accepted steps in the current [`Method::step`] call (returned to the driver, which
    /// counts steps).
    accepted: usize,
    started: bool,
    times: VecDeque<f64>,
    vals: VecDeque<Vec<f64>>,
    /// `ẏ` at the start's double node.
    yp0: Vec<f64>,
    /// `ẏ` of the last accepted point (its `y` is the newest history vector, `vals[0]`).
    yp: Vec<f64>,
    jy: Option<Matrix>,
    jyp: Option<Matrix>,
    iter: Option<Matrix>,
    lin: Option<LinearSolver>,
    jac_valid: bool,
    jac_current: bool,
    /// `α` of the current factorisation (0: none).
    c_fact: f64,
    steps_since_jac: usize,
    /// Newton convergence-rate factor `ρ/(1-ρ)`.
    ss: f64,
    /// Newton iterate (starts as the predictor).
    ycur: Vec<f64>,
    /// The predictor of the step being tried, as [`Bdf::predict`] wrote it into `ycur` (the
    /// Newton iteration then changes `ycur`): the step's error test reads `ycur − ypred`
    /// instead of re-evaluating the predictor from the history.
    ypred: Vec<f64>,
    ypcur: Vec<f64>,
    res: Vec<f64>,
    /// Error weights, only when they differ from the Newton weights (suppressed algebraic
    /// components); otherwise empty and [`Bdf::ewt`] answers `nwt`.
    ewt: Vec<f64>,
    nwt: Vec<f64>,
    /// Whether `ewt` is stored separately.
    ewt_separate: bool,
    /// Splitting of the vector passes ([`System::parallel`], taken at `start`).
    parallel: crate::Parallelism,
    /// Whether the next step is the first after a [`Method::resume`] (checked by step
    /// doubling).
    doubling: bool,
    /// The first accepted step after the last [`Method::resume`] (0: none yet).
    resume_h: f64,
    /// Whether no step has been accepted since the last [`Method::resume`].
    resume_pending: bool,
}

impl Default for Bdf {
    fn default() -> Self {
        Self::new()
    }
}

impl Bdf {
    /// A BDF method; state is set by [`Method::start`].
    ///
    /// ```
    /// use integrators::Method;
    /// let m = integrators::methods::bdf::Bdf::new();
    /// assert_eq!(m.name(), "bdf");
    /// ```
    pub fn new() -> Self {
        Self {
            n: 0,
            pattern: None,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            h_pending: true,
            k: 1,
            k_last: 1,
            steps_at_order: 0,
            steps_since_start: 0,
            accepted: 0,
            started: false,
            times: VecDeque::new(),
            vals: VecDeque::new(),
            yp0: Vec::new(),
            yp: Vec::new(),
            jy: None,
            jyp: None,
            iter: None,
            lin: None,
            jac_valid: false,
            jac_current: false,
            c_fact: 0.0,
            steps_since_jac: 0,
            ss: 20.0,
            ycur: Vec::new(),
            ypred: Vec::new(),
            ypcur: Vec::new(),
            res: Vec::new(),
            ewt: Vec::new(),
            nwt: Vec::new(),
            ewt_separate: false,
            parallel: crate::Parallelism::Serial,
            doubling: false,
            resume_h: 0.0,
            resume_pending: false,
        }
    }

    /// Error weights (the Newton weights unless algebraic components are suppressed).
    fn ewt(&self) -> &[f64] {
        if self.ewt_separate {
            &self.ewt
        } else {
            &self.nwt
        }
    }

    /// Order used for the last accepted step.
    ///
    /// ```
    /// let m = integrators::methods::bdf::Bdf::new();
    /// assert!(m.order() <= 5);
    /// ```
    pub fn order(&self) -> usize {
        self.k_last
    }

    /// The stored vectors with nonzero coefficients in `ca` (or `cb`): `(vector, ca_j, cb_j)`,
    /// in a fixed-size list (no allocation per call).
    fn items<'s>(&'s self, ca: &[f64; NC], cb: &[f64; NC], m: usize) -> Items<'s> {
        let mut out = Items {
            list: [(&[][..], 0.0, 0.0); NC],
            len: 0,
            // the values' sums over increments from the newest (the derivative item, last, as is)
            base: self.vals.front().map(|v| &v[..]),
            deriv: false,
        };
        for j in (0..=m).filter(|&j| ca[j] != 0.0 || cb[j] != 0.0) {
            let v: &[f64] = if j < m { &self.vals[j] } else { &self.yp0 };
            out.list[out.len] = (v, ca[j], cb[j]);
            out.len += 1;
            out.deriv = j == m;
        }
        out
    }

    /// Value and derivative at `t` of the polynomial through the first `m` history nodes:
    /// `y = Σ p_j·v_j`, `ẏ = Σ p'_j·v_j`, computed block-wise so each input is read once.
    fn poly(&self, m: usize, t: f64, y: &mut [f64], yp: &mut [f64]) {
        self.poly_impl(m, t, y, yp, None);
    }

    /// The predictor for a step to `t_new` from the first `m` history nodes, written into
    /// `ycur`/`ẏcur` (the Newton iteration starts there and the Jacobian is evaluated there),
    /// and in the same pass the error and Newton weights from the last accepted state.
    fn predict(&mut self, sys: &System<'_>, m: usize, t_new: f64) {
        let mut y = std::mem::take(&mut self.ycur);
        let mut yp = std::mem::take(&mut self.ypcur);
        let mut nwt = std::mem::take(&mut self.nwt);
        let mut ewt = std::mem::take(&mut self.ewt);
        let mut pred = std::mem::take(&mut self.ypred);
        pred.resize(y.len(), 0.0);
        let weights = Weights {
            pred: &mut pred,
            nwt: &mut nwt,
            ewt: if self.ewt_separate {
                Some(&mut ewt)
            } else {
                None
            },
            atol: sys.weight_atol(),
            algebraic: sys.algebraic(),
            rtol: sys.opts.rtol,
            map: sys.error_map(),
        };
        self.poly_impl(m, t_new, &mut y, &mut yp, Some(weights));
        (self.ycur, self.ypcur, self.nwt, self.ewt, self.ypred) = (y, yp, nwt, ewt, pred);
    }

    /// [`poly`](Self::poly), optionally also filling the weights from the newest history
    /// vector (block by block, so the vector is read once for both).
    fn poly_impl(
        &self,
        m: usize,
        t: f64,
        y: &mut [f64],
        yp: &mut [f64],
        weights: Option<Weights<'_>>,
    ) {
        let (z, len) = self.nodes(m);
        let mut p = [0.0; NC];
        let mut dp = [0.0; NC];
        interp_coeffs(&z[..len], t, &mut p, &mut dp);
        let items = self.items(&p, &dp, m);
        let items = &items;
        let y0 = &self.vals[0][..];
        let n = y.len();
        let mid = split_point(n, self.parallel);
        if mid == 0 {
            poly_blocks(items, y0, 0, y, yp, weights);
            return;
        }
        // two halves concurrently (same arithmetic per component)
        let (y1, y2) = y.split_at_mut(mid);
        let (yp1, yp2) = yp.split_at_mut(mid);
        let (w1, w2) = match weights {
            None => (None, None),
            Some(w) => {
                let (n1, n2) = w.nwt.split_at_mut(mid);
                let (p1, p2) = w.pred.split_at_mut(mid);
                let (e1, e2) = match w.ewt {
                    Some(e) => {
                        let (e1, e2) = e.split_at_mut(mid);
                        (Some(e1), Some(e2))
                    }
                    None => (None, None),
                };
                let half = |pred, nwt, ewt| Weights {
                    pred,
                    nwt,
                    ewt,
                    atol: w.atol,
                    algebraic: w.algebraic,
                    rtol: w.rtol,
                    map: w.map,
                };
                (Some(half(p1, n1, e1)), Some(half(p2, n2, e2)))
            }
        };
        rayon::join(
            || poly_blocks(items, y0, 0, y1, yp1, w1),
            || poly_blocks(items, y0, mid, y2, yp2, w2),
        );
    }

    /// `α_m = Σ_{j=1..m} 1/(t_new - t_{j-1})` over the stored history.
    fn alpha(&self, m: usize, t_new: f64) -> f64 {
        self.times
            .iter()
            .take(m)
            .map(|&tj| 1.0 / (t_new - tj))
            .sum()
    }

    /// Local error estimate and normalised "scaled derivative" for order `m`, from
    /// `d = y_new - predictor_m(t_new)` (weighted norm `dn`): returns `(err_m, terr_m)`.
    fn estimates(&self, m: usize, t_new: f64, h: f64, dn: f64) -> (f64, f64) {
        let alpha = self.alpha(m, t_new);
        let psi_last = t_new - self.times[m];
        let err = dn / (alpha * psi_last);
        // terr ≈ ‖h^{m+1} y^{(m+1)}‖ = ‖d‖·(m+1)!·h^{m+1}/Π ψ_j
        let mut scale = 1.0;
        for j in 0..=m {
            scale *= (j + 1) as f64 * h / (t_new - self.times[j]);
        }
        (err, dn * scale)
    }

    /// The first `m` history times (at most the stored ones), on the stack, and their count.
    fn nodes(&self, m: usize) -> ([f64; NC], usize) {
        let mut z = [0.0; NC];
        let mut len = 0;
        for (zi, &t) in z.iter_mut().zip(self.times.iter().take(m)) {
            *zi = t;
            len += 1;
        }
        (z, len)
    }

    /// The coefficients of `predictor_m(t_new)` over the history, for each order in `orders`
    /// (built in place: this runs every step, and at a few hundred unknowns a step is a few
    /// microseconds).
    fn order_items<'s>(&'s self, orders: &[usize], t_new: f64) -> [Items<'s>; MAX_NORMS] {
        assert!(orders.len() <= MAX_NORMS, "at most {MAX_NORMS} orders");
        let zero = [0.0; NC];
        let mut out = [Items {
            list: [(&[][..], 0.0, 0.0); NC],
            len: 0,
            base: None,
            deriv: false,
        }; MAX_NORMS];
        for (o, &m) in out.iter_mut().zip(orders) {
            let (z, len) = self.nodes(m + 1);
            let (mut c, mut dp) = ([0.0; NC], [0.0; NC]);
            interp_coeffs(&z[..len], t_new, &mut c, &mut dp);
            *o = self.items(&c, &zero, m + 1);
        }
        out
    }

    /// In one block-wise sweep over the state, for each order `m` in `orders`, the error-weight
    /// norm of `y_new − predictor_m(t_new)`. The first order is the step's own: its difference
    /// is the total Newton correction, i.e. the local error estimate up to a factor, read as
    /// `ycur − ypred` (the step's [`predict`](Self::predict), which must have been for that
    /// order and `t_new`) instead of being re-evaluated from the history: the same sum
    /// (`predict` adds the same products in the same order, its extra items having
    /// coefficient zero), so the same norm. One sweep instead of one per order keeps a large
    /// state's history vectors in L1 across the orders. Each norm is bitwise what
    /// [`ErrorNorm::of`] gives on the same vector.
    fn error_norms(
        &self,
        orders: &[usize],
        t_new: f64,
        norm: ErrorNorm,
        map: &ErrorMap,
    ) -> [f64; MAX_NORMS] {
        let n = self.ycur.len();
        let mut out = [0.0; MAX_NORMS];
        if n == 0 {
            return out;
        }
        let mut items = self.order_items(orders, t_new);
        debug_assert_eq!(self.ypred.len(), n);
        items[0].list[0] = (&self.ypred[..], 1.0, 0.0);
        items[0].len = 1;
        (items[0].base, items[0].deriv) = (None, false);
        let items = &items[..orders.len()];
        let ewt = self.ewt();
        let mid = split_point(n, self.parallel);
        let acc = if mid == 0 {
            norm_blocks(items, &self.ycur, ewt, norm, map, 0, n)
        } else {
            // two halves concurrently; the partial norms are merged (an RMS sum in two parts)
            let ycur = &self.ycur[..];
            let (mut a1, a2) = rayon::join(
                || norm_blocks(items, ycur, ewt, norm, map, 0, mid),
                || norm_blocks(items, ycur, ewt, norm, map, mid, n),
            );
            for (a, b) in a1.iter_mut().zip(&a2) {
                a.merge(b);
            }
            a1
        };
        for (o, a) in out.iter_mut().zip(&acc) {
            *o = a.finish(n);
        }
        out
    }

    /// The component with the largest weighted local error `|y_new − predictor_k|·w` (for the
    /// failure report of a step that failed its error test).
    fn worst_error(&self, k: usize, t_new: f64) -> Option<usize> {
        let items = self.order_items(&[k], t_new);
        let pred = |i: usize| -> f64 { items[0].at(i).0 };
        worst_of(
            self.ycur
                .iter()
                .zip(self.ewt())
                .enumerate()
                .map(|(i, (y, w))| (y - pred(i)) * w),
        )
    }

    /// The per-step working vectors, from the system's spares (every entry of these is
    /// written before it is read: predictor, Newton update, residual, weights).
    fn ensure_work(&mut self, sys: &mut System<'_>) {
        let n = self.n;
        for v in [
            &mut self.ycur,
            &mut self.ypcur,
            &mut self.res,
            &mut self.nwt,
        ] {
            if v.len() != n {
                *v = sys.take_vec();
            }
        }
    }

    /// The Newton matrices and solver, from the system's spares where it has them (the
    /// consistent initialisation's, already paged in). A banded solver combines
    /// `J(0) + α·∂F/∂ẏ` in place, so its scratch matrix is an empty stand-in.
    fn ensure_linalg(&mut self, sys: &mut System<'_>) {
        if self.jy.is_none() {
            self.jy = Some(sys.take_matrix());
            self.jyp = Some(sys.take_matrix());
            let lin = sys.take_solver();
            self.iter = Some(if lin.combines_in_place() {
                Matrix::zeros(0, &Pattern::Dense)
            } else {
                sys.new_matrix()
            });
            self.lin = Some(lin);
        }
    }

    fn give_up(&self, last: &LastFailure, h: f64) -> SolverError {
        let (kind, comp) = match last {
            LastFailure::ErrorTest(c) => (ErrorKind::StepSizeTooSmall { h }, *c),
            LastFailure::Newton(c) => (ErrorKind::NewtonFailure, *c),
            LastFailure::Recoverable(reason, c) => (reason.clone().into(), *c),
        };
        SolverError::new(kind, self.t, comp)
    }
}

impl Method for Bdf {
    fn name(&self) -> &'static str {
        "bdf"
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
        self.parallel = sys.parallel();
        if y.len() != n || yp.len() != n {
            return Err(SolverError::new(
                ErrorKind::InvalidInput(format!(
                    "state length {} / derivative length {} differ from the problem dimension {n}",
                    y.len(),
                    yp.len()
                )),
                t,
                None,
            ));
        }
        let pattern_changed = self.pattern.as_ref() != Some(sys.pattern());
        // the history goes back to the spares (a restart keeps one node)
        for v in self.vals.drain(..) {
            sys.give_vec(v);
        }
        if n != self.n || pattern_changed {
            self.n = n;
            self.pattern = Some(sys.pattern().clone());
            // the same band at a new size (a line that gained cells): the Newton matrices and
            // the factor storage grow in place (refilled before use), else they are rebuilt
            let grown = !pattern_changed
                && self.jy.as_mut().is_some_and(|m| m.grow(n))
                && self.jyp.as_mut().is_some_and(|m| m.grow(n))
                && self.lin.as_mut().is_some_and(|l| l.grow(n))
                && self.lin.as_ref().is_some_and(|l| l.combines_in_place());
            if !grown {
                self.jy = None;
                self.jyp = None;
                self.iter = None;
                self.lin = None;
            }
            // the working vectors are taken at the first step (`ensure_work`), after the
            // starting-step estimate has handed its scratch back
            for v in [
                &mut self.ycur,
                &mut self.ypcur,
                &mut self.res,
                &mut self.nwt,
            ] {
                sys.give_vec(std::mem::take(v));
            }
        }
        self.ewt_separate =
            sys.opts.suppress_algebraic && sys.algebraic().iter().any(|&is_alg| is_alg);
        self.ewt.clear();
        if self.ewt_separate {
            self.ewt.resize(n, 0.0);
        }
        self.jac_valid = false;
        self.jac_current = false;
        self.c_fact = 0.0;
        self.ss = 20.0;
        self.t = t;
        self.t_prev = t;
        for (v, from) in [(&mut self.yp, yp), (&mut self.yp0, yp)] {
            if v.len() != n {
                *v = sys.take_vec();
            }
            v.copy_from_slice(from);
        }
        self.times.clear();
        self.times.push_back(t);
        self.times.push_back(t);
        for _ in 0..2 {
            let mut v = sys.take_vec();
            v.copy_from_slice(y);
            self.vals.push_back(v);
        }
        self.k = 1;
        self.k_last = 1;
        self.steps_at_order = 0;
        self.steps_since_start = 0;
        self.started = true;
        self.doubling = false;
        match h.or(sys.opts.h0) {
            Some(h) if h > 0.0 && h.is_finite() => {
                self.h = h.min(sys.opts.h_max);
                self.h_pending = false;
            }
            _ => {
                self.h = 0.0;
                self.h_pending = true;
            }
        }
        Ok(())
    }

    /// Goes on after a resizing event the problem maps (see [`Method::resume`]): a restart at
    /// order 1 from the mapped `(t, y, ẏ)` with the pre-event step size, whose first step is
    /// checked by step doubling (`Bdf::step_doubled`) instead of against the extrapolated
    /// `ẏ`. A division makes the solution kink (each daughter grows at its parent's absolute
    /// rate, so the tissue's growth rate jumps and the velocities relax to new values within a
    /// time `∝ K`): any predictor built from before the event — mapped history or restart
    /// derivative — misses the new slope by `Δv`, its error estimate `≈ Δv·h/2` cuts the step
    /// to `≈ 2·rtol·x/Δv` and the step then takes ten or more steps to grow back (measured
    /// with the history mapped onto the new layout: 7.2 steps and 1.6 rejections per division
    /// at K = 1e-5), while backward Euler itself is accurate across the kink once the
    /// transient is shorter than the step.
    fn resume(
        &mut self,
        sys: &mut System<'_>,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<bool, SolverError> {
        let h = self.h;
        if !(self.started && h > 0.0 && h.is_finite()) {
            return Ok(false);
        }
        let (had_jacobian, age) = (self.jac_valid, self.steps_since_jac);
        self.start(sys, t, y, yp, Some(h))?;
        // the Newton matrices grew in place (same band): the problem may map them onto the
        // new layout, re-evaluating only the rows the event changed
        if had_jacobian {
            if let (Some(jy), Some(jyp)) = (self.jy.as_mut(), self.jyp.as_mut()) {
                if jy.n() == y.len() && sys.problem.map_jacobian(t, y, yp, jy, jyp) == Ok(true) {
                    sys.stats.jacobians_mapped += 1;
                    self.jac_valid = true;
                    self.steps_since_jac = age;
                }
            }
        }
        self.doubling = true;
        self.resume_pending = true;
        Ok(true)
    }

    fn step(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<usize, SolverError> {
        self.accepted = 0;
        let t0 = self.t;
        self.step_once(sys, t_stop)?;
        if self.resume_pending && self.accepted > 0 {
            self.resume_pending = false;
            self.resume_h = self.t - t0;
        }
        Ok(self.accepted)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn t_prev(&self) -> f64 {
        self.t_prev
    }

    fn y(&self) -> &[f64] {
        self.vals.front().map_or(&[], |v| v)
    }

    fn yp(&self) -> &[f64] {
        &self.yp
    }

    fn h_next(&self) -> f64 {
        self.h
    }

    fn dense_output_controlled(&self) -> bool {
        true
    }

    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        if self.t == self.t_prev || t == self.t {
            y.copy_from_slice(&self.vals[0]);
            yp.copy_from_slice(&self.yp);
            return;
        }
        let m = (self.k_last + 1).min(self.times.len());
        self.poly(m, t, y, yp);
    }
}

mod doubling;
mod kernels;
mod newton;
mod stepping;
use kernels::*;
#[cfg(test)]
mod tests;
