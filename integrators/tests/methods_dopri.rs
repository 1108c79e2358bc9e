//! Dormand–Prince 5(4): exact solutions, dense output, residual-form ẏ solve (mass matrices),
//! applicability checks and the observed order from a fixed-step sweep.

mod methods_common;

use integrators::{ErrorKind, MethodKind};
use methods_common::*;

const DOPRI: MethodKind = MethodKind::Dopri;

/// End and dense-output errors below 10⁻⁸.
const TIGHT: Bound = Bound::Fixed {
    end: 1e-8,
    dense: Some(1e-8),
};

#[test]
fn linear_2x2_matches_exact_solution_with_dense_output() {
    check_exact(
        DOPRI,
        &mut Case::new(Linear2, 3.0),
        &opts(1e-9, 1e-11),
        true,
        TIGHT,
    );
}

#[test]
fn explicit_ode_costs_about_six_residuals_per_step() {
    let (run, _) = Case::new(Nonlinear2, 10.0).run(DOPRI, &opts(1e-8, 1e-10), false);
    let s = run.stats;
    eprintln!("dopri cost: {s:?}");
    let attempts = s.steps + s.rejected_steps;
    // 6 stages per attempt, one extra residual per re-measurement (≤ every 16 steps, after
    // rejections and at start), plus initialisation and the two FD Jacobians at start.
    assert!(
        s.residual_calls <= 6 * attempts + attempts / 8 + s.rejected_steps + 20,
        "{s:?}"
    );
    assert_eq!(
        s.factorizations - run.init_stats.factorizations,
        0,
        "∂F/∂ẏ = I: no factorisation needed"
    );
}

#[test]
fn observed_order_is_five_on_a_nonlinear_ode() {
    check_order(
        DOPRI,
        &mut Case::new(Nonlinear2, 10.0),
        &[25, 50, 100, 200],
        5.0,
    );
}

#[test]
fn mass_matrix_problems_via_newton_on_ydot() {
    for sd in [false, true] {
        check_exact(
            DOPRI,
            &mut Case::new(
                MassProblem {
                    state_dependent: sd,
                },
                2.0,
            ),
            &opts(1e-9, 1e-11),
            true,
            TIGHT,
        );
    }
}

#[test]
fn algebraic_components_are_not_applicable() {
    let mut m = integrators::methods::build(DOPRI);
    let o = opts(1e-6, 1e-8);
    let err = integrate(m.as_mut(), &mut Dae1, &o, 0.0, &[0.0, 1.0], 1.0, None)
        .err()
        .expect("must fail");
    assert!(matches!(err.kind, ErrorKind::NotApplicable(_)), "{err}");
}

/// Prothero–Robinson, `ẏ = −λ (y − cos t) − sin t`, `y(0) = 1`: the solution is `cos t` for
/// every `λ`, and the problem is stiff for `λ ≫ 1` (its rate `λ`, the solution's `1`).
struct ProtheroRobinson {
    lambda: f64,
    /// With `Some(d)`: an event every `d` that leaves `y` as it is but restarts the method
    /// (`Modified`), as a dividing line's divisions do; the next one at `next`.
    restart_every: Option<f64>,
    next: f64,
}

impl ProtheroRobinson {
    fn new(lambda: f64) -> Self {
        Self {
            lambda,
            restart_every: None,
            next: f64::INFINITY,
        }
    }
}

impl integrators::Problem for ProtheroRobinson {
    fn dim(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), integrators::ResidualError> {
        r[0] = yp[0] + self.lambda * (y[0] - t.cos()) + t.sin();
        Ok(())
    }
    fn num_events(&self) -> usize {
        usize::from(self.restart_every.is_some())
    }
    fn events(&mut self, t: f64, _y: &[f64], g: &mut [f64]) {
        g[0] = t - self.next;
    }
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<integrators::EventAction, integrators::ResidualError> {
        self.next += self.restart_every.unwrap_or(f64::INFINITY);
        Ok(integrators::EventAction::Modified)
    }
}

