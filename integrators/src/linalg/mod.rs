//! Linear algebra by pattern: the iteration-matrix storage [`Matrix`] (dense, banded or sparse)
//! and [`LinearSolver`], which factorises it with the algorithm that fits the pattern:
//! dense LU (faer), banded LU with partial pivoting in O(n·b²) (hand-written: no maintained
//! crate offers one), sparse LU (faer) with the symbolic factorisation reused until the pattern
//! changes, or (chosen by [`crate::LinearSolverChoice::Iterative`]) ILU(0)-preconditioned
//! BiCGStab for sparse patterns.
//!
//! Also the "complex pair" construction used by Radau IIA: the real 2n×2n matrix
//! `[[A, -B], [B, A]]` with rows/columns interleaved so that a banded pattern stays banded.

//!
//! Layout: [`dense`](self) (faer LU), `banded` (hand-written `dgbtrf`-style LU), `sparse` (faer
//! sparse LU with cached symbolic analysis), `iterative` (ILU(0) from `faer-precond`, BiCGStab
//! with a Newton-aware stopping rule on CSR kernels), `complex_pair` (Radau's real 2n form),
//! `entries` (where a Jacobian sweep adds its entries: a matrix or a band's column window).
//! This file holds the public types and dispatches by pattern.
//!
//! ```
//! use integrators::linalg::{LinearSolver, Matrix};
//! use integrators::Pattern;
//! let p = Pattern::Banded { lower: 1, upper: 1 };
//! let mut m = Matrix::zeros(3, &p);
//! for i in 0..3 {
//!     m.add(i, i, 4.0);
//!     if i > 0 { m.add(i, i - 1, -1.0); m.add(i - 1, i, -1.0); }
//! }
//! let mut lu = LinearSolver::new(3, &p);
//! lu.factor(&m).unwrap();
//! let mut b = vec![3.0, 2.0, 3.0];
//! lu.solve_in_place(&mut b);
//! assert!(b.iter().all(|x| (x - 1.0).abs() < 1e-14));
//! ```

mod banded;
mod complex_pair;
mod dense;
mod entries;
mod iterative;
mod sparse;

pub use entries::{BandColumns, EntrySink};
pub use iterative::{KrylovCounters, LinearTolerance};

use std::sync::Arc;

use crate::pattern::Pattern;

/// Iteration-matrix storage shaped by a [`Pattern`].
///
/// ```
/// use integrators::linalg::Matrix;
/// use integrators::Pattern;
/// let mut m = Matrix::zeros(3, &Pattern::Banded { lower: 1, upper: 1 });
/// m.add(1, 0, 2.0);
/// m.add(1, 0, 0.5); // adds, as a Jacobian assembly does
/// assert_eq!((m.get(1, 0), m.get(0, 2), m.n()), (2.5, 0.0, 3));
/// ```
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
///
/// ```
/// use integrators::linalg::Matrix;
/// use integrators::Pattern;
/// let mut m = Matrix::zeros(2, &Pattern::Dense);
/// m.set(0, 1, 4.0);
/// let Matrix::Dense(d) = &m else { unreachable!() };
/// assert_eq!(d.data, [0.0, 0.0, 4.0, 0.0]); // column-major: (0, 1) is the third value
/// ```
#[derive(Clone, Debug)]
pub struct DenseMatrix {
    /// Dimension.
    pub n: usize,
    /// Values, column-major.
    pub data: Vec<f64>,
}

/// Band matrix with `lower` sub- and `upper` super-diagonals (storage layout is the
/// implementation's; use [`Matrix::add`] / [`Matrix::get`]).
///
/// ```
/// use integrators::linalg::Matrix;
/// use integrators::Pattern;
/// let m = Matrix::zeros(5, &Pattern::Banded { lower: 2, upper: 1 });
/// let Matrix::Banded(b) = &m else { unreachable!() };
/// assert_eq!((b.n, b.lower, b.upper), (5, 2, 1));
/// ```
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
///
/// ```
/// use integrators::linalg::Matrix;
/// use integrators::{Pattern, SparsityPattern};
/// let p = SparsityPattern::from_entries(3, &[(0, 0), (1, 1), (2, 2), (2, 0)]);
/// let m = Matrix::zeros(3, &Pattern::Sparse(std::sync::Arc::new(p)));
/// let Matrix::Sparse(s) = &m else { unreachable!() };
/// assert_eq!(s.values.len(), 4); // one value per stored entry
/// ```
#[derive(Clone, Debug)]
pub struct SparseMatrix {
    /// The pattern.
    pub pattern: std::sync::Arc<crate::SparsityPattern>,
    /// Values aligned with `pattern.row_idx()`.
    pub values: Vec<f64>,
}

