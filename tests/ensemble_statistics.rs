//! Ensembles of seeded stochastic division (`[sweep] ensemble = { realisations = R }`): the
//! statistics files are the same whatever `--jobs` runs them; with a zero-width threshold
//! distribution every realisation is the deterministic area-rule line, so every quantile is
//! that run's value; with a finite width the columns are the realisations' mean and quantiles
//! (recomputed here from `summary.json`); a one-realisation ensemble is refused by key.

use std::path::{Path, PathBuf};

const SCENARIO: &str = r#"
name = "ensemble"
[output]
series = [0, 1, 2, 2.5, 3, 4, 6]
[model]
kind = "line"
models = ["discrete"]
cells = 20
right_end = "free"
K = 1e-5
growth = { sigma0 = 0.1 }
division = { rule = "random_area", mean = 2.0, spread = 0.2 }
[sweep]
ensemble = { realisations = 6 }
"#;

fn run(text: &str, tag: &str, jobs: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ct_ensemble_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("scenario_in.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let code = celltissue::cli::main_from([
        "celltissue",
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-plots",
        "--jobs",
        jobs,
    ]);
    assert_eq!(code, 0);
    out
}

/// The CSV as a header and rows of numbers.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn column(h: &[String], name: &str) -> usize {
    h.iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

#[test]
fn ensemble_files_do_not_depend_on_the_number_of_jobs() {
    let one = run(SCENARIO, "jobs1", "1");
    let two = run(SCENARIO, "jobs2", "2");
    for f in [
        "ensemble_discrete.csv",
        "ensemble_divisions_discrete.csv",
        "ensemble_ages_discrete.csv",
    ] {
        let (a, b) = (
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
        );
        assert!(a == b, "{f} differs between --jobs 1 and 2");
    }
}

#[test]
fn zero_spread_realisations_are_the_deterministic_line() {
    let ens = run(
        &SCENARIO.replace("spread = 0.2", "spread = 0.0"),
        "zero",
        "1",
    );
    let det = run(
        &SCENARIO
            .replace(
                "rule = \"random_area\", mean = 2.0, spread = 0.2",
                "rule = \"area\"",
            )
            .replace("[sweep]\nensemble = { realisations = 6 }", ""),
        "det",
        "1",
    );
    let (h, rows) = csv(&ens.join("ensemble_discrete.csv"));
    let (dh, drows) = csv(&det.join("series_discrete.csv"));
    for name in ["length", "cells"] {
        let d = column(&dh, name);
        for (row, drow) in rows.iter().zip(&drows) {
            for suffix in ["mean", "p05", "median", "p95"] {
                let v = row[column(&h, &format!("{name}_{suffix}"))];
                assert!(
                    (v - drow[d]).abs() <= 1e-12 * drow[d].abs(),
                    "{name}_{suffix} at t = {}: {v} vs {}",
                    row[0],
                    drow[d]
                );
            }
        }
    }
    // the first divisions of the deterministic line happen by t = 2.5 (N grows from 20)
    assert!(drows[3][column(&dh, "cells")] > 20.0);
}

#[test]
fn ensemble_columns_are_the_realisations_mean_and_quantiles() {
    let out = run(SCENARIO, "stats", "2");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let runs = summary["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 6);
    let (h, rows) = csv(&out.join("ensemble_discrete.csv"));
    let mut spread_seen = false;
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[column(&h, "realisations")], 6.0);
        let mut n: Vec<f64> = runs
            .iter()
            .map(|r| r["series"]["cells"][i].as_f64().unwrap())
            .collect();
        n.sort_by(f64::total_cmp);
        let mean = n.iter().sum::<f64>() / 6.0;
        // 6 values: the 5 % quantile sits a quarter of the way from the first to the second
        let p05 = n[0] + 0.25 * (n[1] - n[0]);
        let median = 0.5 * (n[2] + n[3]);
        assert!((row[column(&h, "cells_mean")] - mean).abs() < 1e-12);
        assert!((row[column(&h, "cells_p05")] - p05).abs() < 1e-12);
        assert!((row[column(&h, "cells_median")] - median).abs() < 1e-12);
        spread_seen |= n[5] > n[0];
    }
    assert!(
        spread_seen,
        "the seeds should give different division times"
    );
    // division locations: fractions over the bins add up to 1
    let (dh, drows) = csv(&out.join("ensemble_divisions_discrete.csv"));
    let total: f64 = drows.iter().map(|r| r[column(&dh, "fraction")]).sum();
    assert!((total - 1.0).abs() < 1e-12, "{total}");
    // ages at division: 20 bins from the least to the largest age of any realisation, each
    // bin's mean the realisations' mean count in it (recomputed from the summary's records)
    let ages: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| {
            r["divisions"]
                .as_array()
                .unwrap()
                .iter()
                .map(|d| d["age"].as_f64().unwrap())
                .collect()
        })
        .collect();
    let all = ages.iter().flatten();
    let lo = all.clone().copied().fold(f64::INFINITY, f64::min);
    let hi = all.copied().fold(0.0, f64::max);
    let (ah, arows) = csv(&out.join("ensemble_ages_discrete.csv"));
    assert_eq!(arows.len(), 20);
    assert!((arows[0][column(&ah, "bin_lo")] - lo).abs() <= 1e-12 * lo);
    assert!((arows[19][column(&ah, "bin_hi")] - hi).abs() <= 1e-12 * hi);
    for row in &arows {
        let (a, b) = (row[column(&ah, "bin_lo")], row[column(&ah, "bin_hi")]);
        let last = b >= hi * (1.0 - 1e-12);
        let mean = ages
            .iter()
            .map(|v| v.iter().filter(|&&x| x >= a && (x < b || last)).count() as f64)
            .sum::<f64>()
            / 6.0;
        assert!(
            (row[column(&ah, "per_realisation_mean")] - mean).abs() < 1e-12,
            "[{a}, {b}): {row:?} against {mean}"
        );
    }
    // the cells of this weakly dragged line grow about as fast as unstressed ones
    // (2(θ − 1) for θ ∈ [1.8, 2.2]) and the first generation divides by t = 6
    assert!(lo > 1.6 && hi < 2.6, "[{lo}, {hi}]");
}

#[test]
fn an_ensemble_needs_two_realisations() {
    let text = SCENARIO.replace("realisations = 6", "realisations = 1");
    let e = celltissue::scenario::load_str(&text, Path::new("e.toml"), &[]).unwrap_err();
    assert_eq!(e.key_name(), Some("sweep.ensemble.realisations"), "{e}");
}
