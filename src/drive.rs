//! [`drive`]: the one integration loop every runner uses — line, ring, proliferating line,
//! sheet, shear column and registered modes. It turns the [`SolveSettings`] into the
//! integrators' options, integrates from `t = 0` piecewise between the model's breakpoints (a
//! restart with a consistent `ẏ` at each, where the forcing is not smooth), hands every
//! requested output, accepted and rejected step and event to the caller's [`DriveObserver`]
//! inside the solver (so observations follow an array through resizes), and sums the work
//! counters over the pieces. The runners turn what it returns into their own records and
//! messages.

use crate::settings::SolveSettings;
use integrators::observer::{AcceptedStep, Observer, RejectedStep};
use integrators::{EventRecord, OptionsError, Problem, SolveFailure, Solver, Stats};

/// What [`drive`] reports to while it integrates: an [`Observer`] of the solver (every
/// requested output, and each accepted step, rejected attempt — with its cause and worst
/// unknown — and handled event it wants, across the pieces between breakpoints) that may also
/// refuse an output, stopping the run: after each output, [`drive_observed`] takes the
/// observer's refusal, if any. [`drive`] takes a closure observing outputs only.
///
/// ```
/// use celltissue::drive::{drive_observed, DriveObserver};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// use integrators::observer::{AcceptedStep, Observer, RejectedStep};
/// /// The smallest step taken and the rejected attempts.
/// struct Steps { h_min: f64, rejected: Vec<RejectedStep> }
/// impl<P> Observer<P> for Steps {
///     fn accepted(&mut self, _: &P, s: &AcceptedStep, _: &[f64]) {
///         self.h_min = self.h_min.min(s.t - s.t_prev);
///     }
///     fn rejected(&mut self, _: &P, s: &RejectedStep) { self.rejected.push(s.clone()); }
/// }
/// impl<P> DriveObserver<P> for Steps {} // refuses nothing
/// let mut p = LineParams::unit_cells(50);
/// p.k = 1.0.into();
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let y0 = line.initial_state();
/// let mut steps = Steps { h_min: f64::INFINITY, rejected: Vec::new() };
/// let d = drive_observed(&mut ArrayProblem::new(line), &SolveSettings::default(), &y0,
///                        &[10.0], &[], &mut steps);
/// assert!(d.error.is_none() && steps.h_min < 1e-3);
/// assert_eq!(steps.rejected.len(), d.stats.rejected_steps);
/// ```
pub trait DriveObserver<P>: Observer<P> {
    /// Why the observer refused the output it was last given, if it did (taken: the next call
    /// gives `None` unless it refuses again). The run stops after the current piece with this
    /// message. Default: it refuses nothing.
    fn take_refusal(&mut self) -> Option<String> {
        None
    }
}

impl<P, O: DriveObserver<P> + ?Sized> DriveObserver<P> for &mut O {
    fn take_refusal(&mut self) -> Option<String> {
        (**self).take_refusal()
    }
}

/// An observer of outputs only, from a closure that may refuse one (what [`drive`] wraps its
/// closure in).
struct OnOutput<F> {
    observe: F,
    refusal: Option<String>,
}

/// What an output closure given to [`drive`] returns to refuse an output: any error
/// (`Err("why".into())` for a message).
pub type Refusal = Box<dyn std::error::Error + Send + Sync>;

impl<P, F> Observer<P> for OnOutput<F>
where
    F: FnMut(&P, f64, &[f64], &[f64]) -> Result<(), Refusal>,
{
    fn output(&mut self, problem: &P, t: f64, y: &[f64], yp: &[f64]) {
        if let Err(e) = (self.observe)(problem, t, y, yp) {
            self.refusal = Some(e.to_string());
        }
    }
}

impl<P, F> DriveObserver<P> for OnOutput<F>
where
    F: FnMut(&P, f64, &[f64], &[f64]) -> Result<(), Refusal>,
{
    fn take_refusal(&mut self) -> Option<String> {
        self.refusal.take()
    }
}

/// One piece's view of the caller's observer: outputs after a refusal, and the piece's own
/// stop when it is not a requested output, are not passed on.
struct Piece<'o, O> {
    observer: &'o mut O,
    stop: f64,
    requested_stop: bool,
    refused: Option<String>,
}

