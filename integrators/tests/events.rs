//! Event location and actions: stop, continue, modify (bouncing ball), resize (doubling the
//! number of unknowns; banded pattern growing), and the no-double-firing rule.

mod common;

use common::opts;
use common::{max_abs_diff, residual_fn};
use integrators::{EventAction, MethodKind, Options, Pattern, Problem, ResidualError, Solver};

fn tight() -> Options {
    opts(1e-9, 1e-12)
}

/// ẏ = −y, event y − 1/2 (root at ln 2), with a configurable action.
struct HalfLife {
    action: EventAction,
    seen: Vec<f64>,
}

impl Problem for HalfLife {
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
    fn num_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0] - 0.5;
    }
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        assert_eq!(fired, &[0]);
        self.seen.push(t);
        Ok(self.action.clone())
    }
}

#[test]
fn event_located_within_1e_10_and_stop() {
    let mut p = HalfLife {
        action: EventAction::Stop,
        seen: vec![],
    };
    // The root is located on the dense output to event_tol (1e-12); the dense output itself
    // carries the global integration error (δy/y ≈ δt here), so the solve must be accurate to
    // ~1e-11 for t* to be within 1e-10 of ln 2. (At rtol = 1e-9 the global error, and so the
    // event-time error, is ≈ 1e-8.)
    let o = opts(1e-12, 1e-14);
    let sol = Solver::new(MethodKind::Bdf, o)
        .solve(&mut p, 0.0, &[1.0], &[0.25, 0.5, 5.0])
        .unwrap();
    let ln2 = 2f64.ln();
    let te = sol.events[0].t;
    eprintln!("t* = {te:.16}, ln 2 = {ln2:.16}, diff {:e}", te - ln2);
    assert!((te - ln2).abs() < 1e-10, "{te}");
    // outputs before the event, then the stop entry at t*
    assert_eq!(sol.t.len(), 3);
    assert_eq!(&sol.t[..2], &[0.25, 0.5]);
    assert_eq!(sol.t[2], te);
    assert_eq!(sol.t_last, te);
    assert!((sol.y[2][0] - 0.5).abs() < 1e-9);
    assert_eq!(sol.events.len(), 1);
    assert_eq!(sol.events[0].action, EventAction::Stop);
}

/// Event functions of `y`, written into `g`.
type EventFns = Box<dyn Fn(f64, &mut [f64])>;

/// `ẏ = 1` from 0 (so `y = t`) with `n` event functions of `y` and a fixed action, recording
/// each call's time and fired list.
struct UnitRate {
    n: usize,
    events: EventFns,
    action: EventAction,
    calls: Vec<(f64, Vec<usize>)>,
}

impl UnitRate {
    fn new(n: usize, action: EventAction, events: impl Fn(f64, &mut [f64]) + 'static) -> Self {
        Self {
            n,
            events: Box::new(events),
            action,
            calls: vec![],
        }
    }
}

impl Problem for UnitRate {
    fn dim(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        _y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        r[0] = yp[0] - 1.0;
        Ok(())
    }
    fn num_events(&self) -> usize {
        self.n
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        (self.events)(y[0], g);
    }
    fn handle_event(
        &mut self,
        t: f64,
        fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        self.calls.push((t, fired.to_vec()));
        Ok(self.action.clone())
    }
}

#[test]
fn event_location_to_1e_10_on_exact_dense_output() {
    // y = t, so the interpolant is exact and the root of the first function must be found to
    // the event tolerance
    let c = std::f64::consts::LN_2;
    let sol = Solver::new(MethodKind::Bdf, Options::default())
        .solve(
            // a root at c where the function is flat (slope 1e-3), and one beyond the span
            &mut UnitRate::new(2, EventAction::Stop, move |y, g| {
                g[0] = (y - c).powi(3) + 1e-3 * (y - c);
                g[1] = y - 10.0;
            }),
            0.0,
            &[0.0],
            &[5.0],
        )
        .unwrap();
    let te = sol.events[0].t;
    eprintln!("t* - c = {:e}", te - c);
    assert!((te - c).abs() < 1e-10, "{te}");
    assert_eq!(sol.events[0].fired, vec![0]);
}