/// Factorises a [`Matrix`] by its pattern and solves with it.
///
/// Zero (or non-finite) pivots and non-finite matrix entries are reported as `Err(column)`;
/// nothing here panics on singular or NaN input.
///
/// ```
/// use integrators::linalg::{LinearSolver, Matrix};
/// use integrators::Pattern;
/// let p = Pattern::Banded { lower: 1, upper: 1 };
/// // [[2, 1, 0], [1, 2, 1], [0, 1, 2]] x = [3, 4, 3]  ⇒  x = [1, 1, 1]
/// let mut a = Matrix::zeros(3, &p);
/// for i in 0..3 { a.add(i, i, 2.0); }
/// for i in 0..2 { a.add(i, i + 1, 1.0); a.add(i + 1, i, 1.0); }
/// let mut lu = LinearSolver::new(3, &p);
/// lu.factor(&a).unwrap();
/// let mut x = vec![3.0, 4.0, 3.0];
/// lu.solve_in_place(&mut x);
/// assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-14));
/// // a zero pivot is an error naming a column, not a panic
/// assert!(lu.factor(&Matrix::zeros(3, &p)).is_err());
/// ```
pub struct LinearSolver {
    pub(crate) inner: Inner,
}

pub(crate) enum Inner {
    Dense(dense::DenseLu),
    Banded(banded::BandLu),
    Sparse(Box<sparse::SparseLu>),
    Iterative(Box<iterative::IterativeSolver>),
}

/// A per-component map applied to a solution as the solver produces it
/// ([`LinearSolver::solve_in_place_map`]). A trait rather than a closure so that an
/// implementation can mark [`map`](SolutionMap::map) `#[inline(always)]`: the solver's loops
/// call it once per component, and a call there costs more than a small update.
///
/// ```
/// use integrators::linalg::SolutionMap;
/// /// Stores `x + offset_j` (e.g. a Newton update applied as the solution is produced).
/// struct Shift<'a>(&'a [f64]);
/// impl SolutionMap for Shift<'_> {
///     fn map(&mut self, j: usize, x: f64) -> f64 { x + self.0[j] }
/// }
/// let mut s = Shift(&[1.0, 2.0]);
/// assert_eq!(s.map(1, 0.5), 2.5);
/// ```
pub trait SolutionMap {
    /// The value stored for solution component `j`, given its value `x`.
    fn map(&mut self, j: usize, x: f64) -> f64;

    /// Splits into a map for components `0..mid` and one for `mid..` (still called with the
    /// global index `j`), so a solver may run the two halves on two threads; `Err(self)` (the
    /// default) when the map cannot be split.
    fn split(self, mid: usize) -> Result<(Self, Self), Self>
    where
        Self: Sized,
    {
        let _ = mid;
        Err(self)
    }

    /// Folds the state a second half (from [`split`](SolutionMap::split)) accumulated into
    /// this one, which the solver then returns.
    fn merge(&mut self, other: Self)
    where
        Self: Sized,
    {
        let _ = other;
    }
}

/// Index of the first non-finite value. Blocks of 64 are tested branch-free (all-ones
/// exponent bits; the compiler vectorises the test) and only a block that has one is searched:
/// a per-element early exit keeps the loop scalar, which on a 10⁶-entry state checked every
/// step was a measurable share of a solve.
pub(crate) fn first_non_finite(v: &[f64]) -> Option<usize> {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    const B: usize = 64;
    let any_bad = |c: &[f64]| c.iter().fold(false, |a, x| a | (x.to_bits() & EXP == EXP));
    let mut blocks = v.chunks_exact(B);
    for (k, block) in (&mut blocks).enumerate() {
        if any_bad(block) {
            return block.iter().position(|x| !x.is_finite()).map(|i| k * B + i);
        }
    }
    let rest = blocks.remainder();
    rest.iter()
        .position(|x| !x.is_finite())
        .map(|i| v.len() - rest.len() + i)
}

/// The checks every sparse factorisation starts with: `pattern` is the solver's own (`own`;
/// a different one is a programmer error: panic), `values` has its length, and every value is
/// finite — else `Err(column)` of the first non-finite entry, reported like a zero pivot.
pub(crate) fn check_sparse_values(
    own: &Arc<crate::SparsityPattern>,
    pattern: &Arc<crate::SparsityPattern>,
    values: &[f64],
) -> Result<(), usize> {
    assert!(
        Arc::ptr_eq(pattern, own) || **pattern == **own,
        "sparse matrix pattern differs from the solver's (create a new LinearSolver)"
    );
    assert_eq!(values.len(), own.nnz(), "sparse value length mismatch");
    match first_non_finite(values) {
        Some(k) => Err(own.col_ptr().partition_point(|&s| s <= k).saturating_sub(1)),
        None => Ok(()),
    }
}

