//! Maxwell and standard-linear-solid cells on the line (docs/model.md §8.3, derivation in
//! docs/viscoelasticity.md): a finite-strain Maxwell branch `α = a_e a_v`, branch stress
//! `σ_m = μ_m/μ · σ_el(a_e)`, flow rule `ȧ_v/a_v = σ_m/η_m`, with `a_v` an unknown per cell.
//!
//! * small-strain ramp-and-hold at `K = 0` against the linear solution
//!   `σ_m(t) = 4μ_m ∫₀ᵗ ε'(u) e^{−(t−u)/τ} du`, `τ = η_m/(4μ_m)` (quadrature here), and the
//!   discrepancy shrinks in proportion to the strain (it is the law's nonlinearity);
//! * the fitted relaxation time is `η_m/(4μ_m)` for four branch viscosities;
//! * SLS → elastic as `μ_m → 0`, the difference linear in `μ_m`;
//! * a Maxwell line at `K = 0` relaxes to zero stress at finite strain (`a_v → λ`);
//! * discrete and continuum agree (continuum converging to the discrete line);
//! * the Jacobian pattern holds every dependence of the residual (the coloured AD Jacobian is
//!   used with a branch), and the scenario keys are parsed and checked by name.

use crate::common::{maxwell_ramp_stress, poly_strain};
use celltissue::boundary::{Ramp, RightEnd};
use celltissue::cell::MaxwellBranch;
use celltissue::line::build::{discrete, LineParams};
use celltissue::line::run::integrate;
use celltissue::line::{run_line, Line, LineConfig, OutputTimes, SolveSettings};
use celltissue::observe::ModelKind;
use celltissue::{ArrayProblem, CellArray, NeoHookean};
use std::collections::HashSet;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn tight() -> SolveSettings {
    SolveSettings {
        rtol: 1e-10,
        atol: 1e-13,
        ..Default::default()
    }
}

/// `n` unit cells without drag, prescribed end on the polynomial ramp (`l = n(1 − k₁ s)`).
fn ramp_line(n: usize, k1: f64, t_ramp: f64, branch: Option<MaxwellBranch>) -> Line<NeoHookean> {
    let mut p = LineParams::unit_cells(n);
    p.right = RightEnd::Prescribed(Ramp::Polynomial {
        l0: n as f64,
        k1,
        t_ramp,
    });
    p.maxwell = branch;
    // the solver's absolute tolerance comes from the line (in cell units): strains here are
    // as small as 1e-5
    p.atol_cell = 1e-13;
    discrete(nh(), &p).unwrap()
}

/// Cell stress σ of every cell at each time (the line is uniform at K = 0: cell 1's).
fn stress_series(line: Line<NeoHookean>, times: &[f64]) -> Vec<Vec<f64>> {
    let traj = integrate(&mut ArrayProblem::new(line), &tight(), times);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    assert_eq!(traj.snapshots.len(), times.len());
    traj.snapshots.iter().map(|s| s.sigma.clone()).collect()
}

/// Max over the output times of `|σ − σ_lin| / max|σ_lin|` for a ramp of `k1`.
fn ramp_and_hold_error(k1: f64, sls: bool) -> f64 {
    let (mu_m, eta_m, t_r) = (0.5, 1.0, 1.0);
    let tau = eta_m / (4.0 * mu_m);
    let branch = if sls {
        MaxwellBranch::standard_linear_solid(mu_m, eta_m)
    } else {
        MaxwellBranch::maxwell(mu_m, eta_m)
    }
    .unwrap();
    let times: Vec<f64> = (0..=40).map(|i| i as f64 * 0.1).collect();
    let sig = stress_series(ramp_line(4, k1, t_r, Some(branch)), &times);
    let lin: Vec<f64> = times
        .iter()
        .map(|&t| {
            let elastic = if sls {
                4.0 * poly_strain(t, k1, t_r)
            } else {
                0.0
            };
            elastic + maxwell_ramp_stress(t, k1, t_r, 4.0 * mu_m, tau)
        })
        .collect();
    let peak = lin.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    sig.iter()
        .zip(&lin)
        .map(|(s, l)| {
            // K = 0: every cell carries the same stress
            let spread = s.iter().map(|v| (v - s[0]).abs()).fold(0.0, f64::max);
            assert!(spread <= 1e-6 * peak, "spread {spread:e} of {peak:e}");
            (s[0] - l).abs() / peak
        })
        .fold(0.0, f64::max)
}

#[test]
fn small_strain_ramp_and_hold_matches_the_linear_solution() {
    for sls in [false, true] {
        let e3 = ramp_and_hold_error(1e-3, sls);
        let e4 = ramp_and_hold_error(1e-4, sls);
        println!("sls={sls}: max |σ − σ_lin|/peak at k₁ = 1e-3, 1e-4: {e3:.3e}, {e4:.3e}");
        assert!(e4 < 1e-4, "sls={sls}: {e4}");
        // the discrepancy is the nonlinearity of the finite-strain law: O(k₁)
        let ratio = e3 / e4;
        assert!((7.0..14.0).contains(&ratio), "sls={sls}: ratio {ratio}");
    }
}

