//! Discrete → continuum convergence on the macroscale-fixed family (docs/model.md §5.4): l₀ = N,
//! K = 1/N, exponential ramp with ramp time N, compared at t = 0.5N in scaled positions x/N
//! against a very fine conservative-continuum reference (n = 3200). Prescribed end: error
//! O(N⁻²) with Ref max errors 3.7e-8, 9.3e-9, 2.3e-9, 5.8e-10, 1.4e-10 for N = 25, 50, 100, 200, 400.
//! Identity: the continuum scheme with n = N reproduces the discrete trajectory to round-off.

use celltissue::line::build::{continuum, discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::line::LineConfig;
use celltissue::{ArrayProblem, NeoHookean};

fn params(n: usize) -> LineParams {
    let cfg = LineConfig {
        cells: n,
        k: (1.0 / n as f64).into(),
        t_ramp: n as f64,
        ..Default::default()
    };
    cfg.params(1e-14)
}

fn settings() -> SolveSettings {
    SolveSettings {
        rtol: 1e-12,
        atol: 1e-14,
        ..Default::default()
    }
}

/// Scaled boundary positions x_j/N at t = 0.5N (j = 0..=n).
fn positions(n_cells: usize, nodes: Option<usize>) -> Vec<f64> {
    let p = params(n_cells);
    let nh = NeoHookean::new(1.0).unwrap();
    let line = match nodes {
        None => discrete(nh, &p).unwrap(),
        Some(m) => continuum(nh, &p, m).unwrap(),
    };
    let mut prob = ArrayProblem::new(line);
    let t = 0.5 * n_cells as f64;
    let traj = integrate(&mut prob, &settings(), &[t]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    traj.snapshots[0]
        .x
        .iter()
        .map(|x| x / n_cells as f64)
        .collect()
}

#[test]
fn prescribed_end_error_falls_as_n_minus_2() {
    let fine = 3200;
    let reference = positions(100, Some(fine));
    let refs = [3.7e-8, 9.3e-9, 2.3e-9, 5.8e-10, 1.4e-10];
    let mut errs = Vec::new();
    for (i, &n) in [25usize, 50, 100, 200, 400].iter().enumerate() {
        let x = positions(n, None);
        let stride = fine / n;
        let err = (0..=n)
            .map(|j| (x[j] - reference[j * stride]).abs())
            .fold(0.0, f64::max);
        println!("N = {n}: max |x/N − ref| = {err:.3e} (Ref {:.1e})", refs[i]);
        errs.push(err);
        assert!(
            (err / refs[i] - 1.0).abs() < 0.05,
            "N = {n}: {err:e} vs Ref {:e}",
            refs[i]
        );
    }
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            ratio > 3.5 && ratio < 4.5,
            "error ratio per doubling {ratio}"
        );
    }
}

#[test]
fn continuum_with_n_equal_n_reproduces_discrete() {
    let a = positions(40, None);
    let b = positions(40, Some(40));
    let err = a
        .iter()
        .zip(&b)
        .map(|(u, v)| (u - v).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-15, "{err:e}");
}
