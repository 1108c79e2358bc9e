//! `celltissue list` shows every bundled scenario, every bundled scenario passes
//! `celltissue validate`, and the Chapter 2 scenarios run and meet independent references.

use celltissue::boundary::{Ramp, RightEnd};
use celltissue::line::build::{continuum, discrete};
use celltissue::line::static_solve::static_equilibrium;
use celltissue::observe::{ModelKind, Profile, RunRecord};
use celltissue::scenario::execute::run_spec;
use celltissue::scenario::{ModelConfig, RunSpec};
use celltissue::NeoHookean;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bundled() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v
}

#[test]
fn list_prints_every_bundled_scenario() {
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .arg("list")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let files = bundled();
    assert!(files.len() >= 6, "expected the Chapter 2 scenarios");
    for f in files {
        let table: toml::Table = toml::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
        let name = table["name"].as_str().unwrap();
        let line = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("`{name}` not listed:\n{stdout}"));
        if let Some(desc) = table.get("description").and_then(|d| d.as_str()) {
            assert!(line.contains(desc), "{line}");
        }
    }
}

#[test]
fn every_bundled_scenario_validates() {
    for f in bundled() {
        let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
            .arg("validate")
            .arg(&f)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {}",
            f.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(String::from_utf8_lossy(&out.stdout).contains("ok"));
    }
}

/// Largest |a − b| / |b| over two profiles.
fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

/// The static equilibrium of a run's line held at length `l` (same discretisation).
fn static_at(run: &RunSpec, l: f64) -> celltissue::line::static_solve::StaticSolution {
    let ModelConfig::Line(cfg) = &run.config else {
        panic!("{}: a line scenario", run.label)
    };
    let mut p = cfg.params(1e-8);
    p.right = RightEnd::Prescribed(Ramp::Constant(l));
    let nh = NeoHookean::new(1.0).unwrap();
    let line = match run.model {
        ModelKind::Discrete => discrete(nh, &p).unwrap(),
        ModelKind::Continuum => continuum(nh, &p, run.nodes.unwrap()).unwrap(),
    };
    static_equilibrium(&line, l).unwrap()
}

/// The profile at time `t`.
fn profile(rec: &RunRecord, t: f64) -> &Profile {
    rec.profiles.iter().find(|p| p.t == t).unwrap()
}