#[test]
fn relaxation_time_is_the_branch_viscosity_over_four_mu_m() {
    let (mu_m, t_r, k1) = (0.5, 0.2, 1e-4);
    for eta_m in [0.5, 1.0, 2.0, 4.0] {
        let tau = eta_m / (4.0 * mu_m);
        let (t1, t2) = (t_r + tau, t_r + 3.0 * tau);
        let branch = MaxwellBranch::maxwell(mu_m, eta_m).unwrap();
        let sig = stress_series(ramp_line(3, k1, t_r, Some(branch)), &[0.0, t1, t2]);
        let fit = (t2 - t1) / (sig[1][0] / sig[2][0]).ln();
        println!("eta_m = {eta_m}: fitted τ = {fit:.8}, η_m/(4μ_m) = {tau}");
        // the finite-strain law relaxes at 4μ_m/η_m·(1 + O(k₁))
        assert!(
            (fit / tau - 1.0).abs() < 5e-4,
            "eta_m = {eta_m}: {fit} vs {tau}"
        );
    }
}

/// End stress at several times of a line with drag on the exponential ramp (finite strain).
fn finite_strain_stress(branch: Option<MaxwellBranch>) -> Vec<f64> {
    let mut p = LineParams::unit_cells(20);
    p.k = 0.5.into();
    p.right = RightEnd::Prescribed(Ramp::Exponential {
        l0: 20.0,
        k1: 0.1,
        t_ramp: 1.0,
    });
    p.maxwell = branch;
    p.atol_cell = 1e-13;
    let times = [0.0, 0.5, 1.0, 2.0, 5.0];
    let traj = integrate(
        &mut ArrayProblem::new(discrete(nh(), &p).unwrap()),
        &tight(),
        &times,
    );
    assert!(traj.error.is_none(), "{:?}", traj.error);
    traj.snapshots
        .iter()
        .flat_map(|s| s.sigma.clone())
        .collect()
}

