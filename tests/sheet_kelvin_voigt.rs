//! Kelvin–Voigt cells in the uniaxial sheet (docs/viscoelasticity.md, "Kelvin–Voigt in the
//! sheet"): each principal direction carries `η α̇ᵢ`, the free top `σ₃₃ = 0` fixes the pressure,
//! so `σᵢᵢ += η(α̇ᵢ − α̇₃)` and `p += η α̇₃`.
//!
//! * a periodic single row (`λ₂ ≡ 1`) is the viscous line of Ch. 2, run by the line's own
//!   code: series agree to the solvers' tolerance;
//! * a drag-free sheet under a finite ramp is in homogeneous uniaxial stress with
//!   `λ₂ = λ₃ = λ₁^{-1/2}` and `σ₁₁ = μ(λ₁² − λ₁⁻¹) + η λ̇₁ (1 + ½ λ₁^{-3/2})` exactly;
//! * the viscosity changes the path, not the end: the relaxed state is the elastic one;
//! * the continuum converges under grid refinement with viscosity;
//! * the scenario key is parsed and checked by name.

use crate::common::sheet_solver;
use celltissue::cell::ViscosityModel;
use celltissue::line::{run_line, LineConfig};
use celltissue::observe::{ModelKind, RunRecord};
use celltissue::runner::OutputTimes;
use celltissue::sheet::{run_sheet, Ramp, SheetConfig, TopBoundary};
use celltissue::NeoHookean;

fn nh() -> NeoHookean {
    NeoHookean::new(1.0).unwrap()
}

fn kv(eta: f64) -> Option<ViscosityModel> {
    Some(ViscosityModel::KelvinVoigt { eta })
}

fn run(
    cfg: &SheetConfig,
    model: ModelKind,
    grid: Option<(usize, usize)>,
    out: &OutputTimes,
) -> RunRecord {
    let rec = run_sheet(cfg, &nh(), model, grid, &sheet_solver(1e-10, 1e-13), out).unwrap();
    assert!(rec.error.is_none(), "{:?}", rec.error);
    rec
}

#[test]
fn periodic_single_row_is_the_viscous_line() {
    // λ₂ ≡ 1, so α₃ = 1/λ₁ and σ₁₁ = μ(λ₁² − λ₁⁻²) + η λ̇₁(1 + λ₁⁻²), p = μλ₁⁻² − η λ̇₁ λ₁⁻²:
    // the line's stress and pressure with its free lateral direction played by the height
    // (β₀ = γ₀ = 1, so the face areas agree too).
    let times = [0.2, 0.5, 1.0, 2.0, 5.0];
    let out = OutputTimes::at(&times);
    let sheet = run(
        &SheetConfig {
            cells_x: 20,
            cells_y: 1,
            drag: Some(1.0),
            top: TopBoundary::Periodic,
            viscosity: kv(0.5),
            ..Default::default()
        },
        ModelKind::Discrete,
        None,
        &out,
    );
    let line_cfg: LineConfig = toml::from_str(
        "cells = 20\nK = 1.0\neta = 0.5\nk1 = 0.1\nt_ramp = 1.0\nramp = \"exponential\"",
    )
    .unwrap();
    let line = run_line(
        &line_cfg,
        ModelKind::Discrete,
        None,
        &sheet_solver(1e-10, 1e-13),
        &out,
    );
    assert!(line.error.is_none(), "{:?}", line.error);
    let elastic = run(
        &SheetConfig {
            cells_x: 20,
            cells_y: 1,
            drag: Some(1.0),
            top: TopBoundary::Periodic,
            ..Default::default()
        },
        ModelKind::Discrete,
        None,
        &out,
    );
    let mut worst = 0.0f64;
    for i in 0..times.len() {
        for (a, b, c) in [
            (
                &sheet.series.max_pressure,
                &line.series.max_pressure,
                &elastic.series.max_pressure,
            ),
            (
                &sheet.series.min_stretch,
                &line.series.min_stretch,
                &elastic.series.min_stretch,
            ),
        ] {
            worst = worst.max((a[i] - b[i]).abs() / b[i].abs());
            // the viscosity matters: the elastic sheet is far from both
            assert!(
                (c[i] - b[i]).abs() > 1e3 * (a[i] - b[i]).abs(),
                "t = {}",
                times[i]
            );
        }
    }
    eprintln!("periodic KV sheet vs KV line: worst relative difference {worst:e}");
    assert!(worst < 1e-7, "{worst:e}");
}

