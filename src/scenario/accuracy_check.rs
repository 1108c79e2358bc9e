//! The accuracy check (`solver.accuracy_check = true`): each run repeated at a tenfold tighter
//! tolerance and compared with itself, cell by cell at the profile times and in the smallest
//! and largest stretch at every series time.
//!
//! The accuracy contract (docs/model.md §8.1) bounds each step's error in cell units. What a
//! run's stretches err by in the end also depends on what the model does with those errors:
//! they add up where a cell is driven faster than it relaxes (Fig 2.5 at K = 10 early in its
//! ramp: 35·rtol), and a model that amplifies perturbations (a ring whose active stress
//! softens its cells) grows them far past rtol (docs/limitations.md); no error test sees
//! either. Where a run's
//! error falls with the tolerance, its difference from the same run at rtol/10 estimates that
//! error; a difference past the contract's 10·rtol is reported as a note on the run and a
//! warning of the command line. [`super::execute::run_spec`] calls [`check`] after a run that
//! finished; [`compare`] is the comparison alone.

use super::load::RunSpec;
use crate::observe::{AccuracyCheck, Profile, RunRecord};
use crate::settings::SolveSettings;

/// How much tighter the check's run is, in `rtol` and in `atol`.
pub const FACTOR: f64 = 10.0;

/// The largest stretch difference, in units of the run's rtol, that the check passes: the
/// contract's bound.
pub const CONTRACT: f64 = 10.0;

/// The settings of the check's run: `rtol` and `atol` over [`FACTOR`], ten times the steps
/// (a tighter run takes more), and no check of its own.
///
/// ```
/// use celltissue::scenario::accuracy_check::tightened;
/// use celltissue::SolveSettings;
/// let s = SolveSettings { accuracy_check: true, ..Default::default() };
/// let t = tightened(&s);
/// assert_eq!((t.rtol, t.atol, t.accuracy_check), (1e-7, 1e-9, false));
/// assert_eq!(t.max_steps, 10 * s.max_steps);
/// ```
pub fn tightened(solver: &SolveSettings) -> SolveSettings {
    SolveSettings {
        rtol: solver.rtol / FACTOR,
        atol: solver.atol / FACTOR,
        max_steps: solver.max_steps.saturating_mul(FACTOR as usize),
        accuracy_check: false,
        ..*solver
    }
}

/// Runs `spec` at the [`tightened`] settings and compares `rec` (the run at `spec`'s own)
/// with it; the note says what a reader of the run should know: a difference past
/// [`CONTRACT`]·rtol, a check run that failed, or nothing compared.
///
/// ```
/// use celltissue::scenario::{accuracy_check, execute, load_str};
/// let text = "name = \"c\"\n[output]\nseries = [0, 1]\nprofiles = [1]\n[model]\n\
///             kind = \"line\"\nmodels = [\"discrete\"]\ncells = 8\nK = 1";
/// let s = load_str(text, "c.toml".as_ref(), &[])?;
/// let rec = execute::run_spec(&s.runs[0]); // without the check
/// let (c, note) = accuracy_check::check(&s.runs[0], &rec);
/// assert_eq!((c.rtol, c.profiles_compared, c.series_times_compared), (1e-7, 1, 2));
/// assert!(c.stretch_over_rtol <= accuracy_check::CONTRACT && note.is_none());
/// # Ok::<(), celltissue::scenario::ScenarioError>(())
/// ```
pub fn check(spec: &RunSpec, rec: &RunRecord) -> (AccuracyCheck, Option<String>) {
    let solver = tightened(&spec.solver);
    let tight_spec = RunSpec {
        solver,
        ..spec.clone()
    };
    let tight = super::execute::run_spec(&tight_spec);
    let result = match &tight.error {
        Some(e) => AccuracyCheck {
            rtol: solver.rtol,
            atol: solver.atol,
            steps: tight.stats.steps,
            failed: Some(e.clone()),
            ..Default::default()
        },
        None => AccuracyCheck {
            steps: tight.stats.steps,
            ..compare(rec, &tight, spec.solver.rtol, spec.solver.atol)
        },
    };
    let note = verdict(&result);
    (result, note)
}

