//! Plotting never hangs, aborts or draws unreadable axes, whatever the data: the three inputs
//! that once hung or allocated until abort (a log time axis down to 1e-300, a log
//! sweep axis over [1e-300, 0.1]) run end to end within a time bound, the third (a subnormal
//! 5e-324 output time on a log axis) is rejected by name before anything runs, and extreme
//! ranges, a subnormal among them, plot directly.

use celltissue::output::plot::{plot_chart, tick_label, Axis, Chart, Curve, Style};
use celltissue::output::{self};
use celltissue::scenario::{execute, load_str};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// Generous: each case takes well under a second; before the fix they never finished.
const BOUND: Duration = Duration::from_secs(120);

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs and writes a scenario on a worker thread; fails if it takes longer than [`BOUND`].
fn run_within_bound(name: &str, text: &str) -> (PathBuf, output::Written) {
    let dir = tmp(name);
    let (tx, rx) = mpsc::channel();
    let (text, d) = (text.to_string(), dir.clone());
    std::thread::spawn(move || {
        let s = load_str(&text, Path::new("case.toml"), &[]).unwrap();
        let summary = execute::run_all(&s, execute::run_spec, |_| {});
        let _ = tx.send(output::write_all(&d, &s, &summary).map_err(|e| e.to_string()));
    });
    let written = rx
        .recv_timeout(BOUND)
        .unwrap_or_else(|_| panic!("{name}: plotting did not finish within {BOUND:?}"))
        .unwrap();
    assert!(written.plot_errors.is_empty(), "{:?}", written.plot_errors);
    (dir, written)
}

fn png(dir: &Path, name: &str) {
    let b = std::fs::read(dir.join(name)).unwrap_or_else(|_| panic!("{name} missing"));
    assert_eq!(&b[1..4], b"PNG", "{name}");
}

#[test]
fn log_time_axis_down_to_1e_300_finishes() {
    let (dir, _) = run_within_bound(
        "plots_1e-300",
        r#"
name = "h1"
[output]
series = [0, 1e-300, 1]
[model]
kind = "line"
models = ["discrete"]
cells = 10
[plots]
time_axis = "log"
"#,
    );
    png(&dir, "series_max_pressure.png");
}

#[test]
fn log_sweep_axis_from_1e_300_finishes() {
    let (dir, _) = run_within_bound(
        "plots_sweep_1e-300",
        r#"
name = "h2"
[output]
series = [0, 1]
profiles = [1]
[model]
kind = "line"
models = ["discrete"]
cells = 10
[sweep]
parameter = "k1"
values = [1e-300, 0.1]
[plots]
sweep_axis = "log"
"#,
    );
    png(&dir, "sweep_pressure.png");
}

#[test]
fn a_subnormal_time_is_rejected_before_anything_runs() {
    // it used to reach the log axis and allocate until abort; a scenario now names it (any
    // subnormal number is rejected), and a chart given one still draws
    // (`extreme_ranges_plot_directly`, its second case)
    let text = r#"
name = "h3"
[output]
series = [0, 5e-324, 1]
[model]
kind = "line"
models = ["discrete"]
cells = 10
[plots]
time_axis = "log"
"#;
    let e = load_str(text, Path::new("case.toml"), &[]).unwrap_err();
    assert_eq!(e.key_name(), Some("output.series[1]"), "{e}");
    assert!(e.to_string().contains("subnormal"), "{e}");
}

#[test]
fn extreme_ranges_plot_directly() {
    let dir = tmp("plots_extreme");
    std::fs::create_dir_all(&dir).unwrap();
    type Case = (Axis, Axis, Vec<(f64, f64)>);
    let cases: Vec<Case> = vec![
        (
            Axis::Linear,
            Axis::Linear,
            vec![(-f64::MAX, f64::MAX), (f64::MAX, -f64::MAX)],
        ),
        (
            Axis::Log,
            Axis::Log,
            vec![(5e-324, 5e-324), (f64::MAX, f64::MAX)],
        ),
        (
            Axis::Log,
            Axis::Linear,
            vec![(f64::MIN_POSITIVE, 1.0), (1.0, 1.0 + 1e-15)],
        ),
        (
            Axis::Linear,
            Axis::Linear,
            vec![(0.0, 1.0), (1.0, 1.0 + 1e-9), (2.0, 1.0 - 1e-9)],
        ),
    ];
    for (i, (xa, ya, pts)) in cases.into_iter().enumerate() {
        let chart = Chart {
            title: format!("case {i}"),
            x_label: "x".into(),
            y_label: "y".into(),
            x_axis: xa,
            y_axis: ya,
            curves: vec![Curve::new("c", Style::Line, 0, pts)],
        };
        let path = dir.join(format!("case{i}.png"));
        let (tx, rx) = mpsc::channel();
        let p = path.clone();
        std::thread::spawn(move || tx.send(plot_chart(&p, &chart).map_err(|e| e.to_string())));
        rx.recv_timeout(BOUND)
            .unwrap_or_else(|_| panic!("case {i} did not finish"))
            .unwrap();
        png(&dir, &format!("case{i}.png"));
    }
}

#[test]
fn ticks_of_a_1e_9_spread_are_distinct() {
    // shear spread noise around 1 (once every tick read "1.0")
    let step = 2e-9 / 10.0;
    let labels: Vec<String> = (0..5)
        .map(|k| tick_label(Axis::Linear, 1.0 - 1e-9 + k as f64 * 5e-10, step))
        .collect();
    let mut unique = labels.clone();
    unique.dedup();
    assert_eq!(unique.len(), labels.len(), "{labels:?}");
}
