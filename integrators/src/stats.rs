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
    /// Newton matrices carried across a resize by the problem's map
    /// ([`crate::Problem::map_jacobian`]) instead of evaluated afresh.
    pub jacobians_mapped: usize,
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

impl Stats {
    /// Every counter by name, in declaration order: what a record of the run lists (one
    /// mapping for every caller, so no counter is dropped).
    ///
    /// ```
    /// let s = integrators::Stats { steps: 3, krylov_iterations: 7, ..Default::default() };
    /// let c = s.counters();
    /// assert_eq!(c.len(), 16);
    /// assert!(c.contains(&("steps", 3)) && c.contains(&("krylov_iterations", 7)));
    /// ```
    pub fn counters(&self) -> [(&'static str, usize); 16] {
        [
            ("steps", self.steps),
            ("rejected_steps", self.rejected_steps),
            ("error_test_failures", self.error_test_failures),
            ("newton_failures", self.newton_failures),
            ("residual_calls", self.residual_calls),
            ("directional_calls", self.directional_calls),
            ("jacobian_evals", self.jacobian_evals),
            ("jacobians_mapped", self.jacobians_mapped),
            ("factorizations", self.factorizations),
            ("symbolic_factorizations", self.symbolic_factorizations),
            ("linear_solves", self.linear_solves),
            ("newton_iterations", self.newton_iterations),
            ("krylov_iterations", self.krylov_iterations),
            ("krylov_failures", self.krylov_failures),
            ("events", self.events),
            ("resizes", self.resizes),
        ]
    }
}

/// Sums the counters of two solves (e.g. the pieces of a run restarted at breakpoints).
///
/// ```
/// let mut a = integrators::Stats { steps: 2, krylov_failures: 1, ..Default::default() };
/// a += &integrators::Stats { steps: 3, krylov_failures: 4, ..Default::default() };
/// assert_eq!((a.steps, a.krylov_failures), (5, 5));
/// ```
impl std::ops::AddAssign<&Stats> for Stats {
    fn add_assign(&mut self, b: &Stats) {
        // destructured, so that a new counter cannot be forgotten here
        let Stats {
            steps,
            rejected_steps,
            error_test_failures,
            newton_failures,
            residual_calls,
            directional_calls,
            jacobian_evals,
            jacobians_mapped,
            factorizations,
            symbolic_factorizations,
            linear_solves,
            newton_iterations,
            krylov_iterations,
            krylov_failures,
            events,
            resizes,
        } = *b;
        self.steps += steps;
        self.rejected_steps += rejected_steps;
        self.error_test_failures += error_test_failures;
        self.newton_failures += newton_failures;
        self.residual_calls += residual_calls;
        self.directional_calls += directional_calls;
        self.jacobian_evals += jacobian_evals;
        self.jacobians_mapped += jacobians_mapped;
        self.factorizations += factorizations;
        self.symbolic_factorizations += symbolic_factorizations;
        self.linear_solves += linear_solves;
        self.newton_iterations += newton_iterations;
        self.krylov_iterations += krylov_iterations;
        self.krylov_failures += krylov_failures;
        self.events += events;
        self.resizes += resizes;
    }
}
