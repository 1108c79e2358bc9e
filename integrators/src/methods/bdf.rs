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
/// Steps after which the Jacobian is refreshed even if Newton converges.
const MAX_JAC_AGE: usize = 50;

/// Why the last attempt failed (for the error reported when retries run out).
#[derive(Clone, Debug)]
enum LastFailure {
    ErrorTest(Option<usize>),
    Newton(Option<usize>),
    Recoverable(RecoverableCause, Option<usize>),
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
}

impl Default for Bdf {
    fn default() -> Self {
        Self::new()
    }
}

/// Newton-form interpolation through the nodes `z` (newest first; two equal adjacent nodes mean
/// the second carries the derivative item, index `z.len()`): coefficients over the items of
/// `p(t)` and `p'(t)`.
fn interp_coeffs(z: &[f64], t: f64, p: &mut [f64; NC], dp: &mut [f64; NC]) {
    let m = z.len();
    debug_assert!((1..NC).contains(&m));
    let mut table = [[0.0; NC]; NC];
    for (i, row) in table.iter_mut().enumerate().take(m) {
        row[i] = 1.0;
    }
    *p = [0.0; NC];
    *dp = [0.0; NC];
    let mut w = 1.0;
    let mut dw = 0.0;
    for level in 0..m {
        for q in 0..=m {
            p[q] += table[0][q] * w;
            dp[q] += table[0][q] * dw;
        }
        if level + 1 == m {
            break;
        }
        dw = dw * (t - z[level]) + w;
        w *= t - z[level];
        for i in 0..m - level - 1 {
            let den = z[i + level + 1] - z[i];
            if den == 0.0 {
                let mut e = [0.0; NC];
                e[m] = 1.0;
                table[i] = e;
            } else {
                let next = table[i + 1];
                for (cur, nxt) in table[i].iter_mut().zip(next).take(m + 1) {
                    *cur = (nxt - *cur) / den;
                }
            }
        }
    }
}

/// Where a vector pass of length `n` is split in two halves (run by [`rayon::join`]): a
/// block boundary near the middle, or 0 (no split) when `parallel` does not split `n`.
fn split_point(n: usize, parallel: crate::Parallelism) -> usize {
    if !parallel.splits(n) || n < 2 * BLK {
        return 0;
    }
    (n / 2) / BLK * BLK
}

/// The predictor (and optionally the weights) for components `lo..lo + y.len()`: `y`, `yp`
/// and the weights' outputs are that range's slices, the history vectors, `y0` (the newest,
/// for the weights) and the weights' inputs are whole vectors.
fn poly_blocks(
    items: &[(&[f64], f64, f64)],
    y0: &[f64],
    lo: usize,
    y: &mut [f64],
    yp: &mut [f64],
    mut weights: Option<Weights<'_>>,
) {
    let n = y.len();
    let mut s = 0;
    while s < n {
        let e = (s + BLK).min(n);
        let (yb, ypb) = (&mut y[s..e], &mut yp[s..e]);
        yb.fill(0.0);
        ypb.fill(0.0);
        for &(v, a, b) in items {
            let vb = &v[lo + s..lo + e];
            for ((yi, ypi), &x) in yb.iter_mut().zip(ypb.iter_mut()).zip(vb) {
                *yi += a * x;
                *ypi += b * x;
            }
        }
        if let Some(w) = weights.as_mut() {
            // the Newton weights are the error weights without the suppression of algebraic
            // components, as in `System::error_weights`
            let rtol = w.rtol;
            if w.map.is_empty() {
                let (yb0, atol) = (&y0[lo + s..lo + e], &w.atol[lo + s..lo + e]);
                for ((nw, yi), a) in w.nwt[s..e].iter_mut().zip(yb0).zip(atol) {
                    *nw = 1.0 / (rtol * yi.abs() + a);
                }
            } else {
                // cell-level weights (differences with the partner, read from the whole y0)
                w.map.weights(y0, w.atol, rtol, lo + s, &mut w.nwt[s..e]);
            }
            if let Some(ew) = w.ewt.as_mut() {
                let alg = &w.algebraic[lo + s..lo + e];
                for ((ewi, &nw), &is_alg) in ew[s..e].iter_mut().zip(&w.nwt[s..e]).zip(alg) {
                    *ewi = if is_alg { 0.0 } else { nw };
                }
            }
        }
        s = e;
    }
}

