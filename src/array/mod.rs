//! The [`CellArray`] trait — a deformation mode of an array of cells (line, sheet, shear
//! column…) written once as a residual generic over the [`Scalar`] — and [`ArrayProblem`], the
//! one generic adapter that turns any cell array into an [`integrators::Problem`]:
//! plain `f64` residuals, and exact directional derivatives by forward-mode AD (`Dual64`), from
//! which the integrators assemble the declared banded/sparse Jacobian by column colouring
//! (a handful of seeds, independent of the number of cells) — or, when the array provides
//! it ([`CellArray::jacobian`], the line does), the array's own Jacobian in one sweep.
//!
//! Discrete and continuum builders both produce cell arrays: the conservative continuum scheme
//! is the same array with `n` segments of reference size `h` (docs/model.md §3.3a, §4.3), so new
//! cell laws and deformation modes plug in here without touching the integrators.

use crate::scalar::Scalar;
use integrators::{EventAction, JacobianSink, Pattern, Problem, ResidualError};
use num_dual::Dual64;

/// A deformation mode of an array of cells, as a residual-form DAE `F(t, y, ẏ) = 0`.
///
/// Implementors write [`residual`](CellArray::residual) once, generically over the scalar; the
/// framework evaluates it in `f64` and in dual numbers. Events (e.g. cell division) may resize
/// the array.
///
/// A chain of `n` linear springs (stiffness `k`) between a wall at 0 and an end held at
/// `l`, every bead dragged by the substrate (`K ẋⱼ = k(xⱼ₊₁ − 2xⱼ + xⱼ₋₁)`): it relaxes to
/// equal spacing. The full guide is `docs/guide-deformation-mode.md`.
///
/// ```
/// use celltissue::{ArrayProblem, CellArray, Scalar};
/// use integrators::{MethodKind, Options, Pattern, ResidualError, Solver};
///
/// struct Chain { n: usize, k: f64, drag: f64, l: f64 }
/// impl CellArray for Chain {
///     fn dim(&self) -> usize { self.n - 1 } // interior beads x₁ … x_{n−1}
///     fn pattern(&self) -> Pattern { Pattern::Banded { lower: 1, upper: 1 } }
///     fn residual<S: Scalar>(&self, _t: f64, y: &[S], yp: &[S], r: &mut [S])
///         -> Result<(), ResidualError> {
///         let x = |j: usize| if j == 0 { S::from(0.0) }
///                            else if j == self.n { S::from(self.l) } else { y[j - 1] };
///         for j in 1..self.n {
///             let force = (x(j + 1) - x(j) * 2.0 + x(j - 1)) * self.k;
///             r[j - 1] = yp[j - 1] * self.drag - force;
///         }
///         Ok(())
///     }
/// }
/// let chain = Chain { n: 10, k: 1.0, drag: 1.0, l: 9.0 };
/// let y0: Vec<f64> = (1..10).map(|j| j as f64).collect(); // rest spacing 1, end pulled in
/// let mut problem = ArrayProblem::new(chain);
/// let sol = Solver::new(MethodKind::Bdf, Options::default())
///     .solve(&mut problem, 0.0, &y0, &[200.0])?;
/// for (j, x) in sol.y[0].iter().enumerate() {
///     assert!((x - 0.9 * (j + 1) as f64).abs() < 1e-3); // equal spacing l/n
/// }
/// # Ok::<(), integrators::SolveFailure>(())
/// ```
pub trait CellArray {
    /// Number of unknowns.
    fn dim(&self) -> usize;

    /// Jacobian structure (banded for lines, sparse for sheets).
    fn pattern(&self) -> Pattern;

    /// `r = F(t, y, ẏ)`, generic over the scalar. Return `ResidualError::Recoverable` naming the
    /// unknown for states outside the model's domain (e.g. non-positive stretch), so the
    /// integrator rejects the step instead of converging on a mirror branch.
    fn residual<S: Scalar>(
        &self,
        t: f64,
        y: &[S],
        yp: &[S],
        r: &mut [S],
    ) -> Result<(), ResidualError>;

