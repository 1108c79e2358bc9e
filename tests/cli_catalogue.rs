//! `celltissue list` shows every bundled scenario, and every bundled scenario passes
//! `celltissue validate`.

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

#[test]
fn chapter_2_scenarios_run_discrete_n100_and_continuum() {
    for n in [5, 6, 7, 8, 9, 10] {
        let f = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/fig2_{n}.toml"));
        let s = celltissue::scenario::load(&f, &[]).unwrap();
        assert_eq!(s.figure.as_deref(), Some(format!("2.{n}").as_str()));
        let models: Vec<_> = s.runs.iter().map(|r| r.model).collect();
        assert!(models.contains(&celltissue::observe::ModelKind::Discrete));
        assert!(models.contains(&celltissue::observe::ModelKind::Continuum));
        for r in &s.runs {
            let celltissue::scenario::ModelConfig::Line(cfg) = &r.config else {
                panic!("fig2_{n} is a line scenario")
            };
            assert_eq!(cfg.n_cells(), 100, "fig2_{n}");
            assert!(r.sweep.is_some(), "fig2_{n} sweeps");
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
