//! Bad scenario input through the built binary: exit code 2, the key named on stderr, no panic,
//! and no output directory or file written.

use std::path::{Path, PathBuf};
use std::process::Command;

const GOOD: &str = r#"
name = "small"
description = "10 cells"
[output]
series = [0, 0.5, 1]
profiles = [1]
[model]
kind = "line"
cells = 10
mu = 1.0
k1 = 0.1
K = 1.0
"#;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `celltissue run` on `text` with `sets`; asserts exit code 2, `key` on stderr, no output.
fn rejects(case: &str, text: &str, sets: &[&str], key: &str) {
    let dir = tmp(&format!("cli_err_{case}"));
    let file = dir.join("s.toml");
    std::fs::write(&file, text).unwrap();
    let out_dir = dir.join("out");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_celltissue"));
    cmd.arg("run").arg(&file).arg("--out").arg(&out_dir);
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    let out = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{case}: {stderr}");
    assert!(
        stderr.contains(key),
        "{case}: stderr does not name `{key}`: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{case}: {stderr}");
    assert!(!out_dir.exists(), "{case}: output written for bad input");
}

#[test]
fn unknown_key_is_named() {
    rejects(
        "unknown",
        &GOOD.replace("K = 1.0", "K = 1.0\nkay = 2"),
        &[],
        "model.kay",
    );
    rejects("unknown_top", &format!("colour = 1\n{GOOD}"), &[], "colour");
}

#[test]
fn wrong_type_is_named() {
    rejects(
        "type",
        &GOOD.replace("cells = 10", "cells = \"ten\""),
        &[],
        "model.cells",
    );
}

#[test]
fn zero_cells_is_rejected_with_range() {
    rejects(
        "cells0",
        &GOOD.replace("cells = 10", "cells = 0"),
        &[],
        "model.cells",
    );
    rejects(
        "cells0_range",
        &GOOD.replace("cells = 10", "cells = 0"),
        &[],
        ">= 1",
    );
}

#[test]
fn negative_modulus_is_rejected() {
    rejects(
        "mu",
        &GOOD.replace("mu = 1.0", "mu = -1.0"),
        &[],
        "model.mu",
    );
}

#[test]
fn k1_at_least_one_is_rejected() {
    rejects("k1", &GOOD.replace("k1 = 0.1", "k1 = 1.2"), &[], "model.k1");
    rejects(
        "k1_range",
        &GOOD.replace("k1 = 0.1", "k1 = 1.2"),
        &[],
        "< 1",
    );
}

#[test]
fn bad_set_path_or_value_is_named() {
    rejects("set_unknown", GOOD, &["model.Kay=0.1"], "model.Kay");
    rejects("set_through", GOOD, &["model.K.x=1"], "model.K.x");
    rejects("set_value", GOOD, &["model.cells=many"], "model.cells");
    rejects(
        "set_method",
        GOOD,
        &["solver.method=euler"],
        "solver.method",
    );
    rejects("set_malformed", GOOD, &["model.K"], "model.K");
}

#[test]
fn bad_output_times_and_solver_are_named() {
    rejects(
        "times",
        &GOOD.replace("series = [0, 0.5, 1]", "series = [1, 0]"),
        &[],
        "output.series",
    );
    rejects(
        "rtol",
        &format!("{GOOD}[solver]\nrtol = 0\n"),
        &[],
        "solver.rtol",
    );
    rejects(
        "norm",
        &format!("{GOOD}[solver]\nnorm = \"l2\"\n"),
        &[],
        "solver.norm",
    );
    rejects(
        "linsolve",
        &format!("{GOOD}[solver]\nlinear_solver = \"gmres\"\n"),
        &[],
        "solver.linear_solver",
    );
    // the iterative solver is for sheets; GOOD is a line
    rejects(
        "linsolve_line",
        &format!("{GOOD}[solver]\nlinear_solver = \"iterative\"\n"),
        &[],
        "solver.linear_solver",
    );
}

