//! Driver behaviour: input validation, typed errors with partial solutions, observers, custom
//! methods, method selection by name.

mod common;

use common::opts;
use common::{residual_fn, Decay};
use integrators::interrupt::Interrupt;
use integrators::methods::bdf::Bdf;
use integrators::{ErrorKind, MethodKind, Options, Problem, ResidualError, Solver};

fn bdf() -> Solver {
    Solver::new(MethodKind::Bdf, Options::default())
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let cases: Vec<(f64, Vec<f64>, Vec<f64>)> = vec![
        (0.0, vec![1.0, 2.0], vec![1.0]), // wrong y0 length
        (0.0, vec![f64::NAN], vec![1.0]), // non-finite y0
        (0.0, vec![1.0], vec![]),         // no output times
        (0.0, vec![1.0], vec![2.0, 1.0]), // unsorted
        (1.0, vec![1.0], vec![0.5]),      // before t0
        (0.0, vec![1.0], vec![f64::INFINITY]),
    ];
    for (t0, y0, t_out) in cases {
        let e = bdf().solve(&mut Decay, t0, &y0, &t_out).unwrap_err();
        assert!(
            matches!(e.error.kind, ErrorKind::InvalidInput(_)),
            "{y0:?} {t_out:?}: {e}"
        );
    }
    let bad = Options {
        rtol: -1.0,
        ..Default::default()
    };
    let e = Solver::new(MethodKind::Bdf, bad)
        .solve(&mut Decay, 0.0, &[1.0], &[1.0])
        .unwrap_err();
    assert!(matches!(e.error.kind, ErrorKind::InvalidInput(_)));
}

#[test]
fn outputs_at_t0_and_repeated_times() {
    let sol = bdf()
        .solve(&mut Decay, 0.0, &[1.0], &[0.0, 1.0, 1.0, 2.0])
        .unwrap();
    assert_eq!(sol.t, vec![0.0, 1.0, 1.0, 2.0]);
    assert_eq!(sol.y[0], vec![1.0]);
    assert!((sol.yp[0][0] + 1.0).abs() < 1e-12, "consistent ẏ0");
    assert!((sol.y[3][0] - (-2f64).exp()).abs() < 1e-5);
    assert_eq!(sol.t_last, 2.0);
}

/// Fatal residual error after t = 0.5.
fn fatal() -> impl Problem {
    residual_fn(1, |t, y, yp, r| {
        if t > 0.5 {
            return Err(ResidualError::Fatal("model broke".into()));
        }
        r[0] = yp[0] + y[0];
        Ok(())
    })
}

#[test]
fn fatal_residual_error_aborts_with_partial_solution() {
    let e = bdf()
        .solve(&mut fatal(), 0.0, &[1.0], &[0.25, 1.0])
        .unwrap_err();
    assert!(
        matches!(e.error.kind, ErrorKind::Residual(ref m) if m.contains("model broke")),
        "{e}"
    );
    assert_eq!(e.partial.t, vec![0.25]);
    assert!(e.partial.t_last <= 0.5);
}

/// A residual that is out of its domain (Recoverable) for y < 0.2 while the solution decays
/// through it: the solver must fail cleanly, not loop or panic.
fn domain() -> impl Problem {
    residual_fn(1, |_t, y, yp, r| {
        if y[0] < 0.2 {
            return Err(ResidualError::Recoverable {
                reason: "negative length".into(),
                component: Some(0),
            });
        }
        r[0] = yp[0] + y[0];
        Ok(())
    })
}

#[test]
fn recoverable_domain_error_fails_cleanly_at_the_boundary() {
    let e = bdf()
        .solve(&mut domain(), 0.0, &[1.0], &[1.0, 5.0])
        .unwrap_err();
    eprintln!("{e}");
    assert_eq!(e.error.component, Some(0));
    // y = e^{-t} reaches 0.2 at t = ln 5
    assert!((e.error.t - 5f64.ln()).abs() < 1e-3, "{}", e.error.t);
    assert_eq!(e.partial.t, vec![1.0]);
}

#[test]
fn too_many_steps() {
    let o = Options {
        max_steps: 5,
        ..Default::default()
    };
    let e = Solver::new(MethodKind::Bdf, o)
        .solve(&mut Decay, 0.0, &[1.0], &[100.0])
        .unwrap_err();
    assert_eq!(e.error.kind, ErrorKind::TooManySteps(5));
    assert_eq!(e.partial.stats.steps, 5);
}

