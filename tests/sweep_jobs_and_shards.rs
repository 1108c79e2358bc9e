//! `run --jobs N` and `run --shard i/n` + `merge`: the outputs are byte for byte those of one
//! sequential `run` (`summary.json` compared with its timing field `wall_seconds` removed), for
//! a line sweep, a sweep of the continuum's grid (whose repeated discrete runs are solved once,
//! or in each shard without their source) and a sheet sweep (whose runs also write VTK/PNG
//! snapshots while running);
//! shards that do not fit together are refused with exit code 2, naming what is wrong.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const LINE: &str = r#"
name = "line_sweep"
[output]
series = { start = 0, stop = 2, count = 21 }
profiles = [0, 1, 2]
[model]
kind = "line"
models = ["discrete", "continuum"]
nodes = 11
cells = 10
[sweep]
parameter = "K"
values = [0.1, 1, 10]
[plots]
position = true
"#;

const SHEET: &str = r#"
name = "sheet_sweep"
[output]
series = { start = 0, stop = 1, count = 6 }
profiles = [1]
[model]
kind = "sheet"
models = ["discrete"]
cells_x = 3
cells_y = 3
k_th = 1.0
k1 = 0.1
top = "free"
[sweep]
parameter = "drag_exponent"
values = [0.0, 1.0]
labels = ["0", "1"]
"#;

/// A sweep of the continuum's grid: its discrete runs repeat the first one's solve, and in
/// three shards two of them are solved where their source is not.
const GRID: &str = r#"
name = "grid_sweep"
[output]
series = { start = 0, stop = 2, count = 11 }
profiles = [1]
[model]
kind = "line"
cells = 12
K = 1
[sweep]
parameter = "nodes"
values = [4, 6, 24]
"#;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn cli(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_celltissue"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Drops the fields that differ between processes: `wall_seconds` and the provenance (date,
/// command line).
fn drop_timing(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            m.remove("wall_seconds");
            m.remove("provenance");
            m.values_mut().for_each(drop_timing);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(drop_timing),
        _ => {}
    }
}

/// Every file of a directory; `summary.json` without its timing and provenance fields.
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let mut bytes = std::fs::read(&p).unwrap();
        if name == "summary.json" {
            let text = String::from_utf8(bytes).unwrap();
            assert!(text.contains("wall_seconds"));
            let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
            drop_timing(&mut v);
            bytes = serde_json::to_vec_pretty(&v).unwrap();
        }
        m.insert(name, bytes);
    }
    m
}

fn assert_same(a: &Path, b: &Path) {
    let (ca, cb) = (contents(a), contents(b));
    assert_eq!(
        ca.keys().collect::<Vec<_>>(),
        cb.keys().collect::<Vec<_>>(),
        "file lists of {} and {}",
        a.display(),
        b.display()
    );
    for (name, bytes) in &ca {
        assert!(bytes == &cb[name], "{name} differs");
    }
}

/// Sequential, `--jobs 2`, `--jobs 3`, three shards merged and two shards by SLURM variables
/// merged all write the same directory.
fn check(name: &str, text: &str, runs: usize) {
    let root = tmp(name);
    let scenario = root.join("s.toml");
    std::fs::write(&scenario, text).unwrap();
    let s = scenario.to_str().unwrap();
    let out = |d: &str| root.join(d).to_string_lossy().into_owned();
    ok(&cli(&["run", s, "-q", "--out", &out("seq")], &[]));
    assert!(contents(&root.join("seq")).len() > runs);
    for jobs in ["2", "3"] {
        let d = out(&format!("jobs{jobs}"));
        ok(&cli(&["run", s, "-q", "--jobs", jobs, "--out", &d], &[]));
        assert_same(&root.join("seq"), Path::new(&d));
    }
    for i in 0..3 {
        let shard = format!("{i}/3");
        ok(&cli(
            &[
                "run",
                s,
                "-q",
                "--shard",
                &shard,
                "--out",
                &out(&format!("sh{i}")),
            ],
            &[],
        ));
    }
    // any order of the shard directories
    ok(&cli(
        &[
            "merge",
            &out("sh2"),
            &out("sh0"),
            &out("sh1"),
            "-q",
            "--out",
            &out("merged"),
        ],
        &[],
    ));
    assert_same(&root.join("seq"), &root.join("merged"));
    // `--shard auto` from a SLURM array --array=1-2 (task ids relative to the minimum)
    for id in ["1", "2"] {
        let env = [
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
        ];
        ok(&cli(
            &[
                "run",
                s,
                "-q",
                "--shard",
                "auto",
                "--jobs",
                "2",
                "--out",
                &out(&format!("slurm{id}")),
            ],
            &env,
        ));
    }
    ok(&cli(
        &[
            "merge",
            &out("slurm1"),
            &out("slurm2"),
            "-q",
            "--out",
            &out("slurm"),
        ],
        &[],
    ));
    assert_same(&root.join("seq"), &root.join("slurm"));
}

