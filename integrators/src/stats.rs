//! Work counters. Everything costly is counted so that tests can pin costs.

/// Counts of the work done by a solve.
///
/// ```
/// let s = integrators::Stats::default();
/// assert_eq!(s.steps, 0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (error test or Newton failure).
    pub rejected_steps: usize,
    /// Steps rejected by the local error test.
    pub error_test_failures: usize,
    /// Steps rejected because Newton failed to converge.
    pub newton_failures: usize,
    /// Residual evaluations (including those for finite-difference Jacobians).
    pub residual_calls: usize,
    /// Directional-derivative evaluations (for AD Jacobians).
    pub directional_calls: usize,
    /// Jacobian evaluations (any source).
    pub jacobian_evals: usize,
    /// Numeric LU factorisations.
    pub factorizations: usize,
    /// Symbolic factorisations (sparse only; reused until the pattern changes).
    pub symbolic_factorizations: usize,
    /// Linear solves with a factorisation.
    pub linear_solves: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Krylov iterations of the iterative linear solver (0 with the direct solver).
    pub krylov_iterations: usize,
    /// Iterative solves that did not reach their tolerance (each fails a Newton iteration).
    pub krylov_failures: usize,
    /// Events handled.
    pub events: usize,
    /// Resizes performed.
    pub resizes: usize,
}