#[test]
fn custom_boxed_method_and_observer() {
    let solver = Solver::with_method(Box::new(Bdf::new()), Options::default());
    assert_eq!(solver.method_name(), "bdf");
    let mut seen = Vec::new();
    let sol = solver
        .solve_with(&mut Decay, 0.0, &[1.0], &[0.5, 1.0], |p, t, y, yp| {
            seen.push((p.dim(), t, y[0], yp[0]))
        })
        .unwrap();
    assert_eq!(seen.len(), 2);
    assert_eq!(seen[1].1, 1.0);
    assert_eq!(seen[1].2, sol.y[1][0]);
    // the boxed method is reusable
    let again = solver.solve(&mut Decay, 0.0, &[2.0], &[1.0]).unwrap();
    assert!((again.y[0][0] - 2.0 * (-1f64).exp()).abs() < 1e-5);
}

#[test]
fn methods_by_name() {
    for name in ["bdf", "esdirk", "radau"] {
        let kind: MethodKind = name.parse().unwrap();
        let o = opts(1e-8, 1e-10);
        let sol = Solver::new(kind, o)
            .solve(&mut Decay, 0.0, &[1.0], &[1.0])
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!((sol.y[0][0] - (-1f64).exp()).abs() < 1e-6, "{name}");
    }
}

/// Everything the driver reports, in order.
#[derive(Default)]
struct Log {
    outputs: Vec<f64>,
    accepted: Vec<integrators::observer::AcceptedStep>,
    rejected: Vec<integrators::observer::RejectedStep>,
    events: Vec<integrators::EventRecord>,
}

impl<P> integrators::Observer<P> for Log {
    fn output(&mut self, _: &P, t: f64, _: &[f64], _: &[f64]) {
        self.outputs.push(t);
    }
    fn accepted(&mut self, _: &P, step: &integrators::observer::AcceptedStep, _: &[f64]) {
        self.accepted.push(*step);
    }
    fn rejected(&mut self, _: &P, step: &integrators::observer::RejectedStep) {
        self.rejected.push(step.clone());
    }
    fn event(&mut self, _: &P, event: &integrators::EventRecord, _: &[f64]) {
        self.events.push(event.clone());
    }
}

/// The observer sees every accepted step (contiguous, covering `[t0, t_end]`, as many as
/// `Stats::steps` counts), every rejected attempt (as many as `Stats::rejected_steps`), and
/// every output, for each method.
#[test]
fn observer_sees_every_step_rejection_and_output() {
    for kind in MethodKind::ALL {
        let stiff = kind.is_stiff();
        // stiff for the implicit methods (rejections at the start); a decay for DOPRI
        let lambda = if stiff { 1e4 } else { 1.0 };
        let mut p = residual_fn(1, move |t, y, yp, r| {
            r[0] = yp[0] + lambda * (y[0] - t.cos());
            Ok(())
        });
        let mut log = Log::default();
        let opts = Options {
            h0: Some(0.5),
            ..Default::default()
        };
        let sol = Solver::new(kind, opts)
            .solve_observed(&mut p, 0.0, &[3.0], &[0.5, 1.0], &mut log)
            .unwrap();
        let name = kind.name();
        assert_eq!(log.outputs, [0.5, 1.0], "{name}");
        let substeps: usize = log.accepted.iter().map(|s| s.substeps).sum();
        assert_eq!(substeps, sol.stats.steps, "{name}");
        assert_eq!(log.rejected.len(), sol.stats.rejected_steps, "{name}");
        assert!(
            !log.rejected.is_empty(),
            "{name}: h0 = 0.5 must be rejected"
        );
        assert_eq!(log.accepted[0].t_prev, 0.0, "{name}");
        assert_eq!(log.accepted.last().unwrap().t, 1.0, "{name}");
        for w in log.accepted.windows(2) {
            assert_eq!(w[0].t, w[1].t_prev, "{name}: steps must be contiguous");
        }
        for r in &log.rejected {
            assert!(r.h > 0.0 && (0.0..1.0).contains(&r.t), "{name}: {r}");
            assert_eq!(r.component, Some(0), "{name}: {r}");
        }
        assert!(log.events.is_empty());
    }
}

