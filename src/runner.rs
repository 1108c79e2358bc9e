//! [`run_recorded`]: the one run-and-record loop of every model — line, ring, proliferating
//! line, proliferating continuum, sheet, shear column and registered modes. A runner builds
//! its array from its configuration, then hands it here with a [`Recorder`] that says what a
//! state is recorded as (a [`SeriesRow`] at the series times, a [`Profile`] at the profile
//! times) and how a failure reads in the model's terms. The loop integrates with
//! [`crate::drive`], records inside the solver's observer (so records follow an array through
//! resizes), refuses a non-finite observation (the run stops there with the reason: records
//! never hold NaN), and returns the series, profiles, counters and error the runner puts in
//! its [`crate::observe::RunRecord`].

use crate::array::{ArrayProblem, CellArray};
use crate::drive::{drive_observed, DriveError, DriveObserver};
use crate::observe::{Profile, RunStats, Series};
use crate::settings::SolveSettings;
use integrators::error::short_number;
use integrators::observer::{Observer, RejectCause, RejectedStep};
use integrators::{RecoverableCause, SolveFailure};
use std::time::Instant;

/// Requested output times (each list increasing, `t ≥ 0`; the run starts at `t = 0`): the
/// one output request of every runner.
///
/// ```
/// use celltissue::runner::OutputTimes;
/// let t = OutputTimes { series: vec![0.0, 1.0, 2.0], profiles: vec![1.0, 5.0] };
/// assert_eq!(t.merged(), [0.0, 1.0, 2.0, 5.0]); // the integrator's output times
/// assert!(OutputTimes::at(&[1.0]).profiles.is_empty());
/// assert_eq!(OutputTimes::at(&[-1.0]).check().unwrap_err().to_string(), "output time -1 must be finite and >= 0");
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputTimes {
    /// Times of the scalar series.
    pub series: Vec<f64>,
    /// Times of the profiles.
    pub profiles: Vec<f64>,
}

/// An output time that is negative or not finite ([`OutputTimes::check`]).
///
/// ```
/// use celltissue::runner::OutputTimeError;
/// let e = OutputTimeError { time: f64::NAN };
/// assert_eq!(e.to_string(), "output time NaN must be finite and >= 0");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("output time {time} must be finite and >= 0")]
pub struct OutputTimeError {
    /// The first such time.
    pub time: f64,
}

/// Why a [`Recorder`] could not observe a state, in the model's terms (a cell out of its
/// domain, an observation the model cannot make there).
///
/// ```
/// use celltissue::runner::ObservationError;
/// use integrators::ResidualError;
/// let e = ObservationError::from(ResidualError::Recoverable {
///     reason: "cell 3 has non-positive stretch".into(),
///     component: Some(2),
/// });
/// assert_eq!(e.to_string(), "cell 3 has non-positive stretch");
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{reason}")]
pub struct ObservationError {
    /// The model's reason.
    pub reason: String,
}

impl From<integrators::ResidualError> for ObservationError {
    /// The residual error's message is its reason.
    fn from(e: integrators::ResidualError) -> Self {
        Self {
            reason: e.to_string(),
        }
    }
}

/// Why a state was not recorded (the run stops there with this message).
#[derive(Debug, thiserror::Error)]
enum RecordError {
    /// The recorder could not observe the state.
    #[error("observation at t = {} failed: {source}", short_number(*.t))]
    Observation { t: f64, source: ObservationError },
    /// What was observed holds a NaN or an infinity.
    #[error("non-finite state at t = {} ({what})", short_number(*.t))]
    NonFinite { t: f64, what: String },
}

impl OutputTimes {
    /// Series at `series`, no profiles.
    ///
    /// ```
    /// use celltissue::runner::OutputTimes;
    /// let o = OutputTimes::at(&[0.0, 1.0]);
    /// assert_eq!((o.series.as_slice(), o.profiles.is_empty()), (&[0.0, 1.0][..], true));
    /// ```
    pub fn at(series: &[f64]) -> Self {
        Self {
            series: series.to_vec(),
            profiles: Vec::new(),
        }
    }

