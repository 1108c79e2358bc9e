//! Radau IIA (order 5): exact solutions, stiff benchmarks, mass matrices, an index-1 DAE, the
//! banded complex-pair path, and the observed order from a fixed-step sweep.

mod methods_common;

use integrators::methods::radau::Radau5;
use integrators::{ErrorKind, Method, Options};
use methods_common::*;

/// Jacobian evaluations of the starting-step estimate: one consistent initialisation at the
/// trial point `t₀ + h₀` (one Newton iteration on a linear problem).
const START_ESTIMATE_JACOBIANS: usize = 1;

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
        &mut Radau5::new(),
        &mut Linear2,
        &opts(1e-8, 1e-10),
        0.0,
        &[1.0, 0.0],
        3.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Linear2::exact(3.0));
    assert!(e < 1e-8, "end error {e:e}");
    assert!(run.dense_err < 1e-7, "dense error {:e}", run.dense_err);
    // ẏ at the end is the derivative of the exact solution
    let yp_ex = [
        -Linear2::exact(3.0)[0] + 2.0 * Linear2::exact(3.0)[1],
        -2.0 * Linear2::exact(3.0)[0] - Linear2::exact(3.0)[1],
    ];
    assert!(max_err(&run.yp, &yp_ex) < 1e-7);
    // linear problem with an exact Jacobian: Newton converges in one iteration, the Jacobian is
    // kept (θ ≤ 0.001): exactly one refresh (= 2 Jacobian evaluations) after the starting-step
    // estimate.
    assert_eq!(
        run.stats.jacobian_evals - run.init_stats.jacobian_evals,
        START_ESTIMATE_JACOBIANS + 2,
        "{:?}",
        run.stats
    );
    // cost pin (measured 98 steps: RADAU5's embedded order-3 estimate is conservative here)
    assert!(run.stats.steps <= 110, "{:?}", run.stats);
}

