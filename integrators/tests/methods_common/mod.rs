//! Shared problems, a minimal stepping loop and one checking helper per kind of expectation for
//! the method tests (ESDIRK, Radau IIA, Dormand–Prince). The loop drives a [`Method`] directly
//! through [`System`], independent of the driver, so that the methods are tested on their own;
//! each method's test file is then a list of "this method, this case, these expectations":
//!
//! * [`Case`] — a problem with its initial value, end time and exact solution;
//! * [`check_exact`] — end (and dense-output) error against the exact solution, by a [`Bound`];
//! * [`check_order`] — observed order from a fixed-step sweep;
//! * [`check_robertson`], [`check_van_der_pol`] — stiff benchmarks against a tight Radau IIA run.
#![allow(dead_code)]

use integrators::linalg::Matrix;
use integrators::system::{System, SystemCache};
use integrators::{
    Method, MethodKind, Options, Pattern, Problem, ResidualError, SolverError, Stats,
};

/// Result of [`integrate`].
pub struct Run {
    pub y: Vec<f64>,
    pub yp: Vec<f64>,
    pub stats: Stats,
    /// Counters after consistent initialisation (before the method's first step).
    pub init_stats: Stats,
    /// Largest dense-output error at step midpoints against `exact` (if given).
    pub dense_err: f64,
}

impl Run {
    /// Jacobian evaluations after consistent initialisation (the method's own, including its
    /// starting-step estimate).
    pub fn method_jacobians(&self) -> usize {
        self.stats.jacobian_evals - self.init_stats.jacobian_evals
    }
}

/// Integrates from `t0` to `t_end` with `method`, stepping until `t_end` is reached. If
/// `exact` is given, the dense output is checked at the midpoint of every step.
pub fn integrate(
    method: &mut dyn Method,
    problem: &mut dyn Problem,
    opts: &Options,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    exact: Option<&dyn Fn(f64) -> Vec<f64>>,
) -> Result<Run, SolverError> {
    let mut stats = Stats::default();
    let mut cache = SystemCache::default();
    cache.rebuild(problem, opts).expect("cache");
    let n = y0.len();
    let mut y = y0.to_vec();
    let mut yp = vec![0.0; n];
    let mut dense_err: f64 = 0.0;
    let init_stats;
    {
        let mut sys = System::new(problem, opts, &mut stats, &mut cache);
        sys.consistent_init(t0, &mut y, &mut yp)?;
        init_stats = *sys.stats;
        method.start(&mut sys, t0, &y, &yp, None)?;
        let mut yi = vec![0.0; n];
        let mut ypi = vec![0.0; n];
        while method.t() < t_end {
            // the driver counts steps; here this loop is the driver
            sys.stats.steps += method.step(&mut sys, t_end)?;
            assert!(method.t() <= t_end);
            if let Some(ex) = exact {
                let tm = 0.5 * (method.t_prev() + method.t());
                method.interpolate(tm, &mut yi, &mut ypi);
                let e = ex(tm);
                dense_err = dense_err.max(max_err(&yi, &e));
                // both ends reproduce the step's states
                method.interpolate(method.t(), &mut yi, &mut ypi);
                for (a, b) in yi.iter().zip(method.y()) {
                    assert!((a - b).abs() <= 1e-12 * (1.0 + a.abs()));
                }
            }
        }
        assert_eq!(method.t(), t_end, "must land exactly on t_stop");
    }
    Ok(Run {
        y: method.y().to_vec(),
        yp: method.yp().to_vec(),
        stats,
        init_stats,
        dense_err,
    })
}

