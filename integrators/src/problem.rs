//! The user's side of the contract: a residual-form DAE `F(t, y, ẏ) = 0` with declared
//! structure, tolerances, algebraic flags and events (which may stop, modify or resize it).

use crate::linalg::Matrix;
use crate::pattern::Pattern;

/// Where a user-supplied Jacobian is written: a matrix already shaped by the declared
/// [`Pattern`]; call [`Matrix::add`] for each structural nonzero.
pub type JacobianSink = Matrix;

/// Why a residual could not be evaluated.
///
/// `Recoverable` makes the integrator reject the current step (or Newton iterate) and retry with
/// a smaller step — use it for states outside the model's domain (e.g. a non-positive cell
/// length). `Fatal` aborts the solve with the message.
///
/// ```
/// use integrators::{MethodKind, Options, Problem, ResidualError, Solver};
/// /// ẏ = 1 with y > 2 outside the domain: the solve stops there, naming the component.
/// struct Wall;
/// impl Problem for Wall {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) -> Result<(), ResidualError> {
///         if y[0] > 2.0 {
///             return Err(ResidualError::Recoverable { reason: "past the wall".into(), component: Some(0) });
///         }
///         r[0] = yp[0] - 1.0;
///         Ok(())
///     }
/// }
/// let e = Solver::new(MethodKind::Bdf, Options::default()).solve(&mut Wall, 0.0, &[0.0], &[5.0]).unwrap_err();
/// assert!(e.to_string().contains("past the wall"), "{e}");
/// assert!(e.partial.t_last < 2.0 + 1e-9); // what it had computed is kept
/// ```
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ResidualError {
    /// The state is outside the domain; a smaller step may avoid it.
    #[error("{reason}")]
    Recoverable {
        /// Human-readable reason.
        reason: String,
        /// Component (unknown index) responsible, if known.
        component: Option<usize>,
    },
    /// Evaluation cannot succeed; stop.
    #[error("{0}")]
    Fatal(String),
}

/// What the driver does after an event function changes sign.
///
/// ```
/// use integrators::EventAction;
/// // a division that added a cell: the problem resized, the driver restarts on the new layout
/// let a = EventAction::Resized;
/// assert_ne!(a, EventAction::Continue);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Nothing changed; keep integrating.
    Continue,
    /// Stop the integration at the event time (the solution is returned as a success).
    Stop,
    /// `y` (and possibly parameters) were modified in place; dimension unchanged. The driver
    /// recomputes a consistent `ẏ` and restarts the method.
    Modified,
    /// The problem changed dimension: `y` has the new length, and `dim()`, `pattern()`,
    /// `atol()`, `algebraic()` and `num_events()` now describe the new problem. The driver
    /// rebuilds its linear-algebra workspace for the new pattern, recomputes a consistent `ẏ`
    /// and restarts the method cleanly.
    Resized,
}

/// An index-1 DAE in residual form `F(t, y, ẏ) = 0`.
///
/// Only [`dim`](Problem::dim) and [`residual`](Problem::residual) are required. Everything
/// else has a default: a dense pattern, finite-difference Jacobians, scalar tolerances from
/// [`crate::Options`], all components differential, and no events.
///
/// ```
/// use integrators::{Problem, ResidualError};
/// /// ẏ = -y
/// struct Decay;
/// impl Problem for Decay {
///     fn dim(&self) -> usize { 1 }
///     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64])
///         -> Result<(), ResidualError> { r[0] = yp[0] + y[0]; Ok(()) }
/// }
/// ```
pub trait Problem {
    /// Number of unknowns.
    fn dim(&self) -> usize;

    /// Evaluates `r = F(t, y, ẏ)`.
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError>;

    /// The structure of `∂F/∂y + c·∂F/∂ẏ` (default dense).
    fn pattern(&self) -> Pattern {
        Pattern::Dense
    }