#[test]
fn continue_does_not_refire_the_same_root() {
    let mut p = HalfLife {
        action: EventAction::Continue,
        seen: vec![],
    };
    let sol = Solver::new(MethodKind::Bdf, tight())
        .solve(&mut p, 0.0, &[1.0], &[1.0, 3.0])
        .unwrap();
    assert_eq!(p.seen.len(), 1, "{:?}", p.seen);
    assert!((sol.y[1][0] - (-3f64).exp()).abs() < 1e-8);
}

/// Events `y − rᵢ` on `y = t`, each call continuing.
fn thresholds(roots: Vec<f64>) -> UnitRate {
    UnitRate::new(roots.len(), EventAction::Continue, move |y, g| {
        for (g, r) in g.iter_mut().zip(&roots) {
            *g = y - r;
        }
    })
}

#[test]
fn roots_within_the_event_tolerance_fire_together_once() {
    // two roots a fraction of event_tol (1e-12 on this span) apart, at positions that put the
    // root finder's final bracket anywhere between them: one event firing both, never again
    let tol = Options::default().event_tol;
    for r in [0.3, 0.7, 1.1, 1.9, 2.5] {
        for frac in [0.05, 0.3, 0.6, 0.95] {
            let mut p = thresholds(vec![r, r + frac * tol]);
            Solver::new(MethodKind::Bdf, tight())
                .solve(&mut p, 0.0, &[0.0], &[3.0])
                .unwrap();
            assert_eq!(p.calls.len(), 1, "r = {r}, δ = {frac}·tol: {:?}", p.calls);
            assert_eq!(p.calls[0].1, vec![0, 1], "r = {r}, δ = {frac}·tol");
            assert!((p.calls[0].0 - r).abs() <= 2.0 * tol, "{:?}", p.calls);
        }
    }
    // three tolerances apart they are two events, in order
    let mut p = thresholds(vec![1.0, 1.0 + 3.0 * tol]);
    Solver::new(MethodKind::Bdf, tight())
        .solve(&mut p, 0.0, &[0.0], &[3.0])
        .unwrap();
    let fired: Vec<Vec<usize>> = p.calls.iter().map(|c| c.1.clone()).collect();
    assert_eq!(fired, vec![vec![0], vec![1]], "{:?}", p.calls);
}

/// Bouncing ball: h'' = −g, bounce with restitution e when h crosses 0 downwards.
struct Ball {
    e: f64,
    bounces: Vec<f64>,
}

impl Problem for Ball {
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
        r[1] = yp[1] + 9.81;
        Ok(())
    }
    fn num_events(&self) -> usize {
        1
    }
    fn events(&mut self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn handle_event(
        &mut self,
        t: f64,
        _fired: &[usize],
        y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        self.bounces.push(t);
        y[1] *= -self.e;
        Ok(EventAction::Modified)
    }
}