/// Max-norm of `a − b`.
pub fn max_err(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Least-squares slope of `log(err)` against `log(h)`.
pub fn fitted_order(hs: &[f64], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Fixed-step sweep: error at `t_end` for `n_steps` steps each; returns (h, err) pairs.
pub fn fixed_step_sweep(
    make: &dyn Fn() -> Box<dyn Method>,
    problem: &mut dyn Problem,
    t_end: f64,
    y0: &[f64],
    exact: &dyn Fn(f64) -> Vec<f64>,
    n_steps: &[usize],
    tol: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut hs = Vec::new();
    let mut errs = Vec::new();
    for &ns in n_steps {
        let h = t_end / ns as f64;
        let opts = Options {
            rtol: tol,
            atol: tol,
            fixed_step: Some(h),
            ..Default::default()
        };
        let mut m = make();
        let run = integrate(m.as_mut(), problem, &opts, 0.0, y0, t_end, None).expect("fixed run");
        // exactly ns steps (the last may be a round-off sliver shorter)
        assert!(
            run.stats.steps == ns || run.stats.steps == ns + 1,
            "{} steps for {ns}",
            run.stats.steps
        );
        hs.push(h);
        errs.push(max_err(&run.y, &exact(t_end)));
    }
    (hs, errs)
}

// ---------------------------------------------------------------------------------------------
// Cases and checks
// ---------------------------------------------------------------------------------------------

/// `Options` with these tolerances, everything else default.
pub fn opts(rtol: f64, atol: f64) -> Options {
    Options {
        rtol,
        atol,
        ..Default::default()
    }
}

/// A problem with a closed-form solution.
pub trait Solved: Problem + Clone + std::fmt::Debug + 'static {
    /// The exact solution at `t`.
    fn solution(&self, t: f64) -> Vec<f64>;
    /// Initial value (default: the solution at `t = 0`).
    fn y0(&self) -> Vec<f64> {
        self.solution(0.0)
    }
}

/// A test problem on `[0, t_end]` with its initial value and exact solution.
pub struct Case {
    /// The problem's `Debug` form, for messages.
    pub name: String,
    pub problem: Box<dyn Problem>,
    pub y0: Vec<f64>,
    pub t_end: f64,
    pub exact: Box<dyn Fn(f64) -> Vec<f64>>,
}

impl Case {
    /// `problem` on `[0, t_end]` from its [`Solved::y0`].
    pub fn new<P: Solved>(problem: P, t_end: f64) -> Self {
        let solved = problem.clone();
        Self {
            name: format!("{problem:?}"),
            y0: problem.y0(),
            problem: Box::new(problem),
            t_end,
            exact: Box::new(move |t| solved.solution(t)),
        }
    }

    /// Integrates with a fresh method of `kind` (checking the dense output at every step
    /// midpoint when `dense`); returns the run and its max-norm error at `t_end`.
    pub fn run(&mut self, kind: MethodKind, o: &Options, dense: bool) -> (Run, f64) {
        let exact: &dyn Fn(f64) -> Vec<f64> = &*self.exact;
        let mut m = integrators::methods::build(kind);
        let run = integrate(
            m.as_mut(),
            self.problem.as_mut(),
            o,
            0.0,
            &self.y0,
            self.t_end,
            dense.then_some(exact),
        )
        .unwrap_or_else(|e| panic!("{kind} {}: {e}", self.name));
        let e = max_err(&run.y, &exact(self.t_end));
        (run, e)
    }
}

/// What [`check_exact`] asserts about the errors.
#[derive(Clone, Copy, Debug)]
pub enum Bound {
    /// End error below `end`; dense-output error below `dense` if given.
    Fixed { end: f64, dense: Option<f64> },
    /// For a per-step error controller (TR-BDF2: order-2 solution, error per step ≤ tol): on
    /// non-expanding problems the global error is bounded by the sum of the local tolerances,
    /// `steps · (rtol·ymax + atol)`, not by `rtol`, which no per-step controller promises. The
    /// end error (and, if `dense`, the dense-output error) must be below that sum.
    LocalSum { ymax: f64, dense: bool },
}

/// Runs `kind` on `case` with `o` and asserts `bound` on the errors; `dense` also checks the
/// dense output at every step midpoint (and that both step ends reproduce the states).
pub fn check_exact(
    kind: MethodKind,
    case: &mut Case,
    o: &Options,
    dense: bool,
    bound: Bound,
) -> Run {
    let (run, e) = case.run(kind, o, dense);
    let name = &case.name;
    eprintln!(
        "{kind} {name}: err {e:e} dense {:e} {:?}",
        run.dense_err, run.stats
    );
    let (end, dense_bound) = match bound {
        Bound::Fixed { end, dense } => (end, dense),
        Bound::LocalSum { ymax, dense } => {
            let sum = run.stats.steps as f64 * (o.rtol * ymax + o.atol);
            (sum, dense.then_some(sum))
        }
    };
    assert!(e < end, "{kind} {name}: end error {e:e} vs {end:e}");
    if let Some(d) = dense_bound {
        assert!(
            run.dense_err < d,
            "{kind} {name}: dense error {:e} vs {d:e}",
            run.dense_err
        );
    }
    run
}

/// Fixed-step sweep of `kind` on `case` with these step counts; asserts that the fitted order
/// is `expected ± 0.3`.
pub fn check_order(kind: MethodKind, case: &mut Case, n_steps: &[usize], expected: f64) {
    let (hs, errs) = fixed_step_sweep(
        &|| integrators::methods::build(kind),
        case.problem.as_mut(),
        case.t_end,
        &case.y0,
        &*case.exact,
        n_steps,
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!(
        "{kind} {} fixed-step errors {errs:?} -> observed order {p:.3}",
        case.name
    );
    assert!(
        (p - expected).abs() <= 0.3,
        "{kind} {}: observed order {p}",
        case.name
    );
}

/// Runs `kind` with `o` and the reference Radau IIA with `reference` on `problem` over
/// `[0, t_end]`; returns both.
fn with_reference(
    kind: MethodKind,
    problem: &mut dyn Problem,
    y0: &[f64],
    t_end: f64,
    o: &Options,
    reference: &Options,
) -> (Run, Run) {
    let mut m = integrators::methods::build(kind);
    let run = integrate(m.as_mut(), problem, o, 0.0, y0, t_end, None).unwrap();
    let mut r = integrators::methods::build(MethodKind::Radau);
    let reference = integrate(r.as_mut(), problem, reference, 0.0, y0, t_end, None).unwrap();
    eprintln!("{kind}: {:?} ref {:?} {:?}", run.y, reference.y, run.stats);
    (run, reference)
}

/// Robertson on `[0, 10⁵]` at `rtol = 10⁻⁶` against Radau IIA at `rtol = 10⁻¹¹`: mass is
/// conserved to 10⁻⁶, `y1`, `y3` agree to 10⁻⁴ and `y2` to 10⁻³ (relative). Returns the run for
/// per-method cost pins.
pub fn check_robertson(kind: MethodKind) -> Run {
    let (run, reference) = with_reference(
        kind,
        &mut Robertson,
        &[1.0, 0.0, 0.0],
        1e5,
        &opts(1e-6, 1e-8),
        &opts(1e-11, 1e-8),
    );
    let sum: f64 = run.y.iter().sum();
    assert!((sum - 1.0).abs() < 1e-6, "mass {sum}");
    for i in [0, 2] {
        let rel = (run.y[i] - reference.y[i]).abs() / reference.y[i].abs();
        assert!(
            rel < 1e-4,
            "component {i}: {} vs {}",
            run.y[i],
            reference.y[i]
        );
    }
    let rel = (run.y[1] - reference.y[1]).abs() / reference.y[1].abs();
    assert!(rel < 1e-3, "y2: {} vs {}", run.y[1], reference.y[1]);
    run
}

/// Van der Pol with `μ = 1000` on `[0, 3000]` at `rtol = atol = tol` completes and its `y1(3000)`
/// agrees with Radau IIA at `10⁻¹⁰` to `rel · max(|y1|, 1)`. Returns the run.
pub fn check_van_der_pol(kind: MethodKind, tol: f64, rel: f64) -> Run {
    let (run, reference) = with_reference(
        kind,
        &mut VanDerPol { mu: 1000.0 },
        &[2.0, 0.0],
        3000.0,
        &opts(tol, tol),
        &opts(1e-10, 1e-10),
    );
    assert!((run.y[0] - reference.y[0]).abs() < rel * reference.y[0].abs().max(1.0));
    run
}

/// `y[i−1] − 2y[i] + y[i+1]` with zero values outside `y` (homogeneous Dirichlet ends).
fn second_difference(y: &[f64], i: usize) -> f64 {
    let l = if i > 0 { y[i - 1] } else { 0.0 };
    let r = if i + 1 < y.len() { y[i + 1] } else { 0.0 };
    l - 2.0 * y[i] + r
}

// ---------------------------------------------------------------------------------------------
// Problems
// ---------------------------------------------------------------------------------------------

/// Linear 2×2 ODE `ẏ = [[-1, 2], [-2, -1]] y`, `y(0) = (1, 0)`:
/// `y = e^{-t} (cos 2t, −sin 2t)`. Analytic Jacobian.
#[derive(Clone, Debug)]
pub struct Linear2;

impl Solved for Linear2 {
    fn solution(&self, t: f64) -> Vec<f64> {
        let e = (-t).exp();
        vec![e * (2.0 * t).cos(), -e * (2.0 * t).sin()]
    }
    fn y0(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
}

impl Problem for Linear2 {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] - (-y[0] + 2.0 * y[1]);
        r[1] = yp[1] - (-2.0 * y[0] - y[1]);
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut Matrix,
    ) -> Result<bool, ResidualError> {
        jac.add(0, 0, 1.0 + c);
        jac.add(0, 1, -2.0);
        jac.add(1, 0, 2.0);
        jac.add(1, 1, 1.0 + c);
        Ok(true)
    }
}

/// Smooth nonlinear, non-autonomous ODE (finite-difference Jacobian):
/// `ẏ1 = −y1²`, `ẏ2 = cos(t)·y2`, `y(0) = (1, 1)`: `y = (1/(1+t), exp(sin t))`.
#[derive(Clone, Debug)]
pub struct Nonlinear2;

impl Solved for Nonlinear2 {
    fn solution(&self, t: f64) -> Vec<f64> {
        vec![1.0 / (1.0 + t), t.sin().exp()]
    }
}

impl Problem for Nonlinear2 {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] + y[0] * y[0];
        r[1] = yp[1] - t.cos() * y[1];
        Ok(())
    }
}

