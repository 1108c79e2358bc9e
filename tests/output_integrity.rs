//! Output integrity through the built binary: a used output directory is
//! refused unless `--replace`, which removes only files celltissue wrote; `--no-plots` writes
//! data only; no temporary file survives a run; SIGINT during a sweep keeps the finished runs,
//! stops the one in progress with what it computed, and lists it in `summary.json`.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_celltissue"))
}

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scenario(dir: &Path, name: &str, param: &str) -> PathBuf {
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(
        &p,
        format!(
            r#"
name = "{name}"
[output]
series = [0, 1]
profiles = [1]
[model]
kind = "line"
models = ["discrete"]
cells = 8
[sweep]
parameter = "{param}"
values = [0.5, 1]
"#
        ),
    )
    .unwrap();
    p
}

fn run(file: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    bin()
        .arg("run")
        .arg(file)
        .arg("--out")
        .arg(out)
        .arg("-q")
        .args(extra)
        .output()
        .unwrap()
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_used_directory_is_refused_and_replace_removes_only_our_files() {
    let d = tmp("integrity_replace");
    let out = d.join("out");
    let (a, b) = (scenario(&d, "first", "K"), scenario(&d, "second", "eta"));
    assert_eq!(run(&a, &out, &[]).status.code(), Some(0));
    assert!(out.join("series_discrete_K=0.5.csv").exists());
    std::fs::write(out.join("my_notes.txt"), "keep me").unwrap();
    let before = names(&out);
    let r = run(&b, &out, &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("scenario `first`") && err.contains("--replace"),
        "{err}"
    );
    assert_eq!(names(&out), before, "a refused run changed the directory");
    let r = run(&b, &out, &["--replace"]);
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let after = names(&out);
    assert!(after.iter().all(|n| !n.contains("K=")), "{after:?}");
    assert!(after.iter().any(|n| n.contains("eta=")));
    assert_eq!(
        std::fs::read_to_string(out.join("my_notes.txt")).unwrap(),
        "keep me"
    );
    // rerunning the same scenario into its own directory needs no flag
    std::fs::remove_file(out.join("my_notes.txt")).unwrap();
    assert_eq!(run(&b, &out, &[]).status.code(), Some(0));
}

#[test]
fn no_plots_writes_data_only_and_leaves_no_temporary_file() {
    let d = tmp("integrity_no_plots");
    let out = d.join("out");
    let a = scenario(&d, "np", "K");
    assert_eq!(run(&a, &out, &["--no-plots"]).status.code(), Some(0));
    let n = names(&out);
    assert!(n.iter().all(|f| !f.ends_with(".png")), "{n:?}");
    assert!(n.iter().all(|f| !f.contains(".partial")), "{n:?}");
    assert!(n.contains(&"summary.json".to_string()) && n.iter().any(|f| f.ends_with(".npz")));
    let m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join(".celltissue-manifest.json")).unwrap(),
    )
    .unwrap();
    let listed: Vec<&str> = m["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(listed.len(), n.len() - 1, "manifest {listed:?} vs {n:?}");
}

/// Writes the slow three-run sweep into `d` and starts `run` on it: the first run takes
/// milliseconds, the second (10⁶ cells up to t = 1000) many seconds; the third is not reached.
/// Returns the child once the first run's progress line has been read, and the other lines.
fn start_slow_sweep(
    d: &Path,
    out: &Path,
) -> (
    std::process::Child,
    std::io::Lines<BufReader<std::process::ChildStderr>>,
) {
    let file = d.join("slow.toml");
    std::fs::write(
        &file,
        r#"
name = "slow"
[output]
series = [0, 1, 1000]
[model]
kind = "line"
models = ["discrete"]
cells = 1000000
K = 10.0
[sweep]
parameter = "cells"
values = [10, 1000000, 20]
"#,
    )
    .unwrap();
    let mut child = bin()
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(out)
        .arg("--no-plots")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    assert!(first.starts_with("[1/3]"), "{first}");
    (child, lines)
}

#[test]
fn sigint_keeps_finished_runs_and_names_the_interrupted_ones() {
    let d = tmp("integrity_sigint");
    let out = d.join("out");
    // wait for the first run's progress line, then interrupt
    let (mut child, lines) = start_slow_sweep(&d, &out);
    let t0 = Instant::now();
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    let status = child.wait().unwrap();
    assert!(
        t0.elapsed() < Duration::from_secs(60),
        "the interrupt was not prompt"
    );
    assert_eq!(status.code(), Some(130), "{rest:?}");
    // the stopped run is reported as interrupted, not as failed
    assert!(
        rest.iter()
            .any(|l| l.starts_with("interrupted: 2 run(s) not finished"))
            && !rest.iter().any(|l| l.contains("run(s) failed")),
        "{rest:?}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2, "{rest:?}");
    assert_eq!(runs[0]["label"], "discrete cells=10");
    assert!(runs[0].get("error").is_none());
    // the run in progress was stopped, not abandoned: its record holds what it computed
    assert_eq!(runs[1]["label"], "discrete cells=1e6");
    let error = runs[1]["error"].as_str().unwrap();
    assert!(error.contains("interrupted"), "{error}");
    assert_eq!(runs[1]["series"]["t"][0], 0.0, "{}", runs[1]["series"]);
    assert_eq!(
        v["interrupted"],
        serde_json::json!(["discrete cells=1e6", "discrete cells=20"])
    );
    assert!(out.join("run_discrete_cells=10.npz").exists());
    assert!(out.join("run_discrete_cells=1e6.npz").exists());
    assert!(!out.join("run_discrete_cells=20.npz").exists());
    assert!(names(&out).iter().all(|f| !f.contains(".partial")));
}

/// One SIGTERM delivered twice within microseconds (coreutils' `timeout` signals the program
/// and then its process group) is one interrupt: the finished and stopped runs are written.
/// Taken as "interrupt again", the second copy made the program quit without writing.
#[test]
fn a_signal_delivered_twice_at_once_is_one_interrupt() {
    let d = tmp("integrity_sigterm_twice");
    let out = d.join("out");
    let (mut child, lines) = start_slow_sweep(&d, &out);
    let id = child.id().to_string();
    for _ in 0..2 {
        let kill = Command::new("kill").args(["-TERM", &id]).status().unwrap();
        assert!(kill.success());
    }
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{rest:?}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["runs"].as_array().unwrap().len(), 2, "{rest:?}");
    assert!(out.join("run_discrete_cells=10.npz").exists());
}