/// The error-norm sweep of [`Bdf::error_norms`] over components `lo..hi`: one accumulator
/// per order in `items` (the norm of `y_new − predictor_m`).
fn norm_blocks(
    items: &[Items<'_>],
    ycur: &[f64],
    ewt: &[f64],
    norm: ErrorNorm,
    map: &ErrorMap,
    lo: usize,
    hi: usize,
) -> [NormAcc; MAX_NORMS] {
    let mut buf = [0.0; BLK];
    let mut acc = [NormAcc::new(norm); MAX_NORMS];
    if !map.is_empty() {
        // cell-level quantities: the difference of a component's error with its partner's,
        // taken from the block's buffer or (a partner outside the block) recomputed
        let mut s = lo;
        while s < hi {
            let e = (s + BLK).min(hi);
            for (it, a) in items.iter().zip(acc.iter_mut()) {
                let b = &mut buf[..e - s];
                b.fill(0.0);
                for &(v, c, _) in it.as_slice() {
                    for (bi, &x) in b.iter_mut().zip(&v[s..e]) {
                        *bi += c * x;
                    }
                }
                let b = &buf[..e - s];
                let err = |p: usize| -> f64 {
                    if (s..e).contains(&p) {
                        ycur[p] - b[p - s]
                    } else {
                        ycur[p] - it.as_slice().iter().map(|&(v, c, _)| c * v[p]).sum::<f64>()
                    }
                };
                for i in s..e {
                    let q = map.quantity_with(i, ycur[i] - b[i - s], err);
                    a.push(q * ewt[i]);
                }
                map.for_each_end(s, e, ewt, |i, we| a.push(err(i) * we));
            }
            s = e;
        }
        return acc;
    }
    let mut s = lo;
    while s < hi {
        let e = (s + BLK).min(hi);
        let (yb, wb) = (&ycur[s..e], &ewt[s..e]);
        for (it, a) in items.iter().zip(acc.iter_mut()) {
            let b = &mut buf[..e - s];
            b.fill(0.0);
            for &(v, c, _) in it.as_slice() {
                for (bi, &x) in b.iter_mut().zip(&v[s..e]) {
                    *bi += c * x;
                }
            }
            for ((bi, yi), wi) in b.iter().zip(yb).zip(wb) {
                a.push((yi - bi) * wi);
            }
        }
        s = e;
    }
    acc
}

/// The Newton norm of `v` (weights `w`) through a non-empty error map, on two threads for a
/// large state (the halves' partial norms are merged, as [`Bdf::error_norms`] does). The end
/// rows ([`ErrorMap::with_end`]) are tested as in the error test: without them a Newton
/// correction that moves the boundary next to a driven end together with its neighbours (a
/// smooth profile, small in every difference) passes while the end cell's stretch is far from
/// converged — measured on fig2_6's continuum (n = 2000, K = 1e-5, rtol 1e-6), an accepted
/// first step left that cell at λ = 0.48 against 0.999.
fn map_norm(
    map: &ErrorMap,
    v: &[f64],
    w: &[f64],
    norm: ErrorNorm,
    parallel: crate::Parallelism,
) -> f64 {
    let n = v.len();
    let mid = split_point(n, parallel);
    let sum = if mid == 0 {
        map.norm_range(v, w, norm, 0, n)
    } else {
        let (mut first, second): (NormSum, NormSum) = rayon::join(
            || map.norm_range(v, w, norm, 0, mid),
            || map.norm_range(v, w, norm, mid, n),
        );
        first.merge(&second);
        first
    };
    sum.finish(norm, n)
}

/// Index of the largest `|v_i w_i|`.
fn worst(v: &[f64], w: &[f64]) -> Option<usize> {
    worst_of(v.iter().zip(w).map(|(a, b)| a * b))
}

/// Index of the largest `|x_i|`, or of the first NaN.
fn worst_of(xs: impl Iterator<Item = f64>) -> Option<usize> {
    let mut best = None;
    let mut bv = -1.0;
    for (i, x) in xs.enumerate() {
        let x = x.abs();
        if x > bv || x.is_nan() {
            bv = x;
            best = Some(i);
            if x.is_nan() {
                break;
            }
        }
    }
    best
}

/// The per-component Newton update, applied by the linear solve as each component of
/// `J⁻¹F` is found ([`System::solve_map`]).
struct NewtonUpdate<'a> {
    /// Global index of `y[0]` (non-zero for the second half of a split).
    off: usize,
    y: &'a mut [f64],
    yp: &'a mut [f64],
    w: &'a [f64],
    scale: f64,
    alpha: f64,
    acc: NormAcc,
}