    /// Exact directional derivative, e.g. by forward-mode AD: writes `r = F(t, y, ẏ)` and
    /// `dr = ∂F/∂y·v + c·∂F/∂ẏ·v`. Return `Ok(false)` (the default) if not provided; the
    /// Jacobian is then built from coloured finite differences.
    #[allow(clippy::too_many_arguments)]
    fn directional(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _v: &[f64],
        _c: f64,
        _r: &mut [f64],
        _dr: &mut [f64],
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Full iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ`, added into `jac` (which is zeroed and shaped
    /// by [`pattern`](Problem::pattern)). Return `Ok(false)` (the default) if not provided:
    /// the solver then stops asking (and stops zeroing a matrix for it) until the problem is
    /// resized, so the answer must not depend on `(t, y, ẏ, c)`.
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _c: f64,
        _jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Per-component absolute tolerances (length `dim()`), or `None` to use
    /// [`crate::Options::atol`] for every component.
    fn atol(&self) -> Option<Vec<f64>> {
        None
    }

    /// How the local-error and Newton tests measure the components (see [`crate::error_map`]):
    /// `None` (the default) tests each component against `rtol·|y_i| + atol_i`; a map of
    /// cell-level rows makes the tests measure stretches (differences of neighbouring
    /// positions over their cell) and so translation invariant. Read with
    /// [`atol`](Problem::atol) at the start and after every resize.
    fn error_map(&self) -> Option<crate::ErrorMap> {
        None
    }

    /// Which components are algebraic (no `ẏ_i` in `F`). Algebraic components are excluded from
    /// the local error test when [`crate::Options::suppress_algebraic`] is set, and consistent
    /// initialisation solves for them instead of for their derivatives. Default: none.
    fn algebraic(&self) -> Vec<bool> {
        vec![false; self.dim()]
    }

    /// Whether what is read from the outputs depends on `ẏ` beyond the state (a Kelvin–Voigt
    /// cell's stress reads its strain rate). The solver then solves each output's `ẏ` from its
    /// `y`, as it makes a problem with algebraic components consistent: an interpolated `ẏ` is
    /// not error-controlled (a viscous line's pressure erred by 13·rtol at rtol 1e-6 and
    /// 66·rtol at 1e-8 from it, against 2.5 and 6 from solved rates). Costs about three
    /// residuals and solves per output (∂F/∂ẏ is factorised once and kept across outputs), or
    /// a consistent initialisation per output when the problem has algebraic components.
    /// Default: false.
    fn outputs_read_rates(&self) -> bool {
        false
    }

    /// Number of event functions (may change after a resize).
    fn num_events(&self) -> usize {
        0
    }

    /// Evaluates the event functions `g_i(t, y)` into `g` (length `num_events()`).
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Called at a located event time `t` with the indices of the functions that changed sign
    /// there (in increasing index order). The problem may modify `y` in place or replace it by a
    /// vector of a new length (then return [`EventAction::Resized`]). `yp` is the interpolated
    /// derivative at `t`, for information (the driver recomputes a consistent one).
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        Ok(EventAction::Stop)
    }

    /// Called after a [`EventAction::Modified`] / [`EventAction::Resized`] event, once `ẏ` has
    /// been made consistent at `(t, y)` and before the method restarts from it. The method
    /// extrapolates the restart derivative (its predictor and first error estimate), so when an
    /// event starts a fast transient whose effect on `y` is below the tolerances (a new cell
    /// boundary that starts at rest and catches up with its neighbours within a time far
    /// shorter than a step), the problem may replace those components of `ẏ` by the
    /// derivative of the smooth solution it relaxes to. The corrector still solves the
    /// residual exactly, so only the predictor changes. Default: keep the consistent `ẏ`.
    fn restart_derivative(&mut self, _t: f64, _y: &[f64], _yp: &mut [f64]) {}

    /// After an event answered [`EventAction::Resized`]: writes into `new` (the new
    /// dimension) the image of `old`, a vector of the layout *before* that event — a state at
    /// time `t` (`derivative = false`) or a time derivative (`derivative = true`, where affine
    /// offsets drop out). With such a map the driver carries the interpolated `ẏ` across the
    /// resize and the method resumes from the mapped state ([`crate::Method::resume`]; BDF at
    /// order 1 with its step size and Newton matrices) instead of restarting from a
    /// consistent initialisation (the SUNDIALS `CVodeResizeHistory` idea; a state map lets a
    /// method map its past solution values too, which BDF does not do: a division kinks the
    /// solution, and a predictor built from before it misses the new slope). The map should
    /// follow the material each unknown describes (a split cell's new boundary at the
    /// parent's midpoint). Returns `false` when there is no such map (default): the driver
    /// then restarts the method.
    fn map_history(&self, _t: f64, _old: &[f64], _derivative: bool, _new: &mut [f64]) -> bool {
        false
    }

    /// After a resize that [`map_history`](Problem::map_history) mapped: rewrites the Newton
    /// matrices a method kept from before the event — `jy = ∂F/∂y` and `jyp = ∂F/∂ẏ` in the
    /// old layout, their storage already grown to the new size — onto the new layout, with
    /// every row the event changed evaluated afresh at `(t, y, ẏ)` (see [`Matrix::remap`]).
    /// The rest stay as old as they were: a simplified Newton iteration needs only an
    /// approximate matrix, and a local event (a cell dividing) then costs no Jacobian of the
    /// whole problem. `Ok(false)` (default) when there is no such map: the method evaluates
    /// fresh matrices.
    fn map_jacobian(
        &self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _jy: &mut Matrix,
        _jyp: &mut Matrix,
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Called by the solver before it integrates, with [`crate::Parallelism::threads`] of [`crate::Options::parallel`]: the most
    /// threads the problem's own evaluations (residual, directional derivatives) may use.
    /// Default: ignore it (evaluate on the calling thread).
    fn set_threads(&mut self, _threads: usize) {}
}