    /// Every time finite and `≥ 0`; else the first that is not.
    ///
    /// ```
    /// use celltissue::runner::{OutputTimeError, OutputTimes};
    /// assert!(OutputTimes::at(&[0.0, 1.0]).check().is_ok());
    /// assert_eq!(OutputTimes::at(&[1.0, -1.0]).check(), Err(OutputTimeError { time: -1.0 }));
    /// ```
    pub fn check(&self) -> Result<(), OutputTimeError> {
        match self
            .series
            .iter()
            .chain(&self.profiles)
            .find(|t| !(t.is_finite() && **t >= 0.0))
        {
            Some(&time) => Err(OutputTimeError { time }),
            None => Ok(()),
        }
    }

    /// Sorted, deduplicated union of both lists (finite times only).
    ///
    /// ```
    /// use celltissue::runner::OutputTimes;
    /// let o = OutputTimes { series: vec![2.0, 0.0, 1.0], profiles: vec![1.0, 5.0] };
    /// assert_eq!(o.merged(), [0.0, 1.0, 2.0, 5.0]);
    /// ```
    pub fn merged(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self
            .series
            .iter()
            .chain(&self.profiles)
            .copied()
            .filter(|t| t.is_finite())
            .collect();
        t.sort_by(f64::total_cmp);
        t.dedup();
        t
    }
}

/// The scalar values recorded at one series time: the five every record has, and the model's
/// own (`extra`, by name).
///
/// ```
/// use celltissue::runner::SeriesRow;
/// use celltissue::observe::Series;
/// let row = SeriesRow { length: 10.0, extra: vec![("cells".into(), 10.0)], ..Default::default() };
/// let mut s = Series::default();
/// s.push_row(0.5, &row);
/// assert_eq!((s.t[0], s.length[0], s.extra["cells"][0]), (0.5, 10.0, 10.0));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeriesRow {
    /// The array's length (a sheet's or mode's own measure; the shear column's top
    /// displacement).
    pub length: f64,
    /// Largest pressure.
    pub max_pressure: f64,
    /// Smallest pressure.
    pub min_pressure: f64,
    /// Largest stretch (`tan θ` on a shear column).
    pub max_stretch: f64,
    /// Smallest stretch.
    pub min_stretch: f64,
    /// Further series by name.
    pub extra: Vec<(String, f64)>,
}

impl SeriesRow {
    /// The first non-finite value's name, if any.
    fn non_finite(&self) -> Option<&str> {
        let fixed = [
            ("length", self.length),
            ("max_pressure", self.max_pressure),
            ("min_pressure", self.min_pressure),
            ("max_stretch", self.max_stretch),
            ("min_stretch", self.min_stretch),
        ];
        fixed
            .into_iter()
            .chain(self.extra.iter().map(|(k, v)| (k.as_str(), *v)))
            .find(|(_, v)| !v.is_finite())
            .map(|(k, _)| k)
    }

    /// The five fixed values from a profile's extremes (pressure and stretch), with `length`
    /// and no extra series.
    ///
    /// ```
    /// use celltissue::observe::Profile;
    /// use celltissue::runner::SeriesRow;
    /// let p = Profile { stretch: vec![0.9, 1.1], pressure: vec![2.0, 1.0], ..Default::default() };
    /// let row = SeriesRow::from_profile(&p, 5.0);
    /// assert_eq!((row.max_pressure, row.min_stretch, row.length), (2.0, 0.9, 5.0));
    /// ```
    pub fn from_profile(p: &Profile, length: f64) -> Self {
        let extreme = |v: &[f64], max: bool| {
            v.iter()
                .copied()
                .reduce(if max { f64::max } else { f64::min })
                .unwrap_or(f64::NAN)
        };
        Self {
            length,
            max_pressure: extreme(&p.pressure, true),
            min_pressure: extreme(&p.pressure, false),
            max_stretch: extreme(&p.stretch, true),
            min_stretch: extreme(&p.stretch, false),
            extra: Vec::new(),
        }
    }
}

