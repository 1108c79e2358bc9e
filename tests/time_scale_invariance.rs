//! Scale invariance. Time: a line posed on times of 1e-100 or 1e100 (its drag, growth rate,
//! ramp time and viscosity scaled with them) is as accurate as the unit-time line: against a
//! tight unit-time reference, its stretches and pressures err by at most twice what the
//! unit-time run's do at the same tolerance. (Not bit for bit: a_tol is absolute, so the
//! weights of the rates, and with them the starting step, change with the time scale.) Three limits of absolute time broke it and are fixed: events
//! located to an absolute 1e-12 (a dividing line at 1e-100 divided at the ends of steps and
//! erred by 600·rtol), BDF's interpolation coefficients overflowing at steps below 1e-62 and
//! the starting step reading an overflowed norm as a negligible one (docs/model.md §2.9, §8.1).
//! Lengths and stresses: scaled by powers of two near 1e±100, nothing changes by a bit.
//! Sheets (free top, elastic and Kelvin–Voigt) on times of 1e∓100: as accurate as at unit time.

use crate::common::profile_gap as gap;
use celltissue::observe::RunRecord;
use celltissue::scenario::{execute::run_spec, load_str};

/// The model keys that carry time, for a time scale `s`.
type TimedKeys = dyn Fn(f64) -> String;

/// The discrete run of a line with time scale `s` at `rtol` (a_tol = rtol/100); `extra(s)`
/// adds the model's timed keys.
fn line(s: f64, rtol: f64, k: f64, extra: &TimedKeys) -> RunRecord {
    let text = format!(
        "name = \"ts\"\n[solver]\nrtol = {rtol:e}\natol = {:e}\n[output]\nseries = [0]\n\
         profiles = [{:e}, {:e}, {:e}]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\n\
         cells = 50\nK = {:e}\n{}",
        rtol * 1e-2,
        0.5 * s,
        s,
        3.0 * s,
        k * s,
        extra(s)
    );
    let scenario = load_str(&text, std::path::Path::new("ts.toml"), &[]).unwrap();
    let rec = run_spec(&scenario.runs[0]);
    assert!(rec.error.is_none(), "s = {s:e}: {:?}", rec.error);
    rec
}

#[test]
fn lines_on_times_of_1e_minus_100_and_1e100_match_the_unit_time_line() {
    let cases: [(&str, f64, &TimedKeys); 3] = [
        ("dividing, free end", 1e-2, &|s| {
            format!(
                "right_end = \"free\"\ngrowth = {{ sigma0 = 0.1, gm = {:e} }}\n\
                 division = {{ rule = \"area\", ratio = 2 }}\n",
                1.0 / s
            )
        }),
        ("viscous, prescribed ramp", 1.0, &|s| {
            format!("t_ramp = {s:e}\neta = {:e}\n", 0.5 * s)
        }),
        ("active ring", 0.1, &|s| {
            format!(
                "right_end = \"periodic\"\nactive = {{ beta = -1, omega = {:e} }}\n",
                0.2 / s
            )
        }),
    ];
    let rtol = 1e-8;
    for (name, k, extra) in cases {
        let reference = line(1.0, 1e-11, k, extra);
        let errors = |rec: &RunRecord| {
            (
                gap(rec, &reference, |p| &p.stretch),
                gap(rec, &reference, |p| &p.pressure),
            )
        };
        let unit = errors(&line(1.0, rtol, k, extra));
        // powers of two near 1e∓100, so the scaled inputs are exact
        for s in [2f64.powi(-332), 2f64.powi(332)] {
            let scaled = errors(&line(s, rtol, k, extra));
            eprintln!(
                "{name}, s = {s:e}: stretch {:.2e}, pressure {:.2e} (at s = 1: {:.2e}, {:.2e})",
                scaled.0, scaled.1, unit.0, unit.1
            );
            assert!(
                scaled.0 <= 2.0 * unit.0.max(rtol) && scaled.1 <= 2.0 * unit.1.max(rtol),
                "{name}, s = {s:e}: {scaled:?} against {unit:?} at s = 1"
            );
        }
    }
}

/// The discrete run of a line with lengths scaled by `l` and stresses by `m` (cell length, μ,
/// drag `K·m/l`, and the model's stress keys through `extra(m)`), at rtol 1e-8.
fn scaled_line(l: f64, m: f64, k: f64, extra: &TimedKeys) -> RunRecord {
    let text = format!(
        "name = \"ls\"\n[solver]\nrtol = 1e-8\natol = 1e-10\n[output]\nseries = [0]\n\
         profiles = [0.5, 1, 3]\n[model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 50\n\
         cell_length = {l:e}\nlaw = {{ law = \"neo_hookean\", mu = {m:e} }}\nK = {:e}\n{}",
        k * m / l,
        extra(m)
    );
    let scenario = load_str(&text, std::path::Path::new("ls.toml"), &[]).unwrap();
    let rec = run_spec(&scenario.runs[0]);
    assert!(rec.error.is_none(), "l = {l:e}, m = {m:e}: {:?}", rec.error);
    rec
}