/// The note a check leaves on its run, if any: the difference past [`CONTRACT`]·rtol, the
/// check run's failure, or no profile compared.
///
/// ```
/// use celltissue::observe::AccuracyCheck;
/// use celltissue::scenario::accuracy_check::verdict;
/// let within = AccuracyCheck { rtol: 1e-7, profiles_compared: 2, stretch_over_rtol: 3.0,
///     ..Default::default() };
/// assert_eq!(verdict(&within), None);
/// let past = AccuracyCheck { stretch_over_rtol: 86.0, cell: 4, t: 0.06, ..within };
/// assert!(verdict(&past).unwrap().contains("86·rtol in the stretch of cell 4 at t = 0.06"));
/// ```
pub fn verdict(c: &AccuracyCheck) -> Option<String> {
    let tight = integrators::error::short_number(c.rtol);
    if let Some(e) = &c.failed {
        return Some(format!(
            "the accuracy check could not compare: the same run at rtol {tight} failed: {e}"
        ));
    }
    if c.profiles_compared == 0 && c.series_times_compared == 0 {
        return Some(format!(
            "the accuracy check compared nothing: the run at rtol {tight} holds other cells at \
             every profile time and no series time has finite stretches in both, or the run \
             records neither"
        ));
    }
    let past = if c.stretch_over_rtol > CONTRACT {
        format!(
            "{:.0}·rtol in the stretch of cell {} at t = {}",
            c.stretch_over_rtol,
            c.cell,
            brief(c.t)
        )
    } else if c.series_stretch_over_rtol > CONTRACT {
        format!(
            "{:.0}·rtol in the smallest or largest stretch at t = {}",
            c.series_stretch_over_rtol,
            brief(c.series_t)
        )
    } else {
        return None;
    };
    Some(format!(
        "the same run at rtol {tight} differs by {past}, past the accuracy contract's \
         {CONTRACT}·rtol: this run's stretches may err by as much (the steps' errors add up \
         where cells are driven faster than they relax, and a model that amplifies \
         perturbations grows them; docs/limitations.md)"
    ))
}

/// Four significant digits, written as briefly as they allow.
fn brief(t: f64) -> f64 {
    format!("{t:.3e}").parse::<f64>().unwrap_or(t)
}

/// The largest differences of `run` (at `rtol`, `atol`) from `tight` over the profiles where
/// both hold the same cells, and of the series' smallest and largest stretch at every series
/// time, each over the contract's weight `|value| + atol/rtol` of the tighter run's value;
/// non-finite values are left out. `rtol` and `atol` of the result are
/// the run's over [`FACTOR`]; its `steps` are left at 0.
///
/// ```
/// use celltissue::observe::{Profile, RunRecord};
/// use celltissue::scenario::accuracy_check::compare;
/// # fn record(stretch: Vec<f64>) -> RunRecord {
/// #     RunRecord { label: "r".into(), model: celltissue::observe::ModelKind::Discrete,
/// #         parameters: serde_json::json!({}), series: Default::default(),
/// #         profiles: vec![Profile { t: 1.0, pressure: vec![1.0; stretch.len()], stretch,
/// #             ..Default::default() }],
/// #         stats: Default::default(), divisions: vec![], error: None, notes: vec![],
/// #         reference: None, accuracy_check: None }
/// # }
/// let run = record(vec![0.9, 1.100001]);
/// let tight = record(vec![0.9, 1.1]);
/// let c = compare(&run, &tight, 1e-6, 1e-8);
/// assert_eq!((c.cell, c.profiles_compared, c.series_times_compared), (1, 1, 0));
/// assert!((c.stretch_over_rtol - 1e-6 / (1.1 + 1e-2) / 1e-6).abs() < 1e-6);
/// ```
pub fn compare(run: &RunRecord, tight: &RunRecord, rtol: f64, atol: f64) -> AccuracyCheck {
    let floor = atol / rtol;
    let mut c = AccuracyCheck {
        rtol: rtol / FACTOR,
        atol: atol / FACTOR,
        ..Default::default()
    };
    for (p, q) in run.profiles.iter().zip(&tight.profiles) {
        if p.stretch.len() != q.stretch.len() || p.pressure.len() != q.pressure.len() {
            c.profiles_skipped += 1;
            continue;
        }
        c.profiles_compared += 1;
        for (a, b) in stretch_fields(p).zip(stretch_fields(q)) {
            for (i, d) in differences(a, b, floor) {
                if d > c.stretch_difference {
                    (c.stretch_difference, c.t, c.cell) = (d, q.t, i);
                }
            }
        }
        for (_, d) in differences(&p.pressure, &q.pressure, floor) {
            c.pressure_difference = c.pressure_difference.max(d);
        }
    }
    c.stretch_over_rtol = c.stretch_difference / rtol;
    let (a, b) = (&run.series, &tight.series);
    for (i, t) in a.t.iter().enumerate().take(b.t.len()) {
        let at = |s: &[f64]| s.get(i).copied().filter(|v| v.is_finite());
        let pairs = [
            (at(&a.min_stretch), at(&b.min_stretch)),
            (at(&a.max_stretch), at(&b.max_stretch)),
        ];
        if pairs.iter().any(|(x, y)| x.is_none() || y.is_none()) {
            continue;
        }
        c.series_times_compared += 1;
        for (x, y) in pairs.into_iter().filter_map(|(x, y)| x.zip(y)) {
            let d = (x - y).abs() / (y.abs() + floor) / rtol;
            if d > c.series_stretch_over_rtol {
                (c.series_stretch_over_rtol, c.series_t) = (d, *t);
            }
        }
    }
    c
}