#[test]
fn line_sweep_outputs_do_not_depend_on_jobs_or_shards() {
    check("line", LINE, 6);
}

#[test]
fn grid_sweep_outputs_do_not_depend_on_where_its_discrete_line_is_solved() {
    check("grid", GRID, 6);
}

#[test]
fn sheet_sweep_outputs_and_snapshots_do_not_depend_on_jobs_or_shards() {
    check("sheet", SHEET, 2);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("sheet")
        .join("seq");
    // the snapshots written during the runs (and copied from the shards by `merge`)
    let vtk = contents(&dir)
        .keys()
        .filter(|n| n.ends_with(".vtu") || n.ends_with(".vtk"))
        .count();
    assert!(vtk >= 2, "no VTK snapshots in {}", dir.display());
}

#[test]
fn shards_that_do_not_fit_are_refused() {
    let root = tmp("bad_shards");
    let scenario = root.join("s.toml");
    std::fs::write(&scenario, LINE).unwrap();
    let s = scenario.to_str().unwrap();
    let out = |d: &str| root.join(d).to_string_lossy().into_owned();
    for i in 0..2 {
        ok(&cli(
            &[
                "run",
                s,
                "-q",
                "--shard",
                &format!("{i}/2"),
                "--out",
                &out(&format!("a{i}")),
            ],
            &[],
        ));
    }
    ok(&cli(
        &[
            "run",
            s,
            "-q",
            "--shard",
            "0/2",
            "--set",
            "model.cells=12",
            "--out",
            &out("other"),
        ],
        &[],
    ));
    let err = |args: &[&str]| {
        let o = cli(args, &[]);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let e = err(&["merge", &out("a0"), "--out", &out("m1")]);
    assert!(
        e.contains("3 of 6 runs missing") && e.contains("1/2"),
        "{e}"
    );
    assert!(e.contains("continuum K=1,"), "{e}");
    let e = err(&["merge", &out("a0"), &out("a0"), "--out", &out("m2")]);
    assert!(e.contains("given twice"), "{e}");
    let e = err(&["merge", &out("a1"), &out("other"), "--out", &out("m3")]);
    assert!(e.contains("different runs"), "{e}");
    let e = err(&["merge", &out("nothing"), "--out", &out("m4")]);
    assert!(
        e.contains("shard.json") && e.contains("is not the output of `celltissue run --shard"),
        "{e}"
    );
    for m in ["m1", "m2", "m3", "m4"] {
        assert!(!root.join(m).exists(), "{m} written");
    }
    for (shard, needle) in [
        ("2/2", "from 0 to 1"),
        ("x", "i/n"),
        ("auto", "SLURM_ARRAY_TASK_ID"),
    ] {
        let e = err(&["run", s, "--shard", shard, "--out", &out("never")]);
        assert!(e.contains(needle), "{shard}: {e}");
    }
    let e = err(&["run", s, "--jobs", "0", "--out", &out("never")]);
    assert!(e.contains("--jobs") && e.contains("≥ 1"), "{e}");
    assert!(!root.join("never").exists());
}