#[test]
fn observed_order_is_five_on_a_nonlinear_ode() {
    let ex = |t: f64| Nonlinear2::exact(t);
    let (hs, errs) = fixed_step_sweep(
        &|| Box::new(Radau5::new()),
        &mut Nonlinear2,
        1.0,
        &[1.0, 1.0],
        &ex,
        &[5, 10, 20, 40],
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!("radau fixed-step errors {errs:?} -> observed order {p:.3}");
    assert!((p - 5.0).abs() <= 0.3, "observed order {p}");
}

#[test]
fn robertson_conserves_mass_and_matches_tight_reference() {
    let y0 = [1.0, 0.0, 0.0];
    let run = integrate(
        &mut Radau5::new(),
        &mut Robertson,
        &opts(1e-6, 1e-8),
        0.0,
        &y0,
        1e5,
        None,
    )
    .unwrap();
    let reference = integrate(
        &mut Radau5::new(),
        &mut Robertson,
        &opts(1e-11, 1e-8),
        0.0,
        &y0,
        1e5,
        None,
    )
    .unwrap();
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
    eprintln!(
        "robertson radau rtol 1e-6: {:?} ref {:?} {:?}",
        run.y, reference.y, run.stats
    );
    assert!(run.stats.steps < 300, "{:?}", run.stats);
}

#[test]
fn van_der_pol_mu_1000_completes_and_matches_tight_run() {
    let y0 = [2.0, 0.0];
    let mut p = VanDerPol { mu: 1000.0 };
    let run = integrate(
        &mut Radau5::new(),
        &mut p,
        &opts(1e-6, 1e-6),
        0.0,
        &y0,
        3000.0,
        None,
    )
    .unwrap();
    let reference = integrate(
        &mut Radau5::new(),
        &mut p,
        &opts(1e-10, 1e-10),
        0.0,
        &y0,
        3000.0,
        None,
    )
    .unwrap();
    eprintln!(
        "vdp radau: {:?} ref {:?} {:?}",
        run.y, reference.y, run.stats
    );
    assert!((run.y[0] - reference.y[0]).abs() < 1e-3 * reference.y[0].abs().max(1.0));
    assert!(run.stats.steps < 2000, "{:?}", run.stats);
}

#[test]
fn constant_mass_matrix_matches_exact_solution() {
    let ex = |t: f64| Nonlinear2::exact(t);
    let run = integrate(
        &mut Radau5::new(),
        &mut MassProblem {
            state_dependent: false,
        },
        &opts(1e-9, 1e-11),
        0.0,
        &[1.0, 1.0],
        2.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Nonlinear2::exact(2.0));
    assert!(e < 1e-8, "{e:e}");
    assert!(run.dense_err < 1e-7, "{:e}", run.dense_err);
}

#[test]
fn state_dependent_mass_matrix_matches_exact_solution() {
    let ex = |t: f64| Nonlinear2::exact(t);
    let run = integrate(
        &mut Radau5::new(),
        &mut MassProblem {
            state_dependent: true,
        },
        &opts(1e-9, 1e-11),
        0.0,
        &[1.0, 1.0],
        2.0,
        Some(&ex),
    )
    .unwrap();
    let e = max_err(&run.y, &Nonlinear2::exact(2.0));
    assert!(e < 1e-8, "{e:e}");
    assert!(run.dense_err < 1e-7, "{:e}", run.dense_err);
}

#[test]
fn index1_dae_matches_exact_solution() {
    let ex = |t: f64| Dae1::exact(t);
    for suppress in [true, false] {
        let o = Options {
            suppress_algebraic: suppress,
            ..opts(1e-9, 1e-11)
        };
        let run = integrate(
            &mut Radau5::new(),
            &mut Dae1,
            &o,
            0.0,
            &[0.0, 1.0],
            5.0,
            Some(&ex),
        )
        .unwrap();
        let e = max_err(&run.y, &Dae1::exact(5.0));
        assert!(e < 1e-8, "suppress={suppress}: {e:e}");
        assert!(run.dense_err < 1e-7, "{:e}", run.dense_err);
    }
}

#[test]
fn observed_order_on_index1_dae() {
    let ex = |t: f64| Dae1::exact(t);
    let (hs, errs) = fixed_step_sweep(
        &|| Box::new(Radau5::new()),
        &mut Dae1,
        1.0,
        &[0.0, 1.0],
        &ex,
        &[5, 10, 20, 40],
        1e-12,
    );
    let p = fitted_order(&hs, &errs);
    eprintln!("radau index-1 DAE fixed-step errors {errs:?} -> observed order {p:.3}");
    assert!((p - 5.0).abs() <= 0.3, "observed order {p}");
}

#[test]
fn banded_heat_equation_through_complex_pair_path() {
    let mut p = Heat { n: 200 };
    let y0 = p.exact(0.0);
    let t_end = 0.1;
    let exact = p.exact(t_end);
    let run = integrate(
        &mut Radau5::new(),
        &mut p,
        &opts(1e-8, 1e-10),
        0.0,
        &y0,
        t_end,
        None,
    )
    .unwrap();
    let e = max_err(&run.y, &exact);
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    eprintln!("heat radau: err {e:e} (max |u| {scale:e}) {:?}", run.stats);
    assert!(e < 1e-7 * scale.max(1e-3) + 1e-9, "{e:e}");
    // linear problem, exact Jacobian: one Jacobian refresh for the whole run
    assert_eq!(
        run.stats.jacobian_evals - run.init_stats.jacobian_evals,
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
    assert!(max_err(&a.y, &Linear2::exact(1.0)) < 1e-7);
    let mut p = Heat { n: 50 };
    let y0 = p.exact(0.0);
    let b = integrate(&mut m, &mut p, &o, 0.0, &y0, 0.05, None).unwrap();
    assert!(max_err(&b.y, &p.exact(0.05)) < 1e-7);
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
        let a = integrate(
            &mut Radau5::new(),
            &mut Nonlinear2,
            &o,
            0.0,
            &[1.0, 1.0],
            2.0,
            None,
        )
        .unwrap();
        let b = integrate(
            &mut Radau5::new(),
            &mut MassProblem {
                state_dependent: false,
            },
            &o,
            0.0,
            &[1.0, 1.0],
            2.0,
            None,
        )
        .unwrap();
        let c = integrate(
            &mut Radau5::new(),
            &mut MassProblem {
                state_dependent: true,
            },
            &o,
            0.0,
            &[1.0, 1.0],
            2.0,
            None,
        )
        .unwrap();
        let d = integrate(
            &mut Radau5::new(),
            &mut Dae1,
            &o,
            0.0,
            &[0.0, 1.0],
            2.0,
            None,
        )
        .unwrap();
        let l = integrate(
            &mut Radau5::new(),
            &mut Linear2,
            &o,
            0.0,
            &[1.0, 0.0],
            2.0,
            None,
        )
        .unwrap();
        eprintln!("rtol {rtol:e}: ode {:e} ({} st) cmass {:e} ({}) smass {:e} ({}) dae {:e} ({}) lin {:e} ({})",
            max_err(&a.y, &Nonlinear2::exact(2.0)), a.stats.steps,
            max_err(&b.y, &Nonlinear2::exact(2.0)), b.stats.steps,
            max_err(&c.y, &Nonlinear2::exact(2.0)), c.stats.steps,
            max_err(&d.y, &Dae1::exact(2.0)), d.stats.steps,
            max_err(&l.y, &Linear2::exact(2.0)), l.stats.steps);
    }
}