/// Robertson's chemical kinetics (stiff), FD Jacobian, per-component atol.
pub struct Robertson;

impl Problem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] - (-0.04 * y[0] + 1e4 * y[1] * y[2]);
        r[1] = yp[1] - (0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1]);
        r[2] = yp[2] - 3e7 * y[1] * y[1];
        Ok(())
    }
    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![1e-8, 1e-14, 1e-8])
    }
}

/// Van der Pol, `ÿ = μ(1 − y²)ẏ − y` as a first-order system, analytic Jacobian.
pub struct VanDerPol {
    pub mu: f64,
}

impl Problem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] - y[1];
        r[1] = yp[1] - (self.mu * (1.0 - y[0] * y[0]) * y[1] - y[0]);
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut Matrix,
    ) -> Result<bool, ResidualError> {
        jac.add(0, 0, c);
        jac.add(0, 1, -1.0);
        jac.add(1, 0, -(-2.0 * self.mu * y[0] * y[1] - 1.0));
        jac.add(1, 1, c - self.mu * (1.0 - y[0] * y[0]));
        Ok(true)
    }
}

/// Mass-matrix problem `M(y)·ẏ = M(y)·g(t, y)` whose solution is that of `ẏ = g` for the
/// nonlinear `g` of [`Nonlinear2`]; `M` is constant `[[2, 1], [1, 1]]` or state-dependent
/// `[[2 + y1², 1], [1, 1 + y2²]]`. The residual is `M(y)(ẏ − g(t, y))`.
#[derive(Clone, Debug)]
pub struct MassProblem {
    pub state_dependent: bool,
}