/// A profile's stretches: along x (tan θ on a shear column) and, on a sheet, along y.
fn stretch_fields(p: &Profile) -> impl Iterator<Item = &[f64]> {
    std::iter::once(p.stretch.as_slice()).chain(p.extra.get("stretch_y").map(Vec::as_slice))
}

/// `(i, |a_i − b_i| / (|b_i| + floor))` wherever both are finite.
fn differences<'a>(
    a: &'a [f64],
    b: &'a [f64],
    floor: f64,
) -> impl Iterator<Item = (usize, f64)> + 'a {
    a.iter()
        .zip(b)
        .enumerate()
        .filter(|(_, (x, y))| x.is_finite() && y.is_finite())
        .map(move |(i, (x, y))| (i, (x - y).abs() / (y.abs() + floor)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observe::ModelKind;

    fn record(profiles: Vec<Profile>) -> RunRecord {
        RunRecord {
            label: "r".into(),
            model: ModelKind::Discrete,
            parameters: serde_json::json!({}),
            series: Default::default(),
            profiles,
            stats: Default::default(),
            divisions: vec![],
            error: None,
            notes: vec![],
            reference: None,
            accuracy_check: None,
        }
    }

    fn profile(t: f64, stretch: &[f64]) -> Profile {
        Profile {
            t,
            stretch: stretch.to_vec(),
            pressure: vec![1.0; stretch.len()],
            ..Default::default()
        }
    }

    #[test]
    fn profiles_of_other_cells_are_skipped_and_a_sheet_s_second_direction_counts() {
        let mut sheet = profile(2.0, &[1.0, 1.0]);
        sheet
            .extra
            .insert("stretch_y".into(), vec![1.0, 1.0 + 3e-6]);
        let mut sheet_tight = profile(2.0, &[1.0, 1.0]);
        sheet_tight.extra.insert("stretch_y".into(), vec![1.0, 1.0]);
        let run = record(vec![profile(1.0, &[1.0, 1.0, 1.0]), sheet]);
        let tight = record(vec![profile(1.0, &[1.0, 1.0]), sheet_tight]);
        let c = compare(&run, &tight, 1e-6, 1e-8);
        assert_eq!((c.profiles_compared, c.profiles_skipped), (1, 1));
        assert_eq!((c.t, c.cell), (2.0, 1));
        assert!((c.stretch_over_rtol - 3.0 / 1.01).abs() < 1e-6, "{c:?}");
        assert!(verdict(&c).is_none());
    }

    #[test]
    fn the_series_extremes_are_compared_at_every_series_time() {
        let series = |min: &[f64], max: &[f64]| crate::observe::Series {
            t: vec![0.0, 1.0, 2.0],
            min_stretch: min.to_vec(),
            max_stretch: max.to_vec(),
            ..Default::default()
        };
        let mut run = record(vec![]);
        run.series = series(&[1.0, 0.9 + 2e-5, f64::NAN], &[1.0, 1.1, 1.2]);
        let mut tight = record(vec![]);
        tight.series = series(&[1.0, 0.9, 0.8], &[1.0, 1.1, 1.2]);
        let c = compare(&run, &tight, 1e-6, 1e-8);
        assert_eq!((c.series_times_compared, c.series_t), (2, 1.0));
        assert!(
            (c.series_stretch_over_rtol - 2e-5 / 0.91 / 1e-6).abs() < 1e-6,
            "{c:?}"
        );
        let note = verdict(&c).expect("past the contract");
        assert!(
            note.contains("22·rtol in the smallest or largest stretch at t = 1"),
            "{note}"
        );
    }

    #[test]
    fn non_finite_values_are_left_out_and_nothing_compared_is_noted() {
        let run = record(vec![profile(1.0, &[f64::NAN, 1.0])]);
        let tight = record(vec![profile(1.0, &[1.0, 1.0])]);
        let c = compare(&run, &tight, 1e-6, 1e-8);
        assert_eq!((c.stretch_difference, c.profiles_compared), (0.0, 1));
        let none = compare(&record(vec![]), &record(vec![]), 1e-6, 1e-8);
        assert!(verdict(&none).unwrap().contains("compared nothing"));
    }
}