#[test]
fn drag_free_sheet_follows_the_exact_finite_strain_solution() {
    // Without drag every cell is in uniaxial stress, σ₂₂ = σ₃₃ = 0, and directions 2 and 3 are
    // alike (both free, both carrying η α̇ᵢ), so λ₂ = λ₃ = λ₁^{-1/2} at every instant, viscous
    // or not; then σ₁₁ = μ(λ₁² − λ₁⁻¹) + η λ̇₁ (1 + ½ λ₁^{-3/2}) exactly (small strain:
    // 3μ(ε + t_k ε̇), t_k = η/2μ). A 20 % shortening on the polynomial ramp (t_r = 1), held after.
    let (k1, eta) = (0.2, 0.8);
    let ramp = Ramp::Polynomial { t_ramp: 1.0 };
    let times: Vec<f64> = (1..=15).map(|i| i as f64 * 0.1).collect();
    let out = OutputTimes {
        series: times.clone(),
        profiles: times.clone(),
    };
    let rec = run(
        &SheetConfig {
            cells_x: 3,
            cells_y: 2,
            drag: Some(0.0),
            k1,
            ramp,
            viscosity: kv(eta),
            ..Default::default()
        },
        ModelKind::Discrete,
        None,
        &out,
    );
    let (mut worst_l2, mut worst_s, mut viscous_peak) = (0.0f64, 0.0f64, 0.0f64);
    for p in &rec.profiles {
        let l1 = ramp.length(1.0, k1, p.t);
        let l1dot = ramp.length_rate(1.0, k1, p.t);
        let viscous = eta * l1dot * (1.0 + 0.5 * l1.powf(-1.5));
        let s11 = (l1 * l1 - 1.0 / l1) + viscous;
        viscous_peak = viscous_peak.max(viscous.abs());
        for (a, s) in p.extra["stretch_y"].iter().zip(&p.extra["sigma11"]) {
            worst_l2 = worst_l2.max((a - l1.powf(-0.5)).abs());
            worst_s = worst_s.max((s - s11).abs());
        }
    }
    // at mid-ramp the viscous stress (−0.38) exceeds the elastic one (−0.30)
    assert!(viscous_peak > 0.2, "{viscous_peak}");
    eprintln!("drag-free KV sheet vs exact: |Δλ₂| ≤ {worst_l2:e}, |Δσ₁₁| ≤ {worst_s:e}");
    // rtol 1e-10; the stress holds the rates, which come from the solver's interpolant, one
    // order less accurate than the state: measured |Δλ₂| 1.7e-9, |Δσ₁₁| 8.5e-9 (2.7e-10 at
    // the ramp's end t = 1, a breakpoint: 8e-6 when the run stepped across it)
    assert!(
        worst_l2 < 1e-8 && worst_s < 5e-8,
        "{worst_l2:e} {worst_s:e}"
    );
}

#[test]
fn viscosity_changes_the_path_not_the_relaxed_state() {
    let out = OutputTimes::at(&[1.0, 200.0]);
    let base = SheetConfig {
        cells_x: 6,
        cells_y: 4,
        ..Default::default()
    };
    let elastic = run(&base, ModelKind::Discrete, None, &out);
    let viscous = run(
        &SheetConfig {
            viscosity: kv(2.0),
            ..base
        },
        ModelKind::Discrete,
        None,
        &out,
    );
    let h = |r: &RunRecord, i: usize| r.series.extra["mean_height"][i];
    assert!((h(&elastic, 0) - h(&viscous, 0)).abs() > 1e-3);
    for key in ["max_pressure", "min_stretch"] {
        let (e, v) = match key {
            "max_pressure" => (&elastic.series.max_pressure, &viscous.series.max_pressure),
            _ => (&elastic.series.min_stretch, &viscous.series.min_stretch),
        };
        assert!((e[1] - v[1]).abs() < 1e-8, "{key}: {} vs {}", e[1], v[1]);
    }
    assert!((h(&elastic, 1) - h(&viscous, 1)).abs() < 1e-8);
}

#[test]
fn continuum_with_viscosity_converges_under_refinement() {
    let cfg = SheetConfig {
        viscosity: kv(1.0),
        ..Default::default()
    };
    let out = OutputTimes::at(&[1.0]);
    let vals: Vec<f64> = [10, 20, 40]
        .iter()
        .map(|&n| {
            run(&cfg, ModelKind::Continuum, Some((n, n)), &out)
                .series
                .extra["mean_height"][0]
        })
        .collect();
    let d: Vec<f64> = vals.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    eprintln!("KV sheet mean H(1) on 10², 20², 40²: {vals:?}, differences {d:?}");
    assert!(d[1] < 0.6 * d[0], "{vals:?}");
}

#[test]
fn the_scenario_key_is_parsed_and_checked_by_name() {
    let cfg: SheetConfig =
        toml::from_str("viscosity = { model = \"kelvin_voigt\", eta = 1.5 }").unwrap();
    assert!(cfg.validate().is_ok());
    assert_eq!(cfg.params().eta, 1.5);
    let bad: SheetConfig =
        toml::from_str("viscosity = { model = \"kelvin_voigt\", eta = -1.0 }").unwrap();
    let e = bad.validate().unwrap_err();
    assert_eq!(e.key, "viscosity.eta");
    assert!(e.to_string().contains(">= 0"), "{e}");
}
