//! Linear algebra by pattern: the iteration-matrix storage [`Matrix`] (dense, banded or sparse)
//! and [`LinearSolver`], which factorises it with the algorithm that fits the pattern:
//! dense LU (faer), banded LU with partial pivoting in O(n·b²) (hand-written: no maintained
//! crate offers one), sparse LU (faer) with the symbolic factorisation reused until the pattern
//! changes.
//!
//! Also the "complex pair" construction used by Radau IIA: the real 2n×2n matrix
//! `[[A, -B], [B, A]]` with rows/columns interleaved so that a banded pattern stays banded.

// IMPLEMENTATION NOTE: skeleton signatures fixed by the integrators design; bodies are filled in
// by the linalg work item.

use crate::pattern::Pattern;

/// Iteration-matrix storage shaped by a [`Pattern`].
#[derive(Clone, Debug)]
pub enum Matrix {
    /// Column-major dense `n × n`.
    Dense(DenseMatrix),
    /// Band storage.
    Banded(BandMatrix),
    /// CSC values over a [`crate::SparsityPattern`].
    Sparse(SparseMatrix),
}

/// Dense column-major matrix.
#[derive(Clone, Debug)]
pub struct DenseMatrix {
    /// Dimension.
    pub n: usize,
    /// Values, column-major.
    pub data: Vec<f64>,
}

/// Band matrix with `lower` sub- and `upper` super-diagonals (storage layout is the
/// implementation's; use [`Matrix::add`] / [`Matrix::get`]).
#[derive(Clone, Debug)]
pub struct BandMatrix {
    /// Dimension.
    pub n: usize,
    /// Sub-diagonals.
    pub lower: usize,
    /// Super-diagonals.
    pub upper: usize,
    /// Storage (implementation-defined layout, with room for pivoting fill).
    pub data: Vec<f64>,
}

/// Sparse matrix: values over a shared pattern.
#[derive(Clone, Debug)]
pub struct SparseMatrix {
    /// The pattern.
    pub pattern: std::sync::Arc<crate::SparsityPattern>,
    /// Values aligned with `pattern.row_idx()`.
    pub values: Vec<f64>,
}

/// Factorises a [`Matrix`] by its pattern and solves with it.
pub struct LinearSolver {
    #[allow(dead_code)]
    pub(crate) inner: (),
}

impl Matrix {
    /// A zero `n × n` matrix with the given pattern.
    pub fn zeros(n: usize, pattern: &Pattern) -> Self {
        let _ = (n, pattern);
        unimplemented!("linalg work item")
    }
    /// Dimension.
    pub fn n(&self) -> usize {
        unimplemented!("linalg work item")
    }
    /// Sets every stored value to zero (keeps the pattern).
    pub fn set_zero(&mut self) {
        unimplemented!("linalg work item")
    }
    /// Adds `v` to entry `(i, j)`. Entries outside the pattern are a programmer error (panics in
    /// debug builds, ignored in release).
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let _ = (i, j, v);
        unimplemented!("linalg work item")
    }
    /// Entry `(i, j)` (0 outside the pattern).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let _ = (i, j);
        unimplemented!("linalg work item")
    }
    /// `out = self · x`.
    pub fn mul_vec(&self, x: &[f64], out: &mut [f64]) {
        let _ = (x, out);
        unimplemented!("linalg work item")
    }
    /// `self = a·self + b·other` (same pattern).
    pub fn axpby(&mut self, a: f64, b: f64, other: &Matrix) {
        let _ = (a, b, other);
        unimplemented!("linalg work item")
    }
}

/// Pattern of the real `2n × 2n` "complex pair" matrix `[[A, -B], [B, A]]` with rows and
/// columns interleaved (`2i` real part, `2i+1` imaginary part): banded `(l, u)` becomes banded
/// `(2l+1, 2u+1)`, sparse becomes sparse with 2×2 blocks, dense stays dense.
pub fn complex_pair_pattern(n: usize, pattern: &Pattern) -> Pattern {
    let _ = (n, pattern);
    unimplemented!("linalg work item")
}

/// Fills `out` (shaped by [`complex_pair_pattern`]) with the interleaved
/// `[[a·J0 + α·J1, -β·J1], [β·J1, a·J0 + α·J1]]`, i.e. the real form of `(J0 + (α+iβ)·J1)`
/// with `a = 1`. Used by Radau IIA for the complex eigenvalue pair of `A⁻¹`.
pub fn fill_complex_pair(j0: &Matrix, j1: &Matrix, alpha: f64, beta: f64, out: &mut Matrix) {
    let _ = (j0, j1, alpha, beta, out);
    unimplemented!("linalg work item")
}

impl LinearSolver {
    /// A solver for `n × n` matrices with this pattern.
    pub fn new(n: usize, pattern: &Pattern) -> Self {
        let _ = (n, pattern);
        unimplemented!("linalg work item")
    }
    /// Numeric LU factorisation (sparse: symbolic analysis on first call, reused after). Returns
    /// `Err(column)` on a zero pivot.
    pub fn factor(&mut self, m: &Matrix) -> Result<(), usize> {
        let _ = m;
        unimplemented!("linalg work item")
    }
    /// Solves in place with the last factorisation.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let _ = b;
        unimplemented!("linalg work item")
    }
    /// Whether the last `factor` created a new symbolic factorisation (for statistics).
    pub fn last_factor_was_symbolic(&self) -> bool {
        unimplemented!("linalg work item")
    }
}
