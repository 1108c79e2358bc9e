//! The driver: consistent initialisation, stepping, output at requested times, event location
//! and actions (stop / modify / resize), statistics and errors with the partial solution.

use crate::problem::EventAction;
use crate::stats::Stats;

/// One handled event.
#[derive(Clone, Debug, PartialEq)]
pub struct EventRecord {
    /// Located event time.
    pub t: f64,
    /// Indices of the event functions that changed sign.
    pub fired: Vec<usize>,
    /// What the problem did.
    pub action: EventAction,
    /// Problem dimension after the action.
    pub dim_after: usize,
}

/// Output of a solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solution {
    /// Output times reached (the requested ones, plus the stop time of a `Stop` event).
    pub t: Vec<f64>,
    /// States at `t` (lengths may differ across resizes).
    pub y: Vec<Vec<f64>>,
    /// Derivatives at `t`.
    pub yp: Vec<Vec<f64>>,
    /// Events handled, in time order.
    pub events: Vec<EventRecord>,
    /// Work counters.
    pub stats: Stats,
    /// Last accepted time.
    pub t_last: f64,
    /// Last accepted state.
    pub y_last: Vec<f64>,
}

/// SKELETON: `Solver` is filled in by the driver/BDF work item.
pub struct Solver;