#[test]
fn syntax_error_and_missing_file() {
    rejects("syntax", "name = ", &[], "not valid TOML");
    let dir = tmp("cli_err_missing");
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .args(["run", "/nonexistent/x.toml", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
    assert!(!dir.join("out").exists());
}

#[test]
fn inputs_a_run_would_reject_exit_2_before_anything_is_written() {
    // each once accepted by `validate` before, then a failed run with files written
    rejects(
        "gauss_nan",
        &GOOD.replace(
            "mu = 1.0",
            "mu = { type = \"gaussian\", base = 1, amplitude = 1, centre = nan, width = 0.1 }",
        ),
        &[],
        "model.mu.centre",
    );
    rejects(
        "cell_length",
        &GOOD.replace("k1 = 0.1", "k1 = 0.1\ncell_length = 1e308"),
        &[],
        "model.cell_length",
    );
    rejects(
        "nodes1",
        &GOOD.replace("k1 = 0.1", "k1 = 0.1\nnodes = 1"),
        &[],
        "model.nodes",
    );
    rejects(
        "capacity",
        GOOD,
        &["model.cells=9223372036854775807"],
        "model.cells",
    );
    rejects(
        "sheet_energy",
        "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"sheet\"\nenergy = { law = \"neo_hookean\", mu = 5 }\n",
        &[],
        "model.law",
    );
    rejects(
        "shear_axial_law",
        "name = \"s\"\n[output]\nseries = [0, 1]\n[model]\nkind = \"shear\"\nlaw = { law = \"expression\", W = \"mu/2*(I1 - 3) + k*(l1 - 1)^2\", mu = 1, k = 1 }\n",
        &[],
        "model.law",
    );
}

/// The runs of a sweep are held together until they are written: each run's profiles fit
/// the machine's memory, but three of them would not. `validate` passes (a run alone fits, as
/// on a cluster with one run per shard); `run` exits 2 naming `output.profiles` before writing.
#[test]
fn profiles_of_a_whole_sweep_that_cannot_be_held_exit_2() {
    let Some(avail) = celltissue::scenario::limits::available_memory() else {
        return; // no /proc/meminfo: the check is skipped there too
    };
    // each run ≈ 0.5 of the available memory at its bytes per value: 1 000 profile times
    let per_value = celltissue::scenario::limits::PROFILE_BYTES_PER_VALUE;
    let cells = (0.5 * avail / per_value / 1000.0).round();
    let text = format!(
        "name = \"p\"\n[output]\nseries = [0, 1]\n\
         profiles = {{ start = 0, stop = 1, count = 1000, spacing = \"linear\" }}\n\
         [model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = {cells}\n\
         [sweep]\nparameter = \"K\"\nvalues = [1, 2, 3]\n"
    );
    let dir = tmp("cli_err_profiles_sweep");
    let file = dir.join("s.toml");
    std::fs::write(&file, &text).unwrap();
    let validated = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .arg("validate")
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(
        validated.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&validated.stderr)
    );
    rejects("profiles_sweep", &text, &[], "output.profiles");
}

#[test]
fn set_of_a_swept_key_exits_2_naming_the_conflict() {
    let swept = format!("{GOOD}[sweep]\nparameter = \"K\"\nvalues = [0.1, 1]\n");
    rejects(
        "swept_set",
        &swept,
        &["model.K=0.1"],
        "conflicts with the sweep",
    );
    rejects(
        "swept_value",
        &swept,
        &["sweep.values=[0.1, -1]"],
        "sweep.values[1]",
    );
}

/// `--unset` removes a key so that it takes its default: the way to run a scenario that sets
/// a BDF-only key (`solver.jacobian_age`) with another method. Unsetting a key the scenario
/// does not have, or a swept one, exits 2 naming it.
#[test]
fn unset_removes_a_key_and_names_one_it_cannot_remove() {
    let validate = |sets: &[&str]| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_celltissue"));
        cmd.arg("validate").arg("fig3_3");
        for s in sets {
            cmd.arg(s);
        }
        let o = cmd.output().unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, err) = validate(&["--set", "solver.method=radau"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("solver.jacobian_age") && err.contains("remove it"),
        "{err}"
    );
    let (code, err) = validate(&[
        "--set",
        "solver.method=radau",
        "--unset",
        "solver.jacobian_age",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = validate(&["--unset", "solver.jacobian_ag"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("solver.jacobian_ag") && err.contains("does not have"),
        "{err}"
    );
    let (code, err) = validate(&["--unset", "model.K"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("model.K") && err.contains("swept"), "{err}");
    // the run itself: a ring that unsets its random stiffness runs with the default μ = 1
    let dir = tmp("cli_unset_run");
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .args([
            "run",
            "ch5_ring_division",
            "-q",
            "--no-plots",
            "--unset",
            "model.mu",
        ])
        .args([
            "--set",
            "output.series=[0, 1]",
            "--set",
            "output.profiles=[1]",
        ])
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let written = std::fs::read_to_string(dir.join("out/scenario.toml")).unwrap();
    let table: toml::Table = toml::from_str(&written).unwrap();
    assert!(table["model"].get("mu").is_none(), "{written}");
}

#[test]
fn validate_exits_2_on_what_run_rejects() {
    let dir = tmp("cli_err_validate");
    let file = dir.join("s.toml");
    std::fs::write(&file, GOOD.replace("k1 = 0.1", "k1 = 0.1\nnodes = 1")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_celltissue"))
        .arg("validate")
        .arg(&file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("model.nodes"), "{stderr}");
}