/// Hairer's stiffness test finds the stiff case, with `h·ρ` at DOPRI5's stability boundary
/// on the negative real axis (3.3), and not the non-stiff one; the stiff steps stay stable
/// and accurate (the test reports, it does not change the steps).
#[test]
fn the_stiffness_test_finds_the_stability_limit_only_where_the_problem_is_stiff() {
    let o = opts(1e-6, 1e-8);
    for (lambda, stiff) in [(1e4, true), (1.0, false)] {
        let mut m = integrators::methods::build(DOPRI);
        let t_end = if stiff { 1.0 } else { 2000.0 };
        let run = integrate(
            m.as_mut(),
            &mut ProtheroRobinson::new(lambda),
            &o,
            0.0,
            &[1.0],
            t_end,
            None,
        )
        .expect("DOPRI stays stable at its stability limit");
        assert!(
            (run.y[0] - t_end.cos()).abs() < 1e-5,
            "λ = {lambda}: {} against {}",
            run.y[0],
            t_end.cos()
        );
        let limit = m.stability_limit();
        if stiff {
            // ≈ 3.3/λ per step: the test runs from the 1000th step on and fails 15 times
            assert!(run.stats.steps > 1015, "{:?}", run.stats);
            let limit = limit.expect("stiff at λ = 1e4");
            assert!(
                limit.h_rho > 3.25 && limit.h_rho < 3.4,
                "h·ρ = {}",
                limit.h_rho
            );
            assert!(limit.since > 0.0 && limit.since < t_end, "{limit:?}");
            assert_eq!(limit.component, Some(0));
        } else {
            assert!(
                run.stats.steps > 1000,
                "the test must have run: {:?}",
                run.stats
            );
            assert_eq!(limit, None, "λ = 1 is not stiff");
        }
    }
}

/// Through the driver: a stiff solve whose span at the stability-limited step would pass
/// `max_steps` stops as soon as the limit is found, with `ErrorKind::Stiff` and the steps so
/// far kept; the same solve within the budget completes, accurately.
#[test]
fn a_stiff_solve_that_would_exceed_max_steps_stops_early_and_says_why() {
    let solve = |max_steps: usize| {
        let o = integrators::Options {
            max_steps,
            ..opts(1e-6, 1e-8)
        };
        integrators::Solver::new(DOPRI, o).solve(
            &mut ProtheroRobinson::new(1e4),
            0.0,
            &[1.0],
            &[1.0, 100.0],
        )
    };
    // 100 time units at h ≈ 3.3e-4: about 3e5 steps
    let e = solve(100_000).expect_err("3e5 steps exceed 1e5");
    match e.error.kind {
        ErrorKind::Stiff {
            h_rho,
            projected_steps,
            max_steps,
        } => {
            assert!(h_rho > 3.25 && h_rho < 3.4, "{h_rho}");
            assert!(
                projected_steps > 2e5 && projected_steps < 4e5,
                "{projected_steps}"
            );
            assert_eq!(max_steps, 100_000);
        }
        ref k => panic!("expected Stiff, got {k:?}"),
    }
    // stopped when the limit was found (1000 steps, then 15 failed tests), not at the budget
    assert!(e.partial.stats.steps < 1100, "{:?}", e.partial.stats);
    assert!(
        e.error.t < 1.0 && e.partial.t_last == e.error.t,
        "{}",
        e.error
    );
    assert!(
        e.error.to_string().contains("use an implicit method"),
        "{}",
        e.error
    );
    let sol = solve(1_000_000).expect("within the default budget it completes");
    let last = sol.y.last().expect("outputs")[0];
    assert!((last - 100f64.cos()).abs() < 1e-5, "{last}");
}

/// The stiffness test's counts carry across the restarts of events, so a stiff problem with
/// an event every 30 steps is still found (its counts used to start again at each restart,
/// and the first test comes after 1 000 steps).
#[test]
fn a_stiff_solve_with_frequent_restarts_is_still_found() {
    let o = integrators::Options {
        max_steps: 100_000,
        ..opts(1e-6, 1e-8)
    };
    // an event every 0.01: about 30 steps at the stability limit
    let mut p = ProtheroRobinson {
        restart_every: Some(0.01),
        next: 0.01,
        ..ProtheroRobinson::new(1e4)
    };
    let e = integrators::Solver::new(DOPRI, o)
        .solve(&mut p, 0.0, &[1.0], &[100.0])
        .expect_err("3e5 steps exceed 1e5");
    assert!(matches!(e.error.kind, ErrorKind::Stiff { .. }), "{e}");
    assert!(e.partial.stats.events > 10, "{:?}", e.partial.stats);
    assert!(e.partial.stats.steps < 1300, "{:?}", e.partial.stats);
}