#[test]
fn lengths_and_stresses_scaled_by_powers_of_two_near_1e100_change_no_bit() {
    // the tested quantities are stretches in cell units and the residual rows scale as one,
    // so scaling by powers of two (exact) must give the same steps and stretches bit for bit
    // and the pressures times m exactly
    let cases: [(&str, f64, &TimedKeys); 3] = [
        ("dividing, free end", 1e-2, &|m| {
            format!(
                "right_end = \"free\"\ngrowth = {{ sigma0 = {:e} }}\n\
                 division = {{ rule = \"area\", ratio = 2 }}\n",
                0.1 * m
            )
        }),
        ("viscous, prescribed ramp", 1.0, &|m| {
            format!("t_ramp = 1\neta = {:e}\n", 0.5 * m)
        }),
        ("active ring", 0.1, &|m| {
            format!(
                "right_end = \"periodic\"\nactive = {{ beta = -1, omega = 0.2 }}\n\
                 active_amplitude = {m:e}\n"
            )
        }),
    ];
    let (tiny, huge) = (2f64.powi(-332), 2f64.powi(332));
    for (name, k, extra) in cases {
        let unit = scaled_line(1.0, 1.0, k, extra);
        for (l, m) in [(tiny, 1.0), (huge, 1.0), (1.0, tiny), (1.0, huge)] {
            let rec = scaled_line(l, m, k, extra);
            assert_eq!(
                rec.stats.steps, unit.stats.steps,
                "{name}, l = {l:e}, m = {m:e}"
            );
            for (p, q) in rec.profiles.iter().zip(&unit.profiles) {
                assert_eq!(p.stretch, q.stretch, "{name}, l = {l:e}, m = {m:e}");
                let scaled: Vec<f64> = q.pressure.iter().map(|x| x * m).collect();
                assert_eq!(p.pressure, scaled, "{name}, l = {l:e}, m = {m:e}");
            }
        }
    }
}

/// The discrete and continuum runs of a 10 × 6 free-top sheet with time scale `s` at `rtol`
/// (drag, ramp time and a Kelvin–Voigt η scaled with it).
fn sheet(s: f64, rtol: f64, eta: f64) -> Vec<RunRecord> {
    let text = format!(
        "name = \"ss\"\n[solver]\nrtol = {rtol:e}\natol = {:e}\n[output]\nseries = [0]\n\
         profiles = [{:e}, {s:e}, {:e}]\n[model]\nkind = \"sheet\"\n\
         models = [\"discrete\", \"continuum\"]\ncells_x = 10\ncells_y = 6\nk_th = {s:e}\n\
         k1 = 0.1\nramp = {{ kind = \"exponential\", t_ramp = {s:e} }}\ntop = \"free\"\n\
         viscosity = {{ model = \"kelvin_voigt\", eta = {:e} }}\n",
        rtol * 1e-2,
        0.5 * s,
        3.0 * s,
        eta * s
    );
    let scenario = load_str(&text, std::path::Path::new("ss.toml"), &[]).unwrap();
    scenario
        .runs
        .iter()
        .map(|spec| {
            let rec = run_spec(spec);
            assert!(rec.error.is_none(), "s = {s:e}: {:?}", rec.error);
            rec
        })
        .collect()
}

#[test]
fn sheets_on_times_of_1e_minus_100_and_1e100_are_as_accurate_as_the_unit_time_sheet() {
    // measured at rtol 1e-8: 6e-9 to 6.4e-8 in stretch and pressure, as at unit time
    let rtol = 1e-8;
    for eta in [0.0, 0.5] {
        let reference = sheet(1.0, 1e-11, eta);
        let errors = |runs: &[RunRecord]| -> Vec<(f64, f64)> {
            runs.iter()
                .zip(&reference)
                .map(|(rec, r)| (gap(rec, r, |p| &p.stretch), gap(rec, r, |p| &p.pressure)))
                .collect()
        };
        let unit = errors(&sheet(1.0, rtol, eta));
        for s in [2f64.powi(-332), 2f64.powi(332)] {
            for (scaled, unit) in errors(&sheet(s, rtol, eta)).iter().zip(&unit) {
                eprintln!("η = {eta}, s = {s:e}: {scaled:?} against {unit:?} at s = 1");
                assert!(
                    scaled.0 <= 2.0 * unit.0.max(rtol) && scaled.1 <= 2.0 * unit.1.max(rtol),
                    "η = {eta}, s = {s:e}: {scaled:?} against {unit:?}"
                );
            }
        }
    }
}

/// An output far beyond the problem's time scale: a unit-time line (K = 1, the end moved by
/// 0.1 over a unit ramp) asked for t = 1e50, 1e100 and 1e300 reaches it, at its exact
/// equilibrium (every stretch 0.9, to the default rtol 1e-6), with each implicit method. The starting step's probes
/// began at 1e-6 of the span and gave up after eight shrinks by 1e-2, leaving 1e28 at a span
/// of 1e50, untested: BDF then cut it by 0.25 per failure and stopped at t = 0 ("cell 10 has
/// non-positive stretch"). The probes now shrink to the step floor.
#[test]
fn an_output_at_1e300_of_a_unit_time_line_is_its_equilibrium() {
    for method in ["bdf", "radau", "esdirk"] {
        for t_end in ["1e50", "1e100", "1e300"] {
            let text = format!(
                "name = \"far\"\n[solver]\nmethod = \"{method}\"\n[output]\nseries = [0, {t_end}]\n\
                 [model]\nkind = \"line\"\nmodels = [\"discrete\"]\ncells = 10\nK = 1.0\nk1 = 0.1\n"
            );
            let scenario = load_str(&text, std::path::Path::new("far.toml"), &[]).unwrap();
            let rec = run_spec(&scenario.runs[0]);
            assert!(
                rec.error.is_none(),
                "{method}, t = {t_end}: {:?}",
                rec.error
            );
            let s = &rec.series;
            for lam in [s.min_stretch[1], s.max_stretch[1]] {
                // (measured: BDF and Radau IIA within 6e-16, ESDIRK 4.5e-9 to 7.1e-9)
                assert!((lam - 0.9).abs() < 1e-6, "{method}, t = {t_end}: λ = {lam}");
            }
        }
    }
}
