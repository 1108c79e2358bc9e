//! TR-BDF2 (ESDIRK): exact solutions, stiff benchmarks, an index-1 DAE, mass matrices and the
//! observed order from a fixed-step sweep.
//!
//! TR-BDF2 controls the local error *per step* (order-2 solution, error per step ≤ tol), so the
//! error checks use [`Bound::LocalSum`] (and, separately, tolerance proportionality), not
//! `error < rtol`, which no per-step controller promises.

mod methods_common;

use integrators::MethodKind;
use methods_common::*;

const ESDIRK: MethodKind = MethodKind::Esdirk;

#[test]
fn linear_2x2_matches_exact_solution_with_dense_output() {
    let mut case = Case::new(Linear2, 3.0);
    let bound = Bound::LocalSum {
        ymax: 1.0,
        dense: true,
    };
    let run = check_exact(ESDIRK, &mut case, &opts(1e-7, 1e-9), true, bound);
    // tolerance proportionality: 100× tighter tolerance, error ≥ 10× smaller (≈ 100^(2/3))
    let e = max_err(&run.y, &Linear2.solution(3.0));
    let (_, e2) = case.run(ESDIRK, &opts(1e-9, 1e-11), false);
    eprintln!("esdirk linear rtol 1e-7: {e:e}, rtol 1e-9: {e2:e}");
    assert!(e2 < e / 10.0, "{e2:e} vs {e:e}");
}

#[test]
fn observed_order_is_two_on_a_nonlinear_ode() {
    check_order(
        ESDIRK,
        &mut Case::new(Nonlinear2, 1.0),
        &[10, 20, 40, 80, 160],
        2.0,
    );
}

#[test]
fn observed_order_on_index1_dae() {
    check_order(
        ESDIRK,
        &mut Case::new(Dae1, 1.0),
        &[10, 20, 40, 80, 160],
        2.0,
    );
}

#[test]
fn robertson_conserves_mass_and_matches_radau_reference() {
    check_robertson(ESDIRK);
}

/// At `rtol = 1e-6` this order-2 method's phase error through the relaxation jumps is not a
/// smooth function of the tolerance: `|Δy1(3000)|` measured 1.8e-3 … 2.9e-2 over nine rtol
/// from 5e-7 to 2e-6 (7.7e-4 … 2.8e-2 before the retry cap after repeated error-test failures;
/// at 1e-6 itself 2.4e-2, before 9.8e-3), so a tight bound there would pin luck: at 1e-6 it
/// must complete on the right branch; its accuracy is checked at 1e-8, where it errs by 9.8e-6.
#[test]
fn van_der_pol_mu_1000_completes_and_matches_radau() {
    check_van_der_pol(ESDIRK, 1e-6, 3e-2);
    check_van_der_pol(ESDIRK, 1e-8, 1e-4);
}

#[test]
fn index1_dae_matches_exact_solution() {
    let bound = Bound::LocalSum {
        ymax: 1.5,
        dense: true,
    };
    check_exact(
        ESDIRK,
        &mut Case::new(Dae1, 5.0),
        &opts(1e-8, 1e-10),
        true,
        bound,
    );
}

#[test]
fn state_dependent_mass_matrix_matches_exact_solution() {
    let bound = Bound::LocalSum {
        ymax: 2.5,
        dense: false,
    };
    let mut case = Case::new(
        MassProblem {
            state_dependent: true,
        },
        2.0,
    );
    check_exact(ESDIRK, &mut case, &opts(1e-8, 1e-10), true, bound);
}

#[test]
fn banded_heat_equation_matches_exact_solution() {
    let bound = Bound::LocalSum {
        ymax: 1.0,
        dense: false,
    };
    let run = check_exact(
        ESDIRK,
        &mut Case::new(Heat { n: 200 }, 0.1),
        &opts(1e-7, 1e-9),
        false,
        bound,
    );
    // linear problem with an exact Jacobian: one refresh (2 evaluations) for the whole run,
    // plus one for the starting-step estimate (a consistent initialisation at the trial point)
    assert_eq!(run.method_jacobians(), 3);
}
