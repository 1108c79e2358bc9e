//! Iterative sparse solver: an ILU(0) preconditioner built by "factor" and right-preconditioned
//! BiCGStab run by "solve", for large sparse iteration matrices where a sparse direct LU costs
//! superlinearly in `n` (fill-in).
//!
//! Both pieces come from crates: BiCGStab is `faer::matrix_free::bicgstab`, ILU(0) is
//! `faer_precond::Ilu0` (symbolic structure built once per pattern, numeric refactorisation
//! without allocation). This file only wires them to [`super::LinearSolver`]'s
//! factor/solve contract:
//!
//! * `factor` copies the matrix values (the Krylov iteration needs `A` itself, not only its
//!   factors) and refactorises ILU(0); a zero pivot (or a pattern without its diagonal, which
//!   [`crate::SparsityPattern::from_entries`] never builds) is `Err(column)`, like a direct LU;
//! * `solve` starts from `x = 0` and iterates until `‖b − A x‖₂ ≤ rtol·‖b‖₂`. If that is not
//!   reached within `max_iters` (or a non-finite value appears), the right-hand side is
//!   overwritten with NaN. Every method treats a non-finite Newton update as a failed Newton
//!   iteration, i.e. a recoverable step failure: the step is retried smaller (where the
//!   iteration matrix is better conditioned). No panic, and no silently inaccurate solution.
//!
//! Scratch space is allocated once per pattern and kept in a `RefCell` because
//! `LinearSolver::solve_in_place` takes `&self`.

use std::cell::{Cell, RefCell};
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::bicgstab::{bicgstab, bicgstab_scratch, BicgParams};
use faer::matrix_free::{IdentityPrecond, InitialGuessStatus};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, MatRef, Par};
use faer_precond::ilu0::{Ilu0Error, SymbolicIlu0};
use faer_precond::Ilu0;

use super::first_non_finite;
use crate::options::IterativeSettings;
use crate::pattern::SparsityPattern;

/// Counters of the Krylov iterations made by one [`super::LinearSolver`] (for statistics and
/// performance reports).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KrylovCounters {
    /// Solves attempted.
    pub solves: usize,
    /// BiCGStab iterations summed over all solves.
    pub iterations: usize,
    /// Solves that did not reach the tolerance (answered with NaN).
    pub failures: usize,
    /// Most iterations taken by one converged solve.
    pub max_iterations: usize,
}

/// ILU(0)-preconditioned BiCGStab over a fixed sparsity pattern.
pub(crate) struct IterativeSolver {
    pattern: Arc<SparsityPattern>,
    settings: IterativeSettings,
    values: Vec<f64>,
    ilu: Option<Ilu0<usize, f64>>,
    scratch: RefCell<Option<MemBuffer>>,
    x: RefCell<Vec<f64>>,
    factored: bool,
    pub(crate) last_symbolic: bool,
    counters: Cell<KrylovCounters>,
}

impl IterativeSolver {
    pub(crate) fn new(pattern: Arc<SparsityPattern>, settings: IterativeSettings) -> Self {
        // Validate the CSC structure once (sorted, in-range row indices); every later view is
        // built unchecked (see `structure`).
        let _ = SymbolicSparseColMatRef::new_checked(
            pattern.n(),
            pattern.n(),
            pattern.col_ptr(),
            None,
            pattern.row_idx(),
        );
        Self {
            pattern,
            settings,
            values: Vec::new(),
            ilu: None,
            scratch: RefCell::new(None),
            x: RefCell::new(Vec::new()),
            factored: false,
            last_symbolic: false,
            counters: Cell::new(KrylovCounters::default()),
        }
    }

    pub(crate) fn counters(&self) -> KrylovCounters {
        self.counters.get()
    }

