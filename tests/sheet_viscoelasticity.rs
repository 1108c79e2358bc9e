//! Maxwell and standard-linear-solid cells in the uniaxial sheet (docs/viscoelasticity.md, "The
//! sheet"): viscous stretches `a₁, a₂` per cell, branch stresses `μ_m/μ · σᵢᵢ(λ₁/a₁, λ₂/a₂)`,
//! isochoric flow `ȧᵢ/aᵢ = 2 dev(σ_m)ᵢᵢ/η_m` (σ₃₃ = 0).
//!
//! * small-strain ramp-and-hold at `K = 0` (free top: uniaxial stress in the plane) against the
//!   linear solution `σ₁₁ = 3μ ε·[SLS] + 3μ_m ∫₀ᵗ ε'(u) e^{−(t−u)/τ} du`, `τ = η_m/(4μ_m)`;
//!   the discrepancy shrinks in proportion to the strain (the law's nonlinearity);
//! * the fitted relaxation time is `η_m/(4μ_m)`, the same as on the line;
//! * SLS → elastic as `μ_m → 0`, the difference linear in `μ_m`;
//! * a Maxwell sheet with drag relaxes to zero stress at finite strain (`aᵢ → λᵢ`);
//! * the continuum converges under grid refinement with a branch;
//! * the scenario keys are parsed and checked by name.

use crate::common::{maxwell_ramp_stress, poly_strain, sheet_solver};
use celltissue::cell::ViscosityModel;
use celltissue::observe::{ModelKind, Profile, RunRecord};
use celltissue::runner::OutputTimes;
use celltissue::sheet::{run_sheet, Ramp, SheetConfig};
use celltissue::NeoHookean;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn sls(mu_m: f64, eta_m: f64) -> Option<ViscosityModel> {
    Some(ViscosityModel::StandardLinearSolid { mu_m, eta_m })
}

fn maxwell(mu_m: f64, eta_m: f64) -> Option<ViscosityModel> {
    Some(ViscosityModel::Maxwell { mu_m, eta_m })
}

/// A `cells × cells` sheet without drag on the polynomial ramp of length `t_r`.
fn ramp_sheet(cells: usize, k1: f64, t_r: f64, viscosity: Option<ViscosityModel>) -> SheetConfig {
    SheetConfig {
        cells_x: cells,
        cells_y: cells,
        drag: Some(0.0),
        k1,
        ramp: Ramp::Polynomial { t_ramp: t_r },
        viscosity,
        ..Default::default()
    }
}

/// The discrete runs' relative tolerance.
const RTOL: f64 = 1e-10;

/// The discrete run with per-cell profiles at `times`.
fn run(cfg: &SheetConfig, times: &[f64]) -> RunRecord {
    let out = OutputTimes {
        series: times.to_vec(),
        profiles: times.to_vec(),
    };
    let rec = run_sheet(
        cfg,
        &nh(),
        ModelKind::Discrete,
        None,
        &sheet_solver(RTOL, 1e-13),
        &out,
    )
    .unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    assert_eq!(rec.profiles.len(), times.len());
    rec
}

fn column<'a>(p: &'a Profile, key: &str) -> &'a [f64] {
    &p.extra[key]
}

