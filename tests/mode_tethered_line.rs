//! A deformation mode from outside the library (`examples/tethered_line.rs`, compiled here as
//! a module: the same file a user writes) registered by one call and run from scenarios:
//! discrete and continuum against the exact steady state of the linearised problem, its
//! parameters validated by key, and the whole CLI path writing data and plots.

#[allow(dead_code)]
#[path = "../examples/tethered_line.rs"]
mod tethered_line;

use celltissue::observe::RunRecord;
use celltissue::scenario::{execute::run_spec, load_str};
use celltissue::StrainEnergy;
use std::path::Path;
use std::sync::Once;

fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(tethered_line::register);
}

const SCENARIO: &str = r#"
name = "tethered"
[output]
series = [0, 1, 300]
profiles = [300]
[model]
kind = "tethered_line"
models = ["discrete", "continuum"]
nodes = 80
cells = 20
K = 1.0
tether = 0.2
k1 = 0.001
[solver]
rtol = 1e-10
atol = 1e-12
"#;

fn run(text: &str) -> Vec<RunRecord> {
    register();
    let s = load_str(text, Path::new("tethered.toml"), &[]).unwrap();
    s.runs
        .iter()
        .map(|spec| {
            let rec = run_spec(spec);
            assert!(rec.error.is_none(), "{}: {:?}", rec.label, rec.error);
            rec
        })
        .collect()
}

/// Largest distance, relative to the end's displacement `k₁L₀`, of the steady boundary
/// displacements (recovered from the cell stretches) from the linearised discrete solution
/// `u_j = −k₁L₀ sinh(θj)/sinh(θn)`, `cosh θ = 1 + k_h h/(2E)`.
fn linear_theory_error(rec: &RunRecord, k1: f64) -> f64 {
    let p = rec.profiles.last().unwrap();
    assert_eq!(p.t, 300.0);
    let n = p.stretch.len();
    let (cells, tether) = (20.0, 0.2);
    let h = cells / n as f64;
    let k_h = tether * h; // per-boundary tether of a segment of length h (cell length 1)
    let e = celltissue::NeoHookean::new(1.0).unwrap().line(1.0).dsigma;
    let theta = (1.0 + k_h * h / (2.0 * e)).acosh();
    let u_end = -k1 * cells;
    let mut x = 0.0;
    let mut worst: f64 = 0.0;
    for (j, lambda) in p.stretch.iter().enumerate() {
        x += lambda * h;
        let reference = (j + 1) as f64 * h;
        let u_exact = u_end * (theta * (j + 1) as f64).sinh() / (theta * n as f64).sinh();
        worst = worst.max(((x - reference) - u_exact).abs());
    }
    worst / u_end.abs()
}

#[test]
fn a_registered_mode_reaches_the_exact_linear_steady_state_discrete_and_continuum() {
    let small = run(SCENARIO);
    let smaller = run(&SCENARIO.replace("k1 = 0.001", "k1 = 0.0005"));
    for (a, b) in small.iter().zip(&smaller) {
        let (e1, e2) = (linear_theory_error(a, 1e-3), linear_theory_error(b, 5e-4));
        println!(
            "{}: steady error vs linear theory {e1:.3e} (k1 = 1e-3), {e2:.3e} (5e-4), ratio {:.3}",
            a.label,
            e1 / e2
        );
        // the departure is the law's nonlinearity, O(k₁) relative: halving k₁ halves it
        assert!(e1 < 1e-2, "{}: {e1}", a.label);
        assert!(
            (e1 / e2 - 2.0).abs() < 0.1,
            "{}: ratio {}",
            a.label,
            e1 / e2
        );
        // the pulled end is prescribed: l(t) = L₀(1 − k₁(1 − e^{−t}))
        let l1 = a.series.length[1];
        assert!((l1 - 20.0 * (1.0 - 1e-3 * (1.0 - (-1f64).exp()))).abs() < 1e-12);
    }
    assert_eq!(
        small[1].profiles[0].stretch.len(),
        80,
        "continuum on `nodes` segments"
    );
}

#[test]
fn a_registered_modes_parameters_are_checked_by_key() {
    register();
    let err = |text: &str| load_str(text, Path::new("t.toml"), &[]).unwrap_err();
    let e = err(&SCENARIO.replace("tether = 0.2", "tether = -1"));
    assert_eq!(e.key_name(), Some("model.tether"), "{e}");
    assert!(e.to_string().contains("must be finite and >= 0"), "{e}");
    let e = err(&SCENARIO.replace("tether = 0.2", "tetherr = 0.2"));
    assert_eq!(e.key_name(), Some("model.tetherr"), "{e}");
    let e = err(&SCENARIO.replace("kind = \"tethered_line\"", "kind = \"tethered\""));
    assert_eq!(e.key_name(), Some("model.kind"));
    assert!(
        e.to_string().contains("line, sheet, shear, tethered_line"),
        "{e}"
    );
}

#[test]
fn a_registered_mode_runs_through_the_cli_with_outputs_and_plots() {
    register();
    let dir = std::env::temp_dir().join(format!("celltissue_tethered_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scenario = format!("{}/examples/tethered_line.toml", env!("CARGO_MANIFEST_DIR"));
    let out = dir.to_str().unwrap();
    let code = celltissue::cli::main_from(["celltissue", "run", &scenario, "--out", out]);
    assert_eq!(code, 0);
    for file in [
        "summary.json",
        "series_discrete_tether=0.1.csv",
        "profiles_continuum_tether=1.csv",
        "series_length.png",
        "series_max_tether_force.png",
        "profiles_stretch_tether=1.png",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["runs"].as_array().unwrap().len(), 6);
    assert_eq!(summary["runs"][0]["parameters"]["kind"], "tethered_line");
    let _ = std::fs::remove_dir_all(&dir);
}
