//! Declared Jacobian structure: dense, banded or sparse, and the column colourings used to
//! build a Jacobian from a handful of residual (or directional-derivative) evaluations.
//!
//! Structure is data: a problem states its pattern once per topology (and again after a
//! resize); the linear algebra in [`crate::linalg`] and the Jacobian builder in
//! [`crate::jacobian`] both dispatch on it.

use std::sync::Arc;

/// The sparsity structure of `∂F/∂y + c·∂F/∂ẏ`.
///
/// ```
/// use integrators::Pattern;
/// let p = Pattern::Banded { lower: 1, upper: 1 };
/// assert_eq!(p.colour_count(1000), 3);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Pattern {
    /// Every entry may be nonzero.
    Dense,
    /// Nonzeros only for `i - j <= lower` and `j - i <= upper` (row `i`, column `j`).
    Banded {
        /// Number of sub-diagonals.
        lower: usize,
        /// Number of super-diagonals.
        upper: usize,
    },
    /// An explicit pattern (compressed sparse column, sorted rows, diagonal included).
    Sparse(Arc<SparsityPattern>),
}

/// A compressed-sparse-column pattern of an `n × n` matrix.
///
/// ```
/// use integrators::SparsityPattern;
/// // 3×3 tridiagonal
/// let p = SparsityPattern::from_entries(3, &[(0,0),(1,0),(0,1),(1,1),(2,1),(1,2),(2,2)]);
/// assert_eq!(p.nnz(), 7);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SparsityPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl SparsityPattern {
    /// Builds a pattern from `(row, col)` pairs; duplicates are merged and the diagonal is
    /// always added (iteration matrices need it).
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!((p.n(), p.nnz()), (3, 4)); // duplicates merged
    /// ```
    pub fn from_entries(n: usize, entries: &[(usize, usize)]) -> Self {
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &(i, j) in entries {
            assert!(i < n && j < n, "pattern entry ({i},{j}) outside {n}×{n}");
            cols[j].push(i);
        }
        for (j, c) in cols.iter_mut().enumerate() {
            c.push(j);
            c.sort_unstable();
            c.dedup();
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in cols {
            row_idx.extend_from_slice(&c);
            col_ptr.push(row_idx.len());
        }
        Self {
            n,
            col_ptr,
            row_idx,
        }
    }

    /// Matrix dimension.
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!(p.n(), 3);
    /// ```
    pub fn n(&self) -> usize {
        self.n
    }
    /// Number of structural nonzeros.
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!(p.nnz(), 4);
    /// ```
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
    /// Column pointers (length `n + 1`).
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!(p.col_ptr(), [0, 2, 3, 4]); // column 0 holds rows 0 and 2
    /// ```
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }
    /// Row indices, column by column, sorted within each column.
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!(p.row_idx(), [0, 2, 1, 2]);
    /// ```
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }
    /// Rows of column `j`.
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!(p.column(0), [0, 2]);
    /// ```
    pub fn column(&self, j: usize) -> &[usize] {
        &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]]
    }
    /// Position of entry `(i, j)` in the value array, if structurally present.
    ///
    /// ```
    /// use integrators::SparsityPattern;
    /// // a 3 × 3 pattern with one off-diagonal entry (2, 0); the diagonal is always added
    /// let p = SparsityPattern::from_entries(3, &[(2, 0), (2, 0)]);
    /// assert_eq!((p.position(2, 0), p.position(0, 2)), (Some(1), None));
    /// ```
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let c = self.column(j);
        c.binary_search(&i).ok().map(|k| self.col_ptr[j] + k)
    }
}

impl Pattern {
    /// Number of colours (residual or directional-derivative evaluations) needed to build the
    /// Jacobian of an `n`-dimensional problem with this pattern.
    ///
    /// ```
    /// use integrators::Pattern;
    /// // a tridiagonal Jacobian of any size costs three evaluations
    /// assert_eq!(Pattern::Banded { lower: 1, upper: 1 }.colour_count(1000), 3);
    /// assert_eq!(Pattern::Dense.colour_count(7), 7);
    /// ```
    pub fn colour_count(&self, n: usize) -> usize {
        self.colouring(n).1
    }

