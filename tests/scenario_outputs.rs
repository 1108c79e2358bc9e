//! Output writers on records from a tiny fake model (no integrator involved): summary.json has
//! the documented schema, CSVs are long-format and complete, the PNG set matches the figure layout,
//! and non-finite numbers never reach a file.

use celltissue::observe::{ModelKind, Profile, RunRecord, RunStats, Series, Summary};
use celltissue::output::{self, finite, plot};
use celltissue::scenario::{execute, load_str, RunSpec, Scenario};
use std::path::{Path, PathBuf};

const SCENARIO: &str = r#"
name = "fake"
description = "fake records"
figure = "2.5"
[output]
series = { start = 0.01, stop = 10, count = 20, spacing = "log", zero = true }
profiles = [0, 1, 10]
[model]
kind = "line"
cells = 8
[sweep]
parameter = "K"
values = [0.01, 1, 10]
[plots]
time_axis = "log"
sweep_axis = "log"
position = true
rectangles = true
"#;

/// A fake run: uniform compression approaching `1 - 0.1` at a rate set by the swept K.
fn fake(spec: &RunSpec) -> RunRecord {
    let k = spec.sweep.as_ref().and_then(|p| p.value).unwrap_or(1.0);
    let n = 8;
    let lam = |t: f64| 1.0 - 0.1 * (1.0 - (-t / (1.0 + k)).exp());
    let mut series = Series::default();
    for &t in &spec.times.series {
        series.t.push(t);
        series.length.push(n as f64 * lam(t));
        series.max_pressure.push(lam(t).powi(-2) * 1.01);
        series.min_pressure.push(lam(t).powi(-2));
        series.max_stretch.push(lam(t));
        series.min_stretch.push(lam(t) * 0.99);
    }
    let profiles = spec
        .times
        .profiles
        .iter()
        .map(|&t| Profile {
            t,
            x_ref: (0..n).map(|j| j as f64 + 0.5).collect(),
            x: (0..n).map(|j| (j as f64 + 0.5) * lam(t)).collect(),
            stretch: vec![lam(t); n],
            pressure: (0..n).map(|j| lam(t).powi(-2) + 0.01 * j as f64).collect(),
            extra: Default::default(),
        })
        .collect();
    let mut rec = RunRecord {
        label: String::new(),
        model: spec.model,
        parameters: serde_json::json!({}),
        series,
        profiles,
        stats: RunStats {
            steps: 10,
            residual_calls: 20,
            jacobians: 2,
            wall_seconds: 0.001,
            extra: Default::default(),
        },
        divisions: vec![],
        error: None,
        notes: Vec::new(),
        reference: None,
        accuracy_check: None,
    };
    execute::finish(spec, &mut rec);
    rec
}

fn scenario() -> Scenario {
    load_str(SCENARIO, Path::new("fake.toml"), &[]).unwrap()
}

fn out_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn summary_json_has_the_schema_and_labels() {
    let s = scenario();
    let summary = execute::run_all(&s, fake, |_| {});
    let dir = out_dir("outputs_schema");
    let w = output::write_all(&dir, &s, &summary).unwrap();
    assert!(w.plot_errors.is_empty(), "{:?}", w.plot_errors);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["scenario"], "fake");
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 6);
    assert_eq!(runs[0]["label"], "discrete K=0.01");
    assert_eq!(runs[1]["model"], "continuum");
    for r in runs {
        for key in [
            "label",
            "model",
            "parameters",
            "series",
            "profile_times",
            "arrays",
            "stats",
        ] {
            assert!(r.get(key).is_some(), "missing {key}");
        }
        for key in [
            "t",
            "length",
            "max_pressure",
            "min_pressure",
            "max_stretch",
            "min_stretch",
        ] {
            assert_eq!(r["series"][key].as_array().unwrap().len(), 21, "{key}");
        }
        // profiles live in the run's .npz (tests/array_data.rs reads them back)
        assert!(
            r.get("profiles").is_none(),
            "summary.json repeats the profiles"
        );
        assert!(dir.join(r["arrays"].as_str().unwrap()).exists());
        for key in ["steps", "residual_calls", "jacobians", "wall_seconds"] {
            assert!(r["stats"][key].is_number(), "stats {key}");
        }
        assert_eq!(r["parameters"]["sweep"]["parameter"], "K");
        assert_eq!(r["parameters"]["solver"]["method"], "bdf");
    }
    assert!(!std::fs::read_to_string(dir.join("summary.json"))
        .unwrap()
        .contains("null"));
}