impl Solved for MassProblem {
    fn solution(&self, t: f64) -> Vec<f64> {
        Nonlinear2.solution(t)
    }
}

impl MassProblem {
    fn mass(&self, y: &[f64]) -> [[f64; 2]; 2] {
        if self.state_dependent {
            [[2.0 + y[0] * y[0], 1.0], [1.0, 1.0 + y[1] * y[1]]]
        } else {
            [[2.0, 1.0], [1.0, 1.0]]
        }
    }
}

impl Problem for MassProblem {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        let m = self.mass(y);
        let d = [yp[0] + y[0] * y[0], yp[1] - t.cos() * y[1]];
        r[0] = m[0][0] * d[0] + m[0][1] * d[1];
        r[1] = m[1][0] * d[0] + m[1][1] * d[1];
        Ok(())
    }
}

/// Semi-explicit index-1 DAE with a nonlinear constraint:
/// `ẏ1 = y2 − y1`, `0 = y2³ + y2 − (q³ + q)` with `q = cos t + y1`;
/// `y(0) = (0, 1)`, exact solution `y1 = sin t`, `y2 = cos t + sin t`.
#[derive(Clone, Debug)]
pub struct Dae1;

impl Solved for Dae1 {
    fn solution(&self, t: f64) -> Vec<f64> {
        vec![t.sin(), t.cos() + t.sin()]
    }
}

