//! Dormand–Prince 5(4): exact solutions, dense output, residual-form ẏ solve (mass matrices),
//! applicability checks and the observed order from a fixed-step sweep.

mod methods_common;

use integrators::methods::dopri::Dopri5;
use integrators::{ErrorKind, Options};
use methods_common::*;

fn opts(rtol: f64, atol: f64) -> Options {
    Options {
        rtol,
        atol,
        ..Default::default()
    }
}

#[test]
fn linear_2x2_matches_exact_solution_with_dense_output() {
    let ex = |t: f64| Linear2::exact(t);
    let run = integrate(
        &mut Dopri5::new(),
        &mut Linear2,
        &opts(1e-9, 1e-11),
        0.0,
        &[1.0, 0.0],
        3.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Linear2::exact(3.0));
    eprintln!(
        "dopri linear: err {e:e} dense {:e} {:?}",
        run.dense_err, run.stats
    );
    assert!(e < 1e-8, "end error {e:e}");
    assert!(run.dense_err < 1e-8, "dense error {:e}", run.dense_err);
}

#[test]
fn explicit_ode_costs_about_six_residuals_per_step() {
    let run = integrate(
        &mut Dopri5::new(),
        &mut Nonlinear2,
        &opts(1e-8, 1e-10),
        0.0,
        &[1.0, 1.0],
        10.0,
        None,
    )
    .unwrap();
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
    let ex = |t: f64| Nonlinear2::exact(t);
    let (hs, errs) = fixed_step_sweep(
        &|| Box::new(Dopri5::new()),
        &mut Nonlinear2,
        10.0,
        &[1.0, 1.0],
        &ex,
        &[25, 50, 100, 200],
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!("dopri fixed-step errors {errs:?} -> observed order {p:.3}");
    assert!((p - 5.0).abs() <= 0.3, "observed order {p}");
}

#[test]
fn mass_matrix_problems_via_newton_on_ydot() {
    let ex = |t: f64| Nonlinear2::exact(t);
    for sd in [false, true] {
        let run = integrate(
            &mut Dopri5::new(),
            &mut MassProblem {
                state_dependent: sd,
            },
            &opts(1e-9, 1e-11),
            0.0,
            &[1.0, 1.0],
            2.0,
            Some(&ex),
        )
        .unwrap();
        let e = max_err(&run.y, &Nonlinear2::exact(2.0));
        eprintln!("dopri mass sd={sd}: err {e:e} {:?}", run.stats);
        assert!(e < 1e-8, "state_dependent={sd}: {e:e}");
        assert!(run.dense_err < 1e-8, "{:e}", run.dense_err);
    }
}

#[test]
fn algebraic_components_are_not_applicable() {
    let err = integrate(
        &mut Dopri5::new(),
        &mut Dae1,
        &opts(1e-6, 1e-8),
        0.0,
        &[0.0, 1.0],
        1.0,
        None,
    )
    .err()
    .expect("must fail");
    assert!(matches!(err.kind, ErrorKind::NotApplicable(_)), "{err}");
}