/// What a run records of its array `A`'s states, and how its failures read.
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::{Line, OutputTimes};
/// use celltissue::observe::Profile;
/// use celltissue::runner::{run_recorded, ObservationError, Recorder, SeriesRow};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// /// Records only the first free boundary's position x₁ (the state's first unknown).
/// struct FirstBoundary;
/// impl Recorder<Line<NeoHookean>> for FirstBoundary {
///     fn series_row(&mut self, _: &Line<NeoHookean>, _t: f64, y: &[f64], _: &[f64])
///         -> Result<SeriesRow, ObservationError> {
///         Ok(SeriesRow { length: y[0], ..Default::default() })
///     }
///     fn profile(&mut self, _: &Line<NeoHookean>, t: f64, y: &[f64], _: &[f64])
///         -> Result<Profile, ObservationError> {
///         Ok(Profile { t, x: y.to_vec(), ..Default::default() })
///     }
/// }
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(5)).unwrap();
/// let y0 = line.initial_state();
/// let times = OutputTimes { series: vec![0.0, 1.0], profiles: vec![1.0] };
/// let r = run_recorded(&mut ArrayProblem::new(line), &y0, &[], &SolveSettings::default(),
///                      &times, &mut FirstBoundary);
/// assert!(r.error.is_none());
/// assert_eq!(r.series.length, [1.0, 1.0]); // a line held at its rest length stays at rest
/// assert_eq!(r.profiles.len(), 1);
/// ```
pub trait Recorder<A> {
    /// The series values of the state at `t`.
    fn series_row(
        &mut self,
        array: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<SeriesRow, ObservationError>;

    /// The profile of the state at `t`.
    fn profile(
        &mut self,
        array: &A,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<Profile, ObservationError>;

    /// The message of a failed solve, in the model's terms; `rejected` is the last step the
    /// model itself rejected (its own reason), if any. Default: the solver's message, with
    /// the model's reason first when the step that failed had one.
    fn explain(
        &self,
        _array: &A,
        failure: &SolveFailure,
        rejected: Option<&RejectedStep>,
    ) -> String {
        let solver = failure.error.to_string();
        match model_reason(failure, rejected) {
            Some(r) => format!("{r}; solver: {solver}"),
            None => solver,
        }
    }
}

/// The model's own reason for rejecting the step that failed ("cell 4 has non-positive
/// stretch … in the step from t = … (h = …)"), when the solver's error does not already say
/// it: the last rejected step, if it started at or after the failure and the model (not the
/// error test or Newton) rejected it.
///
/// ```
/// use celltissue::runner::model_reason;
/// use integrators::observer::{RejectCause, RejectedStep};
/// use integrators::{ErrorKind, RecoverableCause, SolveFailure, SolverError};
/// let failure = SolveFailure {
///     error: SolverError::new(ErrorKind::StepSizeTooSmall { h: 1e-14 }, 3.0, Some(5)),
///     partial: Box::default(),
/// };
/// let step = RejectedStep {
///     t: 3.0, h: 1e-4, component: Some(5),
///     cause: RejectCause::Recoverable(RecoverableCause::Rejected("cell 6 collapsed".into())),
/// };
/// assert_eq!(model_reason(&failure, Some(&step)).unwrap(),
///            "cell 6 collapsed in the step from t = 3 (h = 1.0e-4)");
/// // an error-test rejection is no reason of the model's
/// let step = RejectedStep { cause: RejectCause::ErrorTest, ..step };
/// assert_eq!(model_reason(&failure, Some(&step)), None);
/// ```
pub fn model_reason(failure: &SolveFailure, rejected: Option<&RejectedStep>) -> Option<String> {
    let r = rejected?;
    let RejectCause::Recoverable(RecoverableCause::Rejected(reason)) = &r.cause else {
        return None;
    };
    let solver = failure.error.to_string();
    (r.t >= failure.error.t && !solver.contains(reason.as_str())).then(|| {
        format!(
            "{reason} in the step from t = {} (h = {:.1e})",
            short_number(r.t),
            r.h
        )
    })
}

/// What [`run_recorded`] returns: the recorded series and profiles, the work counters and
/// wall time, and the error that stopped the run early (everything before it is kept).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::run::LineRecorder;
/// use celltissue::runner::{run_recorded, OutputTimes, Recording};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let mut p = LineParams::unit_cells(10);
/// p.k = 1.0.into();
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let y0 = line.initial_state();
/// let times = OutputTimes { series: vec![0.0, 0.5, 1.0], profiles: vec![1.0] };
/// let r: Recording = run_recorded(&mut ArrayProblem::new(line), &y0, &[],
///                                 &SolveSettings::default(), &times, &mut LineRecorder);
/// assert!(r.error.is_none() && r.stats.steps > 0);
/// assert_eq!((r.series.t.len(), r.profiles.len(), r.y_last.len()), (3, 1, y0.len()));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// The series at the series times reached.
    pub series: Series,
    /// The profiles at the profile times reached.
    pub profiles: Vec<Profile>,
    /// Work counters (summed over restarts) and wall time.
    pub stats: RunStats,
    /// Why the run stopped early.
    pub error: Option<String>,
    /// The last state reached.
    pub y_last: Vec<f64>,
}

/// Integrates `problem` from `(0, y0)` (restarting at `breakpoints`) with `settings`, and
/// records with `recorder` a series row at each of `times.series` and a profile at each of
/// `times.profiles` (see [`Recorder`] for a recorder of one's own). Output times must be
/// finite and `≥ 0` (a runner checks them first). An observation with a non-finite value
/// stops the run there:
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::line::Line;
/// use celltissue::observe::Profile;
/// use celltissue::runner::{run_recorded, ObservationError, OutputTimes, Recorder, SeriesRow};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// /// A length that is NaN from t = 1 on.
/// struct Broken;
/// impl Recorder<Line<NeoHookean>> for Broken {
///     fn series_row(&mut self, _: &Line<NeoHookean>, t: f64, _: &[f64], _: &[f64])
///         -> Result<SeriesRow, ObservationError> {
///         Ok(SeriesRow { length: if t < 1.0 { 1.0 } else { f64::NAN }, ..Default::default() })
///     }
///     fn profile(&mut self, _: &Line<NeoHookean>, t: f64, _: &[f64], _: &[f64])
///         -> Result<Profile, ObservationError> { Ok(Profile { t, ..Default::default() }) }
/// }
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
/// let y0 = line.initial_state();
/// let r = run_recorded(&mut ArrayProblem::new(line), &y0, &[], &SolveSettings::default(),
///                      &OutputTimes::at(&[0.0, 0.5, 1.0, 2.0]), &mut Broken);
/// assert_eq!(r.series.t, [0.0, 0.5]); // nothing non-finite is recorded
/// assert_eq!(r.error.unwrap(), "non-finite state at t = 1 (series `length`)");
/// ```
pub fn run_recorded<A: CellArray, R: Recorder<A>>(
    problem: &mut ArrayProblem<A>,
    y0: &[f64],
    breakpoints: &[f64],
    settings: &SolveSettings,
    times: &OutputTimes,
    recorder: &mut R,
) -> Recording {
    let start = Instant::now();
    let t_out = times.merged();
    let mut watch = Watch {
        recorder,
        series_at: Cursor::new(&times.series),
        profiles_at: Cursor::new(&times.profiles),
        series: Series::default(),
        profiles: Vec::new(),
        rejected: None,
        refusal: None,
    };
    let driven = drive_observed(problem, settings, y0, &t_out, breakpoints, &mut watch);
    let error = driven.error.map(|e| match e {
        DriveError::Solver(f) => {
            watch
                .recorder
                .explain(&problem.array, &f, watch.rejected.as_ref())
        }
        other => other.to_string(),
    });
    Recording {
        series: watch.series,
        profiles: watch.profiles,
        stats: RunStats::from_stats(&driven.stats, start.elapsed().as_secs_f64()),
        error,
        y_last: driven.y_last,
    }
}

/// The observer [`run_recorded`] drives with: records at the outputs, keeps the last step the
/// model rejected.
struct Watch<'a, R> {
    recorder: &'a mut R,
    series_at: Cursor,
    profiles_at: Cursor,
    series: Series,
    profiles: Vec<Profile>,
    rejected: Option<RejectedStep>,
    refusal: Option<String>,
}

