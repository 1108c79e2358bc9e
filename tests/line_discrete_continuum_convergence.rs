//! Discrete → continuum convergence on the macroscale-fixed family (docs/model.md §5.4): l₀ = N,
//! K = 1/N, exponential ramp with ramp time N, compared at t = 0.5N in scaled positions x/N
//! against a very fine conservative-continuum reference (n = 3200). Prescribed end: error
//! O(N⁻²) with Ref max errors 3.7e-8, 9.3e-9, 2.3e-9, 5.8e-10, 1.4e-10 for N = 25, 50, 100, 200, 400.
//! Self-similarity: the continuum with n segments of the N = 100 problem is the scaled discrete
//! n-cell member of the family.

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

/// rtol bounds each cell's stretch error (the cell-unit contract). 1e-11 is as tight as
/// doubles allow here: the n = 3200 reference has positions up to 100 on segments of 1/32, so
/// one rounding of a position is a stretch change of 2.2e-16·100·32 ≈ 7e-13, and at rtol
/// 1e-12 the error test meets that noise (the step size collapses to 1e-22 at t ≈ 1e-8).
fn settings() -> SolveSettings {
    SolveSettings {
        rtol: 1e-11,
        atol: 1e-13,
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

/// Self-similarity of the family, through the continuum builder: the continuum of the
/// N = 100 problem with n segments (h = 100/n, drag K·h per node, λ = Δx/h) is, after
/// x → x·n/100 and t → t·n/100, exactly the discrete n-cell member of the family (K = 1/n,
/// ramp time n). So its scaled positions at t = 50 must equal the discrete ones at t = n/2 to
/// the integrators' accuracy, for n ≠ 100 — a wrong h-scaling of the drag, stretch or ramp in
/// the continuum builder would show as an O(1) difference. (For n = N the two are the same
/// code path, so that case is not checked.)
#[test]
fn continuum_of_n_segments_is_the_scaled_discrete_n_cell_line() {
    // (h = 4, 2, 0.5 scale by powers of two, so those agree bitwise; h = 2.5 and 0.625 do not)
    for n in [25usize, 40, 50, 160, 200] {
        let c = positions(100, Some(n));
        let d = positions(n, None);
        // positions(100, ·) scales by 100 and compares at t = 50; positions(n, None) scales by
        // n at t = n/2: both are x/l₀ at t/l₀ = ½
        let err = c
            .iter()
            .zip(&d)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max);
        println!("n = {n}: max |x_c/100 − x_d/n| = {err:.2e}");
        assert_eq!(c.len(), n + 1);
        assert!(err < 1e-10, "n = {n}: {err:e}");
    }
}