impl Problem for Dae1 {
    fn dim(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        let q = t.cos() + y[0];
        r[0] = yp[0] - (y[1] - y[0]);
        r[1] = y[1] * y[1] * y[1] + y[1] - (q * q * q + q);
        Ok(())
    }
    fn algebraic(&self) -> Vec<bool> {
        vec![false, true]
    }
}

/// Semi-discrete heat equation `u_t = u_xx` on (0, 1), `u = 0` at both ends, `n` interior
/// points, banded(1, 1) with an analytic Jacobian. With `u(x, 0) = sin(πx)` the semi-discrete
/// solution is exactly `sin(πx_i)·exp(−λt)`, `λ = (4/Δx²) sin²(πΔx/2)`.
#[derive(Clone, Debug)]
pub struct Heat {
    pub n: usize,
}

impl Solved for Heat {
    fn solution(&self, t: f64) -> Vec<f64> {
        let dx = self.dx();
        let lam = 4.0 / (dx * dx) * (std::f64::consts::PI * dx / 2.0).sin().powi(2);
        (0..self.n)
            .map(|i| (std::f64::consts::PI * (i as f64 + 1.0) * dx).sin() * (-lam * t).exp())
            .collect()
    }
}

impl Heat {
    pub fn dx(&self) -> f64 {
        1.0 / (self.n as f64 + 1.0)
    }
}

impl Problem for Heat {
    fn dim(&self) -> usize {
        self.n
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        let k = 1.0 / (self.dx() * self.dx());
        for i in 0..self.n {
            r[i] = yp[i] - k * second_difference(y, i);
        }
        Ok(())
    }
    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 1, upper: 1 }
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut Matrix,
    ) -> Result<bool, ResidualError> {
        let k = 1.0 / (self.dx() * self.dx());
        for i in 0..self.n {
            jac.add(i, i, c + 2.0 * k);
            if i > 0 {
                jac.add(i, i - 1, -k);
            }
            if i + 1 < self.n {
                jac.add(i, i + 1, -k);
            }
        }
        Ok(true)
    }
}

/// Nonlinear reaction–diffusion `u_t = D u_xx + u²(1 − u)` on (0, 1) with `u = 0` at the ends,
/// banded(1, 1), FD Jacobian (coloured). Initial value `u0(x) = sin(πx)`.
pub struct ReactionDiffusion {
    pub n: usize,
    pub d: f64,
}

impl ReactionDiffusion {
    pub fn y0(&self) -> Vec<f64> {
        let dx = 1.0 / (self.n as f64 + 1.0);
        (0..self.n)
            .map(|i| (std::f64::consts::PI * (i as f64 + 1.0) * dx).sin())
            .collect()
    }
}

impl Problem for ReactionDiffusion {
    fn dim(&self) -> usize {
        self.n
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        let n = self.n;
        let dx = 1.0 / (n as f64 + 1.0);
        let k = self.d / (dx * dx);
        for i in 0..n {
            r[i] = yp[i] - k * second_difference(y, i) - y[i] * y[i] * (1.0 - y[i]);
        }
        Ok(())
    }
    fn pattern(&self) -> Pattern {
        Pattern::Banded { lower: 1, upper: 1 }
    }
}