impl Matrix {
    /// A zero `n × n` matrix with the given pattern (band widths are clamped to `n − 1`).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// assert_eq!((m.n(), m.get(0, 1)), (3, -1.0));
    /// ```
    pub fn zeros(n: usize, pattern: &Pattern) -> Self {
        match pattern {
            Pattern::Dense => Matrix::Dense(DenseMatrix {
                n,
                data: vec![0.0; n * n],
            }),
            Pattern::Banded { lower, upper } => {
                Matrix::Banded(BandMatrix::zeros(n, *lower, *upper))
            }
            Pattern::Sparse(p) => {
                assert_eq!(
                    p.n(),
                    n,
                    "sparse pattern is {}×{}, not {n}×{n}",
                    p.n(),
                    p.n()
                );
                Matrix::Sparse(SparseMatrix {
                    pattern: Arc::clone(p),
                    values: vec![0.0; p.nnz()],
                })
            }
        }
    }
    /// Dimension.
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// assert_eq!(m.n(), 3);
    /// ```
    pub fn n(&self) -> usize {
        match self {
            Matrix::Dense(m) => m.n,
            Matrix::Banded(m) => m.n,
            Matrix::Sparse(m) => m.pattern.n(),
        }
    }

    /// Grows a band matrix to `n × n` in place, keeping its storage, when its band is the same
    /// at the new size; `false` for any other change (the caller then allocates a new one).
    /// Its entries are stale: refill before use.
    pub(crate) fn grow(&mut self, n: usize) -> bool {
        match self {
            Matrix::Banded(m) => m.grow(n),
            _ => n == self.n(),
        }
    }
    /// Moves the entries onto a new index layout in place, for a problem that grew by
    /// insertions (see [`crate::Problem::map_jacobian`]): `src[i]` is the old index of new
    /// index `i` (`usize::MAX` for an inserted one; sources increase and `src[i] ≤ i`), and
    /// entry `(i, j)` takes the old `(src[i], src[j])` when both exist, the two moved by the
    /// same amount, and row `i` is not marked in `fresh_rows`; every other entry of the band
    /// becomes zero, ready for fresh rows to be added. The matrix must already have the new
    /// size (its old entries where [`Matrix`]'s growth left them). Banded matrices only:
    /// `false` (nothing changed) for the others or for a map that is not a growth.
    ///
    /// ```
    /// use integrators::{linalg::Matrix, Pattern};
    /// // tridiagonal 3 × 3 grown to 4 × 4 by inserting index 1
    /// let pattern = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(4, &pattern);
    /// for (i, j, v) in [(0, 0, 1.0), (0, 1, 2.0), (1, 0, 3.0), (1, 1, 4.0), (1, 2, 5.0), (2, 1, 6.0), (2, 2, 7.0)] {
    ///     m.set(i, j, v);
    /// }
    /// let none = usize::MAX;
    /// assert!(m.remap(&[0, none, 1, 2], &[false, true, false, false]));
    /// assert_eq!((m.get(0, 0), m.get(2, 2), m.get(2, 3), m.get(3, 2), m.get(3, 3)), (1.0, 4.0, 5.0, 6.0, 7.0));
    /// // entries across the insertion and the fresh row are zero
    /// assert_eq!((m.get(0, 1), m.get(1, 1), m.get(2, 1)), (0.0, 0.0, 0.0));
    /// ```
    pub fn remap(&mut self, src: &[usize], fresh_rows: &[bool]) -> bool {
        match self {
            Matrix::Banded(m) => m.remap(src, fresh_rows),
            _ => false,
        }
    }