    /// Copies the matrix and builds its ILU(0) preconditioner.
    pub(crate) fn factor(
        &mut self,
        pattern: &Arc<SparsityPattern>,
        values: &[f64],
    ) -> Result<(), usize> {
        assert!(
            Arc::ptr_eq(pattern, &self.pattern) || **pattern == *self.pattern,
            "sparse matrix pattern differs from the solver's (create a new LinearSolver)"
        );
        assert_eq!(
            values.len(),
            self.pattern.nnz(),
            "sparse value length mismatch"
        );
        self.factored = false;
        self.last_symbolic = false;
        if let Some(k) = first_non_finite(values) {
            let cp = self.pattern.col_ptr();
            return Err(cp.partition_point(|&s| s <= k).saturating_sub(1));
        }
        let n = self.pattern.n();
        if n == 0 {
            self.factored = true;
            return Ok(());
        }
        self.values.clear();
        self.values.extend_from_slice(values);
        let structure = structure(&self.pattern);
        if self.ilu.is_none() {
            let sym = SymbolicIlu0::try_new(structure).map_err(|e| ilu_column(&e))?;
            self.ilu = Some(Ilu0::new_with_symbolic(sym));
            self.last_symbolic = true;
        }
        let a = SparseColMatRef::new(structure, &self.values);
        self.ilu
            .as_mut()
            .expect("ILU allocated")
            .refactorize(a)
            .map_err(|e| ilu_column(&e))?;
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` in place (NaN on non-convergence; see the module docs).
    pub(crate) fn solve(&self, b: &mut [f64]) {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        let n = self.pattern.n();
        assert_eq!(b.len(), n, "right-hand side length mismatch");
        if n == 0 {
            return;
        }
        let ilu = self.ilu.as_ref().expect("factored");
        let a = SparseColMatRef::new(structure(&self.pattern), &self.values);
        let mut scratch = self.scratch.borrow_mut();
        let mem = scratch.get_or_insert_with(|| {
            MemBuffer::new(bicgstab_scratch(
                IdentityPrecond { dim: n },
                ilu,
                a,
                1,
                Par::Seq,
            ))
        });
        let mut x = self.x.borrow_mut();
        x.clear();
        x.resize(n, 0.0);
        let params = BicgParams {
            // `x = 0` is passed as a possibly non-zero guess on purpose: faer 0.24's bicgstab
            // leaves its residual vector uninitialised under `InitialGuessStatus::Zero`
            // (it only sets `r = b − A x` in the other branch); one extra product avoids that.
            initial_guess: InitialGuessStatus::MaybeNonZero,
            abs_tolerance: 0.0,
            rel_tolerance: self.settings.rtol,
            max_iters: self.settings.max_iters,
            ..Default::default()
        };
        let res = bicgstab(
            MatMut::from_column_major_slice_mut(&mut x, n, 1),
            IdentityPrecond { dim: n },
            ilu,
            a,
            MatRef::from_column_major_slice(b, n, 1),
            params,
            |_| {},
            Par::Seq,
            MemStack::new(mem),
        );
        let mut c = self.counters.get();
        c.solves += 1;
        match res {
            Ok(info) if first_non_finite(&x).is_none() => {
                c.iterations += info.iter_count;
                c.max_iterations = c.max_iterations.max(info.iter_count);
                b.copy_from_slice(&x);
            }
            Ok(info) => {
                c.iterations += info.iter_count;
                c.failures += 1;
                b.fill(f64::NAN);
            }
            Err(_) => {
                c.iterations += self.settings.max_iters;
                c.failures += 1;
                b.fill(f64::NAN);
            }
        }
        self.counters.set(c);
    }
}

/// Column named by an ILU(0) error (0 when the error names none).
fn ilu_column(e: &Ilu0Error) -> usize {
    match e {
        Ilu0Error::MissingDiagonal { col }
        | Ilu0Error::UnsortedRowIndices { col }
        | Ilu0Error::ZeroPivot { col } => *col,
        _ => 0,
    }
}

/// faer's view of a pattern, without faer's O(nnz) structure check on every call (it showed
/// up at 3 % of a large sheet's profile: one check per Krylov solve).
fn structure(p: &SparsityPattern) -> SymbolicSparseColMatRef<'_, usize> {
    // SAFETY: `SparsityPattern` is built only by `from_entries`, whose output has
    // `col_ptr` non-decreasing from 0 to `row_idx.len()` and strictly increasing,
    // in-range row indices per column — faer's invariants; `IterativeSolver::new` also checks
    // them once with `new_checked` (which panics on violation).
    unsafe { SymbolicSparseColMatRef::new_unchecked(p.n(), p.n(), p.col_ptr(), None, p.row_idx()) }
}

#[cfg(test)]
mod tests {
    use super::super::{LinearSolver, Matrix};
    use super::*;
    use crate::options::LinearSolverChoice;
    use crate::pattern::Pattern;

    /// Convection–diffusion on a `g × g` grid (5-point stencil, upwinded convection: a
    /// non-symmetric M-matrix) plus `shift·I`, in natural ordering.
    fn grid_matrix(g: usize, shift: f64) -> (Pattern, Matrix) {
        let id = |i: usize, j: usize| i * g + j;
        let mut e = Vec::new();
        for i in 0..g {
            for j in 0..g {
                let r = id(i, j);
                if i > 0 {
                    e.push((r, id(i - 1, j)));
                }
                if i + 1 < g {
                    e.push((r, id(i + 1, j)));
                }
                if j > 0 {
                    e.push((r, id(i, j - 1)));
                }
                if j + 1 < g {
                    e.push((r, id(i, j + 1)));
                }
            }
        }
        let n = g * g;
        let p = Pattern::Sparse(Arc::new(SparsityPattern::from_entries(n, &e)));
        let mut m = Matrix::zeros(n, &p);
        for i in 0..g {
            for j in 0..g {
                let r = id(i, j);
                m.add(r, r, 4.0 + 0.5 + shift);
                if i > 0 {
                    m.add(r, id(i - 1, j), -1.5); // upwind side
                }
                if i + 1 < g {
                    m.add(r, id(i + 1, j), -1.0);
                }
                if j > 0 {
                    m.add(r, id(i, j - 1), -1.0);
                }
                if j + 1 < g {
                    m.add(r, id(i, j + 1), -1.0);
                }
            }
        }
        (p, m)
    }

    fn iterative(rtol: f64, max_iters: usize) -> LinearSolverChoice {
        LinearSolverChoice::Iterative(IterativeSettings { rtol, max_iters })
    }

    #[test]
    fn bicgstab_ilu0_solves_a_known_nonsymmetric_grid_system() {
        let g = 40;
        let n = g * g;
        let (p, m) = grid_matrix(g, 0.0);
        // manufactured solution x*, b = A x*
        let x_star: Vec<f64> = (0..n).map(|k| ((k as f64) * 0.37).sin() + 2.0).collect();
        let mut b = vec![0.0; n];
        m.mul_vec(&x_star, &mut b);
        let mut s = LinearSolver::with_choice(n, &p, iterative(1e-12, 500));
        s.factor(&m).unwrap();
        assert!(s.last_factor_was_symbolic());
        let mut x = b.clone();
        s.solve_in_place(&mut x);
        let err = x
            .iter()
            .zip(&x_star)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err < 1e-9, "max error {err:e}");
        let c = s.krylov_counters();
        assert_eq!((c.solves, c.failures), (1, 0));
        // ILU(0) makes this a short iteration
        assert!(c.iterations >= 1 && c.iterations < 60, "{c:?}");
        // same result as the sparse direct LU
        let mut lu = LinearSolver::new(n, &p);
        lu.factor(&m).unwrap();
        let mut xd = b.clone();
        lu.solve_in_place(&mut xd);
        let diff = x
            .iter()
            .zip(&xd)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(diff < 1e-9, "iterative vs direct {diff:e}");
        // refactorisation with new values reuses the symbolic ILU structure
        let (_, m2) = grid_matrix(g, 3.0);
        s.factor(&m2).unwrap();
        assert!(!s.last_factor_was_symbolic());
        let mut b2 = vec![0.0; n];
        m2.mul_vec(&x_star, &mut b2);
        s.solve_in_place(&mut b2);
        let err2 = b2
            .iter()
            .zip(&x_star)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err2 < 1e-9, "after refactor: {err2:e}");
        // a better-conditioned (shifted) matrix needs fewer iterations per solve
        let c2 = s.krylov_counters();
        assert!(c2.iterations - c.iterations <= c.iterations, "{c:?} {c2:?}");
    }

    #[test]
    fn zero_rhs_is_solved_exactly() {
        let (p, m) = grid_matrix(5, 0.0);
        let mut s = LinearSolver::with_choice(25, &p, iterative(1e-10, 10));
        s.factor(&m).unwrap();
        let mut b = vec![0.0; 25];
        s.solve_in_place(&mut b);
        assert!(b.iter().all(|&v| v == 0.0), "{b:?}");
    }

    #[test]
    fn non_convergence_answers_nan_and_is_counted() {
        let g = 30;
        let (p, m) = grid_matrix(g, 0.0);
        let n = g * g;
        let mut s = LinearSolver::with_choice(n, &p, iterative(1e-14, 1));
        s.factor(&m).unwrap();
        let mut b: Vec<f64> = (0..n).map(|k| (k as f64).cos()).collect();
        s.solve_in_place(&mut b);
        assert!(b.iter().all(|v| v.is_nan()));
        let c = s.krylov_counters();
        assert_eq!((c.solves, c.failures, c.iterations), (1, 1, 1));
    }

    #[test]
    fn zero_pivot_and_non_finite_entries_name_a_column() {
        let (p, mut m) = grid_matrix(4, 0.0);
        let mut s = LinearSolver::with_choice(16, &p, iterative(1e-10, 50));
        m.set(0, 0, 0.0);
        // the first ILU(0) pivot is a₀₀ itself
        assert_eq!(s.factor(&m), Err(0));
        m.set(0, 0, 4.5);
        m.set(9, 10, f64::NAN);
        assert_eq!(s.factor(&m), Err(10));
        m.set(9, 10, -1.0);
        s.factor(&m).unwrap();
    }

    #[test]
    fn non_sparse_patterns_fall_back_to_direct() {
        let p = Pattern::Banded { lower: 1, upper: 1 };
        let mut m = Matrix::zeros(3, &p);
        for i in 0..3 {
            m.add(i, i, 2.0);
        }
        let mut s = LinearSolver::with_choice(3, &p, iterative(1e-8, 10));
        s.factor(&m).unwrap();
        let mut b = vec![2.0; 3];
        s.solve_in_place(&mut b);
        assert_eq!(b, vec![1.0; 3]);
        assert_eq!(s.krylov_counters(), KrylovCounters::default());
    }
}

#[cfg(test)]
mod option_tests {
    use crate::options::{IterativeSettings, LinearSolverChoice, Options};

    #[test]
    fn iterative_settings_are_validated_by_field() {
        for (rtol, max_iters, needle) in [
            (0.0, 10, "linear_solver.rtol"),
            (1.0, 10, "linear_solver.rtol"),
            (f64::NAN, 10, "linear_solver.rtol"),
            (1e-6, 0, "linear_solver.max_iters"),
        ] {
            let o = Options {
                linear_solver: LinearSolverChoice::Iterative(IterativeSettings { rtol, max_iters }),
                ..Options::default()
            };
            let e = o.validate().unwrap_err();
            assert!(e.contains(needle), "{e}");
        }
        assert_eq!(Options::default().linear_solver, LinearSolverChoice::Direct);
    }
}