impl<P, O: DriveObserver<P>> Observer<P> for Piece<'_, O> {
    fn output(&mut self, problem: &P, t: f64, y: &[f64], yp: &[f64]) {
        if self.refused.is_some() || (t == self.stop && !self.requested_stop) {
            return;
        }
        self.observer.output(problem, t, y, yp);
        self.refused = self.observer.take_refusal();
    }
    fn accepted(&mut self, problem: &P, step: &AcceptedStep, y: &[f64]) {
        self.observer.accepted(problem, step, y);
    }
    fn rejected(&mut self, problem: &P, step: &RejectedStep) {
        self.observer.rejected(problem, step);
    }
    fn event(&mut self, problem: &P, event: &EventRecord, y: &[f64]) {
        self.observer.event(problem, event, y);
    }
}

/// Why [`drive`] stopped before the last output time.
///
/// ```
/// use celltissue::drive::{drive, DriveError};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
/// let y0 = line.initial_state();
/// let mut p = ArrayProblem::new(line);
/// // a setting out of range: nothing is integrated, and the key is named
/// let bad = SolveSettings { rtol: 2.0, ..Default::default() };
/// let d = drive(&mut p, &bad, &y0, &[1.0], &[], |_, _, _, _| Ok(()));
/// assert!(matches!(d.error, Some(DriveError::Settings(_))));
/// assert!(d.error.unwrap().to_string().starts_with("solver.rtol"));
/// // an observer that refuses stops the run at that output
/// let d = drive(&mut p, &SolveSettings::default(), &y0, &[0.5, 1.0], &[],
///               |_, t, _, _| if t > 0.7 { Err(format!("no output at {t}").into()) } else { Ok(()) });
/// assert_eq!(d.error.unwrap().to_string(), "no output at 1");
/// ```
#[derive(Debug)]
pub enum DriveError {
    /// A setting out of range (nothing was integrated).
    Settings(OptionsError),
    /// The solver failed; the failure keeps the partial solution and the last accepted state.
    Solver(SolveFailure),
    /// The observer refused an output, with its message (the solve stopped at that output's
    /// piece).
    Observer(String),
}

impl std::fmt::Display for DriveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DriveError::Settings(e) => write!(f, "solver.{e}"),
            DriveError::Solver(e) => write!(f, "{}", e.error),
            DriveError::Observer(m) => f.write_str(m),
        }
    }
}

/// What [`drive`] did: the counters summed over its pieces, the last state reached and its
/// time, and why it stopped early, if it did.
///
/// ```
/// use celltissue::drive::drive;
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(4)).unwrap();
/// let y0 = line.initial_state();
/// let d = drive(&mut ArrayProblem::new(line), &SolveSettings::default(), &y0, &[2.0], &[1.0],
///               |_, _, _, _| Ok(()));
/// // two pieces (restart at the breakpoint t = 1), their counters summed
/// assert!(d.error.is_none() && d.t_last == 2.0 && d.stats.steps > 0);
/// assert_eq!(d.y_last.len(), y0.len());
/// ```
#[derive(Debug)]
pub struct Driven {
    /// Work counters, summed over the pieces (and the failed one's partial work).
    pub stats: Stats,
    /// Time of `y_last`.
    pub t_last: f64,
    /// The last state reached (the initial state if nothing was integrated).
    pub y_last: Vec<f64>,
    /// Why the run stopped early.
    pub error: Option<DriveError>,
}

/// Integrates `problem` from `(0, y0)` through the output times `t_out` (increasing, `≥ 0`;
/// `t = 0` is observed after the consistent initialisation), restarting at each of
/// `breakpoints` inside `(0, t_out.last())`; `observer` is told every output time reached
/// (an `Err` from it stops the run after that piece), and every step, rejection and event.
///
/// ```
/// use celltissue::drive::drive;
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &LineParams::unit_cells(10)).unwrap();
/// let y0 = line.initial_state();
/// let mut seen = Vec::new();
/// let d = drive(&mut ArrayProblem::new(line), &SolveSettings::default(), &y0, &[0.0, 0.5, 2.0],
///               &[1.0], |_, t, _, _| { seen.push(t); Ok(()) });
/// assert!(d.error.is_none());
/// assert_eq!(seen, [0.0, 0.5, 2.0]); // the restart at the breakpoint t = 1 is not an output
/// assert_eq!(d.t_last, 2.0);
/// ```
pub fn drive<P: Problem>(
    problem: &mut P,
    settings: &SolveSettings,
    y0: &[f64],
    t_out: &[f64],
    breakpoints: &[f64],
    observe: impl FnMut(&P, f64, &[f64], &[f64]) -> Result<(), Refusal>,
) -> Driven {
    let observer = OnOutput {
        observe,
        refusal: None,
    };
    drive_observed(problem, settings, y0, t_out, breakpoints, observer)
}