    /// Column colouring: `colour[j]` for each column, and the number of colours. Columns of one
    /// colour share no row, so one evaluation recovers all of them.
    /// Dense: every column its own colour. Banded: `j mod (lower+upper+1)`. Sparse: greedy
    /// colouring of the column-intersection graph.
    ///
    /// ```
    /// use integrators::Pattern;
    /// let (colour, count) = Pattern::Banded { lower: 1, upper: 1 }.colouring(5);
    /// assert_eq!((colour, count), (vec![0, 1, 2, 0, 1], 3));
    /// ```
    pub fn colouring(&self, n: usize) -> (Vec<usize>, usize) {
        match self {
            Pattern::Dense => ((0..n).collect(), n),
            Pattern::Banded { lower, upper } => {
                let w = (lower + upper + 1).min(n.max(1));
                ((0..n).map(|j| j % w).collect(), w.min(n))
            }
            Pattern::Sparse(p) => greedy_colouring(p),
        }
    }

    /// Whether `(i, j)` is structurally nonzero.
    ///
    /// ```
    /// use integrators::Pattern;
    /// let p = Pattern::Banded { lower: 1, upper: 0 };
    /// assert!(p.contains(3, 2) && !p.contains(2, 3));
    /// ```
    pub fn contains(&self, i: usize, j: usize) -> bool {
        match self {
            Pattern::Dense => true,
            Pattern::Banded { lower, upper } => {
                (i >= j && i - j <= *lower) || (j >= i && j - i <= *upper)
            }
            Pattern::Sparse(p) => p.position(i, j).is_some(),
        }
    }

    /// Rows that may be nonzero in column `j` of an `n × n` matrix.
    ///
    /// ```
    /// use integrators::Pattern;
    /// assert_eq!(Pattern::Banded { lower: 1, upper: 1 }.column_rows(4, 0), [0, 1]);
    /// assert_eq!(Pattern::Dense.column_rows(3, 1), [0, 1, 2]);
    /// ```
    pub fn column_rows(&self, n: usize, j: usize) -> Vec<usize> {
        match self {
            Pattern::Dense => (0..n).collect(),
            Pattern::Banded { lower, upper } => {
                (j.saturating_sub(*upper)..(j + lower + 1).min(n)).collect()
            }
            Pattern::Sparse(p) => p.column(j).to_vec(),
        }
    }
}

/// Greedy distance-2 colouring: two columns conflict when they share a row.
fn greedy_colouring(p: &SparsityPattern) -> (Vec<usize>, usize) {
    let n = p.n();
    // rows -> columns (transpose)
    let mut row_cols: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in 0..n {
        for &i in p.column(j) {
            row_cols[i].push(j);
        }
    }
    let mut colour = vec![usize::MAX; n];
    let mut mark: Vec<usize> = Vec::new();
    let mut ncol = 0;
    for j in 0..n {
        for &i in p.column(j) {
            for &k in &row_cols[i] {
                let c = colour[k];
                if c != usize::MAX {
                    if c >= mark.len() {
                        mark.resize(c + 1, usize::MAX);
                    }
                    mark[c] = j;
                }
            }
        }
        let c = (0..).find(|&c| c >= mark.len() || mark[c] != j).unwrap();
        colour[j] = c;
        ncol = ncol.max(c + 1);
    }
    (colour, ncol)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn banded_colouring_is_bandwidth_plus_one() {
        let p = Pattern::Banded { lower: 2, upper: 2 };
        let (c, k) = p.colouring(100);
        assert_eq!(k, 5);
        assert_eq!(c[7], 2);
    }

    #[test]
    fn sparse_colouring_separates_columns_sharing_rows() {
        // cyclic tridiagonal of size 10
        let n = 10;
        let mut e = Vec::new();
        for i in 0..n {
            e.push((i, (i + 1) % n));
            e.push(((i + 1) % n, i));
        }
        let sp = SparsityPattern::from_entries(n, &e);
        let (c, k) = Pattern::Sparse(Arc::new(sp.clone())).colouring(n);
        assert!(k <= 4, "{k}");
        for i in 0..n {
            for j in 0..n {
                if i != j && c[i] == c[j] {
                    for &r in sp.column(i) {
                        assert!(!sp.column(j).contains(&r));
                    }
                }
            }
        }
    }
}