/// A state the problem rejects reaches the observer with the problem's reason and unknown,
/// before the solve fails.
#[test]
fn observer_sees_the_problems_rejection_with_its_reason() {
    let mut log = Log::default();
    let e = bdf()
        .solve_observed(&mut domain(), 0.0, &[1.0], &[1.0, 5.0], &mut log)
        .unwrap_err();
    let last = log.rejected.last().expect("rejections before the failure");
    assert_eq!(
        last.cause,
        integrators::observer::RejectCause::Recoverable(integrators::RecoverableCause::Rejected(
            "negative length".into()
        ))
    );
    assert_eq!(last.component, Some(0));
    assert!(
        last.t + last.h > e.error.t && last.t <= e.error.t + 1e-12,
        "{last} vs {e}"
    );
    assert_eq!(log.rejected.len(), e.partial.stats.rejected_steps);
}

#[test]
fn one_step_methods_end_a_step_at_every_output_unless_told_otherwise() {
    // y' = −y on [0, 1], 100 outputs: a method that lands takes a step per output at least
    let t_out: Vec<f64> = (1..=100).map(|i| i as f64 / 100.0).collect();
    let steps = |kind: MethodKind, land: Option<bool>| {
        let o = Options {
            land_on_outputs: land,
            ..Default::default()
        };
        let sol = Solver::new(kind, o)
            .solve(&mut Decay, 0.0, &[1.0], &t_out)
            .unwrap();
        let err = sol
            .t
            .iter()
            .zip(&sol.y)
            .map(|(t, y)| (y[0] - (-t).exp()).abs())
            .fold(0.0, f64::max);
        println!(
            "{kind} land_on_outputs = {land:?}: {} steps, largest output error {err:e}",
            sol.stats.steps
        );
        // (interpolated, ESDIRK's outputs err by 1e-5: its dense output is not checked)
        if land.unwrap_or(kind != MethodKind::Bdf) {
            assert!(err < 1e-5, "{kind} {land:?}: {err:e}");
        }
        sol.stats.steps
    };
    for kind in [MethodKind::Radau, MethodKind::Esdirk, MethodKind::Dopri] {
        assert!(steps(kind, None) >= 100, "{kind} lands by default");
        assert!(
            steps(kind, Some(false)) < 50,
            "{kind} interpolates when told"
        );
    }
    // BDF's dense output is error-controlled: it interpolates unless told to land
    assert!(steps(MethodKind::Bdf, None) < 100);
    assert!(steps(MethodKind::Bdf, Some(true)) >= 100);
}

/// Two positions 10⁴ apart from the origin whose gap `d = x₁ − x₀` decays as `e^{−t}`, the gap
/// measured as a difference row (a cell whose length is tested, as a line of cells does).
struct ClosingGap;

impl Problem for ClosingGap {
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
        r[0] = yp[0];
        r[1] = yp[1] + (y[1] - y[0]);
        Ok(())
    }
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        Some(
            integrators::ErrorMap::from_rows(vec![
                integrators::Row::Own,
                integrators::Row::Difference { partner: 0 },
            ])
            .unwrap(),
        )
    }
}