impl<R> Watch<'_, R> {
    /// Records the state at `t` if it is a series or profile time; refuses a failed or
    /// non-finite observation.
    fn record<A: CellArray>(
        &mut self,
        p: &ArrayProblem<A>,
        t: f64,
        y: &[f64],
        yp: &[f64],
    ) -> Result<(), RecordError>
    where
        R: Recorder<A>,
    {
        let failed = |source| RecordError::Observation { t, source };
        if self.series_at.hit(t) {
            let row = self
                .recorder
                .series_row(&p.array, t, y, yp)
                .map_err(failed)?;
            if let Some(k) = row.non_finite() {
                let what = format!("series `{k}`");
                return Err(RecordError::NonFinite { t, what });
            }
            self.series.push_row(t, &row);
        }
        if self.profiles_at.hit(t) {
            let profile = self.recorder.profile(&p.array, t, y, yp).map_err(failed)?;
            let fields = [
                &profile.x_ref,
                &profile.x,
                &profile.stretch,
                &profile.pressure,
            ];
            let finite = fields.into_iter().chain(profile.extra.values()).flatten();
            if !finite.copied().all(f64::is_finite) {
                let what = "profile".to_string();
                return Err(RecordError::NonFinite { t, what });
            }
            self.profiles.push(profile);
        }
        Ok(())
    }
}

