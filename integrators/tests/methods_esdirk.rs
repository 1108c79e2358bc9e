//! TR-BDF2 (ESDIRK): exact solutions, stiff benchmarks, an index-1 DAE, mass matrices and the
//! observed order from a fixed-step sweep.

mod methods_common;

use integrators::methods::esdirk::Esdirk;
use integrators::Options;
use methods_common::*;

/// TR-BDF2 controls the local error *per step* (order-2 solution, error per step ≤ tol); on
/// these non-expanding problems the global error is then bounded by the sum of the local
/// tolerances, `steps · (rtol·max|y| + atol)`. The tests check that bound (and, separately,
/// tolerance proportionality), not `error < rtol`, which no per-step controller promises.
fn local_sum_bound(steps: usize, rtol: f64, atol: f64, ymax: f64) -> f64 {
    steps as f64 * (rtol * ymax + atol)
}

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
        &mut Esdirk::new(),
        &mut Linear2,
        &opts(1e-7, 1e-9),
        0.0,
        &[1.0, 0.0],
        3.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Linear2::exact(3.0));
    eprintln!(
        "esdirk linear: err {e:e} dense {:e} {:?}",
        run.dense_err, run.stats
    );
    let bound = local_sum_bound(run.stats.steps, 1e-7, 1e-9, 1.0);
    assert!(e < bound, "end error {e:e} vs {bound:e}");
    assert!(run.dense_err < bound, "dense error {:e}", run.dense_err);
    // tolerance proportionality: 100× tighter tolerance, error ≥ 10× smaller (≈ 100^(2/3))
    let tight = integrate(
        &mut Esdirk::new(),
        &mut Linear2,
        &opts(1e-9, 1e-11),
        0.0,
        &[1.0, 0.0],
        3.0,
        None,
    )
    .unwrap();
    let e2 = max_err(&tight.y, &Linear2::exact(3.0));
    eprintln!("esdirk linear rtol 1e-7: {e:e}, rtol 1e-9: {e2:e}");
    assert!(e2 < e / 10.0, "{e2:e} vs {e:e}");
}

#[test]
fn observed_order_is_two_on_a_nonlinear_ode() {
    let ex = |t: f64| Nonlinear2::exact(t);
    let (hs, errs) = fixed_step_sweep(
        &|| Box::new(Esdirk::new()),
        &mut Nonlinear2,
        1.0,
        &[1.0, 1.0],
        &ex,
        &[10, 20, 40, 80, 160],
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!("esdirk fixed-step errors {errs:?} -> observed order {p:.3}");
    assert!((p - 2.0).abs() <= 0.3, "observed order {p}");
}

#[test]
fn observed_order_on_index1_dae() {
    let ex = |t: f64| Dae1::exact(t);
    let (hs, errs) = fixed_step_sweep(
        &|| Box::new(Esdirk::new()),
        &mut Dae1,
        1.0,
        &[0.0, 1.0],
        &ex,
        &[10, 20, 40, 80, 160],
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!("esdirk index-1 DAE fixed-step errors {errs:?} -> observed order {p:.3}");
    assert!((p - 2.0).abs() <= 0.3, "observed order {p}");
}

#[test]
fn robertson_conserves_mass_and_matches_radau_reference() {
    let y0 = [1.0, 0.0, 0.0];
    let run = integrate(
        &mut Esdirk::new(),
        &mut Robertson,
        &opts(1e-6, 1e-8),
        0.0,
        &y0,
        1e5,
        None,
    )
    .unwrap();
    let reference = integrate(
        &mut integrators::methods::radau::Radau5::new(),
        &mut Robertson,
        &opts(1e-11, 1e-8),
        0.0,
        &y0,
        1e5,
        None,
    )
    .unwrap();
    eprintln!(
        "robertson esdirk: {:?} ref {:?} {:?}",
        run.y, reference.y, run.stats
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
}

#[test]
fn van_der_pol_mu_1000_completes_and_matches_radau() {
    let y0 = [2.0, 0.0];
    let mut p = VanDerPol { mu: 1000.0 };
    let run = integrate(
        &mut Esdirk::new(),
        &mut p,
        &opts(1e-6, 1e-6),
        0.0,
        &y0,
        3000.0,
        None,
    )
    .unwrap();
    let reference = integrate(
        &mut integrators::methods::radau::Radau5::new(),
        &mut p,
        &opts(1e-10, 1e-10),
        0.0,
        &y0,
        3000.0,
        None,
    )
    .unwrap();
    eprintln!(
        "vdp esdirk: {:?} ref {:?} {:?}",
        run.y, reference.y, run.stats
    );
    assert!((run.y[0] - reference.y[0]).abs() < 1e-2 * reference.y[0].abs().max(1.0));
}

#[test]
fn index1_dae_matches_exact_solution() {
    let ex = |t: f64| Dae1::exact(t);
    let run = integrate(
        &mut Esdirk::new(),
        &mut Dae1,
        &opts(1e-8, 1e-10),
        0.0,
        &[0.0, 1.0],
        5.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Dae1::exact(5.0));
    eprintln!(
        "esdirk dae: err {e:e} dense {:e} {:?}",
        run.dense_err, run.stats
    );
    let bound = local_sum_bound(run.stats.steps, 1e-8, 1e-10, 1.5);
    assert!(e < bound, "{e:e} vs {bound:e}");
    assert!(run.dense_err < bound, "{:e}", run.dense_err);
}

#[test]
fn state_dependent_mass_matrix_matches_exact_solution() {
    let ex = |t: f64| Nonlinear2::exact(t);
    let run = integrate(
        &mut Esdirk::new(),
        &mut MassProblem {
            state_dependent: true,
        },
        &opts(1e-8, 1e-10),
        0.0,
        &[1.0, 1.0],
        2.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Nonlinear2::exact(2.0));
    eprintln!("esdirk state-dependent mass: err {e:e} {:?}", run.stats);
    let bound = local_sum_bound(run.stats.steps, 1e-8, 1e-10, 2.5);
    assert!(e < bound, "{e:e} vs {bound:e}");
}

#[test]
fn banded_heat_equation_matches_exact_solution() {
    let mut p = Heat { n: 200 };
    let y0 = p.exact(0.0);
    let t_end = 0.1;
    let exact = p.exact(t_end);
    let run = integrate(
        &mut Esdirk::new(),
        &mut p,
        &opts(1e-7, 1e-9),
        0.0,
        &y0,
        t_end,
        None,
    )
    .unwrap();
    let e = max_err(&run.y, &exact);
    eprintln!("heat esdirk: err {e:e} {:?}", run.stats);
    let bound = local_sum_bound(run.stats.steps, 1e-7, 1e-9, 1.0);
    assert!(e < bound, "{e:e} vs {bound:e}");
    // linear problem with an exact Jacobian: one refresh (2 evaluations) for the whole run,
    // plus one for the starting-step estimate (a consistent initialisation at the trial point)
    assert_eq!(run.stats.jacobian_evals - run.init_stats.jacobian_evals, 3);
}
