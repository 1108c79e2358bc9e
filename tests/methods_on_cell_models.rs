//! Every method on a cell model, not only on the integrators' own test problems:
//! BDF, ESDIRK (TR-BDF2) and Radau IIA on the bundled Fig 2.5 and Fig 2.8 scenarios (discrete
//! N = 100 and continuum n = 101, η = 0, K ∈ {1e-2, 1} and {1e-5, 1}) at rtol 1e-6 and 1e-8
//! (atol 100× smaller), against a tight BDF run (rtol 1e-10, atol 1e-12) of the same scenario.
//! The error is the largest relative difference in stretch and in pressure over every cell and
//! profile time.
//!
//! What is asserted: BDF and Radau IIA land within 10·rtol in stretch everywhere, and within
//! 20·rtol in pressure, which is μ/λ² and so doubles a relative stretch error (measured: BDF
//! 0.1–1.1·rtol in stretch at 1e-6 and up to 6.6·rtol at 1e-8, on Fig 2.8 at K = 1, where
//! its pressure errs by 13·rtol; Radau IIA at most 0.5·rtol). BDF's error there is one draw
//! from a scatter: over rtol 1e-6 … 1e-12 it errs by 0.9–20·rtol (1.4 at 1e-8 before the
//! end cell was tested against its own stretch, 6.7 after; both builds scatter alike), at a
//! compression front inside the line; Radau IIA by 0.02–0.08·rtol. Every method's errors
//! fall at least 10× from rtol 1e-6 to 1e-8, or to the reference's resolution. Dormand–Prince
//! runs where the line is not stiff (Fig 2.5 at K = 10) and is held to the same 10·rtol
//! (measured 0.4–0.7·rtol, in 3 120 steps against BDF's 727 at rtol 1e-6).
//! What is measured and not asserted (printed with `-- --nocapture`; the work–precision table
//! in BENCHMARKS.md): ESDIRK errs by 3–13·rtol at 1e-6 and 13–64·rtol at 1e-8 where its steps
//! are short (K ≥ 1e-2), its error falling like rtol^0.7 (tolerance proportionality under
//! error-per-step control for order 2). The one-step methods end a step at every output time
//! (`land_on_outputs`, their default): interpolated instead, Radau IIA erred by 73·rtol and
//! ESDIRK by 5.9·rtol in stretch at t = 0.5 on Fig 2.8 at K = 1e-5, where the steps are long and
//! their dense output, which no error test checks, carries the error (docs/model.md §8.1).

use crate::common::bundled_runs as runs;
use celltissue::observe::RunRecord;
use celltissue::scenario::execute::run_spec;
use std::path::Path;

/// The reference run's resolution in relative stretch and pressure (rtol 1e-10).
const FLOOR: f64 = 2e-9;

/// Largest relative difference of stretch and of pressure over every profile.
fn errors(a: &RunRecord, b: &RunRecord) -> (f64, f64) {
    let rel = |x: &[f64], y: &[f64]| {
        x.iter()
            .zip(y)
            .map(|(p, q)| ((p - q) / q).abs())
            .fold(0.0, f64::max)
    };
    assert_eq!(a.profiles.len(), b.profiles.len());
    a.profiles
        .iter()
        .zip(&b.profiles)
        .fold((0.0f64, 0.0f64), |(s, p), (x, y)| {
            assert_eq!(x.t, y.t);
            (
                s.max(rel(&x.stretch, &y.stretch)),
                p.max(rel(&x.pressure, &y.pressure)),
            )
        })
}

/// Each method on the scenario's runs at rtol 1e-6 and 1e-8 (atol 100× smaller), against the
/// tight BDF reference: BDF within 10·rtol in stretch and pressure at both tolerances; every
/// method's errors fall by at least 10× from rtol 1e-6 to 1e-8 (convergence as the tolerance
/// falls: a method whose estimate missed an error source would stall).
fn check(name: &str, sweep: &str) {
    check_methods(name, sweep, &["bdf", "esdirk", "radau"]);
}

/// [`check`] for the given methods.
fn check_methods(name: &str, sweep: &str, methods: &[&str]) {
    let reference = runs(
        name,
        &[
            sweep,
            "solver.method=\"bdf\"",
            "solver.rtol=1e-10",
            "solver.atol=1e-12",
        ],
    );
    for &method in methods {
        let m = format!("solver.method=\"{method}\"");
        let mut errs = Vec::new();
        for (rtol, atol) in [(1e-6, 1e-8), (1e-8, 1e-10)] {
            let r = format!("solver.rtol={rtol:e}");
            let a = format!("solver.atol={atol:e}");
            let got = runs(name, &[sweep, &m, &r, &a]);
            let e: Vec<(f64, f64)> = got
                .iter()
                .zip(&reference)
                .map(|(g, r)| {
                    let (es, ep) = errors(g, r);
                    println!(
                        "{name} {} {method} rtol {rtol:e}: {} steps, {:.4} s, stretch error {es:.1e} \
                         ({:.0}·rtol), pressure error {ep:.1e} ({:.0}·rtol)",
                        g.label,
                        g.stats.steps,
                        g.stats.wall_seconds,
                        es / rtol,
                        ep / rtol
                    );
                    // the contract bounds stretches; these cells' pressure μ/λ² doubles a
                    // relative stretch error (|d ln p / d ln λ| = 2), so it is held to twice
                    if method != "esdirk" {
                        assert!(
                            es <= 10.0 * rtol && ep <= 2.0 * 10.0 * rtol,
                            "{name} {} {method} rtol {rtol:e}: stretch {es:e}, pressure {ep:e}",
                            g.label
                        );
                    }
                    (es, ep)
                })
                .collect();
            errs.push(e);
        }
        // an error below FLOOR is the reference's own (BDF at rtol 1e-10 errs by up to a few
        // 1e-10) and cannot fall further
        let falls = |c: f64, f: f64| f <= 0.1 * c || f <= FLOOR;
        for (i, (coarse, fine)) in errs[0].iter().zip(&errs[1]).enumerate() {
            assert!(
                falls(coarse.0, fine.0) && falls(coarse.1, fine.1),
                "{name} run {i} {method}: errors {coarse:?} at rtol 1e-6 but {fine:?} at 1e-8"
            );
        }
    }
}

