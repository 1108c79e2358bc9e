//! Dense LU with partial pivoting: the factorisation is faer's blocked in-place LU
//! (`faer::linalg::lu::partial_pivoting`), kept in a reusable column-major buffer; the
//! single-right-hand-side solve is a plain permuted forward/backward substitution.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::{MatMut, Par};

use super::first_non_finite;

/// Dense LU factors `P·A = L·U` of an `n × n` matrix.
pub(crate) struct DenseLu {
    n: usize,
    /// `L` (strictly lower, unit diagonal implied) and `U` (upper), column-major.
    lu: Vec<f64>,
    /// `perm[i]` = row of `A` that became row `i` of `P·A`.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    factored: bool,
}

impl DenseLu {
    pub(crate) fn new(n: usize) -> Self {
        let req = lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default());
        Self {
            n,
            lu: vec![0.0; n * n],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
            factored: false,
        }
    }

    /// Factorises the column-major `data`. `Err(column)` on a zero or non-finite pivot, or a
    /// non-finite input entry (reported by its column).
    pub(crate) fn factor(&mut self, data: &[f64]) -> Result<(), usize> {
        let n = self.n;
        assert_eq!(data.len(), n * n, "dense matrix size mismatch");
        self.factored = false;
        if let Some(k) = first_non_finite(data) {
            return Err(k / n.max(1));
        }
        self.lu.copy_from_slice(data);
        if n == 0 {
            self.factored = true;
            return Ok(());
        }
        let a = MatMut::from_column_major_slice_mut(&mut self.lu, n, n);
        lu_in_place(
            a,
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        for k in 0..n {
            let p = self.lu[k * n + k];
            if p == 0.0 || !p.is_finite() {
                return Err(k);
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `A·x = b` in place.
    pub(crate) fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        assert_eq!(b.len(), n, "right-hand side length mismatch");
        let mut x: Vec<f64> = self.perm.iter().map(|&p| b[p]).collect();
        // L·z = P·b (unit lower, column oriented)
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                let col = &self.lu[j * n..(j + 1) * n];
                for i in j + 1..n {
                    x[i] -= col[i] * xj;
                }
            }
        }
        // U·x = z
        for j in (0..n).rev() {
            let col = &self.lu[j * n..(j + 1) * n];
            x[j] /= col[j];
            let xj = x[j];
            if xj != 0.0 {
                for i in 0..j {
                    x[i] -= col[i] * xj;
                }
            }
        }
        b.copy_from_slice(&x);
    }
}