#[test]
fn tolerance_below_round_off_stops_where_the_ratio_crosses_the_limit() {
    use integrators::solver::ROUNDOFF_LIMIT;
    let y0 = [1e4, 1e4 + 1.0];
    // rtol 1e-10, atol 1e-12: the gap's round-off ε·(|x₀| + |x₁|) reaches ROUNDOFF_LIMIT of
    // its tolerance rtol·d + atol once d ≤ (ε·2e4/ROUNDOFF_LIMIT − atol)/rtol ≈ 0.168
    let (rtol, atol) = (1e-10, 1e-12);
    let d_limit = (f64::EPSILON * 2e4 / ROUNDOFF_LIMIT - atol) / rtol;
    let t_limit = (1.0 / d_limit).ln();
    let o = Options {
        rtol,
        atol,
        ..Default::default()
    };
    let e = Solver::new(MethodKind::Bdf, o)
        .solve(&mut ClosingGap, 0.0, &y0, &[1.0, 10.0])
        .unwrap_err();
    let ErrorKind::TooMuchAccuracy { ratio } = e.error.kind else {
        panic!("expected TooMuchAccuracy, got {e}");
    };
    assert!(ratio > ROUNDOFF_LIMIT, "{ratio}");
    assert_eq!(e.error.component, Some(1));
    // it stops promptly: before the ratio has doubled (the gap halved once more)
    assert!(
        e.error.t >= t_limit && e.error.t < t_limit + 2f64.ln(),
        "stopped at t = {}, the limit is crossed at {t_limit}",
        e.error.t
    );
    assert!(e.partial.stats.steps <= 2000, "{}", e.partial.stats.steps);
    // what was computed is kept: the output at t = 1 and the last state. The output is the
    // true gap to the accuracy of the global solution there: unshifted (y₀ = (0, 1)) BDF errs
    // by 8.4·(rtol·d + atol) at t = 1 and 36 at t = 2, as its local errors add up on this
    // decay; shifted to 10⁴, with the gap's rounding 0.12 of its tolerance at t = 1, by 24.5
    // at t = 1 in the same 95 steps to t = 2 (`a_gap_far_from_the_origin_takes_the_unshifted_
    // steps`). The last state is the true solution to 10⁴·rtol (close to the floor the
    // accuracy degrades: why it stops).
    assert_eq!(e.partial.t, vec![1.0]);
    let (gap, exact) = (e.partial.y[0][1] - e.partial.y[0][0], (-1f64).exp());
    assert!(
        (gap - exact).abs() <= 100.0 * (rtol * exact + atol),
        "{gap}"
    );
    let gap = e.partial.y_last[1] - e.partial.y_last[0];
    let exact = (-e.error.t).exp();
    assert!(
        (gap / exact - 1.0).abs() <= 1e4 * rtol,
        "{gap} against {exact} at t = {}",
        e.error.t
    );
    assert!(e.to_string().contains("raise rtol and atol"), "{e}");

    // at rtol 1e-6 the same problem runs to t = 10 with the gap to its tolerance
    let sol = Solver::new(MethodKind::Bdf, Options::default())
        .solve(&mut ClosingGap, 0.0, &y0, &[10.0])
        .unwrap();
    let (gap, exact) = (sol.y[0][1] - sol.y[0][0], (-10f64).exp());
    assert!((gap - exact).abs() <= 10.0 * (1e-6 * exact + 1e-8), "{gap}");
}

#[test]
fn a_gap_far_from_the_origin_takes_the_unshifted_steps() {
    // The gap of ClosingGap at rtol 1e-10 from y₀ = (0, 1) and from (10⁴, 10⁴ + 1): BDF's
    // predictor sums increments from the newest value, so the offset enters only through the
    // rounding of the stored positions (0.12 of the gap's tolerance at t = 1). Summed from the
    // positions themselves, its ẏ carried ε·10⁴ times coefficients of order 1/h, and the
    // shifted run took 123 steps against 95.
    let (rtol, atol) = (1e-10, 1e-12);
    let t_out: Vec<f64> = (1..=8).map(|k| 0.25 * k as f64).collect();
    let solve = |y0: [f64; 2]| {
        let o = Options {
            rtol,
            atol,
            ..Default::default()
        };
        Solver::new(MethodKind::Bdf, o)
            .solve(&mut ClosingGap, 0.0, &y0, &t_out)
            .unwrap()
    };
    let (plain, shifted) = (solve([0.0, 1.0]), solve([1e4, 1e4 + 1.0]));
    assert_eq!(plain.stats.steps, 95);
    assert_eq!(shifted.stats.steps, plain.stats.steps);
}

/// ẏ = −y with a hand-written Jacobian that overflows once y falls below 0.5 (a law whose
/// derivative leaves the doubles while its value does not).
struct OverflowingJacobian;

impl Problem for OverflowingJacobian {
    fn dim(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] + y[0];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &[f64],
        _yp: &[f64],
        c: f64,
        jac: &mut integrators::problem::JacobianSink,
    ) -> Result<bool, ResidualError> {
        let d = if y[0] < 0.5 { f64::INFINITY } else { 1.0 };
        jac.add(0, 0, d + c);
        Ok(true)
    }
}

#[test]
fn a_factorisation_on_an_overflowed_jacobian_names_the_entry_not_a_zero_pivot() {
    let e = bdf()
        .solve(&mut OverflowingJacobian, 0.0, &[1.0], &[0.5, 5.0])
        .unwrap_err();
    assert_eq!(
        e.error.kind,
        ErrorKind::NonFiniteMatrix {
            row: 0,
            column: 0,
            value: f64::INFINITY
        },
        "{e}"
    );
    assert_eq!(e.error.component, Some(0));
    // y = e^{−t} crosses 0.5 at t = ln 2; the output before it is kept
    assert!(e.error.t >= 2f64.ln() - 0.1, "{e}");
    assert_eq!(e.partial.t, vec![0.5]);
    assert!(e.to_string().contains("derivatives overflowed"), "{e}");
}

