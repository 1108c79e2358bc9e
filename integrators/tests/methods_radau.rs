//! Radau IIA (order 5): exact solutions, stiff benchmarks, mass matrices, an index-1 DAE, the
//! banded complex-pair path, and the observed order from a fixed-step sweep.

mod methods_common;

use integrators::methods::radau::Radau5;
use integrators::{ErrorKind, Method, MethodKind, Options};
use methods_common::*;

const RADAU: MethodKind = MethodKind::Radau;

/// Jacobian evaluations of the starting-step estimate: one consistent initialisation at the
/// trial point `t₀ + h₀` (one Newton iteration on a linear problem).
const START_ESTIMATE_JACOBIANS: usize = 1;

/// End error below 10⁻⁸, dense-output error below 10⁻⁷.
const TIGHT: Bound = Bound::Fixed {
    end: 1e-8,
    dense: Some(1e-7),
};

#[test]
fn linear_2x2_matches_exact_solution_with_dense_output() {
    let run = check_exact(
        RADAU,
        &mut Case::new(Linear2, 3.0),
        &opts(1e-8, 1e-10),
        true,
        TIGHT,
    );
    // ẏ at the end is the derivative of the exact solution
    let yp_ex = [
        -Linear2.solution(3.0)[0] + 2.0 * Linear2.solution(3.0)[1],
        -2.0 * Linear2.solution(3.0)[0] - Linear2.solution(3.0)[1],
    ];
    assert!(max_err(&run.yp, &yp_ex) < 1e-7);
    // linear problem with an exact Jacobian: Newton converges in one iteration, the Jacobian is
    // kept (θ ≤ 0.001): exactly one refresh (= 2 Jacobian evaluations) after the starting-step
    // estimate.
    assert_eq!(
        run.method_jacobians(),
        START_ESTIMATE_JACOBIANS + 2,
        "{:?}",
        run.stats
    );
    // cost pin (measured 138 steps; 98 while the estimate was tested against RADAU5's
    // 0.1·rtol^(2/3) rather than at most 10·rtol: the embedded order-3 estimate is conservative
    // on this non-stiff problem)
    assert!(run.stats.steps <= 150, "{:?}", run.stats);
}

#[test]
fn observed_order_is_five_on_a_nonlinear_ode() {
    check_order(
        RADAU,
        &mut Case::new(Nonlinear2, 1.0),
        &[5, 10, 20, 40],
        5.0,
    );
}

#[test]
fn robertson_conserves_mass_and_matches_tight_reference() {
    let run = check_robertson(RADAU);
    assert!(run.stats.steps < 300, "{:?}", run.stats);
}

#[test]
fn van_der_pol_mu_1000_completes_and_matches_tight_run() {
    let run = check_van_der_pol(RADAU, 1e-6, 1e-3);
    assert!(run.stats.steps < 2000, "{:?}", run.stats);
}

#[test]
fn constant_mass_matrix_matches_exact_solution() {
    check_exact(
        RADAU,
        &mut Case::new(
            MassProblem {
                state_dependent: false,
            },
            2.0,
        ),
        &opts(1e-9, 1e-11),
        true,
        TIGHT,
    );
}

#[test]
fn state_dependent_mass_matrix_matches_exact_solution() {
    check_exact(
        RADAU,
        &mut Case::new(
            MassProblem {
                state_dependent: true,
            },
            2.0,
        ),
        &opts(1e-9, 1e-11),
        true,
        TIGHT,
    );
}

#[test]
fn index1_dae_matches_exact_solution() {
    for suppress in [true, false] {
        eprintln!("suppress_algebraic = {suppress}");
        let o = Options {
            suppress_algebraic: suppress,
            ..opts(1e-9, 1e-11)
        };
        check_exact(RADAU, &mut Case::new(Dae1, 5.0), &o, true, TIGHT);
    }
}

#[test]
fn observed_order_on_index1_dae() {
    check_order(RADAU, &mut Case::new(Dae1, 1.0), &[5, 10, 20, 40], 5.0);
}

#[test]
fn banded_heat_equation_through_complex_pair_path() {
    let mut case = Case::new(Heat { n: 200 }, 0.1);
    let scale = (case.exact)(0.1).iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let bound = Bound::Fixed {
        end: 1e-7 * scale.max(1e-3) + 1e-9,
        dense: None,
    };
    let run = check_exact(RADAU, &mut case, &opts(1e-8, 1e-10), false, bound);
    // linear problem, exact Jacobian: one Jacobian refresh for the whole run
    assert_eq!(
        run.method_jacobians(),
        START_ESTIMATE_JACOBIANS + 2,
        "{:?}",
        run.stats
    );
}

#[test]
fn restart_with_a_different_dimension() {
    let mut m = Radau5::new();
    let o = opts(1e-8, 1e-10);
    let a = integrate(&mut m, &mut Linear2, &o, 0.0, &[1.0, 0.0], 1.0, None).unwrap();
    assert!(max_err(&a.y, &Linear2.solution(1.0)) < 1e-7);
    let mut p = Heat { n: 50 };
    let y0 = p.solution(0.0);
    let b = integrate(&mut m, &mut p, &o, 0.0, &y0, 0.05, None).unwrap();
    assert!(max_err(&b.y, &p.solution(0.05)) < 1e-7);
}

#[test]
fn step_before_start_is_an_error_not_a_panic() {
    use integrators::system::{System, SystemCache};
    let o = Options::default();
    let mut stats = integrators::Stats::default();
    let mut cache = SystemCache::default();
    let mut p = Linear2;
    cache.rebuild(&p, &o).unwrap();
    let mut sys = System::new(&mut p, &o, &mut stats, &mut cache);
    let err = Radau5::new().step(&mut sys, 1.0).unwrap_err();
    assert!(matches!(err.kind, ErrorKind::InvalidInput(_)));
}

#[test]
#[ignore = "diagnostic: prints achieved error against tolerance"]
fn diag_tolerance_sweep() {
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let o = opts(rtol, rtol * 1e-2);
        for mut case in [
            Case::new(Nonlinear2, 2.0),
            Case::new(
                MassProblem {
                    state_dependent: false,
                },
                2.0,
            ),
            Case::new(
                MassProblem {
                    state_dependent: true,
                },
                2.0,
            ),
            Case::new(Dae1, 2.0),
            Case::new(Linear2, 2.0),
        ] {
            let (run, e) = case.run(RADAU, &o, false);
            eprintln!(
                "rtol {rtol:e}: {} {e:e} ({} st)",
                case.name, run.stats.steps
            );
        }
    }
}