    /// Sets every stored value to zero (keeps the pattern).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// m.set_zero();
    /// assert_eq!(m.get(0, 0), 0.0);
    /// ```
    pub fn set_zero(&mut self) {
        let d = match self {
            Matrix::Dense(m) => &mut m.data,
            Matrix::Banded(m) => &mut m.data,
            Matrix::Sparse(m) => &mut m.values,
        };
        d.iter_mut().for_each(|x| *x = 0.0);
    }
    /// Storage position of `(i, j)`, if structurally present.
    #[inline]
    fn position(&self, i: usize, j: usize) -> Option<usize> {
        match self {
            Matrix::Dense(m) => (i < m.n && j < m.n).then_some(j * m.n + i),
            Matrix::Banded(m) => m.index(i, j),
            Matrix::Sparse(m) => {
                if j < m.pattern.n() {
                    m.pattern.position(i, j)
                } else {
                    None
                }
            }
        }
    }
    #[inline]
    fn values_mut(&mut self) -> &mut [f64] {
        match self {
            Matrix::Dense(m) => &mut m.data,
            Matrix::Banded(m) => &mut m.data,
            Matrix::Sparse(m) => &mut m.values,
        }
    }
    /// Adds `v` to entry `(i, j)`. Entries outside the pattern are a programmer error (panics in
    /// debug builds, ignored in release). Inlinable across crates: user Jacobians call it once
    /// per entry.
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// m.add(0, 1, -1.0);
    /// assert_eq!(m.get(0, 1), -2.0);
    /// ```
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        match self.position(i, j) {
            Some(k) => self.values_mut()[k] += v,
            None => debug_assert!(false, "entry ({i}, {j}) is outside the matrix pattern"),
        }
    }
    /// Overwrites entry `(i, j)` with `v` (same pattern rules as [`add`](Matrix::add)).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// m.set(0, 1, 5.0);
    /// assert_eq!(m.get(0, 1), 5.0);
    /// ```
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        match self.position(i, j) {
            Some(k) => self.values_mut()[k] = v,
            None => debug_assert!(false, "entry ({i}, {j}) is outside the matrix pattern"),
        }
    }
    /// Entry `(i, j)` (0 outside the pattern).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// assert_eq!((m.get(1, 1), m.get(2, 0)), (2.0, 0.0)); // outside the band: 0
    /// ```
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match (self.position(i, j), self) {
            (None, _) => 0.0,
            (Some(k), Matrix::Dense(m)) => m.data[k],
            (Some(k), Matrix::Banded(m)) => m.data[k],
            (Some(k), Matrix::Sparse(m)) => m.values[k],
        }
    }
    /// Rows that are structurally present in column `j`.
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// assert_eq!(m.column_rows(0), [0, 1]);
    /// ```
    pub fn column_rows(&self, j: usize) -> Vec<usize> {
        match self {
            Matrix::Dense(m) => (0..m.n).collect(),
            Matrix::Banded(m) => {
                let (r0, r1) = m.col_range(j);
                (r0..r1).collect()
            }
            Matrix::Sparse(m) => m.pattern.column(j).to_vec(),
        }
    }
    /// The first structurally present entry that is NaN or infinite, column by column, as
    /// `(row, column, value)`: why a factorisation failed when the problem's derivatives
    /// overflowed (a failure path; it walks the whole pattern).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let mut m = Matrix::zeros(3, &Pattern::Banded { lower: 1, upper: 1 });
    /// m.add(2, 1, f64::INFINITY);
    /// assert_eq!(m.first_non_finite(), Some((2, 1, f64::INFINITY)));
    /// m.set(2, 1, 1.0);
    /// assert_eq!(m.first_non_finite(), None);
    /// ```
    pub fn first_non_finite(&self) -> Option<(usize, usize, f64)> {
        (0..self.n()).find_map(|j| {
            self.column_rows(j)
                .into_iter()
                .map(|i| (i, j, self.get(i, j)))
                .find(|&(_, _, v)| !v.is_finite())
        })
    }
    /// `out = self · x`.
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// let mut out = [0.0; 3];
    /// m.mul_vec(&[1.0, 1.0, 1.0], &mut out);
    /// assert_eq!(out, [1.0, 2.0, 2.0]);
    /// ```
    pub fn mul_vec(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n();
        assert!(x.len() == n && out.len() == n, "mul_vec dimension mismatch");
        out.iter_mut().for_each(|o| *o = 0.0);
        match self {
            Matrix::Dense(m) => {
                for (col, &xj) in m.data.chunks_exact(n.max(1)).zip(x) {
                    for (o, &a) in out.iter_mut().zip(col) {
                        *o += a * xj;
                    }
                }
            }
            Matrix::Banded(m) => {
                let ld = m.ld();
                let off = m.lower + m.upper;
                for (j, &xj) in x.iter().enumerate() {
                    let (r0, r1) = m.col_range(j);
                    let base = j * ld + off - j;
                    let col = &m.data[base + r0..base + r1];
                    for (o, &a) in out[r0..r1].iter_mut().zip(col) {
                        *o += a * xj;
                    }
                }
            }
            Matrix::Sparse(m) => {
                let (cp, ri) = (m.pattern.col_ptr(), m.pattern.row_idx());
                for (j, &xj) in x.iter().enumerate() {
                    for k in cp[j]..cp[j + 1] {
                        out[ri[k]] += m.values[k] * xj;
                    }
                }
            }
        }
    }
    /// `self = a·self + b·other` (same pattern).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// let other = m.clone();
    /// m.axpby(2.0, -1.0, &other); // 2m − m
    /// assert_eq!((m.get(0, 0), m.get(0, 1)), (2.0, -1.0));
    /// ```
    pub fn axpby(&mut self, a: f64, b: f64, other: &Matrix) {
        let same = match (&*self, other) {
            (Matrix::Dense(p), Matrix::Dense(q)) => p.n == q.n,
            (Matrix::Banded(p), Matrix::Banded(q)) => {
                p.n == q.n && p.lower == q.lower && p.upper == q.upper
            }
            (Matrix::Sparse(p), Matrix::Sparse(q)) => {
                Arc::ptr_eq(&p.pattern, &q.pattern) || p.pattern == q.pattern
            }
            _ => false,
        };
        assert!(same, "axpby: matrices have different patterns");
        let src = match other {
            Matrix::Dense(m) => &m.data,
            Matrix::Banded(m) => &m.data,
            Matrix::Sparse(m) => &m.values,
        };
        for (d, &s) in self.values_mut().iter_mut().zip(src) {
            *d = a * *d + b * s;
        }
    }
}

