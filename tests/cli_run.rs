//! The built `celltissue` binary end to end on a small scenario (10 cells, t ≤ 2): outputs have
//! the summary.json schema, no NaN, non-trivial PNGs; `--set` overrides reach the run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SMALL: &str = r#"
name = "small"
description = "10 cells, K sweep, t <= 2"
figure = "2.5"
[output]
series = { start = 0, stop = 2, count = 21 }
profiles = [0, 1, 2]
[model]
kind = "line"
models = ["discrete", "continuum"]
nodes = 11
cells = 10
K = 1.0
[sweep]
parameter = "K"
values = [0.1, 1]
[plots]
position = true
rectangles = true
"#;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_celltissue"))
}

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(dir: &Path, extra: &[&str]) -> Output {
    let scenario = dir.join("small.toml");
    std::fs::write(&scenario, SMALL).unwrap();
    bin()
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(dir.join("out"))
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn run_writes_summary_csv_and_plots() {
    let dir = tmp("cli_run_ok");
    let out = run(&dir, &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let text = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
    assert!(
        !text.contains("NaN") && !text.contains("null"),
        "non-finite value written"
    );
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["scenario"], "small");
    let runs = v["runs"].as_array().unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(
        labels,
        [
            "discrete K=0.1",
            "continuum K=0.1",
            "discrete K=1",
            "continuum K=1"
        ]
    );
    for r in runs {
        assert!(r.get("error").is_none(), "{r}");
        assert!(["discrete", "continuum"].contains(&r["model"].as_str().unwrap()));
        let s = &r["series"];
        for key in [
            "t",
            "length",
            "max_pressure",
            "min_pressure",
            "max_stretch",
            "min_stretch",
        ] {
            assert_eq!(s[key].as_array().unwrap().len(), 21, "series.{key}");
        }
        // the prescribed end: l(2) = 10 (1 - 0.1 + 0.1 e^-2)
        let l_end = s["length"][20].as_f64().unwrap();
        assert!(
            (l_end - 10.0 * (0.9 + 0.1 * (-2.0f64).exp())).abs() < 1e-6,
            "{l_end}"
        );
        // profiles are in the run's .npz, summary.json names their times
        assert_eq!(r["profile_times"], serde_json::json!([0.0, 1.0, 2.0]));
        let npz = dir.join("out").join(r["arrays"].as_str().unwrap());
        assert!(npz.exists(), "{}", npz.display());
        for key in ["steps", "residual_calls", "jacobians", "wall_seconds"] {
            assert!(r["stats"][key].is_number(), "stats.{key}");
        }
        assert!(r["stats"]["steps"].as_u64().unwrap() > 0);
        assert_eq!(r["parameters"]["cells"], 10);
    }
    for name in [
        "series_discrete_K=1.csv",
        "profiles_continuum_K=0.1.csv",
        "scenario.toml",
    ] {
        assert!(dir.join("out").join(name).exists(), "{name}");
    }
    for name in [
        "series_max_pressure.png",
        "series_min_stretch.png",
        "profiles_pressure_K=1.png",
        "profiles_stretch_K=0.1.png",
        "profiles_position_K=1.png",
        "sweep_pressure.png",
        "sweep_stretch.png",
        "cells_discrete_K=1.png",
    ] {
        let bytes = std::fs::read(dir.join("out").join(name)).unwrap_or_else(|_| panic!("{name}"));
        assert_eq!(&bytes[1..4], b"PNG");
        assert!(bytes.len() > 5_000, "{name}: {} bytes", bytes.len());
    }
}

#[test]
fn set_overrides_reach_the_run() {
    let dir = tmp("cli_run_set");
    let out = run(
        &dir,
        &[
            "--set",
            "model.models=[\"discrete\"]",
            "--set",
            "sweep.values=[0.5]",
            "--set",
            "solver.method=radau",
            "-q",
        ],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 1);
    assert_eq!(runs[0]["label"], "discrete K=0.5");
    assert_eq!(runs[0]["parameters"]["solver"]["method"], "radau");
    assert_eq!(runs[0]["parameters"]["K"], 0.5);
}

/// Runs `text` as a scenario file; returns the parsed summary.json (asserting exit code 0).
fn run_text(name: &str, text: &str) -> (PathBuf, serde_json::Value) {
    let (dir, v, _) = run_text_stderr(name, text);
    (dir, v)
}

/// [`run_text`], also returning what the run printed on stderr (its warnings).
fn run_text_stderr(name: &str, text: &str) -> (PathBuf, serde_json::Value, String) {
    let dir = tmp(name);
    let file = dir.join("s.toml");
    std::fs::write(&file, text).unwrap();
    let out = bin()
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("-q")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let v = serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
        .unwrap();
    (dir.join("out"), v, stderr)
}

#[test]
fn sheet_and_shear_scenarios_run() {
    let (dir, v) = run_text(
        "cli_run_sheet",
        r#"
name = "sheet"
[output]
series = [0, 1, 2]
profiles = [2]
[model]
kind = "sheet"
models = ["discrete", "continuum"]
nodes = [6, 4]
cells_x = 4
cells_y = 3
"#,
    );
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for r in runs {
        assert!(r.get("error").is_none(), "{r}");
        for key in [
            "mean_pressure",
            "mean_height",
            "mean_stretch_z_over_y",
            "boundary_mismatch_mean",
        ] {
            assert_eq!(
                r["series"][key].as_array().map(|a| a.len()),
                Some(3),
                "{key}"
            );
        }
        assert_eq!(r["parameters"]["law"]["law"], "neo_hookean");
    }
    assert!(dir.join("series_mean_pressure.png").exists());
    let (_, v) = run_text(
        "cli_run_shear",
        r#"
name = "shear"
[output]
series = [0, 1, 2]
[model]
kind = "shear"
nodes = 8
cells = 4
force = 1.0
"#,
    );
    for r in v["runs"].as_array().unwrap() {
        assert!(r.get("error").is_none(), "{r}");
        let top = r["series"]["top_displacement"].as_array().unwrap();
        assert_eq!(top.len(), 3);
        assert!(top[2].as_f64().unwrap() > top[1].as_f64().unwrap());
    }
}

/// A shear column's plots are named for what they hold: its records keep tan θ
/// in the stretch fields and the top displacement in `length`, its files and titles do not.
#[test]
fn shear_plots_are_named_tan_theta_and_top_displacement() {
    let (dir, _) = run_text(
        "cli_run_shear_names",
        r#"
name = "shear"
[output]
series = [0, 1, 2]
profiles = [2]
[model]
kind = "shear"
nodes = 8
cells = 4
[plots]
histories = true
sweep_profiles = [2]
[sweep]
parameter = "force"
values = [0.5, 1.0]
"#,
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    names.sort();
    for want in [
        "series_min_tan_theta.png",
        "series_top_displacement.png",
        "profiles_tan_theta_force=0.5.png",
        "histories_tan_theta_force=1.png",
        "sweep_tan_theta.png",
        "sweep_top_displacement.png",
        "sweep_profiles_tan_theta_t=2.png",
    ] {
        assert!(names.iter().any(|n| n == want), "{want} not in {names:?}");
    }
    assert!(
        !names
            .iter()
            .any(|n| n.contains("stretch") || n.contains("length")),
        "{names:?}"
    );
}

/// `series_cells.png` is drawn where the number of cells changes, not for a tissue that never
/// divides (where a continuum's count is the tissue's N, not its segments: it was drawn as
/// 101 "cells" beside the discrete 100 on Fig 2.5).
#[test]
fn the_number_of_cells_is_plotted_only_where_cells_divide() {
    let (dir, v) = run_text(
        "cli_run_cells_fixed",
        r#"
name = "fixed"
[output]
series = [0, 0.5, 1]
[model]
kind = "line"
cells = 20
nodes = 21
"#,
    );
    assert!(!dir.join("series_cells.png").exists());
    for r in v["runs"].as_array().unwrap() {
        assert_eq!(
            r["series"]["cells"][2].as_f64(),
            Some(20.0),
            "{}",
            r["label"]
        );
    }
    let (dir, v) = run_text(
        "cli_run_cells_dividing",
        r#"
name = "dividing"
[output]
series = { start = 0, stop = 3, count = 7 }
[model]
kind = "line"
models = ["discrete"]
cells = 20
right_end = "free"
K = 1e-5
growth = { sigma0 = 0.1 }
division = { rule = "area" }
"#,
    );
    assert!(v["runs"][0]["series"]["cells"][6].as_f64().unwrap() > 20.0);
    assert!(dir.join("series_cells.png").exists());
}

/// A log sweep axis cannot place a non-positive swept value: the run says which it leaves out
/// of the sweep plots instead of dropping them silently.
#[test]
fn a_log_sweep_axis_names_the_values_it_leaves_out() {
    let (dir, _, stderr) = run_text_stderr(
        "cli_run_log_sweep",
        r#"
name = "lg"
[output]
series = [0, 0.5, 1]
profiles = [1]
[model]
kind = "line"
cells = 10
K = 0.1
[plots]
sweep_axis = "log"
[sweep]
parameter = "k1"
values = [-0.1, 0.1, 0.2]
"#,
    );
    assert!(
        stderr.contains("k1 = -0.1 not positive, left out of the sweep_*.png plots"),
        "{stderr}"
    );
    assert!(dir.join("sweep_stretch.png").exists());
}

/// `solver.linear_solver = "iterative"` reaches a sheet run (Krylov iterations are counted,
/// the choice is recorded in the summary) and gives the direct solver's answer: both runs are
/// BDF at rtol 1e-8, so they agree to a small multiple of their own global errors.
#[test]
fn iterative_linear_solver_from_the_scenario_matches_direct() {
    let text = |linear: &str| {
        format!(
            r#"
name = "sheet"
[output]
series = [0, 0.5, 1, 2, 5]
[model]
kind = "sheet"
models = ["discrete"]
cells_x = 12
cells_y = 8
[solver]
rtol = 1e-8
atol = 1e-10
linear_solver = "{linear}"
"#
        )
    };
    let (_, direct) = run_text("cli_run_sheet_direct", &text("direct"));
    let (_, iter) = run_text("cli_run_sheet_iterative", &text("iterative"));
    let (d, i) = (&direct["runs"][0], &iter["runs"][0]);
    assert!(d.get("error").is_none() && i.get("error").is_none());
    // (counters that stayed 0 may be left out of the summary)
    assert_eq!(d["stats"]["krylov_iterations"].as_f64().unwrap_or(0.0), 0.0);
    assert!(i["stats"]["krylov_iterations"].as_f64().unwrap() > 0.0);
    assert_eq!(
        i["parameters"]["solver"]["linear_solver"]["kind"],
        "iterative"
    );
    assert_eq!(d["parameters"]["solver"]["linear_solver"], "direct");
    for key in ["max_pressure", "mean_height"] {
        let (a, b) = (
            d["series"][key].as_array().unwrap(),
            i["series"][key].as_array().unwrap(),
        );
        for (x, y) in a.iter().zip(b) {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(
                (x - y).abs() <= 1e-6 * x.abs().max(1.0),
                "{key}: {x} vs {y}"
            );
        }
    }
}

/// A sweep of the continuum's grid solves its discrete line once: the other discrete runs get
/// that record under their own labels, and say so in their notes and on the terminal.
#[test]
fn a_sweep_of_the_continuum_grid_solves_the_discrete_line_once() {
    let dir = tmp("grid_sweep");
    let file = dir.join("s.toml");
    let text = "name = \"conv\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\n\
                cells = 40\nK = 1\n[sweep]\nparameter = \"nodes\"\nvalues = [10, 20, 80]\n";
    std::fs::write(&file, text).unwrap();
    let out = bin()
        .args(["run", "--no-plots", "--jobs", "2", "--out"])
        .arg(dir.join("out"))
        .arg(&file)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    for n in [20, 80] {
        let line = format!("discrete nodes={n}: as `discrete nodes=10` (not solved again)");
        assert!(err.contains(&line), "{err}");
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    let runs = v["runs"].as_array().unwrap();
    let run = |label: &str| runs.iter().find(|r| r["label"] == label).unwrap();
    let first = run("discrete nodes=10");
    assert!(first.get("notes").is_none());
    for n in [20, 80] {
        let r = run(&format!("discrete nodes={n}"));
        assert_eq!(
            (&r["series"], &r["stats"]),
            (&first["series"], &first["stats"])
        );
        assert!(r["notes"][0]
            .as_str()
            .unwrap()
            .contains("discrete nodes=10"));
        // the continuum runs are each their own
        assert_ne!(
            run(&format!("continuum nodes={n}"))["series"],
            first["series"]
        );
    }
}

/// A line's continuum left on its default grid (one segment per cell) is the discrete line
/// itself; its record says so, and one on its own grid does not.
#[test]
fn a_continuum_on_one_segment_per_cell_says_it_is_the_discrete_line() {
    let text = |nodes: &str| {
        format!(
            "name = \"d\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\ncells = 8\n\
             K = 1\n{nodes}\n"
        )
    };
    let (_, v) = run_text("default_grid", &text(""));
    let (d, c) = (&v["runs"][0], &v["runs"][1]);
    assert_eq!(d["series"], c["series"]);
    assert!(d.get("notes").is_none());
    let note = c["notes"][0].as_str().unwrap();
    assert!(note.contains("`nodes` = 8, the default") && note.contains("discrete line itself"));
    let (_, v) = run_text("own_grid", &text("nodes = 5"));
    assert!(v["runs"][1].get("notes").is_none());
}

/// The thesis node scheme over a field that jumps from cell to cell reads it at its nodes and
/// says so; over a smooth field it says nothing.
#[test]
fn the_thesis_scheme_says_it_reads_jumping_fields_at_its_nodes() {
    let text = |mu: &str| {
        format!(
            "name = \"t\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"line\"\ncells = 20\n\
             K = 1\nnodes = 11\ncontinuum_scheme = \"thesis\"\nmu = {mu}\n"
        )
    };
    let (_, v) = run_text(
        "thesis_random",
        &text("{ type = \"random\", low = 0.5, high = 2, seed = 1 }"),
    );
    let note = v["runs"][1]["notes"][0].as_str().unwrap();
    assert!(
        note.contains("reads `mu`") && note.contains("at its nodes"),
        "{note}"
    );
    assert!(v["runs"][0].get("notes").is_none());
    let smooth = "{ type = \"gaussian\", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }";
    let (_, v) = run_text("thesis_smooth", &text(smooth));
    assert!(v["runs"][1].get("notes").is_none());
}

/// `solver.accuracy_check`: every run's reading in `summary.json`, and a run past the
/// contract's 10·rtol warned of on stderr with exit 0 (Fig 2.5's line at K = 10 early in its
/// ramp, docs/limitations.md); a run within it leaves no note.
#[test]
fn the_accuracy_check_is_written_and_a_run_past_the_contract_warned_of() {
    let text = |k: &str| {
        format!(
            "name = \"c\"\n[solver]\naccuracy_check = true\n[output]\n\
             series = {{ start = 1e-3, stop = 10, count = 41, spacing = \"log\", zero = true }}\n\
             profiles = [1, 10]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 100\n\
             k1 = 0.1\nramp = \"exponential\"\nt_ramp = 1.0\nK = {k}\n"
        )
    };
    let (_, v, stderr) = run_text_stderr("check_past", &text("10"));
    let c = &v["runs"][0]["accuracy_check"];
    assert_eq!(
        (c["rtol"].as_f64(), c["profiles_compared"].as_u64()),
        (Some(1e-7), Some(2))
    );
    assert!(
        c["series_stretch_over_rtol"].as_f64().unwrap() > 10.0,
        "{c}"
    );
    assert!(
        stderr.contains("warning: discrete: the same run at rtol 1e-7 differs by"),
        "{stderr}"
    );
    assert!(v["runs"][0]["notes"][0]
        .as_str()
        .unwrap()
        .contains("past the accuracy contract"));
    let (_, v, stderr) = run_text_stderr("check_within", &text("0.01"));
    let c = &v["runs"][0]["accuracy_check"];
    assert!(
        c["series_stretch_over_rtol"].as_f64().unwrap() <= 10.0,
        "{c}"
    );
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(v["runs"][0].get("notes").is_none());
}
