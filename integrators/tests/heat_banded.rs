//! 1D heat equation u_t = u_xx on (0, 1), Dirichlet, central differences → banded (1, 1)
//! Jacobian; u(x, 0) = sin(πx), exact u = e^{−π² t} sin(πx).
//!
//! The semi-discrete system has the exact solution e^{−λt} sin(πx_i) with
//! λ = (4/Δx²) sin²(πΔx/2) = π²(1 − (πΔx)²/12 + …), so at t the spatial (discretisation) error
//! relative to the PDE solution is ≈ π² t (πΔx)²/12 — at t = 0.1 about (πΔx)²/12. The time
//! integration error is measured against the semi-discrete exact solution.

mod common;

use common::opts;
use common::Heat;
use integrators::adapters::Ode;
use integrators::{MethodKind, Solver};

#[test]
fn bdf_heat_banded_matches_exact_solution() {
    for (n, exact_jac) in [(100, true), (1000, false)] {
        let mut p = Ode(Heat {
            n,
            exact_jacobian: exact_jac,
        });
        let y0 = p.0.initial();
        let rtol = 1e-7;
        let o = opts(rtol, 1e-10);
        let t = 0.1;
        let sol = Solver::new(MethodKind::Bdf, o)
            .solve(&mut p, 0.0, &y0, &[t])
            .unwrap();
        let y = &sol.y[0];
        let amp = (-std::f64::consts::PI.powi(2) * t).exp();
        let time_err = (0..n)
            .map(|i| (y[i] - p.0.exact_semidiscrete(t, i)).abs())
            .fold(0.0, f64::max)
            / amp;
        let pde_err = (0..n)
            .map(|i| (y[i] - p.0.exact_pde(t, i)).abs())
            .fold(0.0, f64::max)
            / amp;
        let dx = 1.0 / (n + 1) as f64;
        let pi = std::f64::consts::PI;
        let spatial_pred = pi * pi * t * (pi * dx).powi(2) / 12.0;
        eprintln!(
            "n={n}: time err {time_err:.3e}, pde err {pde_err:.3e}, predicted spatial {spatial_pred:.3e}, {:?}",
            sol.stats
        );
        // time error: a small multiple of the tolerance
        assert!(time_err < 20.0 * rtol, "time error {time_err}");
        // total error = spatial error (predicted to 2 digits) + time error
        assert!(
            (pde_err - spatial_pred).abs() < 0.01 * spatial_pred + time_err,
            "pde error {pde_err} vs predicted {spatial_pred}"
        );
        // banded finite differences: 3 colours per Jacobian, never n residual calls
        if !exact_jac {
            assert!(
                sol.stats.residual_calls
                    < sol.stats.newton_iterations + 3 * sol.stats.jacobian_evals + 50,
                "{:?}",
                sol.stats
            );
        }
    }
}

/// `Parallelism::Halves` splits, from its `min_len` unknowns, BDF's predictor/weights and
/// error-norm passes and the twisted tridiagonal factorisation and solve in two halves run by
/// `rayon::join`, each half with the one-thread arithmetic. The threshold is lowered to 4096 so
/// a 20 000-unknown problem exercises every split (the default is 2¹⁵). With the max norm
/// nothing else differs:
/// the two runs are bitwise identical. With the RMS norm (the default) the norms' sums are
/// split in two, so the step sizes differ in their last bits: the runs take the same steps and
/// Newton iterations and agree far below the integration tolerance (`rtol·max|y| = 1e-6`). The
/// bound is 1e-5 of it: measured 4.0e-13 when BDF accumulated its Newton corrections, 1.0e-12
/// since it recomputes `y_new − predictor` from the history, whose cancellation
/// lets the split sums' last bits reach the step sizes.
#[test]
fn two_threads_give_the_one_thread_solution() {
    let n = 20_001;
    let split = integrators::Parallelism::Halves { min_len: 4096 };
    let run = |parallel: integrators::Parallelism, norm: integrators::ErrorNorm| {
        let mut p = Ode(Heat {
            n,
            exact_jacobian: true,
        });
        let y0 = p.0.initial();
        let o = integrators::Options {
            parallel,
            norm,
            ..opts(1e-6, 1e-9)
        };
        Solver::new(MethodKind::Bdf, o)
            .solve(&mut p, 0.0, &y0, &[0.02])
            .unwrap()
    };
    let max = integrators::ErrorNorm::Max;
    let serial = integrators::Parallelism::Serial;
    let (one, two) = (run(serial, max), run(split, max));
    assert_eq!(one.stats, two.stats);
    assert_eq!(one.y, two.y, "max norm: bitwise the one-thread solution");
    let rms = integrators::ErrorNorm::Rms;
    let (one, two) = (run(serial, rms), run(split, rms));
    assert_eq!(one.stats.steps, two.stats.steps);
    assert_eq!(one.stats.newton_iterations, two.stats.newton_iterations);
    let ymax = one.y[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = one.y[0]
        .iter()
        .zip(&two.y[0])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        diff < 1e-5 * 1e-6 * ymax,
        "max difference {diff:e} (max |y| {ymax:e})"
    );
}

#[test]
fn bad_parallel_settings_are_named_input_errors() {
    use integrators::Parallelism;
    for threads in [0, 3] {
        let e = Parallelism::from_threads(threads).unwrap_err();
        assert!(
            e.to_string()
                .starts_with(&format!("threads = {threads} must be 1 or 2")),
            "{e}"
        );
    }
    let mut p = Ode(Heat {
        n: 10,
        exact_jacobian: true,
    });
    let y0 = p.0.initial();
    let o = integrators::Options {
        parallel: Parallelism::Halves { min_len: 1 },
        ..opts(1e-6, 1e-9)
    };
    let e = Solver::new(MethodKind::Bdf, o)
        .solve(&mut p, 0.0, &y0, &[0.02])
        .unwrap_err();
    assert_eq!(
        e.error.kind,
        integrators::ErrorKind::InvalidInput("parallel.min_len = 1 must be at least 2".into())
    );
}