/// Max over the output times of `|σ₁₁ − σ_lin| / max|σ_lin|` for a ramp of `k1`; checks on
/// the way that every cell carries the same stress and `σ₂₂` vanishes.
fn ramp_and_hold_error(k1: f64, standard: bool) -> f64 {
    let (mu_m, eta_m, t_r) = (0.5, 1.0, 1.0);
    let tau = eta_m / (4.0 * mu_m);
    let v = if standard {
        sls(mu_m, eta_m)
    } else {
        maxwell(mu_m, eta_m)
    };
    let times: Vec<f64> = (1..=40).map(|i| i as f64 * 0.1).collect();
    let rec = run(&ramp_sheet(3, k1, t_r, v), &times);
    let lin: Vec<f64> = times
        .iter()
        .map(|&t| {
            let elastic = if standard {
                3.0 * poly_strain(t, k1, t_r)
            } else {
                0.0
            };
            elastic + maxwell_ramp_stress(t, k1, t_r, 3.0 * mu_m, tau)
        })
        .collect();
    let peak = lin.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // By symmetry every cell carries the same stress, so any spread between cells is numerical
    // error: bounded by the run's rtol (1e-10) in stretch, through the small-strain modulus
    // (3(μ + μ_m) for the SLS, 3μ_m for Maxwell). Every output is projected onto the algebraic constraints, the last one too
    // (the step's own Newton iterate, before that projection, differed by 22·rtol in stretch);
    // measured: at most 7e-10 of the peak stress, 0.005·rtol in stretch.
    let modulus = 3.0 * if standard { 1.0 + mu_m } else { mu_m };
    let spread_bound = RTOL * modulus;
    rec.profiles
        .iter()
        .zip(&lin)
        .map(|(p, l)| {
            let s11 = column(p, "sigma11");
            let spread = s11.iter().map(|v| (v - s11[0]).abs()).fold(0.0, f64::max);
            assert!(spread <= spread_bound, "t = {}: spread {spread:e}", p.t);
            let s22 = column(p, "sigma22")
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(s22 <= spread_bound, "t = {}: σ₂₂ {s22:e}", p.t);
            (s11[0] - l).abs() / peak
        })
        .fold(0.0, f64::max)
}

#[test]
fn small_strain_ramp_and_hold_matches_the_linear_solution() {
    for standard in [false, true] {
        let e3 = ramp_and_hold_error(1e-3, standard);
        let e4 = ramp_and_hold_error(1e-4, standard);
        println!("sls={standard}: max |σ₁₁ − σ_lin|/peak at k₁ = 1e-3, 1e-4: {e3:.3e}, {e4:.3e}");
        assert!(e4 < 1e-4, "sls={standard}: {e4}");
        // the discrepancy is the nonlinearity of the finite-strain law: O(k₁)
        let ratio = e3 / e4;
        assert!(
            (7.0..14.0).contains(&ratio),
            "sls={standard}: ratio {ratio}"
        );
    }
}

#[test]
fn relaxation_time_is_the_branch_viscosity_over_four_mu_m() {
    let (mu_m, t_r, k1) = (0.5, 0.2, 1e-4);
    for eta_m in [0.5, 1.0, 2.0, 4.0] {
        let tau = eta_m / (4.0 * mu_m);
        let (t1, t2) = (t_r + tau, t_r + 3.0 * tau);
        let rec = run(&ramp_sheet(2, k1, t_r, maxwell(mu_m, eta_m)), &[t1, t2]);
        let s = [0, 1].map(|i| column(&rec.profiles[i], "sigma11")[0]);
        let fit = (t2 - t1) / (s[0] / s[1]).ln();
        println!("η_m = {eta_m}: τ fitted {fit:.6}, η_m/(4μ_m) = {tau}");
        assert!(
            (fit / tau - 1.0).abs() < 1e-3,
            "η_m = {eta_m}: {fit} vs {tau}"
        );
    }
}

/// Largest difference of any cell's `λ₁`, `λ₂` or pressure between two runs at every time.
fn max_difference(a: &RunRecord, b: &RunRecord) -> f64 {
    let mut d = 0.0f64;
    for (p, q) in a.profiles.iter().zip(&b.profiles) {
        let cols = [
            (&p.stretch[..], &q.stretch[..]),
            (&p.pressure[..], &q.pressure[..]),
            (column(p, "stretch_y"), column(q, "stretch_y")),
        ];
        for (u, v) in cols {
            for (x, y) in u.iter().zip(v) {
                d = d.max((x - y).abs());
            }
        }
    }
    d
}

/// A 5 × 5 sheet with the thesis drag (`K = ½`) and exponential ramp, `k₁ = 0.2`.
fn dragged(viscosity: Option<ViscosityModel>) -> SheetConfig {
    SheetConfig {
        cells_x: 5,
        cells_y: 5,
        k1: 0.2,
        viscosity,
        ..Default::default()
    }
}