/// `K(1 + y²)·ẏ + (1 + t)·y = 0`, `K = 1, 2` (a drag that changes with the state against a
/// stiffening spring; exact rates `ẏ = −(1 + t)y/(K(1 + y²))`), telling the solver whether its
/// outputs read `ẏ`. The drag's change makes a kept factorisation of `∂F/∂ẏ` stale.
struct Relaxing {
    reads_rates: bool,
}

impl Problem for Relaxing {
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
        for i in 0..2 {
            let k = 1.0 + i as f64;
            r[i] = k * (1.0 + y[i] * y[i]) * yp[i] + (1.0 + t) * y[i];
        }
        Ok(())
    }
    fn outputs_read_rates(&self) -> bool {
        self.reads_rates
    }
}

#[test]
fn outputs_that_read_rates_get_them_solved_from_their_state() {
    // interpolated, the outputs' ẏ err by the interpolant's derivative; solved from y they
    // satisfy F(t, y, ẏ) = 0 to the consistent initialisation's 1e-3 of the tolerance
    let times: Vec<f64> = (1..=40).map(|k| 0.1 * k as f64).collect();
    let worst = |reads_rates: bool| {
        let sol = bdf()
            .solve(&mut Relaxing { reads_rates }, 0.0, &[1.0, 2.0], &times)
            .unwrap();
        let mut worst = 0.0f64;
        for ((t, y), yp) in sol.t.iter().zip(&sol.y).zip(&sol.yp) {
            for i in 0..2 {
                let exact = -(1.0 + t) * y[i] / ((1.0 + i as f64) * (1.0 + y[i] * y[i]));
                worst = worst.max((yp[i] - exact).abs() / (1e-6 * exact.abs() + 1e-8));
            }
        }
        worst
    };
    let (solved, interpolated) = (worst(true), worst(false));
    eprintln!("ẏ error in tolerances: solved {solved:.2e}, interpolated {interpolated:.2e}");
    assert!(solved < 1e-3, "{solved:e}");
    assert!(interpolated > 1.0, "{interpolated:e}");
}

/// Raises an [`Interrupt`] at its `after`-th accepted step.
struct RaiseAfter {
    stop: Interrupt,
    after: usize,
    seen: usize,
    t_raised: f64,
}

impl<P> integrators::Observer<P> for RaiseAfter {
    fn accepted(&mut self, _: &P, step: &integrators::observer::AcceptedStep, _: &[f64]) {
        self.seen += 1;
        if self.seen == self.after {
            self.t_raised = step.t;
            self.stop.raise();
        }
    }
}

#[test]
fn an_interrupt_stops_the_solve_before_its_next_step_and_keeps_what_it_computed() {
    for kind in [MethodKind::Bdf, MethodKind::Radau, MethodKind::Esdirk] {
        let stop = Interrupt::new();
        let mut raise = RaiseAfter {
            stop: stop.clone(),
            after: 7,
            seen: 0,
            t_raised: f64::NAN,
        };
        let solver = Solver::new(kind, opts(1e-8, 1e-10));
        let t_out = [0.0, 1e-3, 100.0];
        let e = stop
            .scope(|| solver.solve_observed(&mut Decay, 0.0, &[1.0], &t_out, &mut raise))
            .unwrap_err();
        assert_eq!(e.error.kind, ErrorKind::Interrupted, "{kind:?}");
        // stopped where the flag went up, with the state there and the outputs before it
        assert_eq!(e.partial.stats.steps, 7, "{kind:?}");
        assert_eq!(e.error.t, raise.t_raised, "{kind:?}");
        assert_eq!(e.partial.t_last, raise.t_raised, "{kind:?}");
        assert!((e.partial.y_last[0] - (-raise.t_raised).exp()).abs() < 1e-6);
        assert_eq!(e.partial.t, [0.0, 1e-3], "{kind:?}");
        // the same solver, outside the scope, is not interrupted
        assert!(solver.solve(&mut Decay, 0.0, &[1.0], &t_out).is_ok());
    }
}

#[test]
fn a_solve_on_another_thread_does_not_see_this_threads_interrupt() {
    let stop = Interrupt::new();
    stop.raise();
    let other = std::thread::spawn(|| bdf().solve(&mut Decay, 0.0, &[1.0], &[10.0]));
    let here = stop.scope(|| bdf().solve(&mut Decay, 0.0, &[1.0], &[10.0]));
    assert!(other.join().unwrap().is_ok());
    let e = here.unwrap_err();
    assert_eq!((e.error.kind, e.error.t), (ErrorKind::Interrupted, 0.0));
    assert_eq!(e.partial.y_last, [1.0]);
}