    /// The iteration matrix `J = ∂F/∂y + c·∂F/∂ẏ` at `(t, y, ẏ)`, added into `jac` (zeroed
    /// and shaped by [`pattern`](CellArray::pattern)); see
    /// [`integrators::Problem::jacobian`]. Return `Ok(false)` (the default) if not provided:
    /// [`ArrayProblem`] then builds it from coloured AD directional derivatives of
    /// [`residual`](CellArray::residual), and the solver stops asking until a resize, so the
    /// answer may depend on the array's structure (e.g. a ring) but not on `(t, y, ẏ, c)`.
    /// An implementation must equal the coloured AD Jacobian (the line's is tested against it).
    fn jacobian(
        &self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _c: f64,
        _jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Per-unknown absolute tolerances (cell-sized quantities), or `None` for the solver's.
    fn atol(&self) -> Option<Vec<f64>> {
        None
    }

    /// How the integrators' local-error and Newton tests measure the unknowns (the accuracy
    /// contract of `docs/model.md §8.1`; see [`integrators::error_map`]): a position is
    /// tested through the stretch of its cell — its difference with the other end of the cell
    /// ([`integrators::Row::Difference`]), or, for the first free boundary, against one cell
    /// length ([`integrators::Row::Anchor`]) — and internal variables (growth) on their own.
    /// With [`atol`](CellArray::atol) giving a position `atol × L₀`, a tolerance then bounds
    /// the relative error of every stretch, independent of where the origin is. `None` (the
    /// default) tests each unknown against `rtol·|y| + atol`.
    fn error_map(&self) -> Option<integrators::ErrorMap> {
        None
    }

    /// Algebraic unknowns (no `ẏ` in their residual), e.g. positions when `K = η = 0`.
    fn algebraic(&self) -> Vec<bool> {
        vec![false; self.dim()]
    }

    /// Whether the outputs read rates beyond the state (a Kelvin–Voigt stress reads the strain
    /// rate): the solver then solves each output's `ẏ` from its `y`
    /// ([`integrators::Problem::outputs_read_rates`]).
    fn outputs_read_rates(&self) -> bool {
        false
    }

    /// Number of event functions (e.g. one per cell for division).
    fn num_events(&self) -> usize {
        0
    }

    /// Event functions `g_i(t, y)`.
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Acts on the events that fired at `t` (may resize `y`; see [`integrators::EventAction`]).
    fn handle_event(
        &mut self,
        _t: f64,
        _fired: &[usize],
        _y: &mut Vec<f64>,
        _yp: &[f64],
    ) -> Result<EventAction, ResidualError> {
        Ok(EventAction::Stop)
    }

    /// Derivative the integrator restarts from after a modifying event (see
    /// [`integrators::Problem::restart_derivative`]); default: the consistent one.
    fn restart_derivative(&mut self, _t: f64, _y: &[f64], _yp: &mut [f64]) {}

    /// Maps a vector of the layout before the last resizing event onto the current one (see
    /// [`integrators::Problem::map_history`]); default: no map (the integrator restarts).
    fn map_history(&self, _t: f64, _old: &[f64], _derivative: bool, _new: &mut [f64]) -> bool {
        false
    }

    /// Maps the Newton matrices across the last resizing event, re-evaluating the rows it
    /// changed (see [`integrators::Problem::map_jacobian`]); default: no map (fresh ones).
    fn map_jacobian(
        &self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _jy: &mut integrators::linalg::Matrix,
        _jyp: &mut integrators::linalg::Matrix,
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Threads the residual sweep may use, passed in by the solver from
    /// [`integrators::Options::parallel`] (see [`integrators::Problem::set_threads`]); default:
    /// ignore it.
    fn set_threads(&mut self, _threads: usize) {}
}

/// Adapter: any [`CellArray`] as an [`integrators::Problem`] with exact AD directional
/// derivatives, and the array's own Jacobian when it provides one ([`CellArray::jacobian`]). Reuses its dual-number buffers across calls (no allocation per residual once
/// warmed up, except after a resize).
///
/// ```
/// use celltissue::line::build::{discrete, LineParams};
/// use celltissue::{ArrayProblem, NeoHookean};
/// use integrators::{MethodKind, Options, Problem, Solver};
/// let mut p = LineParams::unit_cells(10);
/// p.k = 1.0.into();
/// let line = discrete(NeoHookean::new(1.0).unwrap(), &p).unwrap();
/// let y0 = line.initial_state();
/// let mut problem = ArrayProblem::new(line);
/// assert_eq!(problem.dim(), y0.len());
/// // any integrator runs it; the array stays readable
/// let sol = Solver::new(MethodKind::Bdf, Options::default())
///     .solve(&mut problem, 0.0, &y0, &[1.0])
///     .unwrap();
/// assert_eq!(problem.array.n_cells(), 10);
/// assert!(sol.stats.steps > 0);
/// ```
pub struct ArrayProblem<A: CellArray> {
    /// The wrapped array (public so observers can read cell fields).
    pub array: A,
    yd: Vec<Dual64>,
    ypd: Vec<Dual64>,
    rd: Vec<Dual64>,
}

impl<A: CellArray> ArrayProblem<A> {
    /// Wraps a cell array.
    ///
    /// ```
    /// use celltissue::line::{discrete, LineParams};
    /// use celltissue::{ArrayProblem, CellArray};
    /// let line = discrete(celltissue::NeoHookean::new(1.0)?, &LineParams::unit_cells(4))?;
    /// let prob = ArrayProblem::new(line); // an integrators::Problem
    /// assert_eq!(prob.array.dim(), 3);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(array: A) -> Self {
        Self {
            array,
            yd: Vec::new(),
            ypd: Vec::new(),
            rd: Vec::new(),
        }
    }
}

impl<A: CellArray> Problem for ArrayProblem<A> {
    integrators::forward_problem!(array: dim, residual, pattern, atol, algebraic, num_events,
        events, handle_event, restart_derivative, map_history, map_jacobian, set_threads);

    fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut JacobianSink,
    ) -> Result<bool, ResidualError> {
        self.array.jacobian(t, y, yp, c, jac)
    }

    fn directional(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        v: &[f64],
        c: f64,
        r: &mut [f64],
        dr: &mut [f64],
    ) -> Result<bool, ResidualError> {
        let n = y.len();
        self.yd.clear();
        self.yd
            .extend(y.iter().zip(v).map(|(&a, &b)| Dual64::new(a, b)));
        self.ypd.clear();
        self.ypd
            .extend(yp.iter().zip(v).map(|(&a, &b)| Dual64::new(a, c * b)));
        self.rd.clear();
        self.rd.resize(n, Dual64::new(0.0, 0.0));
        self.array.residual(t, &self.yd, &self.ypd, &mut self.rd)?;
        for i in 0..n {
            r[i] = self.rd[i].re;
            dr[i] = self.rd[i].eps;
        }
        Ok(true)
    }
}