/// Pattern of the real `2n × 2n` "complex pair" matrix `[[A, -B], [B, A]]` with rows and
/// columns interleaved (`2i` real part, `2i+1` imaginary part): banded `(l, u)` becomes banded
/// `(2l+1, 2u+1)`, sparse becomes sparse with 2×2 blocks, dense stays dense.
///
/// ```
/// use integrators::{linalg::complex_pair_pattern, Pattern};
/// let p = complex_pair_pattern(10, &Pattern::Banded { lower: 1, upper: 2 });
/// assert_eq!(p, Pattern::Banded { lower: 3, upper: 5 });
/// ```
pub fn complex_pair_pattern(n: usize, pattern: &Pattern) -> Pattern {
    complex_pair::pattern(n, pattern)
}

/// Fills `out` (shaped by [`complex_pair_pattern`]) with the interleaved
/// `[[a·J0 + α·J1, -β·J1], [β·J1, a·J0 + α·J1]]`, i.e. the real form of `(J0 + (α+iβ)·J1)`
/// with `a = 1`. Used by Radau IIA for the complex eigenvalue pair of `A⁻¹`.
///
/// A complex right-hand side `b = p + i·q` is passed interleaved (`[p0, q0, p1, q1, …]`) and
/// the solution comes back interleaved the same way.
///
/// ```
/// use integrators::linalg::{complex_pair_pattern, fill_complex_pair, Matrix};
/// use integrators::Pattern;
/// // 1 × 1: J0 = 2, J1 = 1, α + iβ = 3 + 4i gives [[5, −4], [4, 5]]
/// let p = Pattern::Dense;
/// let (mut j0, mut j1) = (Matrix::zeros(1, &p), Matrix::zeros(1, &p));
/// j0.add(0, 0, 2.0);
/// j1.add(0, 0, 1.0);
/// let mut out = Matrix::zeros(2, &complex_pair_pattern(1, &p));
/// fill_complex_pair(&j0, &j1, 3.0, 4.0, &mut out);
/// assert_eq!((out.get(0, 0), out.get(0, 1), out.get(1, 0), out.get(1, 1)), (5.0, -4.0, 4.0, 5.0));
/// ```
pub fn fill_complex_pair(j0: &Matrix, j1: &Matrix, alpha: f64, beta: f64, out: &mut Matrix) {
    complex_pair::fill(j0, j1, alpha, beta, out)
}

impl LinearSolver {
    /// Grows a band solver to `n` unknowns in place when its band is the same at the new size
    /// (factorisation stale); `false` for any other change.
    pub(crate) fn grow(&mut self, n: usize) -> bool {
        match &mut self.inner {
            Inner::Banded(lu) => lu.grow(n),
            _ => false,
        }
    }

    /// A solver for `n × n` matrices with this pattern.
    ///
    /// ```
    /// use integrators::linalg::LinearSolver;
    /// use integrators::Pattern;
    /// let lu = LinearSolver::new(100, &Pattern::Banded { lower: 1, upper: 1 });
    /// assert_eq!(lu.krylov_counters().solves, 0);
    /// ```
    pub fn new(n: usize, pattern: &Pattern) -> Self {
        let inner = match pattern {
            Pattern::Dense => Inner::Dense(dense::DenseLu::new(n)),
            Pattern::Banded { lower, upper } => {
                Inner::Banded(banded::BandLu::new(n, *lower, *upper))
            }
            Pattern::Sparse(p) => {
                assert_eq!(p.n(), n, "sparse pattern dimension mismatch");
                Inner::Sparse(Box::new(sparse::SparseLu::new(Arc::clone(p))))
            }
        };
        Self { inner }
    }
    /// Lets solves split their work where the solver can (the tridiagonal solve: its two
    /// twisted halves, from [`crate::Parallelism::Halves`]' `min_len` unknowns); other solvers
    /// ignore it. Default [`crate::Parallelism::Serial`].
    ///
    /// ```
    /// use integrators::linalg::LinearSolver;
    /// use integrators::{Parallelism, Pattern};
    /// let mut lu = LinearSolver::new(4, &Pattern::Banded { lower: 1, upper: 1 });
    /// lu.set_parallelism(Parallelism::Halves { min_len: 2 });
    /// ```
    pub fn set_parallelism(&mut self, parallel: crate::Parallelism) {
        if let Inner::Banded(lu) = &mut self.inner {
            lu.parallel = parallel;
        }
    }