impl SolutionMap for NewtonUpdate<'_> {
    /// `δ_i = −scale·d_i`; updates `y`, `ẏ` and the norm; returns `δ_i`.
    #[inline(always)]
    fn map(&mut self, i: usize, d: f64) -> f64 {
        let i = i - self.off;
        let di = if self.scale != 1.0 {
            -(d * self.scale)
        } else {
            -d
        };
        self.y[i] += di;
        self.yp[i] += self.alpha * di;
        self.acc.push(di * self.w[i]);
        di
    }

    fn split(self, mid: usize) -> Result<(Self, Self), Self> {
        let at = mid - self.off;
        let (y1, y2) = self.y.split_at_mut(at);
        let (yp1, yp2) = self.yp.split_at_mut(at);
        let (w1, w2) = self.w.split_at(at);
        let half = |off, y, yp, w| NewtonUpdate {
            off,
            y,
            yp,
            w,
            scale: self.scale,
            alpha: self.alpha,
            acc: NormAcc::new(ErrorNorm::Rms),
        };
        let mut a = half(self.off, y1, yp1, w1);
        let mut b = half(mid, y2, yp2, w2);
        (a.acc, b.acc) = (
            self.acc,
            NormAcc {
                sum: 0.0,
                max: 0.0,
                nan: false,
                ..self.acc
            },
        );
        Ok((a, b))
    }

    fn merge(&mut self, other: Self) {
        self.acc.merge(&other.acc);
    }
}

/// Outputs and inputs of the weights pass fused into the predictor ([`Bdf::predict`]).
struct Weights<'a> {
    nwt: &'a mut [f64],
    /// Separate error weights (suppressed algebraic components), if any.
    ewt: Option<&'a mut [f64]>,
    /// [`System::weight_atol`].
    atol: &'a [f64],
    algebraic: &'a [bool],
    rtol: f64,
    /// The problem's error map (empty: the identity).
    map: &'a ErrorMap,
}