#[test]
fn fig2_5_every_method_converges_and_bdf_meets_the_contract() {
    check("fig2_5", "sweep.values=[1e-2, 1]");
}

#[test]
fn fig2_8_every_method_converges_and_bdf_meets_the_contract() {
    check("fig2_8", "sweep.values=[1e-5, 1]");
}

/// Dormand–Prince (explicit) where the cell model is not stiff: Fig 2.5's line at K = 10,
/// whose fastest relaxation, ~μ/K per cell, sets the explicit method's step.
#[test]
fn fig2_5_dopri_converges_where_the_line_is_not_stiff() {
    check_methods("fig2_5", "sweep.values=[10]", &["dopri", "bdf"]);
}

/// Dormand–Prince where the line is stiff (Fig 2.5 at K = 1e-5, to t = 1000): its steps are
/// held at the stability limit, about 2e-6, so the span would take ~5e8 steps. The run stops
/// as soon as the stiffness test finds that (≈ 1 015 steps, at t ≈ 2e-3), saying why and
/// what to use, where it used to crawl to the 10⁶-step cap (t = 1.8, 10.5 s for each of the
/// two runs).
#[test]
fn fig2_5_dopri_stops_early_where_the_line_is_stiff_and_says_why() {
    let f = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fig2_5.toml");
    let sets = ["sweep.values=[1e-5]", "solver.method=\"dopri\""].map(String::from);
    let s = celltissue::scenario::load(&f, &sets).expect("scenario loads");
    for r in &s.runs {
        let rec = run_spec(r);
        let err = rec
            .error
            .as_deref()
            .expect("a stiff line cannot be run explicitly");
        assert!(
            err.contains("stiff") && err.contains("use an implicit method"),
            "{}: {err}",
            r.label
        );
        assert!(rec.stats.steps < 1100, "{}: {:?}", r.label, rec.stats);
    }
}

/// ESDIRK and Radau IIA divide a line with random thresholds (`models/fig3_3_ensemble.toml`,
/// K = 1e-5, seeds 3 and 4, t ≤ 10) to within 10·rtol of a tight BDF run in length, with the
/// same cells. After a division the daughters' relaxation is far faster than the step, and the
/// one-step methods' error estimate hardly fell as the step shrank: ESDIRK retried at about
/// 0.9 of each rejected step and failed 60 times in a row on seed 3 at t = 8.71, h = 3e-6
/// ("step size too small"). From the second error-test failure in a row a retry is now at most
/// 0.3 of the rejected step (measured at t ≤ 12: ESDIRK's length within 7.6e-8 and 4.4e-8 of
/// rtol 1e-9 runs, Radau IIA's within 1.8e-8 and 1.7e-8). A restart's first rejection then
/// retries at most twice the first step the previous restart accepted, as BDF does: ESDIRK's
/// rejections fell from 4 069 to 757 (seed 3; 8 152 → 8 446 steps), Radau IIA's from 1 235 to
/// 635 (3 564 → 3 805 steps). Starting Radau IIA's first steps and retries from stage rates
/// ẏₙ instead of 0 then moved its counters to 3 794 / 635 and 3 835 / 664 (lengths within
/// 2.4e-9 and 1.2e-10 of the reference), and testing the cell at the wall against its own
/// stretch to 4 432 / 638 and 4 432 / 636. The counters are pinned (deterministic), so a cost
/// regression fails.
#[test]
fn one_step_methods_divide_a_line_with_random_thresholds() {
    let sets = |method: &str, rtol: &str| {
        vec![
            format!("solver.method=\"{method}\""),
            format!("solver.rtol={rtol}"),
            "model.models=[\"discrete\"]".to_string(),
            "sweep.ensemble={realisations=2, first_seed=3}".to_string(),
            "output.series=[0, 5, 10]".to_string(),
        ]
    };
    let run = |method: &str, rtol: &str| {
        let s = sets(method, rtol);
        let s: Vec<&str> = s.iter().map(String::as_str).collect();
        runs("fig3_3_ensemble", &s)
    };
    let reference = run("bdf", "1e-9");
    for (method, pinned) in [
        ("esdirk", [(8446, 757), (8478, 766)]),
        ("radau", [(4432, 638), (4432, 636)]),
    ] {
        for ((rec, r), pin) in run(method, "1e-6").iter().zip(&reference).zip(pinned) {
            let last = |x: &RunRecord| (x.series.length[2], x.series.extra["cells"][2]);
            let ((l, n), (l_ref, n_ref)) = (last(rec), last(r));
            let err = ((l - l_ref) / l_ref).abs();
            eprintln!(
                "{method} {}: l = {l} vs {l_ref} ({err:.1e}), N = {n}, {} steps, {} rejected",
                rec.label, rec.stats.steps, rec.stats.extra["rejected_steps"]
            );
            assert_eq!(n, n_ref, "{method} {}", rec.label);
            let counters = (rec.stats.steps, rec.stats.extra["rejected_steps"] as usize);
            assert_eq!(counters, pin, "{method} {}: counters moved", rec.label);
            assert!(err <= 1e-5, "{method} {}: {err:e}", rec.label);
        }
    }
}