/// Every Chapter 2 scenario as shipped (Figs 2.5–2.10: discrete N = 100 and continuum, rtol
/// 1e-6) runs every sweep point, and each run meets a reference that does not come from the
/// code under test, to the accuracy contract's 10·rtol = 1e-5 in stretch and pressure:
/// - 2.5 (exponential ramp, uniform μ): for K = 1e-5 and 1e-2 (relaxed by t = 1000; K ≥ 1
///   relaxes on t ~ K l₀²/4 ≥ 2500) the uniform exact state λ = 0.9, p = 1/0.81;
/// - 2.6 (K = 1e-5, t = 20): the static equilibrium at the run's l(20), uniform and Gaussian;
/// - 2.7 (polynomial ramp, K = 0, uniform μ, any η): the exact uniform solution
///   λ = 1 − k₁s(t), p = (μ + 6ηk₁t(1 − t))/(1 − k₁s)² (docs/model.md §5.3) at every output time;
/// - 2.8 (Gaussian μ, K = 1e-5) and 2.9 (K = 0, η = 1e-5): quasi-static, so the profile at
///   t = 10 is the static equilibrium at l(10);
/// - 2.10 (active ring): the Ref extremes of docs/model.md §5.3 over x and t ∈ [0, 100] (discrete).
#[test]
fn chapter_2_scenarios_run_and_meet_their_references() {
    let tol = 1e-5;
    for fig in [5, 6, 7, 8, 9, 10] {
        let f = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/fig2_{fig}.toml"));
        let s = celltissue::scenario::load(&f, &[]).unwrap();
        assert_eq!(s.figure.as_deref(), Some(format!("2.{fig}").as_str()));
        let models: Vec<_> = s.runs.iter().map(|r| r.model).collect();
        assert!(models.contains(&ModelKind::Discrete) && models.contains(&ModelKind::Continuum));
        for run in &s.runs {
            let ModelConfig::Line(cfg) = &run.config else {
                panic!("fig2_{fig} is a line scenario")
            };
            assert_eq!(cfg.n_cells(), 100, "fig2_{fig}");
            let rec = run_spec(run);
            assert!(
                rec.error.is_none(),
                "fig2_{fig} {}: {:?}",
                run.label,
                rec.error
            );
            let sweep = run.sweep.as_ref().and_then(|w| w.value);
            let label = format!("fig2_{fig} {}", run.label);
            let mut worst: f64 = 0.0;
            match fig {
                5 if sweep.unwrap() <= 1e-2 => {
                    let p = profile(&rec, 1000.0);
                    worst = max_rel(&p.stretch, &vec![0.9; p.stretch.len()])
                        .max(max_rel(&p.pressure, &vec![1.0 / 0.81; p.pressure.len()]));
                }
                6 => {
                    let p = profile(&rec, 20.0);
                    let st = static_at(run, *rec.series.length.last().unwrap());
                    worst = max_rel(&p.stretch, &st.lambda).max(max_rel(&p.pressure, &st.pressure));
                }
                7 => {
                    // stretch at every output time; pressure after the ramp (t ≥ 1, p = μ/λ²)
                    let eta = sweep.unwrap();
                    let mut worst_p_ramp: f64 = 0.0;
                    for (k, &t) in rec.series.t.iter().enumerate() {
                        let tau = t.min(1.0);
                        let sv = 3.0 * tau * tau - 2.0 * tau.powi(3);
                        let lam = 1.0 - 0.1 * sv;
                        let visc = if t < 1.0 {
                            6.0 * eta * 0.1 * t * (1.0 - t)
                        } else {
                            0.0
                        };
                        let p = (1.0 + visc) / (lam * lam);
                        let e = |v: f64, r: f64| ((v - r) / r).abs();
                        worst = worst
                            .max(e(rec.series.min_stretch[k], lam))
                            .max(e(rec.series.max_stretch[k], lam));
                        let ep =
                            e(rec.series.max_pressure[k], p).max(e(rec.series.min_pressure[k], p));
                        if t >= 1.0 {
                            // p = μ/λ²
                            assert!(ep < tol, "{label}: p at t = {t}: {ep:e}");
                        } else {
                            worst_p_ramp = worst_p_ramp.max(ep);
                        }
                    }
                    // during the ramp p carries η·α̇, read from the rates solved at each
                    // output (measured up to 2.7e-7 at η = 10)
                    println!("{label}: pressure during the ramp off by up to {worst_p_ramp:.2e}");
                    assert!(worst_p_ramp < tol, "{label}: {worst_p_ramp:e}");
                }
                8 | 9
                    if (fig == 8 && sweep.unwrap() == 1e-5)
                        || (fig == 9 && sweep.unwrap() == 1e-5) =>
                {
                    let p = profile(&rec, 10.0);
                    let k = rec.series.t.iter().position(|&t| t == 10.0).unwrap();
                    let st = static_at(run, rec.series.length[k]);
                    worst = max_rel(&p.stretch, &st.lambda).max(max_rel(&p.pressure, &st.pressure));
                }
                10 if run.model == ModelKind::Discrete => {
                    let refs = [
                        (1e-5, [1.8223, 0.6220, 1.2680, 0.7408]),
                        (1e-2, [1.8214, 0.6222, 1.2677, 0.7410]),
                        (1.0, [1.2288, 0.8437, 1.0887, 0.9021]),
                        (10.0, [1.0250, 0.9764, 1.0120, 0.9877]),
                    ];
                    let r = refs.iter().find(|(k, _)| *k == sweep.unwrap()).unwrap().1;
                    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
                    let got = [
                        max(&rec.series.max_pressure),
                        min(&rec.series.min_pressure),
                        max(&rec.series.max_stretch),
                        min(&rec.series.min_stretch),
                    ];
                    println!("{label}: extremes {got:.5?} (Ref {r:?})");
                    for (g, r) in got.iter().zip(r) {
                        // the Ref is quoted to 4 decimals; the output series samples t every 0.25
                        assert!((g - r).abs() <= 1e-4, "{label}: {got:?} vs Ref {r}");
                    }
                    continue;
                }
                _ => {
                    println!("{label}: runs (no closed-form reference for this point)");
                    continue;
                }
            }
            // under the cell-unit contract (docs/model.md §8.1) Fig 2.7's uniform stretch is
            // held to 10·rtol like the rest (measured up to 5.0e-7, η = 10)
            println!("{label}: largest relative error {worst:.2e} (allowed {tol:.0e})");
            assert!(worst < tol, "{label}: {worst:e}");
        }
    }
}

#[test]
fn help_and_bad_subcommand() {
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .arg("--help")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .arg("frobnicate")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_bundled_name_runs_from_any_directory_and_an_unknown_name_lists_the_catalogue() {
    let empty = std::env::temp_dir().join(format!("ct_catalogue_{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .args(["validate", "fig2_7"])
        .current_dir(&empty)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .args(["validate", "fig9_9"])
        .current_dir(&empty)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("`fig9_9` is neither a scenario file nor a bundled scenario")
            && err.contains("fig2_5"),
        "{err}"
    );
    std::fs::remove_dir_all(&empty).unwrap();
}