#[test]
fn standard_linear_solid_tends_to_the_elastic_sheet_as_the_branch_modulus_vanishes() {
    let times = [0.5, 1.0, 2.0, 5.0];
    let elastic = run(&dragged(None), &times);
    let d0 = max_difference(&run(&dragged(sls(0.0, 1.0)), &times), &elastic);
    let d2 = max_difference(&run(&dragged(sls(1e-2, 1.0)), &times), &elastic);
    let d3 = max_difference(&run(&dragged(sls(1e-3, 1.0)), &times), &elastic);
    println!("SLS − elastic at μ_m = 0, 1e-2, 1e-3: {d0:.2e}, {d2:.2e}, {d3:.2e}");
    assert!(d0 < 1e-8, "{d0}");
    assert!(d2 > 1e-4, "the branch must act: {d2}");
    // linear in μ_m
    assert!((8.0..12.0).contains(&(d2 / d3)), "ratio {}", d2 / d3);
}

#[test]
fn maxwell_sheet_relaxes_to_zero_stress_at_finite_strain() {
    let (mu_m, eta_m) = (1.0, 1.0); // τ = 0.25
    let rec = run(&dragged(maxwell(mu_m, eta_m)), &[0.5, 60.0]);
    let peak = column(&rec.profiles[0], "sigma11")
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let last = &rec.profiles[1];
    let mut worst_stress = 0.0f64;
    let mut worst_flow = 0.0f64;
    for i in 0..last.stretch.len() {
        worst_stress = worst_stress
            .max(column(last, "sigma11")[i].abs())
            .max(column(last, "sigma22")[i].abs());
        worst_flow = worst_flow
            .max((column(last, "viscous_x")[i] - last.stretch[i]).abs())
            .max((column(last, "viscous_y")[i] - column(last, "stretch_y")[i]).abs());
    }
    println!(
        "Maxwell sheet: peak |σ₁₁| {peak:.3} at t = 0.5; at t = 60 max |σ| {worst_stress:.2e}, \
         max |a − λ| {worst_flow:.2e}, λ₁ ∈ [{:.4}, {:.4}]",
        last.stretch.iter().cloned().fold(f64::INFINITY, f64::min),
        last.stretch.iter().cloned().fold(0.0, f64::max)
    );
    assert!(peak > 0.05, "{peak}");
    assert!(worst_stress < 1e-8, "{worst_stress}");
    assert!(worst_flow < 1e-8, "{worst_flow}");
    // the strain stays: the cells are shortened, not back at rest
    assert!(last.stretch.iter().all(|&l| l < 0.99));
}

#[test]
fn continuum_with_a_branch_converges_under_refinement() {
    let cfg = dragged(sls(0.5, 1.0));
    let out = OutputTimes::at(&[1.0]);
    let vals: Vec<f64> = [5, 10, 20, 40]
        .iter()
        .map(|&n| {
            let r = run_sheet(
                &cfg,
                &nh(),
                ModelKind::Continuum,
                Some((n, n)),
                &sheet_solver(RTOL, 1e-13),
                &out,
            )
            .unwrap();
            assert!(r.error.is_none(), "{:?}", r.error);
            r.series.extra["mean_height"][0]
        })
        .collect();
    let d: Vec<f64> = vals.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    println!("SLS sheet: mean H(1) on 5², 10², 20², 40²: {vals:?}, differences {d:?}");
    assert!(d[1] < 0.6 * d[0] && d[2] < 0.6 * d[1], "{vals:?}");
}

#[test]
fn scenario_keys_are_parsed_and_checked_by_name() {
    let cfg: SheetConfig =
        toml::from_str("viscosity = { model = \"maxwell\", mu_m = 1.0, eta_m = 4.0 }").unwrap();
    assert!(cfg.validate().is_ok());
    let bad: SheetConfig = toml::from_str(
        "viscosity = { model = \"standard_linear_solid\", mu_m = 1.0, eta_m = -1.0 }",
    )
    .unwrap();
    let e = bad.validate().unwrap_err();
    assert_eq!(e.key, "viscosity.eta_m");
    assert!(e.to_string().contains("> 0"), "{e}");
}