/// Up to `NC` history vectors with their coefficients (see `Bdf::items`).
#[derive(Clone, Copy)]
struct Items<'s> {
    list: [(&'s [f64], f64, f64); NC],
    len: usize,
}

impl<'s> Items<'s> {
    fn as_slice(&self) -> &[(&'s [f64], f64, f64)] {
        &self.list[..self.len]
    }
}

/// Running weighted norm of one kind, bitwise equal to [`ErrorNorm::of`] over the same
/// products: RMS sums the squares in index order; max keeps a NaN flag beside the running
/// maximum instead of a NaN-sticky fold, which takes the NaN test off the dependency chain.
#[derive(Clone, Copy)]
struct NormAcc {
    rms: bool,
    sum: f64,
    max: f64,
    nan: bool,
}

impl NormAcc {
    fn new(norm: ErrorNorm) -> Self {
        Self {
            rms: matches!(norm, ErrorNorm::Rms),
            sum: 0.0,
            max: 0.0,
            nan: false,
        }
    }

    #[inline(always)]
    fn push(&mut self, x: f64) {
        if self.rms {
            self.sum += x * x;
        } else {
            let a = x.abs();
            self.nan |= a.is_nan();
            self.max = if a > self.max { a } else { self.max };
        }
    }

    /// Adds the products another accumulator (of the same kind) has seen.
    fn merge(&mut self, other: &NormAcc) {
        self.sum += other.sum;
        self.nan |= other.nan;
        self.max = if other.max > self.max {
            other.max
        } else {
            self.max
        };
    }

    fn finish(&self, n: usize) -> f64 {
        if n == 0 {
            0.0
        } else if self.rms {
            (self.sum / n as f64).sqrt()
        } else if self.nan {
            f64::NAN
        } else {
            self.max
        }
    }
}

impl Bdf {
    /// A BDF method; state is set by [`Method::start`].
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
            ypcur: Vec::new(),
            res: Vec::new(),
            ewt: Vec::new(),
            nwt: Vec::new(),
            ewt_separate: false,
            parallel: crate::Parallelism::Serial,
            doubling: false,
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
    pub fn order(&self) -> usize {
        self.k_last
    }

    /// The stored vectors with nonzero coefficients in `ca` (or `cb`): `(vector, ca_j, cb_j)`,
    /// in a fixed-size list (no allocation per call).
    fn items<'s>(&'s self, ca: &[f64; NC], cb: &[f64; NC], m: usize) -> Items<'s> {
        let mut out = Items {
            list: [(&[][..], 0.0, 0.0); NC],
            len: 0,
        };
        for j in (0..=m).filter(|&j| ca[j] != 0.0 || cb[j] != 0.0) {
            let v: &[f64] = if j < m { &self.vals[j] } else { &self.yp0 };
            out.list[out.len] = (v, ca[j], cb[j]);
            out.len += 1;
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
        let weights = Weights {
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
        (self.ycur, self.ypcur, self.nwt, self.ewt) = (y, yp, nwt, ewt);
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
        let items = items.as_slice();
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
                let (e1, e2) = match w.ewt {
                    Some(e) => {
                        let (e1, e2) = e.split_at_mut(mid);
                        (Some(e1), Some(e2))
                    }
                    None => (None, None),
                };
                let half = |nwt, ewt| Weights {
                    nwt,
                    ewt,
                    atol: w.atol,
                    algebraic: w.algebraic,
                    rtol: w.rtol,
                    map: w.map,
                };
                (Some(half(n1, e1)), Some(half(n2, e2)))
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
    /// norm of `y_new − predictor_m(t_new)` (no predictor is stored). The first order is the
    /// step's own: its difference is the total Newton correction, i.e. the local error
    /// estimate up to a factor. One sweep instead of one per order keeps a large state's
    /// history vectors in L1 across the orders. Each norm is bitwise what [`ErrorNorm::of`]
    /// gives on the same vector.
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
        let items = self.order_items(orders, t_new);
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
        let pred =
            |i: usize| -> f64 { items[0].as_slice().iter().map(|&(v, c, _)| c * v[i]).sum() };
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

    /// Jacobian (if needed) and factorisation for `α`, then simplified Newton from the predictor
    /// (which [`Bdf::predict`] has written into `ycur`/`ẏcur`).
    fn newton(&mut self, sys: &mut System<'_>, t_new: f64, alpha: f64) -> Result<(), NewtonFail> {
        let n = self.n;
        self.ensure_linalg(sys);
        let mut new_fact = false;
        if !self.jac_valid || self.steps_since_jac >= MAX_JAC_AGE {
            let jy = self.jy.as_mut().expect("allocated");
            let jyp = self.jyp.as_mut().expect("allocated");
            let r = sys
                .jacobian(t_new, &self.ycur, &self.ypcur, 0.0, jy)
                .and_then(|_| sys.jacobian(t_new, &self.ycur, &self.ypcur, 1.0, jyp));
            match r {
                Ok(()) => {}
                Err(StepFailure::Recoverable { reason, component }) => {
                    self.jac_valid = false;
                    return Err(NewtonFail::Recoverable(reason, component));
                }
                Err(StepFailure::Fatal(e)) => return Err(NewtonFail::Fatal(e)),
            }
            // jyp = J(1) - J(0) = ∂F/∂ẏ
            jyp.axpby(1.0, -1.0, jy);
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
        let scale = if alpha == self.c_fact {
            1.0
        } else {
            2.0 / (1.0 + alpha / self.c_fact)
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
            // component to one fused update that stores δ in `res`, updates the iterate and
            // accumulates ‖δ‖; the tridiagonal solver runs it inside its backward sweep. (The
            // total correction `y_new − predictor` is not accumulated here: the error test
            // recomputes it from the history in its own sweep, one stream fewer per iteration.)
            let upd = NewtonUpdate {
                off: 0,
                y: &mut self.ycur[..n],
                yp: &mut self.ypcur[..n],
                w: &self.nwt[..n],
                scale,
                alpha,
                acc: NormAcc::new(sys.opts.norm),
            };
            // an iterative solver stops once its error is a small fraction of EPS_NEWT in the
            // Newton norm (inexact Newton, as IDA; see `IterativeSettings`)
            let tol = LinearTolerance {
                weights: &self.nwt,
                norm: sys.opts.norm,
                target: EPS_NEWT,
            };
            let lin = self.lin.as_ref().expect("allocated");
            let upd = sys.solve_map(lin, &mut self.res, Some(&tol), upd);
            let delnrm = if sys.error_map().is_empty() {
                upd.acc.finish(n)
            } else {
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
                    return Err(NewtonFail::NoConvergence(worst(&self.res, &self.nwt)));
                }
                self.ss = rate / (1.0 - rate);
            }
            if self.ss * delnrm <= EPS_NEWT {
                return Ok(());
            }
        }
        Err(NewtonFail::NoConvergence(worst(&self.res, &self.nwt)))
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

impl Bdf {
    /// The first step after a [`Method::resume`]: backward Euler over `h` and over two halves
    /// of it; the halves are the accepted steps, and `‖y_halves − y_full‖` (weighted) is their
    /// error estimate (at order 1 the full step's error is twice the halves', so the
    /// difference estimates the halves' error). Unlike the predictor difference it needs no
    /// smoothness before the step, so a kink at the event costs nothing once its transient
    /// is shorter than `h/2`. On rejection `h` shrinks by the usual factor (the Newton
    /// matrices are kept: `α` changes by a refactorisation); after [`DOUBLING_TRIES`] failed
    /// attempts the ordinary step (error test against the restart's `ẏ`) takes over. On
    /// success the history is the post-event nodes `t + h, t + h/2, t`, from which the
    /// ordinary steps go on.
    fn step_doubled(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<(), SolverError> {
        let opts = sys.opts;
        self.ensure_work(sys);
        let t0 = self.t;
        let mut h = self.h;
        let mut nef = 0usize;
        let mut ncf = 0usize;
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
                Err(NewtonFail::NoConvergence(_)) => {
                    self.jac_valid = false;
                    sys.stats.newton_failures += 1;
                    Some(0.25)
                }
                Err(NewtonFail::Recoverable(..)) => Some(0.25),
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
            let factor = match fail {
                Some(f) => {
                    ncf += 1;
                    Some(f)
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
                sys.stats.rejected_steps += 1;
                if half_pushed {
                    self.pop_accepted(sys, t0);
                }
                h = h_try * f;
                if nef >= DOUBLING_ERROR_TRIES || nef + ncf >= DOUBLING_TRIES || h < h_floor {
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
    fn be_solve(&mut self, sys: &mut System<'_>, t_new: f64) -> Result<(), NewtonFail> {
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
    fn push_accepted(&mut self, sys: &mut System<'_>, t_new: f64) {
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
    fn pop_accepted(&mut self, sys: &mut System<'_>, t0: f64) {
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
        self.start(sys, t, y, yp, Some(h))?;
        self.doubling = true;
        Ok(true)
    }

    fn step(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<usize, SolverError> {
        self.accepted = 0;
        self.step_once(sys, t_stop)?;
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

impl Bdf {
    /// One [`Method::step`]: the accepted steps it takes are counted in `accepted`.
    fn step_once(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<(), SolverError> {
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
                ErrorKind::InvalidInput(format!("t_stop = {t_stop} is not after t = {}", self.t)),
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
                sys.stats.rejected_steps += 1;
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
                sys.stats.rejected_steps += 1;
                last = LastFailure::ErrorTest(self.worst_error(k, t_new));
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
                if nef >= MAX_ERR_FAILS || h < h_floor {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_reproduces_polynomials() {
        // cubic through 4 nodes: exact value and derivative
        let f = |t: f64| 1.0 + 2.0 * t - t * t + 0.5 * t * t * t;
        let df = |t: f64| 2.0 - 2.0 * t + 1.5 * t * t;
        let z = [1.0, 0.7, 0.2, -0.4];
        let mut p = [0.0; NC];
        let mut dp = [0.0; NC];
        interp_coeffs(&z, 1.3, &mut p, &mut dp);
        let v: f64 = (0..4).map(|i| p[i] * f(z[i])).sum();
        let d: f64 = (0..4).map(|i| dp[i] * f(z[i])).sum();
        assert!((v - f(1.3)).abs() < 1e-12);
        assert!((d - df(1.3)).abs() < 1e-12);
    }

    #[test]
    fn split_vector_passes_match_the_whole_pass() {
        // the two-thread split of the predictor/weights pass and of the error-norm sweep, run
        // here on one thread at a block boundary: predictor and weights bitwise, norms merged
        let n = 3 * BLK + 17;
        let vec_of = |k: f64| -> Vec<f64> { (0..n).map(|i| (i as f64 * k).sin() + 1.5).collect() };
        let (h0, h1, h2) = (vec_of(0.3), vec_of(0.7), vec_of(1.1));
        let mut list = [(&[][..], 0.0, 0.0); NC];
        list[0] = (&h0[..], 1.7, 0.4);
        list[1] = (&h1[..], -0.9, -1.3);
        list[2] = (&h2[..], 0.2, 0.9);
        let items = Items { list, len: 3 };
        let atol = vec![1e-6; n];
        let alg: Vec<bool> = (0..n).map(|i| i % 5 == 0).collect();
        // the identity and a line's cell map (anchor + differences with the previous
        // component, so the sweep's partners cross the block and split boundaries)
        let mut rows = vec![crate::Row::Anchor { size: 2.0 }];
        rows.extend((1..n).map(|i| crate::Row::Difference { partner: i - 1 }));
        let line = ErrorMap::from_rows(rows).expect("valid rows");
        for mut map in [ErrorMap::default(), line] {
            let eatol = if map.is_empty() {
                atol.clone()
            } else {
                map.effective_atol(&atol, 1e-3)
            };
            let run = |mid: usize| {
                let (mut y, mut yp, mut nw, mut ew) =
                    (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                let (y1, y2) = y.split_at_mut(mid);
                let (yp1, yp2) = yp.split_at_mut(mid);
                let (n1, n2) = nw.split_at_mut(mid);
                let (e1, e2) = ew.split_at_mut(mid);
                let w = |nwt, ewt| Weights {
                    nwt,
                    ewt: Some(ewt),
                    atol: &eatol,
                    algebraic: &alg,
                    rtol: 1e-3,
                    map: &map,
                };
                poly_blocks(items.as_slice(), &h0, 0, y1, yp1, Some(w(n1, e1)));
                poly_blocks(items.as_slice(), &h0, mid, y2, yp2, Some(w(n2, e2)));
                (y, yp, nw, ew)
            };
            let whole = run(n);
            let split = run(BLK);
            assert_eq!(whole, split);
            let ycur = vec_of(0.5);
            let norm_items = [Items { list, len: 3 }, Items { list, len: 2 }];
            for norm in [ErrorNorm::Max, ErrorNorm::Rms] {
                let a = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, 0, n);
                let mut a1 = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, 0, BLK);
                let a2 = norm_blocks(&norm_items, &ycur, &whole.3, norm, &map, BLK, n);
                for (x, y) in a1.iter_mut().zip(&a2) {
                    x.merge(y);
                }
                let close = |x: f64, y: f64| (x - y).abs() <= 1e-14 * x.abs().max(1e-300);
                // (two orders in the sweep: the other accumulators stay empty)
                for ((x, y), it) in a.iter().zip(&a1).zip(&norm_items) {
                    assert!(
                        x.finish(n) > 0.0 && close(x.finish(n), y.finish(n)),
                        "{norm:?}"
                    );
                    // against the materialised error vector through `ErrorMap::norm`
                    let err: Vec<f64> = (0..n)
                        .map(|i| {
                            ycur[i] - it.as_slice().iter().map(|&(v, c, _)| c * v[i]).sum::<f64>()
                        })
                        .collect();
                    let direct = map.norm(&err, &whole.3, norm);
                    assert!(
                        close(x.finish(n), direct),
                        "{norm:?}: {} vs {direct}",
                        x.finish(n)
                    );
                }
            }
        }
    }

    #[test]
    fn confluent_node_uses_the_derivative() {
        // quadratic through (1, f(1)), and the double node (0, f(0), f'(0))
        let f = |t: f64| 3.0 - t + 2.0 * t * t;
        let df = |t: f64| -1.0 + 4.0 * t;
        let z = [1.0, 0.0, 0.0];
        let mut p = [0.0; NC];
        let mut dp = [0.0; NC];
        interp_coeffs(&z, 0.6, &mut p, &mut dp);
        let v = p[0] * f(1.0) + p[1] * f(0.0) + p[2] * f(0.0) + p[3] * df(0.0);
        let d = dp[0] * f(1.0) + dp[1] * f(0.0) + dp[2] * f(0.0) + dp[3] * df(0.0);
        assert!((v - f(0.6)).abs() < 1e-12);
        assert!((d - df(0.6)).abs() < 1e-12);
    }
}
