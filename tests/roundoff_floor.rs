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

/// A line run at rtol 1e-10, atol 1e-12 with `method`: its `[model]` is `model`, its series
/// `series`.
fn tight(model: &str, series: &str, method: &str) -> RunRecord {
    run(&format!(
        "name = \"tight\"\n[solver]\nmethod = \"{method}\"\nrtol = 1e-10\natol = 1e-12\n\
         [output]\nseries = {series}\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\n{model}"
    ))
}

/// The largest gap between a run's smallest stretch and its reference's (the static
/// equilibrium at l(t)) at the series times from `from` on that the reference covers,
/// relative.
fn stretch_gap_to_reference(r: &RunRecord, from: f64) -> f64 {
    let re = r.reference.as_ref().expect("a reference");
    assert!(re.series.t.iter().any(|&t| t >= from));
    re.series
        .t
        .iter()
        .zip(&re.series.min_stretch)
        .filter(|(&t, _)| t >= from)
        .map(|(t, lam)| {
            let j = r
                .series
                .t
                .iter()
                .position(|s| s == t)
                .expect("a series time");
            (r.series.min_stretch[j] - lam).abs() / lam
        })
        .fold(0.0, f64::max)
}

/// BDF, Radau IIA and ESDIRK at rtol 1e-10 on the line `model` finish, with the smallest
/// stretch within 10·rtol of the static equilibrium at l(t) at the series times from `from` on.
fn every_method_finishes_on_the_static_equilibrium(model: &str, series: &str, from: f64) {
    for method in ["bdf", "radau", "esdirk"] {
        let r = tight(model, series, method);
        assert!(r.error.is_none(), "{method}: {:?}", r.error);
        let gap = stretch_gap_to_reference(&r, from);
        println!(
            "{method}: {} steps, stretch gap to the static equilibrium from t = {from}: {gap:.2e}",
            r.stats.steps
        );
        assert!(gap <= 1e-9, "{method}: {gap:e}");
    }
}

#[test]
fn a_quasi_static_line_restarts_after_its_ramp_at_a_tight_tolerance_with_every_method() {
    // K = 0 and η = 0: every unknown is algebraic, the line is the static equilibrium at l(t).
    // At the restart where the ramp ends (a breakpoint), BDF and Radau IIA used to fail every
    // first step: the first Newton correction was below what positions near 40 resolve at
    // rtol 1e-10, adding it changed nothing, the second correction was the first again and
    // the contraction test read it as divergence (found by `accuracy_contract_fuzz`).
    let model = "cells = 40\n\
        law = { law = \"mooney_rivlin\", c1 = 0.5432425530797865, c2 = 0.17301293920564653 }\n\
        mu = { type = \"random\", low = 2.7027012470447427, high = 2.861371124049751, seed = 87914607 }\n\
        K = 0\nm = 1\neta = 0\nk1 = 0.17589141185832477\nramp = \"polynomial\"\n\
        t_ramp = 0.5992804351501625";
    every_method_finishes_on_the_static_equilibrium(
        model,
        "[0, 0.3, 0.5992804351501625, 1, 2]",
        0.0,
    );
}

#[test]
fn a_viscous_line_restarting_near_rest_at_a_tight_tolerance_initialises_its_rates() {
    // At the ramp's end the cells are nearly at rest; the consistent initialisation of ẏ
    // there reached a weighted update of 1.9e-3 (against its target 1e-3) that no step along
    // it could lower, the residual being at its rounding floor, and the run stopped (found
    // by `accuracy_contract_fuzz`). An update already within the tolerance is accepted there.
    let model = "cells = 7\nlaw = { law = \"neo_hookean\", mu = 1.6819341187211483 }\n\
        mu = { type = \"random\", low = 1.9612683535744728, high = 2.598725897562809, seed = 445271376 }\n\
        K = 0.01785268931779821\nm = 1\neta = 0.03464303338826191\nk1 = 0.31496768034051614\n\
        ramp = \"polynomial\"\nt_ramp = 3.55343466222898";
    // relaxed long before t = 8 (time scales K/μ and η/μ of about 0.01)
    every_method_finishes_on_the_static_equilibrium(model, "[0, 2, 3.55343466222898, 5, 8]", 8.0);
}
