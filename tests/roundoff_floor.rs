//! Tolerances below what a line's (or a sheet's) positions resolve: rejected by `validate` when
//! the array at rest already is past the limit, and stopped by the solver (with what it computed) when a
//! crushed cell gets there during the run — instead of a run that creeps on for hours with
//! steps only rounding noise limits (a 4 000-cell line at rtol 1e-10 used to take 10⁶ steps
//! and 285 s to cover 0.4 of its time span).

use celltissue::observe::RunRecord;
use celltissue::scenario::roundoff::{check_line, line_ratio};
use celltissue::scenario::{execute::run_spec, load_str};
use integrators::solver::ROUNDOFF_LIMIT;
use std::path::Path;

/// 4 000 unit cells, stiff cluster, K = 1, the end pushed in by 400 cell lengths in a unit
/// ramp: the last cells crush to λ ≈ 0.026 by t = 1 (pressure ≈ 1 500).
fn crushed_line(rtol: f64, atol: f64, series: &str) -> String {
    format!(
        r#"
name = "crushed"
[solver]
rtol = {rtol:e}
atol = {atol:e}
[output]
series = {series}
[model]
kind = "line"
models = ["discrete"]
cells = 4000
K = 1
mu = {{ type = "gaussian", base = 1, amplitude = 1, centre = 0.5, width = 0.1 }}
"#
    )
}

fn run(text: &str) -> RunRecord {
    let s = load_str(text, Path::new("crushed.toml"), &[]).unwrap();
    assert_eq!(s.runs.len(), 1);
    run_spec(&s.runs[0])
}

#[test]
fn validate_rejects_a_line_past_the_limit_at_rest_naming_the_tolerance_that_would_run() {
    let e = load_str(
        &crushed_line(1e-15, 1e-17, "[0, 1]"),
        Path::new("crushed.toml"),
        &[],
    )
    .unwrap_err();
    assert_eq!(e.key_name(), Some("solver.rtol"), "{e}");
    assert!(e.to_string().contains("cell 3999"), "{e}");
    // the tightest tolerance the message offers does pass, and just below it does not
    let cells = || std::iter::repeat_n(1.0, 4000);
    let c = line_ratio(cells(), 1e-15, 1e-17);
    let tightest = (1e-15 + 1e-17) * c.ratio / ROUNDOFF_LIMIT;
    assert!(check_line(cells(), tightest * 1.001, 0.0).is_ok());
    assert!(check_line(cells(), tightest * 0.999, 0.0).is_err());
}

#[test]
fn validate_and_the_solver_agree_at_rest() {
    // around the limit, a line at rest (the start of the crushed run) is rejected by validate
    // exactly when the solver would stop before its first step
    let at_rest = line_ratio(std::iter::repeat_n(1.0, 4000), 1.0, 0.0).ratio;
    for factor in [0.9, 0.99, 1.01, 1.1] {
        // rtol + atol = ratio at rtol + atol = 1, over the limit, times 1/factor
        let tol = at_rest / ROUNDOFF_LIMIT / factor;
        let text = crushed_line(tol * 0.99, tol * 0.01, "[0, 1e-9]");
        let validated = load_str(&text, Path::new("crushed.toml"), &[]);
        if factor > 1.0 {
            assert!(validated.is_err(), "factor {factor}");
            // the same tolerances slipped past `validate` stop the solver at t = 0
            let loose = crushed_line(1e-6, 1e-8, "[0, 1e-9]");
            let mut spec = load_str(&loose, Path::new("crushed.toml"), &[])
                .unwrap()
                .runs
                .remove(0);
            (spec.solver.rtol, spec.solver.atol) = (tol * 0.99, tol * 0.01);
            let err = run_spec(&spec).error.expect("the solver must stop");
            assert!(
                err.contains("at t = 0:") && err.contains("too close to round-off"),
                "factor {factor}: {err}"
            );
        } else {
            let rec = run_spec(&validated.unwrap().runs[0]);
            assert!(rec.error.is_none(), "factor {factor}: {:?}", rec.error);
        }
    }
}

#[test]
fn a_cell_crushed_past_the_limit_stops_the_run_promptly_with_its_outputs_kept() {
    // at rest the line is far from the limit (ratio 0.018); the last cell's stretch falls to
    // λ = 0.058 by t ≈ 0.024, where ε·(x₃₉₉₉ + x₃₉₉₈) ≈ 1.8e-12 is a quarter of its stretch
    // tolerance rtol·λ + atol
    let (rtol, atol) = (1e-10, 1e-12);
    assert!(line_ratio(std::iter::repeat_n(1.0, 4000), rtol, atol).ratio < 0.02);
    let rec = run(&crushed_line(rtol, atol, "[0, 0.01, 1]"));
    let err = rec.error.as_deref().expect("the run must stop");
    assert!(err.contains("tolerance too close to round-off"), "{err}");
    assert!(err.contains("x_3999"), "{err}");
    // it stops near t = 0.024 and within 10⁴ steps, not after 10⁶
    let at = err
        .split("at t = ")
        .nth(1)
        .and_then(|s| s.split(':').next())
        .and_then(|s| s.parse::<f64>().ok())
        .expect("failure time in the message");
    assert!(at > 0.01 && at < 0.05, "{err}");
    assert!(rec.stats.steps < 10_000, "{}", rec.stats.steps);
    // the outputs before the failure are kept, NaN-free; the last cell at t = 0.01 is already
    // crushed to λ < 0.1
    assert_eq!(rec.series.t, [0.0, 0.01]);
    let min = rec.series.min_stretch[1];
    assert!(min.is_finite() && min > 0.0 && min < 0.1, "{min}");
}

#[test]
fn a_sheet_past_the_limit_at_rest_is_rejected_by_validate_and_by_the_solver() {
    // 1 000 × 4 unit cells: faces up to x = 1 000, so a stretch is resolved to ≈ 4.4e-13
    let sheet = |rtol: f64| {
        format!(
            "name = \"s\"\n[solver]\nrtol = {rtol:e}\natol = {:e}\n[output]\nseries = [0, 1e-9]\n\
             [model]\nkind = \"sheet\"\nmodels = [\"discrete\"]\ncells_x = 1000\ncells_y = 4\n",
            rtol / 100.0
        )
    };
    let e = load_str(&sheet(3e-13), Path::new("s.toml"), &[]).unwrap_err();
    assert_eq!(e.key_name(), Some("solver.rtol"), "{e}");
    // slipped past `validate`, the same tolerance stops the solver before its first step
    let mut spec = load_str(&sheet(1e-11), Path::new("s.toml"), &[])
        .unwrap()
        .runs
        .remove(0);
    let fine = run_spec(&spec);
    assert!(fine.error.is_none(), "{:?}", fine.error);
    (spec.solver.rtol, spec.solver.atol) = (3e-13, 3e-15);
    let err = run_spec(&spec).error.expect("the solver must stop");
    assert!(
        err.contains("at t = 0:") && err.contains("too close to round-off"),
        "{err}"
    );
}