    /// Whether [`factor_combination`](Self::factor_combination) of two band matrices writes
    /// straight into the factor storage (a banded solver), never touching its `scratch`
    /// matrix, so a caller may pass an empty one instead of a third `n`-sized matrix.
    ///
    /// ```
    /// use integrators::{linalg::LinearSolver, Pattern};
    /// assert!(LinearSolver::new(4, &Pattern::Banded { lower: 1, upper: 1 }).combines_in_place());
    /// assert!(!LinearSolver::new(4, &Pattern::Dense).combines_in_place());
    /// ```
    pub fn combines_in_place(&self) -> bool {
        matches!(self.inner, Inner::Banded(_))
    }

    /// A solver for `n × n` matrices with this pattern, direct or iterative as `choice` says
    /// (the iterative solver applies to sparse patterns only; others get their direct LU).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use integrators::linalg::{LinearSolver, Matrix};
    /// use integrators::{IterativeSettings, LinearSolverChoice, Pattern, SparsityPattern};
    /// let e: Vec<_> = (1..50).flat_map(|i| [(i, i - 1), (i - 1, i)]).collect();
    /// let p = Pattern::Sparse(Arc::new(SparsityPattern::from_entries(50, &e)));
    /// let mut m = Matrix::zeros(50, &p);
    /// for i in 0..50 {
    ///     m.add(i, i, 4.0);
    ///     if i > 0 { m.add(i, i - 1, -1.0); m.add(i - 1, i, -1.5); }
    /// }
    /// let it = LinearSolverChoice::Iterative(IterativeSettings { rtol: 1e-12, max_iters: 50, newton_factor: 0.0 });
    /// let mut s = LinearSolver::with_choice(50, &p, it);
    /// s.factor(&m).unwrap();
    /// let mut b = vec![1.0; 50];
    /// s.solve_in_place(&mut b);
    /// let mut back = vec![0.0; 50];
    /// m.mul_vec(&b, &mut back);
    /// assert!(back.iter().all(|v| (v - 1.0).abs() < 1e-10));
    /// assert_eq!(s.krylov_counters().solves, 1);
    /// ```
    pub fn with_choice(n: usize, pattern: &Pattern, choice: crate::LinearSolverChoice) -> Self {
        match (choice, pattern) {
            (crate::LinearSolverChoice::Iterative(settings), Pattern::Sparse(p)) => {
                assert_eq!(p.n(), n, "sparse pattern dimension mismatch");
                Self {
                    inner: Inner::Iterative(Box::new(iterative::IterativeSolver::new(
                        Arc::clone(p),
                        settings,
                    ))),
                }
            }
            _ => Self::new(n, pattern),
        }
    }
    /// Krylov iteration counters (all zero for a direct solver).
    ///
    /// ```
    /// use integrators::linalg::LinearSolver;
    /// use integrators::Pattern;
    /// assert_eq!(LinearSolver::new(4, &Pattern::Dense).krylov_counters().iterations, 0); // direct
    /// ```
    pub fn krylov_counters(&self) -> KrylovCounters {
        match &self.inner {
            Inner::Iterative(s) => s.counters(),
            _ => KrylovCounters::default(),
        }
    }
    /// Numeric LU factorisation (sparse: symbolic analysis on first call, reused after). Returns
    /// `Err(column)` on a zero pivot (also for a non-finite pivot or matrix entry). After an
    /// error the solver holds no valid factorisation until the next successful `factor`.
    ///
    /// Panics if `m` does not have the solver's pattern (programmer error).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// use integrators::linalg::LinearSolver;
    /// let mut lu = LinearSolver::new(3, &p);
    /// assert!(lu.factor(&m).is_ok());
    /// m.set(2, 2, f64::NAN);
    /// assert!(lu.factor(&m).is_err()); // a non-finite entry is refused
    /// ```
    pub fn factor(&mut self, m: &Matrix) -> Result<(), usize> {
        match (&mut self.inner, m) {
            (Inner::Dense(lu), Matrix::Dense(a)) => lu.factor(&a.data),
            (Inner::Banded(lu), Matrix::Banded(a)) => lu.factor(a),
            (Inner::Sparse(lu), Matrix::Sparse(a)) => lu.factor(&a.pattern, &a.values),
            (Inner::Iterative(it), Matrix::Sparse(a)) => it.factor(&a.pattern, &a.values),
            _ => panic!("LinearSolver::factor: matrix storage does not match the solver's pattern"),
        }
    }
    /// Factorises `a + beta·b` (`a`, `b` and `scratch` of the solver's pattern). Banded
    /// matrices are combined straight into the factor storage (one pass, no scratch write);
    /// other patterns build the sum in `scratch` first. Entries are bitwise those of
    /// `scratch.set_zero(); scratch.axpby(1, 1, a); scratch.axpby(1, beta, b)`.
    ///
    /// ```
    /// use integrators::linalg::{LinearSolver, Matrix};
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 0, upper: 0 };
    /// let (mut a, mut b, mut s) = (Matrix::zeros(2, &p), Matrix::zeros(2, &p), Matrix::zeros(2, &p));
    /// a.add(0, 0, 1.0); a.add(1, 1, 1.0); b.add(0, 0, 1.0); b.add(1, 1, 3.0);
    /// let mut lu = LinearSolver::new(2, &p);
    /// lu.factor_combination(&a, 2.0, &b, &mut s).unwrap(); // diag(3, 7)
    /// let mut x = vec![3.0, 7.0];
    /// lu.solve_in_place(&mut x);
    /// assert_eq!(x, vec![1.0, 1.0]);
    /// ```
    pub fn factor_combination(
        &mut self,
        a: &Matrix,
        beta: f64,
        b: &Matrix,
        scratch: &mut Matrix,
    ) -> Result<(), usize> {
        if let (Inner::Banded(lu), Matrix::Banded(a), Matrix::Banded(b)) = (&mut self.inner, a, b) {
            return lu.factor_combination(a, beta, b);
        }
        scratch.set_zero();
        scratch.axpby(1.0, 1.0, a);
        scratch.axpby(1.0, beta, b);
        self.factor(scratch)
    }
    /// Solves in place with the last factorisation. An iterative solver that does not reach
    /// its tolerance answers NaN in every component (a recoverable failure for the methods).
    ///
    /// Panics if there is no successful factorisation (programmer error).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// use integrators::linalg::LinearSolver;
    /// let mut lu = LinearSolver::new(3, &p);
    /// lu.factor(&m).unwrap();
    /// let mut b = [1.0, 2.0, 2.0];
    /// lu.solve_in_place(&mut b);
    /// assert!(b.iter().all(|x| (x - 1.0).abs() < 1e-15));
    /// ```
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.solve_in_place_to(b, None);
    }
    /// As [`solve_in_place`](Self::solve_in_place), telling an iterative solver how accurate
    /// the solution must be for the caller's Newton iteration (see [`LinearTolerance`] and
    /// [`crate::IterativeSettings`]); direct solvers ignore `tol`.
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// use integrators::linalg::LinearSolver;
    /// let mut lu = LinearSolver::new(3, &p);
    /// lu.factor(&m).unwrap();
    /// let mut b = [1.0, 2.0, 2.0];
    /// lu.solve_in_place_to(&mut b, None); // a direct solve ignores the tolerance
    /// assert!(b.iter().all(|x| (x - 1.0).abs() < 1e-15));
    /// ```
    pub fn solve_in_place_to(&self, b: &mut [f64], tol: Option<&LinearTolerance<'_>>) {
        match &self.inner {
            Inner::Dense(lu) => lu.solve(b),
            Inner::Banded(lu) => lu.solve(b),
            Inner::Sparse(lu) => lu.solve(b),
            Inner::Iterative(it) => it.solve(b, tol),
        }
    }
    /// [`solve_in_place`](Self::solve_in_place), then `b[j] = map.map(j, x_j)` for every
    /// component, in an order of the solver's choosing: the tridiagonal banded solver applies
    /// the map inside its backward sweep (decreasing `j`), which saves the caller a separate
    /// pass over the solution; the others apply it afterwards in increasing `j`.
    ///
    /// ```
    /// use integrators::linalg::{LinearSolver, Matrix, SolutionMap};
    /// use integrators::Pattern;
    /// struct Negate;
    /// impl SolutionMap for Negate {
    ///     fn map(&mut self, _j: usize, x: f64) -> f64 { -x }
    /// }
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 {
    ///     m.add(i, i, 4.0);
    ///     if i > 0 { m.add(i, i - 1, -1.0); m.add(i - 1, i, -1.0); }
    /// }
    /// let mut lu = LinearSolver::new(3, &p);
    /// lu.factor(&m).unwrap();
    /// let mut b = vec![3.0, 2.0, 3.0];
    /// lu.solve_in_place_map(&mut b, None, Negate);
    /// assert!(b.iter().all(|x| (x + 1.0).abs() < 1e-14));
    /// ```
    ///
    /// The map is taken by value and handed back: held in a local of the solver, its fields
    /// (running norms, slice pointers) stay in registers, where behind a reference every store
    /// into the solution would make the compiler reload them.
    pub fn solve_in_place_map<M: SolutionMap + Send>(
        &self,
        b: &mut [f64],
        tol: Option<&LinearTolerance<'_>>,
        mut map: M,
    ) -> M {
        if let Inner::Banded(lu) = &self.inner {
            return lu.solve_map(b, map);
        }
        self.solve_in_place_to(b, tol);
        for (j, v) in b.iter_mut().enumerate() {
            *v = map.map(j, *v);
        }
        map
    }
    /// Whether the last `factor` created a new symbolic factorisation (for statistics).
    ///
    /// ```
    /// use integrators::linalg::Matrix;
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let mut m = Matrix::zeros(3, &p);
    /// for i in 0..3 { m.add(i, i, 2.0); }
    /// m.add(0, 1, -1.0);
    /// use integrators::linalg::LinearSolver;
    /// let mut lu = LinearSolver::new(3, &p);
    /// lu.factor(&m).unwrap();
    /// assert!(!lu.last_factor_was_symbolic()); // only sparse factorisations have a symbolic phase
    /// ```
    pub fn last_factor_was_symbolic(&self) -> bool {
        match &self.inner {
            Inner::Sparse(lu) => lu.last_symbolic,
            Inner::Iterative(it) => it.last_symbolic,
            _ => false,
        }
    }
    /// Whether the last successful factorisation condensed a `(2, 2)` band whose alternate
    /// unknowns couple only to their two neighbours (a line of cells each carrying one
    /// internal variable, as growth) to a tridiagonal Schur complement; see the banded
    /// solver's module documentation. Lets a caller check that its matrices take that path.
    ///
    /// ```
    /// use integrators::linalg::{LinearSolver, Matrix};
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 2, upper: 2 };
    /// let n = 9;
    /// let mut m = Matrix::zeros(n, &p);
    /// for i in 0..n {
    ///     m.add(i, i, 4.0);
    ///     if i > 0 { m.add(i, i - 1, -1.0); m.add(i - 1, i, -1.0); }
    ///     // only the odd unknowns couple two apart: the even ones are eliminated first
    ///     if i >= 2 && i % 2 == 1 { m.add(i, i - 2, 0.5); m.add(i - 2, i, 0.5); }
    /// }
    /// let mut lu = LinearSolver::new(n, &p);
    /// lu.factor(&m).unwrap();
    /// assert!(lu.last_factor_condensed());
    /// let mut x = vec![1.0; n];
    /// lu.solve_in_place(&mut x);
    /// let mut back = vec![0.0; n];
    /// m.mul_vec(&x, &mut back);
    /// assert!(back.iter().all(|v| (v - 1.0).abs() < 1e-14));
    /// ```
    pub fn last_factor_condensed(&self) -> bool {
        match &self.inner {
            Inner::Banded(lu) => lu.is_condensed(),
            _ => false,
        }
    }
    /// Multiply–add count of the last banded factorisation (0 for other patterns); lets tests
    /// check the O(n·l·(l+u)) cost without timing.
    ///
    /// ```
    /// use integrators::linalg::{LinearSolver, Matrix};
    /// use integrators::Pattern;
    /// // a tridiagonal LU costs O(n): doubling n doubles the work
    /// let p = Pattern::Banded { lower: 1, upper: 1 };
    /// let flops = |n: usize| {
    ///     let mut m = Matrix::zeros(n, &p);
    ///     for i in 0..n { m.add(i, i, 4.0); }
    ///     for i in 1..n { m.add(i, i - 1, 1.0); m.add(i - 1, i, 1.0); }
    ///     let mut lu = LinearSolver::new(n, &p);
    ///     lu.factor(&m).unwrap();
    ///     lu.last_factor_flops()
    /// };
    /// assert!((flops(2000) as f64 / flops(1000) as f64 - 2.0).abs() < 0.01);
    /// ```
    pub fn last_factor_flops(&self) -> usize {
        match &self.inner {
            Inner::Banded(lu) => lu.flops,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests;
