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