/// As [`drive`], reporting outputs, accepted and rejected steps and events to `observer` (see
/// [`DriveObserver`] for an observer of one's own). Events, e.g. a proliferating line's
/// divisions:
///
/// ```
/// use celltissue::drive::{drive_observed, DriveObserver};
/// use celltissue::events::{AreaDoubling, Dividing};
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean, SolveSettings};
/// use integrators::{observer::Observer, EventRecord};
/// /// The number of unknowns after each event.
/// struct Sizes(Vec<usize>);
/// impl<P> Observer<P> for Sizes {
///     fn event(&mut self, _: &P, _: &EventRecord, y: &[f64]) { self.0.push(y.len()); }
/// }
/// impl<P> DriveObserver<P> for Sizes {}
/// let mut p = LineParams::unit_cells(4);
/// p.right = celltissue::boundary::RightEnd::Free(None);
/// p.growth = Some(std::sync::Arc::new(celltissue::cell::TanhGrowth::default()));
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let dividing = Dividing::new(line, Box::new(AreaDoubling::default()), 0).unwrap();
/// let y0 = dividing.line.initial_state();
/// let mut sizes = Sizes(Vec::new());
/// let d = drive_observed(&mut ArrayProblem::new(dividing), &SolveSettings::default(), &y0,
///                        &[2.5], &[], &mut sizes);
/// assert!(d.error.is_none());
/// assert_eq!(sizes.0.len(), d.stats.events);
/// assert!(sizes.0.windows(2).all(|w| w[1] > w[0])); // every division adds unknowns
/// ```
pub fn drive_observed<P: Problem>(
    problem: &mut P,
    settings: &SolveSettings,
    y0: &[f64],
    t_out: &[f64],
    breakpoints: &[f64],
    mut observer: impl DriveObserver<P>,
) -> Driven {
    let mut driven = Driven {
        stats: Stats::default(),
        t_last: 0.0,
        y_last: y0.to_vec(),
        error: None,
    };
    let opts = match settings.options() {
        Ok(o) => o,
        Err(e) => {
            driven.error = Some(DriveError::Settings(e));
            return driven;
        }
    };
    let Some(&t_end) = t_out.last() else {
        return driven;
    };
    let solver = Solver::new(settings.method, opts);
    let mut stops: Vec<f64> = breakpoints
        .iter()
        .copied()
        .filter(|&b| b > 0.0 && b < t_end)
        .collect();
    stops.push(t_end);
    for (piece, &stop) in stops.iter().enumerate() {
        let t0 = driven.t_last;
        let mut outs: Vec<f64> = t_out
            .iter()
            .copied()
            .filter(|&t| (t > t0 || (piece == 0 && t >= t0)) && t <= stop)
            .collect();
        let requested_stop = outs.last() == Some(&stop);
        if !requested_stop {
            outs.push(stop);
        }
        let mut piece = Piece {
            observer: &mut observer,
            stop,
            requested_stop,
            refused: None,
        };
        let result = solver.solve_observed(problem, t0, &driven.y_last, &outs, &mut piece);
        let refused = piece.refused;
        match result {
            Ok(sol) => {
                driven.stats += &sol.stats;
                driven.y_last = sol.y_last;
                driven.t_last = sol.t_last;
            }
            Err(f) => {
                driven.stats += &f.partial.stats;
                driven.t_last = f.partial.t_last;
                driven.y_last = f.partial.y_last.clone();
                driven.error = Some(DriveError::Solver(f));
                return driven;
            }
        }
        if let Some(m) = refused {
            driven.error = Some(DriveError::Observer(m));
            return driven;
        }
    }
    driven
}