#[test]
fn bouncing_ball_modified_events_match_closed_form() {
    let g = 9.81;
    let e = 0.8;
    let h0: f64 = 1.0;
    let mut p = Ball { e, bounces: vec![] };
    let t_end = 3.0;
    let sol = Solver::new(MethodKind::Bdf, tight())
        .solve(&mut p, 0.0, &[h0, 0.0], &[t_end])
        .unwrap();
    // bounce times: t1 = sqrt(2h0/g), then intervals 2 v_k / g with v_k = e^k v1
    let v1 = (2.0 * g * h0).sqrt();
    let mut expected = vec![v1 / g];
    let mut v = v1;
    loop {
        v *= e;
        let next = expected.last().unwrap() + 2.0 * v / g;
        if next > t_end {
            break;
        }
        expected.push(next);
    }
    eprintln!(
        "bounces {:?}\nexpected {:?}\n{:?}",
        p.bounces, expected, sol.stats
    );
    assert_eq!(p.bounces.len(), expected.len());
    for (a, b) in p.bounces.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
    assert_eq!(sol.stats.events, expected.len());
    // an observer is handed each event as it is handled, with the state after it
    struct Events(Vec<(f64, f64)>);
    impl<P> integrators::Observer<P> for Events {
        fn event(&mut self, _: &P, e: &integrators::EventRecord, y: &[f64]) {
            self.0.push((e.t, y[1]));
        }
    }
    let mut seen = Events(Vec::new());
    let mut q = Ball { e, bounces: vec![] };
    Solver::new(MethodKind::Bdf, tight())
        .solve_observed(&mut q, 0.0, &[h0, 0.0], &[t_end], &mut seen)
        .unwrap();
    assert_eq!(seen.0.len(), expected.len());
    for (k, ((t, v), b)) in seen.0.iter().zip(&expected).enumerate() {
        // the upward speed after bounce k + 1 is e^(k+1) v1
        let v_up = v1 * e.powi(k as i32 + 1);
        assert!(
            (t - b).abs() < 1e-8 && (v - v_up).abs() < 1e-6,
            "{t} {v} vs {b} {v_up}"
        );
    }
    // state at t_end: free flight after the last bounce
    let tl = *expected.last().unwrap();
    let vl = v1 * e.powi(expected.len() as i32);
    let dt = t_end - tl;
    let h = vl * dt - 0.5 * g * dt * dt;
    assert!((sol.y[0][0] - h).abs() < 1e-7, "{} vs {h}", sol.y[0][0]);
}

/// N independent decays y_i' = −λ_i y_i; at t = 1 every unknown divides into two copies (the
/// copy gets rate λ_i·2). Exact solution known for all components before and after.
struct Dividing {
    rates: Vec<f64>,
    banded: bool,
    sizes: Vec<usize>,
}

impl Problem for Dividing {
    fn dim(&self) -> usize {
        self.rates.len()
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        for i in 0..y.len() {
            r[i] = yp[i] + self.rates[i] * y[i];
        }
        Ok(())
    }
    fn pattern(&self) -> Pattern {
        if self.banded {
            // bandwidth grows with the size (tests a pattern change at resize)
            let b = if self.rates.len() > 4 { 2 } else { 1 };
            Pattern::Banded { lower: b, upper: b }
        } else {
            Pattern::Dense
        }
    }
    fn atol(&self) -> Option<Vec<f64>> {
        Some(vec![1e-12; self.rates.len()])
    }
    fn num_events(&self) -> usize {
        // one event per "cell" before the division, none after
        if self.rates.len() <= 4 {
            1
        } else {
            0
        }
    }
    fn events(&mut self, t: f64, _y: &[f64], g: &mut [f64]) {
        g[0] = t - 1.0;
    }
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        let n = y.len();
        for i in 0..n {
            y.push(y[i]);
            self.rates.push(2.0 * self.rates[i]);
        }
        self.sizes.push(self.rates.len());
        Ok(EventAction::Resized)
    }
}

fn dividing_exact(rates0: &[f64], t: f64) -> Vec<f64> {
    if t < 1.0 {
        rates0.iter().map(|l| (-l * t).exp()).collect()
    } else {
        let mut v: Vec<f64> = rates0.iter().map(|l| (-l * t).exp()).collect();
        for l in rates0 {
            v.push((-l).exp() * (-2.0 * l * (t - 1.0)).exp());
        }
        v
    }
}