impl<A: CellArray, R: Recorder<A>> Observer<ArrayProblem<A>> for Watch<'_, R> {
    fn output(&mut self, p: &ArrayProblem<A>, t: f64, y: &[f64], yp: &[f64]) {
        if let Err(e) = self.record(p, t, y, yp) {
            self.refusal = Some(e.to_string());
        }
    }

    fn rejected(&mut self, _: &ArrayProblem<A>, step: &RejectedStep) {
        if rejected_by_the_model(step) {
            self.rejected = Some(step.clone());
        }
    }
}

impl<A: CellArray, R: Recorder<A>> DriveObserver<ArrayProblem<A>> for Watch<'_, R> {
    fn take_refusal(&mut self) -> Option<String> {
        self.refusal.take()
    }
}

/// Requested times in increasing order and how far the outputs have come: the solver reports
/// outputs in increasing time, so each is matched in amortised O(1) instead of a search of
/// every requested time (O(T²) over a run with T outputs).
struct Cursor {
    times: Vec<f64>,
    next: usize,
}

impl Cursor {
    fn new(times: &[f64]) -> Self {
        let mut times = times.to_vec();
        times.sort_by(f64::total_cmp);
        Self { times, next: 0 }
    }

    /// Whether `t` is one of the times (outputs come in increasing `t`).
    fn hit(&mut self, t: f64) -> bool {
        while self.times.get(self.next).is_some_and(|&s| s < t) {
            self.next += 1;
        }
        self.times.get(self.next) == Some(&t)
    }
}

/// Whether the model itself rejected the step (its residual refused the state), rather than
/// the error test, Newton or a factorisation.
///
/// ```
/// use celltissue::runner::rejected_by_the_model;
/// use integrators::observer::{RejectCause, RejectedStep};
/// use integrators::RecoverableCause;
/// let model = RejectCause::Recoverable(RecoverableCause::Rejected("cell 2 collapsed".into()));
/// let step = RejectedStep { t: 0.0, h: 0.1, cause: model, component: None };
/// assert!(rejected_by_the_model(&step));
/// assert!(!rejected_by_the_model(&RejectedStep { cause: RejectCause::Newton, ..step }));
/// ```
pub fn rejected_by_the_model(step: &RejectedStep) -> bool {
    matches!(
        step.cause,
        RejectCause::Recoverable(RecoverableCause::Rejected(_))
    )
}

#[cfg(test)]
mod tests {
    use super::Cursor;

    /// Outputs in increasing time hit exactly the requested ones, whatever order they were
    /// requested in.
    #[test]
    fn cursor_matches_the_requested_times_in_any_order() {
        let mut c = Cursor::new(&[5.0, 1.0, 3.0]);
        let hits: Vec<bool> = [0.0, 1.0, 2.0, 3.0, 5.0, 6.0]
            .iter()
            .map(|&t| c.hit(t))
            .collect();
        assert_eq!(hits, [false, true, false, true, true, false]);
    }
}