#[test]
fn sls_tends_to_the_elastic_line_as_the_branch_modulus_vanishes() {
    let elastic = finite_strain_stress(None);
    let diff = |mu_m: f64| {
        let s = finite_strain_stress(Some(
            MaxwellBranch::standard_linear_solid(mu_m, 1.0).unwrap(),
        ));
        s.iter()
            .zip(&elastic)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (d0, d2, d3) = (diff(0.0), diff(1e-2), diff(1e-3));
    println!("max |σ_SLS − σ_el|: μ_m = 0: {d0:.2e}, 1e-2: {d2:.3e}, 1e-3: {d3:.3e}");
    assert!(d0 < 1e-8, "{d0}");
    assert!(d2 > 1e-4, "the branch must act: {d2}");
    let ratio = d3 / d2;
    assert!((0.09..0.11).contains(&ratio), "linear in μ_m: {ratio}");
}

#[test]
fn a_maxwell_line_without_drag_relaxes_to_zero_stress() {
    let branch = MaxwellBranch::maxwell(1.0, 2.0).unwrap(); // τ = 0.5
    let line = ramp_line(5, 0.2, 1.0, Some(branch));
    let vi = line.layout().vi.clone();
    let times = [0.0, 1.0, 40.0];
    let traj = integrate(&mut ArrayProblem::new(line), &tight(), &times);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    let peak = traj.snapshots[1].sigma[0].abs();
    let last = traj.snapshots.last().unwrap();
    println!(
        "Maxwell, K = 0, k₁ = 0.2: |σ| at t = 1: {peak:.4}, at t = 40: {:.2e}",
        last.sigma[0]
    );
    assert!(peak > 0.1, "{peak}");
    for s in &last.sigma {
        assert!(s.abs() < 1e-8 * peak, "{s}");
    }
    // fully relaxed: the viscous stretch has taken the whole stretch (a_e = 1)
    for (j, &k) in vi.iter().enumerate() {
        let av = traj.y_last[k];
        assert!(
            (av - last.lambda[j]).abs() < 1e-8,
            "{av} vs {}",
            last.lambda[j]
        );
        assert!(
            (last.lambda[j] - 0.8).abs() < 1e-6,
            "λ = {}",
            last.lambda[j]
        );
    }
}

/// Max difference of the end reaction relative to its largest value, continuum on `n` segments vs the discrete
/// line, for the scenario `extra` (K = 0.01, N = 80, exponential ramp).
fn continuum_error(extra: &str, n: usize) -> f64 {
    let cfg: LineConfig = toml::from_str(&format!("cells = 80\nK = 0.01\n{extra}")).unwrap();
    let times = OutputTimes {
        series: vec![0.5, 1.0, 2.0, 4.0],
        profiles: vec![],
    };
    let series = |model, nodes| {
        let rec = run_line(&cfg, model, nodes, &tight(), &times);
        assert!(rec.error.is_none(), "{:?}", rec.error);
        rec.series.extra["end_reaction"].clone()
    };
    let d = series(ModelKind::Discrete, None);
    let scale = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    series(ModelKind::Continuum, Some(n))
        .iter()
        .zip(&d)
        .map(|(a, b)| (a - b).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn discrete_and_continuum_agree() {
    let sls = r#"viscosity = { model = "standard_linear_solid", mu_m = 0.5, eta_m = 1.0 }"#;
    let maxwell = r#"viscosity = { model = "maxwell", mu_m = 1.0, eta_m = 1.0 }"#;
    for (label, extra) in [("elastic", ""), ("sls", sls), ("maxwell", maxwell)] {
        let (e20, e40) = (continuum_error(extra, 20), continuum_error(extra, 40));
        println!("{label}: end reaction, continuum vs discrete N = 80: n = 20: {e20:.3e}, n = 40: {e40:.3e}");
        // the conservative scheme's error at the early-time boundary layer of the moving end
        // (K = 0.01): ≈ 2–5 % at n = 40, shrinking ≈ 3× per doubling, the same with and
        // without a branch (the Maxwell line's boundary layer is sharper)
        assert!(e40 < 6e-2 && e40 < 0.4 * e20, "{label}: {e20} {e40}");
    }
}

#[test]
fn the_pattern_holds_every_dependence_and_the_own_jacobian_differentiates_it() {
    let mut p = LineParams::unit_cells(6);
    p.k = 0.3.into();
    p.eta = 0.2.into();
    p.right = RightEnd::Free(None);
    p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
    p.maxwell = Some(MaxwellBranch::standard_linear_solid(0.7, 1.3).unwrap());
    let line = discrete(nh(), &p).unwrap();
    let n = line.dim();
    assert_eq!(n, 6 * 3); // (g, a_v, x) per cell, free end
    let mut y = line.initial_state();
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.03 * (i as f64 * 0.9).sin();
    }
    let yp: Vec<f64> = (0..n).map(|i| 0.05 * (i as f64 * 1.7).cos()).collect();
    let pattern: HashSet<(usize, usize)> = line.jacobian_entries().into_iter().collect();
    let res = |y: &[f64], yp: &[f64]| {
        let mut r = vec![0.0; n];
        line.residual(0.1, y, yp, &mut r).unwrap();
        r
    };
    // the line's own Jacobian at c = 1 (∂F/∂y + ∂F/∂ẏ), against the differences below
    let mut jac = integrators::linalg::Matrix::zeros(n, &line.pattern());
    assert!(line.jacobian_into(0.1, &y, &yp, 1.0, &mut jac).unwrap());
    let mut fd = vec![vec![0.0; n]; n];
    let h = 1e-7;
    for col in 0..n {
        for (shift_y, shift_yp) in [(h, 0.0), (0.0, h)] {
            let (mut yy, mut yyp) = (y.clone(), yp.clone());
            yy[col] += shift_y;
            yyp[col] += shift_yp;
            let (r1, r0) = (res(&yy, &yyp), res(&y, &yp));
            for row in 0..n {
                fd[row][col] += (r1[row] - r0[row]) / h;
                if (r1[row] - r0[row]).abs() > 1e-12 {
                    assert!(
                        pattern.contains(&(row, col)),
                        "({row}, {col}) = {} missing: {} / {}",
                        (r1[row] - r0[row]) / h,
                        line.unknown_name(row),
                        line.unknown_name(col)
                    );
                }
            }
        }
    }
    for (row, fd_row) in fd.iter().enumerate() {
        let scale = fd_row.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for (col, &d) in fd_row.iter().enumerate() {
            assert!(
                (jac.get(row, col) - d).abs() < 1e-5 * scale,
                "({row}, {col}): own {} against differences {d}",
                jac.get(row, col)
            );
        }
    }
}

#[test]
fn scenario_keys_are_checked_by_name_and_kelvin_voigt_is_eta() {
    let bad: LineConfig =
        toml::from_str(r#"viscosity = { model = "maxwell", mu_m = -1.0, eta_m = 1.0 }"#).unwrap();
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("viscosity.mu_m"), "{e}");
    let bad: LineConfig = toml::from_str(
        r#"viscosity = { model = "standard_linear_solid", mu_m = 1.0, eta_m = 0.0 }"#,
    )
    .unwrap();
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("viscosity.eta_m"));
    assert!(
        toml::from_str::<LineConfig>(r#"viscosity = { model = "burgers", eta = 1.0 }"#).is_err()
    );
    let times = OutputTimes {
        series: vec![0.5, 1.0],
        profiles: vec![1.0],
    };
    let kv: LineConfig =
        toml::from_str("cells = 10\nK = 0.1\nviscosity = { model = \"kelvin_voigt\", eta = 0.4 }")
            .unwrap();
    let eta: LineConfig = toml::from_str("cells = 10\nK = 0.1\neta = 0.4").unwrap();
    let a = run_line(&kv, ModelKind::Discrete, None, &tight(), &times);
    let b = run_line(&eta, ModelKind::Discrete, None, &tight(), &times);
    assert!(a.error.is_none());
    assert_eq!(a.series.length, b.series.length);
    assert_eq!(a.profiles[0].stretch, b.profiles[0].stretch);
}