#[test]
fn csv_files_are_complete() {
    let s = scenario();
    let summary = execute::run_all(&s, fake, |_| {});
    let dir = out_dir("outputs_csv");
    output::write_all(&dir, &s, &summary).unwrap();
    let series = std::fs::read_to_string(dir.join("series_discrete_K=1.csv")).unwrap();
    let mut lines = series.lines();
    assert_eq!(
        lines.next(),
        Some("t,length,max_pressure,min_pressure,max_stretch,min_stretch")
    );
    assert_eq!(lines.count(), 21);
    let prof = std::fs::read_to_string(dir.join("profiles_continuum_K=10.csv")).unwrap();
    let rows: Vec<&str> = prof.lines().collect();
    assert_eq!(rows[0], "t,X,x,stretch,pressure");
    assert_eq!(rows.len(), 1 + 3 * 8);
    assert!(rows[1].starts_with("0.0,0.5,0.5,1.0,"), "{}", rows[1]);
    let back: toml::Table =
        toml::from_str(&std::fs::read_to_string(dir.join("scenario.toml")).unwrap()).unwrap();
    assert_eq!(back["name"].as_str(), Some("fake"));
}

#[test]
fn png_set_matches_the_figure_layout() {
    let s = scenario();
    let summary = execute::run_all(&s, fake, |_| {});
    let dir = out_dir("outputs_png");
    let w = output::write_all(&dir, &s, &summary).unwrap();
    let expect = [
        "series_max_pressure.png",
        "series_min_stretch.png",
        "series_length.png",
        "profiles_pressure_K=1.png",
        "profiles_stretch_K=0.01.png",
        "profiles_position_K=10.png",
        "profiles_deviation_K=10.png",
        "sweep_pressure.png",
        "sweep_stretch.png",
        "cells_discrete_K=1.png",
    ];
    for name in expect {
        let p = dir.join(name);
        let bytes =
            std::fs::read(&p).unwrap_or_else(|_| panic!("{name} missing; wrote {:?}", w.plots));
        assert_eq!(&bytes[1..4], b"PNG", "{name}");
        assert!(bytes.len() > 5_000, "{name} is only {} bytes", bytes.len());
    }
}

#[test]
fn non_finite_values_are_cut_and_never_written() {
    let s = scenario();
    let mut summary = execute::run_all(&s, fake, |_| {});
    summary.runs[0].series.max_pressure[5] = f64::NAN;
    summary.runs[1].profiles[2].pressure[3] = f64::INFINITY;
    let dir = out_dir("outputs_nan");
    let e = output::write_all(&dir, &s, &summary).unwrap_err();
    assert!(e.to_string().contains("series.max_pressure[5]"), "{e}");
    assert!(
        !dir.exists(),
        "nothing may be written when a NaN is present"
    );
    for r in &mut summary.runs {
        finite::sanitize(r);
    }
    assert_eq!(summary.runs[0].series.t.len(), 5);
    assert!(summary.runs[0]
        .error
        .as_ref()
        .unwrap()
        .contains("non-finite"));
    assert_eq!(summary.runs[1].profiles.len(), 2);
    assert!(finite::check_summary(&summary).is_ok());
    output::write_all(&dir, &s, &summary).unwrap();
}

#[test]
fn plot_rectangles_draws_a_coloured_sheet() {
    let dir = out_dir("outputs_rect");
    std::fs::create_dir_all(&dir).unwrap();
    let rects: Vec<_> = (0..10)
        .flat_map(|j| {
            (0..5).map(move |k| {
                (
                    j as f64,
                    k as f64,
                    j as f64 + 1.0,
                    k as f64 + 1.0,
                    (j * k) as f64,
                )
            })
        })
        .collect();
    let p = dir.join("rects.png");
    plot::plot_rectangles(&p, "sheet", &rects, "pressure").unwrap();
    assert!(std::fs::metadata(&p).unwrap().len() > 5_000);
    assert!(matches!(
        plot::plot_rectangles(&dir.join("none.png"), "x", &[], "p"),
        Err(plot::PlotError::NoData)
    ));
}

#[test]
fn summary_round_trips_through_serde() {
    let s = scenario();
    let summary = execute::run_all(&s, fake, |_| {});
    let text = serde_json::to_string(&summary).unwrap();
    let back: Summary = serde_json::from_str(&text).unwrap();
    assert_eq!(back.runs.len(), summary.runs.len());
    for (a, b) in back.runs.iter().zip(&summary.runs) {
        assert_eq!(a.label, b.label);
        assert_eq!(a.model, b.model);
        assert_eq!(a.series.t.len(), b.series.t.len());
        for (x, y) in a.series.max_pressure.iter().zip(&b.series.max_pressure) {
            assert!((x - y).abs() <= 1e-15 * y.abs(), "{x} vs {y}");
        }
        assert_eq!(a.profiles.len(), b.profiles.len());
    }
    assert_eq!(back.runs[0].model, ModelKind::Discrete);
}
