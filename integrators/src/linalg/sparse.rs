//! Sparse LU through faer: the symbolic analysis (COLAMD column ordering, elimination tree,
//! simplicial/supernodal choice) is computed once per pattern and reused by every numeric
//! refactorisation; a pattern change means a new [`super::LinearSolver`].
//!
//! faer's numeric sparse LU does not report numerically zero pivots (only structurally
//! singular ones), so after each factorisation one probe solve with a vector of ones is made:
//! an exactly zero pivot makes back substitution divide by zero, which always yields a
//! non-finite value, so the probe detects it reliably at the cost of one triangular solve.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::PartialPivLuParams;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Spec};

use super::first_non_finite;
use crate::pattern::SparsityPattern;

/// Sparse LU factors with a reusable symbolic analysis.
pub(crate) struct SparseLu {
    pattern: Arc<SparsityPattern>,
    symbolic: Option<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    factor_mem: Option<MemBuffer>,
    factored: bool,
    pub(crate) last_symbolic: bool,
}

impl SparseLu {
    pub(crate) fn new(pattern: Arc<SparsityPattern>) -> Self {
        Self {
            pattern,
            symbolic: None,
            numeric: NumericLu::new(),
            factor_mem: None,
            factored: false,
            last_symbolic: false,
        }
    }

    /// Numeric factorisation of `values` (aligned with the pattern's row indices); the symbolic
    /// analysis is made on the first call only.
    pub(crate) fn factor(
        &mut self,
        pattern: &Arc<SparsityPattern>,
        values: &[f64],
    ) -> Result<(), usize> {
        self.factored = false;
        self.last_symbolic = false;
        super::check_sparse_values(&self.pattern, pattern, values)?;
        let n = self.pattern.n();
        if n == 0 {
            self.factored = true;
            return Ok(());
        }
        if self.symbolic.is_none() {
            let sym = factorize_symbolic_lu(structure(&self.pattern), Default::default())
                .map_err(|_| 0usize)?;
            let req = sym.factorize_numeric_lu_scratch::<f64>(
                Par::Seq,
                Spec::<PartialPivLuParams, f64>::default(),
            );
            self.factor_mem = Some(MemBuffer::new(req));
            self.symbolic = Some(sym);
            self.last_symbolic = true;
        }
        let sym = self.symbolic.as_ref().expect("symbolic analysis present");
        let pattern = Arc::clone(&self.pattern);
        let a = SparseColMatRef::new(structure(&pattern), values);
        let mem = self.factor_mem.as_mut().expect("scratch present");
        let res = sym.factorize_numeric_lu(
            &mut self.numeric,
            a,
            Par::Seq,
            MemStack::new(mem),
            Default::default(),
        );
        match res {
            Ok(_) => {}
            Err(LuError::SymbolicSingular { index }) => {
                let cp = sym.col_perm();
                let (fwd, _) = cp.arrays();
                return Err(fwd.get(index).copied().unwrap_or(index.min(n - 1)));
            }
            Err(LuError::Generic(_)) => return Err(0),
        }
        self.factored = true;
        // probe for numerically zero pivots
        let mut probe = vec![1.0; n];
        self.solve(&mut probe);
        if let Some(k) = first_non_finite(&probe) {
            self.factored = false;
            return Err(k);
        }
        Ok(())
    }

    /// Solves `A·x = b` in place.
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
        let sym = self.symbolic.as_ref().expect("factored");
        let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(1, Par::Seq));
        let lu = LuRef::new_unchecked(sym, &self.numeric);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut mem));
    }
}

/// faer's view of a pattern.
fn structure(p: &SparsityPattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(p.n(), p.n(), p.col_ptr(), None, p.row_idx())
}
