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
