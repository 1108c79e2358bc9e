//! The real "complex pair" form used by Radau IIA: `J0 + (α+iβ)·J1` acting on `x + iy` is the
//! real `2n × 2n` matrix with 2×2 blocks `[[a, −b], [b, a]]` (`a = J0 + α·J1`, `b = β·J1`), rows
//! and columns interleaved (`2i` real part, `2i+1` imaginary part) so that a banded `(l, u)`
//! pattern stays banded `(2l+1, 2u+1)` and a sparse one stays sparse with 2×2 blocks.

use std::sync::Arc;

use super::Matrix;
use crate::pattern::{Pattern, SparsityPattern};

pub(crate) fn pattern(n: usize, pattern: &Pattern) -> Pattern {
    match pattern {
        Pattern::Dense => Pattern::Dense,
        Pattern::Banded { lower, upper } => {
            let m = n.saturating_sub(1);
            Pattern::Banded {
                lower: 2 * (*lower).min(m) + 1,
                upper: 2 * (*upper).min(m) + 1,
            }
        }
        Pattern::Sparse(p) => {
            assert_eq!(p.n(), n, "sparse pattern dimension mismatch");
            let mut e = Vec::with_capacity(4 * p.nnz());
            for j in 0..n {
                for &i in p.column(j) {
                    for r in 0..2 {
                        for s in 0..2 {
                            e.push((2 * i + r, 2 * j + s));
                        }
                    }
                }
            }
            Pattern::Sparse(Arc::new(SparsityPattern::from_entries(2 * n, &e)))
        }
    }
}

pub(crate) fn fill(j0: &Matrix, j1: &Matrix, alpha: f64, beta: f64, out: &mut Matrix) {
    let n = j0.n();
    assert_eq!(j1.n(), n, "J0 and J1 dimensions differ");
    assert_eq!(out.n(), 2 * n, "complex-pair matrix must be 2n × 2n");
    out.set_zero();
    let put = |i: usize, j: usize, a0: f64, a1: f64, out: &mut Matrix| {
        let a = a0 + alpha * a1;
        let b = beta * a1;
        out.add(2 * i, 2 * j, a);
        out.add(2 * i, 2 * j + 1, -b);
        out.add(2 * i + 1, 2 * j, b);
        out.add(2 * i + 1, 2 * j + 1, a);
    };
    match (j0, j1) {
        (Matrix::Dense(a), Matrix::Dense(b)) => {
            for j in 0..n {
                for i in 0..n {
                    put(i, j, a.data[j * n + i], b.data[j * n + i], out);
                }
            }
        }
        (Matrix::Sparse(a), Matrix::Sparse(b)) if Arc::ptr_eq(&a.pattern, &b.pattern) => {
            for j in 0..n {
                for k in a.pattern.col_ptr()[j]..a.pattern.col_ptr()[j + 1] {
                    put(a.pattern.row_idx()[k], j, a.values[k], b.values[k], out);
                }
            }
        }
        _ => {
            // banded, or differing storage: walk the union of the structures
            for j in 0..n {
                let mut rows = j0.column_rows(j);
                rows.extend(j1.column_rows(j));
                rows.sort_unstable();
                rows.dedup();
                for i in rows {
                    put(i, j, j0.get(i, j), j1.get(i, j), out);
                }
            }
        }
    }
}
