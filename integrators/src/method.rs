//! The [`Method`] trait every time-stepping scheme implements, and [`MethodKind`], which picks one
//! by value or by name.

use crate::error::SolverError;
use crate::system::System;

/// One time-stepping scheme. A method owns its step-size/order state and history, not the
/// problem; the driver ([`crate::Solver`]) owns the loop, output, and events, and restarts the
/// method with [`start`](Method::start) after every event (possibly with a new dimension).
pub trait Method {
    /// Short name (`"bdf"`, `"esdirk"`, `"radau"`, `"dopri"`).
    fn name(&self) -> &'static str;

    /// (Re)starts from a consistent state `(t, y, ẏ)`. `h` is a step-size hint (`None`: the method
    /// estimates one). Called at the start and after every event/resize; the dimension may differ
    /// from the previous call (rebuild workspaces from `sys`).
    fn start(
        &mut self,
        sys: &mut System<'_>,
        t: f64,
        y: &[f64],
        yp: &[f64],
        h: Option<f64>,
    ) -> Result<(), SolverError>;

    /// Continues across a resizing event at `t` (inside the last accepted step) instead of
    /// restarting: the method keeps its history nodes before `t`, maps each onto the new
    /// layout with [`crate::Problem::map_history`] (through `sys.problem`), puts `(t, y, ẏ)` in
    /// front and goes on with its order and step size. `y`, `yp`: the state after the event and
    /// its mapped derivative. Returns `Ok(false)` when it cannot (no history, or the problem
    /// has no map); the driver then calls [`start`](Method::start). Default: `Ok(false)`.
    fn resume(
        &mut self,
        _sys: &mut System<'_>,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
    ) -> Result<bool, SolverError> {
        Ok(false)
    }

    /// Advances by one accepted step, never beyond `t_stop` (landing on it exactly when it is
    /// reached), and returns how many accepted steps that took: 1, or more for a method that
    /// takes internal sub-steps (BDF's restart takes two half steps). The driver counts steps
    /// from it (`Stats::steps`, `Options::max_steps`); a method does not touch `stats.steps`.
    /// Rejected attempts are counted by the method (`Stats::rejected_steps`). On error the
    /// method's state is the last accepted one.
    fn step(&mut self, sys: &mut System<'_>, t_stop: f64) -> Result<usize, SolverError>;

    /// Time of the last accepted step.
    fn t(&self) -> f64;
    /// Time at the start of the last accepted step.
    fn t_prev(&self) -> f64;
    /// State at [`t`](Method::t).
    fn y(&self) -> &[f64];
    /// Derivative at [`t`](Method::t).
    fn yp(&self) -> &[f64];
    /// Step size to try next.
    fn h_next(&self) -> f64;
    /// Dense output: state and derivative at any `t` in `[t_prev, t]`.
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]);
}

/// The available methods, selectable in one line of code or by name.
///
/// ```
/// use integrators::MethodKind;
/// let m: MethodKind = "radau".parse().unwrap();
/// assert_eq!(m, MethodKind::Radau);
/// assert!("euler".parse::<MethodKind>().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MethodKind {
    /// Variable-order (1–5), variable-step BDF in residual form (ode15s / IDA family).
    Bdf,
    /// L-stable ESDIRK (TR-BDF2 with embedded error estimate).
    Esdirk,
    /// Radau IIA, order 5.
    Radau,
    /// Dormand–Prince 5(4), explicit (non-stiff; needs `∂F/∂ẏ` nonsingular).
    Dopri,
}

impl MethodKind {
    /// All methods, in a fixed order.
    pub const ALL: [MethodKind; 4] = [
        MethodKind::Bdf,
        MethodKind::Esdirk,
        MethodKind::Radau,
        MethodKind::Dopri,
    ];

    /// The name accepted by [`std::str::FromStr`].
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Bdf => "bdf",
            MethodKind::Esdirk => "esdirk",
            MethodKind::Radau => "radau",
            MethodKind::Dopri => "dopri",
        }
    }

    /// Whether the method is implicit (handles stiffness and algebraic components).
    pub fn is_stiff(self) -> bool {
        !matches!(self, MethodKind::Dopri)
    }

    /// A fresh method object.
    pub fn build(self) -> Box<dyn Method> {
        crate::methods::build(self)
    }
}

impl std::str::FromStr for MethodKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "bdf" => Ok(MethodKind::Bdf),
            "esdirk" | "trbdf2" | "tr-bdf2" => Ok(MethodKind::Esdirk),
            "radau" | "radau5" | "radauiia" => Ok(MethodKind::Radau),
            "dopri" | "dopri5" | "rk45" => Ok(MethodKind::Dopri),
            other => Err(format!(
                "unknown method `{other}`; valid: bdf, esdirk, radau, dopri"
            )),
        }
    }
}

impl std::fmt::Display for MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
