//! Small-displacement exponential ramp, η = 0 (docs/model.md §5.3): the discrete line (N = 100,
//! k₁ = 1e-4) against the complete linear series solution (particular term + Fourier series);
//! Ref thresholds max_j |λ_j − λ_lin|/k₁ < 1e-5 (K = 1e-4) and < 1e-3 (K = 1e-2) at t = 0.5, 1, 3.
//! And the quasi-static limit: a drag far below the cells' stiffness (K = 1e-20 down to the
//! smallest normal double, where the consistent initialisation's `∂F/∂ẏ` used to cancel to
//! zero, "singular") runs and gives the K = 0 line.

use celltissue::line::{run_line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::ModelKind;
use std::f64::consts::PI;

/// λ_lin(X, t) = 1 − k₁ + k₁ d̆_X with the full series (t_s = K/4, γ₀ = μ = 1).
fn lambda_lin(x: f64, t: f64, k: f64, k1: f64, l0: f64) -> f64 {
    let ts = k / 4.0;
    let a = ts.sqrt();
    let mut dx = l0 * a * (a * x).cos() / (a * l0).sin() * (-t).exp();
    for n in 1..20000 {
        let kn = n as f64 * PI / l0;
        let decay = (-kn * kn * t / ts).exp();
        if decay < 1e-300 {
            break;
        }
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        dx += 2.0 * sign * ts / (kn * kn - ts) * (kn * x).cos() * decay;
    }
    1.0 - k1 + k1 * dx
}

fn max_error(k: f64) -> Vec<f64> {
    let k1 = 1e-4;
    let cfg = LineConfig {
        k: k.into(),
        k1,
        ..Default::default()
    };
    let times = OutputTimes {
        series: vec![0.0, 0.5, 1.0, 3.0],
        profiles: vec![0.5, 1.0, 3.0],
    };
    let s = SolveSettings {
        rtol: 1e-11,
        atol: 1e-13,
        ..Default::default()
    };
    let rec = run_line(&cfg, ModelKind::Discrete, None, &s, &times);
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec.profiles
        .iter()
        .map(|p| {
            p.x_ref
                .iter()
                .zip(&p.stretch)
                .map(|(&x, &l)| (l - lambda_lin(x, p.t, k, k1, 100.0)).abs() / k1)
                .fold(0.0, f64::max)
        })
        .collect()
}

#[test]
fn k_1e_minus_4_matches_linear_series() {
    let e = max_error(1e-4);
    println!("K = 1e-4: max |λ − λ_lin|/k₁ at t = 0.5, 1, 3: {e:?}");
    assert!(e.iter().all(|&v| v < 1e-5), "{e:?}");
}

#[test]
fn k_1e_minus_2_matches_linear_series() {
    let e = max_error(1e-2);
    println!("K = 1e-2: max |λ − λ_lin|/k₁ at t = 0.5, 1, 3: {e:?}");
    assert!(e.iter().all(|&v| v < 1e-3), "{e:?}");
}

#[test]
fn a_drag_far_below_the_stiffness_gives_the_quasi_static_line() {
    let run = |k: f64| {
        let cfg = LineConfig {
            k: k.into(),
            mu: celltissue::cell::Field::Gaussian {
                base: 1.0,
                amplitude: 1.0,
                centre: 0.5,
                width: 0.1,
            },
            ..Default::default()
        };
        let times = OutputTimes {
            series: vec![0.0, 0.5, 1.0, 5.0],
            profiles: vec![0.5, 1.0, 5.0],
        };
        let rec = run_line(
            &cfg,
            ModelKind::Discrete,
            None,
            &SolveSettings::default(),
            &times,
        );
        assert!(rec.error.is_none(), "K = {k:e}: {:?}", rec.error);
        rec.profiles
            .into_iter()
            .flat_map(|p| p.stretch)
            .collect::<Vec<f64>>()
    };
    let quasi_static = run(0.0);
    // (the last: the smallest normal double, 2.2e-308, rounded up; a subnormal K is rejected
    // by the configuration's validation)
    for k in [1e-20, 1e-100, 1e-200, 1e-300, 2.3e-308] {
        let d = run(k)
            .iter()
            .zip(&quasi_static)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // the O(K) difference is far below the contract's 10·rtol at rtol 1e-6
        assert!(d < 1e-5, "K = {k:e}: max |Δλ| = {d:e}");
    }
}