#[test]
fn resize_doubles_unknowns_and_matches_exact_solution() {
    for banded in [false, true] {
        let rates0 = vec![0.5, 1.0, 2.0, 3.0];
        let mut p = Dividing {
            rates: rates0.clone(),
            banded,
            sizes: vec![],
        };
        let t_out = [0.5, 1.0, 1.5, 2.0];
        let mut observed = Vec::new();
        let sol = Solver::new(MethodKind::Bdf, tight())
            .solve_with(&mut p, 0.0, &[1.0; 4], &t_out, |pr, t, y, _| {
                observed.push((t, pr.dim(), y.len()))
            })
            .unwrap();
        eprintln!("banded={banded}: {:?}, {:?}", sol.stats, observed);
        assert_eq!(sol.stats.resizes, 1);
        assert_eq!(sol.events.len(), 1);
        assert!((sol.events[0].t - 1.0).abs() < 1e-10);
        assert_eq!(sol.events[0].dim_after, 8);
        // output at exactly the event time reports the post-event (resized) state
        assert_eq!(sol.y[1].len(), 8);
        assert_eq!(
            observed,
            vec![(0.5, 4, 4), (1.0, 8, 8), (1.5, 8, 8), (2.0, 8, 8)]
        );
        for (k, &t) in t_out.iter().enumerate() {
            let ex = dividing_exact(&rates0, t);
            let err = max_abs_diff(&sol.y[k], &ex);
            // BDF's global error is the sum of controlled local errors: 10–20 × rtol here
            // (1.01e-8 at t = 0.5 with the Hairer starting step, just under 1e-8 with the
            // former 1e-3·span start); the resize itself adds nothing measurable.
            assert!(err < 2e-8, "banded={banded} t={t}: err {err}");
        }
        assert_eq!(sol.y_last.len(), 8);
    }
}

/// A solve whose residual becomes NaN for t > 1 must fail with the partial solution.
fn goes_nan() -> impl Problem {
    residual_fn(2, |t, y, yp, r| {
        r[0] = yp[0] + y[0];
        r[1] = yp[1] + if t > 1.0 { f64::NAN } else { y[1] };
        Ok(())
    })
}

#[test]
fn nan_residual_returns_partial_solution() {
    let fail = Solver::new(MethodKind::Bdf, Options::default())
        .solve(&mut goes_nan(), 0.0, &[1.0, 1.0], &[0.5, 0.9, 2.0])
        .unwrap_err();
    eprintln!("{fail}: {:?}", fail.error);
    assert_eq!(fail.partial.t, vec![0.5, 0.9]);
    assert!((fail.partial.y[1][0] - (-0.9f64).exp()).abs() < 1e-5);
    assert!((fail.error.t - 1.0).abs() < 1e-6, "{}", fail.error.t);
    assert_eq!(fail.error.component, Some(1));
    assert!(fail.partial.t_last <= 1.0 && fail.partial.t_last > 0.999);
    assert!(fail.partial.stats.steps > 0);
}

#[test]
fn all_stiff_methods_handle_a_resize_with_pattern_change() {
    for kind in MethodKind::ALL.into_iter().filter(|k| k.is_stiff()) {
        let rates0 = vec![0.5, 1.0, 2.0, 3.0];
        let mut p = Dividing {
            rates: rates0.clone(),
            banded: true,
            sizes: vec![],
        };
        let t_out = [0.5, 1.5, 2.0];
        let sol = Solver::new(kind, tight())
            .solve(&mut p, 0.0, &[1.0; 4], &t_out)
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!(sol.stats.resizes, 1, "{kind}");
        assert!((sol.events[0].t - 1.0).abs() < 1e-10, "{kind}");
        // the resize must not degrade accuracy: errors after it (t = 1.5, 2) stay at the level
        // the method reaches before it (t = 0.5) on this problem
        let errs: Vec<f64> = t_out
            .iter()
            .enumerate()
            .map(|(k, &t)| max_abs_diff(&sol.y[k], &dividing_exact(&rates0, t)))
            .collect();
        eprintln!("{kind}: errors {errs:?} {:?}", sol.stats);
        let before = errs[0].max(1e-10);
        for &e in &errs[1..] {
            assert!(e < 3.0 * before, "{kind}: {errs:?}");
        }
        assert!(errs[0] < 1e-6, "{kind}: {errs:?}");
    }
}
