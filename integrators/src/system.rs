//! [`System`]: the machinery shared by every method — counted residual calls, the iteration
//! matrix `J = ∂F/∂y + c·∂F/∂ẏ` built by pattern (user Jacobian → exact coloured directional
//! derivatives → coloured finite differences), its factorisation, error weights and norms, and
//! consistent initialisation.
//!
//! SKELETON: the signatures below are the contract between the driver, the methods and the
//! linear algebra. Bodies are filled in by the linalg/jacobian work item.

use crate::error::SolverError;
use crate::linalg::{LinearSolver, Matrix};
use crate::options::Options;
use crate::pattern::Pattern;
use crate::problem::Problem;
use crate::stats::Stats;

/// Why a step attempt failed in a way the method may recover from by reducing the step.
#[derive(Clone, Debug, PartialEq)]
pub enum StepFailure {
    /// Residual reported `ResidualError::Recoverable`, a non-finite value appeared, or a
    /// factorisation was singular: retry with a smaller step.
    Recoverable {
        /// Reason, for the final error message if retries run out.
        reason: String,
        /// Component responsible, if known.
        component: Option<usize>,
    },
    /// Unrecoverable: abort with this error.
    Fatal(SolverError),
}

/// Problem plus shared workspaces and counters, handed to a [`crate::Method`] on every call.
pub struct System<'a> {
    /// The user's problem.
    pub problem: &'a mut dyn Problem,
    /// Options.
    pub opts: &'a Options,
    /// Work counters.
    pub stats: &'a mut Stats,
    /// Cached per-dimension data (pattern, colouring, atol, algebraic mask).
    pub(crate) cache: &'a mut SystemCache,
}

/// Per-dimension data cached by the driver; rebuilt after a resize by [`SystemCache::rebuild`].
#[derive(Default)]
pub struct SystemCache {
    pub(crate) n: usize,
    pub(crate) pattern: Option<Pattern>,
    pub(crate) colour: Vec<usize>,
    pub(crate) ncolours: usize,
    pub(crate) atol: Vec<f64>,
    pub(crate) algebraic: Vec<bool>,
}

impl SystemCache {
    /// Re-reads dimension, pattern, colouring, tolerances and algebraic flags from the problem
    /// (at the start and after every resize). Errors if the problem's declared sizes disagree.
    pub fn rebuild(&mut self, problem: &dyn Problem, opts: &Options) -> Result<(), String> {
        let _ = (problem, opts);
        unimplemented!("linalg/jacobian work item")
    }
}

impl<'a> System<'a> {
    /// Bundles the pieces (the driver calls this).
    pub fn new(
        problem: &'a mut dyn Problem,
        opts: &'a Options,
        stats: &'a mut Stats,
        cache: &'a mut SystemCache,
    ) -> Self {
        Self { problem, opts, stats, cache }
    }

    /// Problem dimension (as cached at the last rebuild).
    pub fn dim(&self) -> usize {
        self.cache.n
    }

    /// Declared pattern.
    pub fn pattern(&self) -> &Pattern {
        self.cache.pattern.as_ref().expect("SystemCache::rebuild not called")
    }

    /// Absolute tolerances per component.
    pub fn atol(&self) -> &[f64] {
        &self.cache.atol
    }

    /// Algebraic-component flags.
    pub fn algebraic(&self) -> &[bool] {
        &self.cache.algebraic
    }

    /// Counted residual evaluation; non-finite output becomes a recoverable failure naming the
    /// component.
    pub fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), StepFailure> {
        let _ = (t, y, yp, r);
        unimplemented!("linalg/jacobian work item")
    }

    /// A zeroed matrix shaped by the current pattern.
    pub fn new_matrix(&self) -> Matrix {
        unimplemented!("linalg/jacobian work item")
    }

    /// A linear solver for the current pattern (symbolic analysis happens at first factor).
    pub fn new_linear_solver(&self) -> LinearSolver {
        unimplemented!("linalg/jacobian work item")
    }

    /// Evaluates `J = ∂F/∂y + c·∂F/∂ẏ` at `(t, y, ẏ)` into `jac` (zeroed first): the problem's
    /// own Jacobian if it provides one, else exact coloured directional derivatives, else
    /// coloured finite differences. Counted as one Jacobian evaluation.
    pub fn jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        c: f64,
        jac: &mut Matrix,
    ) -> Result<(), StepFailure> {
        let _ = (t, y, yp, c, jac);
        unimplemented!("linalg/jacobian work item")
    }

    /// Counted factorisation; a zero pivot is a recoverable failure.
    pub fn factor(&mut self, solver: &mut LinearSolver, m: &Matrix) -> Result<(), StepFailure> {
        let _ = (solver, m);
        unimplemented!("linalg/jacobian work item")
    }

    /// Counted in-place solve with the last factorisation.
    pub fn solve(&mut self, solver: &LinearSolver, b: &mut [f64]) {
        let _ = (solver, b);
        unimplemented!("linalg/jacobian work item")
    }

    /// Error weights `w_i = 1/(rtol·|y_i| + atol_i)`, zero for algebraic components when
    /// `opts.suppress_algebraic`.
    pub fn error_weights(&self, y: &[f64], w: &mut [f64]) {
        let _ = (y, w);
        unimplemented!("linalg/jacobian work item")
    }

    /// Weighted RMS norm `sqrt(mean((v_i·w_i)²))`.
    pub fn wrms(v: &[f64], w: &[f64]) -> f64 {
        let _ = (v, w);
        unimplemented!("linalg/jacobian work item")
    }

    /// Index of the component with the largest `|v_i·w_i|` (for error messages).
    pub fn worst_component(v: &[f64], w: &[f64]) -> Option<usize> {
        let _ = (v, w);
        unimplemented!("linalg/jacobian work item")
    }

    /// Consistent initialisation at `t`: given `y`, solves `F(t, y, ẏ) = 0` for `ẏ` of the
    /// differential components and for the algebraic components of `y` (IDA's YA_YDP), by
    /// damped Newton with the pattern's factorisation. `yp` holds the initial guess on entry.
    pub fn consistent_init(
        &mut self,
        t: f64,
        y: &mut [f64],
        yp: &mut [f64],
    ) -> Result<(), SolverError> {
        let _ = (t, y, yp);
        unimplemented!("linalg/jacobian work item")
    }
}
