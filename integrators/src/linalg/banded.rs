//! Band storage and banded LU with partial pivoting (LAPACK `dgbtrf`/`dgbtrs` layout).
//!
//! faer (like every other maintained pure-Rust crate we know of) has no banded LU, so this one
//! is hand-written: the unblocked `dgbtf2` algorithm. Time is O(n·l·(l+u)) and memory
//! O(n·(2l+u+1)); a band matrix with `l` sub- and `u` super-diagonals is stored column by column
//! with `ld = 2l+u+1` slots per column, entry `(i, j)` at `data[j·ld + l+u+i−j]`. The top `l`
//! slots of every column are zero in a [`BandMatrix`] and receive the fill created by row
//! interchanges (which widen `U` to `l+u` super-diagonals).

use super::BandMatrix;

impl BandMatrix {
    /// A zero `n × n` band matrix; `lower`/`upper` are clamped to `n − 1`.
    pub fn zeros(n: usize, lower: usize, upper: usize) -> Self {
        let m = n.saturating_sub(1);
        let (lower, upper) = (lower.min(m), upper.min(m));
        let ld = 2 * lower + upper + 1;
        Self {
            n,
            lower,
            upper,
            data: vec![0.0; ld * n],
        }
    }

    /// Slots per column of the storage (`2·lower + upper + 1`).
    pub fn ld(&self) -> usize {
        2 * self.lower + self.upper + 1
    }

    /// Storage index of `(i, j)`, or `None` outside the band.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> Option<usize> {
        if i >= self.n || j >= self.n || i > j + self.lower || j > i + self.upper {
            return None;
        }
        Some(j * self.ld() + self.lower + self.upper + i - j)
    }

    /// Rows `r0..r1` of column `j` that lie in the band.
    #[inline]
    pub(crate) fn col_range(&self, j: usize) -> (usize, usize) {
        (
            j.saturating_sub(self.upper),
            (j + self.lower + 1).min(self.n),
        )
    }
}

/// LU factors of a band matrix, `dgbtrf` layout, with the operation count of the last
/// factorisation (multiply–adds) so the O(n·l·(l+u)) cost can be checked without timing.
#[derive(Clone, Debug)]
pub(crate) struct BandLu {
    n: usize,
    l: usize,
    u: usize,
    ab: Vec<f64>,
    ipiv: Vec<usize>,
    factored: bool,
    /// Multiply–add count of the last factorisation.
    pub(crate) flops: usize,
}

impl BandLu {
    pub(crate) fn new(n: usize, lower: usize, upper: usize) -> Self {
        let shape = BandMatrix::zeros(n, lower, upper);
        Self {
            n,
            l: shape.lower,
            u: shape.upper,
            ab: vec![0.0; shape.data.len()],
            ipiv: vec![0; n],
            factored: false,
            flops: 0,
        }
    }

    /// Factorises `m` (same shape as given to [`BandLu::new`]). `Err(column)` on a zero or
    /// non-finite pivot, or a non-finite entry.
    pub(crate) fn factor(&mut self, m: &BandMatrix) -> Result<(), usize> {
        assert!(
            m.n == self.n && m.lower == self.l && m.upper == self.u,
            "band matrix shape mismatch"
        );
        self.factored = false;
        self.flops = 0;
        let (n, l, u) = (self.n, self.l, self.u);
        let ld = 2 * l + u + 1;
        let kv = l + u;
        self.ab.copy_from_slice(&m.data);
        for j in 0..n {
            let col = &mut self.ab[j * ld..(j + 1) * ld];
            // fill slots must start at zero whatever the caller stored there
            col[..l].iter_mut().for_each(|x| *x = 0.0);
            if col[l..].iter().any(|x| !x.is_finite()) {
                return Err(j);
            }
        }
        let ab = &mut self.ab;
        // index of the last column touched by a row interchange so far
        let mut ju = 0usize;
        for j in 0..n {
            let km = l.min(n - 1 - j);
            // pivot search in A(j..=j+km, j)
            let base = j * ld + kv;
            let mut jp = 0;
            let mut best = ab[base].abs();
            for i in 1..=km {
                let v = ab[base + i].abs();
                if v > best {
                    best = v;
                    jp = i;
                }
            }
            self.ipiv[j] = j + jp;
            let piv = ab[base + jp];
            if piv == 0.0 || !piv.is_finite() {
                return Err(j);
            }
            ju = ju.max((j + u + jp).min(n - 1));
            if jp != 0 {
                // swap rows j and j+jp over columns j..=ju: A(r, c) lives at c·ld + kv + r − c
                for c in j..=ju {
                    let a = c * ld + kv + j - c;
                    ab.swap(a, a + jp);
                }
            }
            if km > 0 {
                let inv = 1.0 / ab[base];
                for i in 1..=km {
                    ab[base + i] *= inv;
                }
                for c in j + 1..=ju {
                    let top = c * ld + kv + j - c;
                    let a = ab[top];
                    if a != 0.0 {
                        for i in 1..=km {
                            ab[top + i] -= ab[base + i] * a;
                        }
                    }
                    self.flops += km;
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `A·x = b` in place (`dgbtrs`, no transpose).
    pub(crate) fn solve(&self, b: &mut [f64]) {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        let (n, l, u) = (self.n, self.l, self.u);
        assert_eq!(b.len(), n, "right-hand side length mismatch");
        let ld = 2 * l + u + 1;
        let kv = l + u;
        let ab = &self.ab;
        if l > 0 {
            for j in 0..n.saturating_sub(1) {
                let lm = l.min(n - 1 - j);
                let p = self.ipiv[j];
                if p != j {
                    b.swap(j, p);
                }
                let bj = b[j];
                if bj != 0.0 {
                    let base = j * ld + kv;
                    for i in 1..=lm {
                        b[j + i] -= ab[base + i] * bj;
                    }
                }
            }
        }
        for j in (0..n).rev() {
            let base = j * ld + kv;
            b[j] /= ab[base];
            let bj = b[j];
            if bj != 0.0 {
                for i in j.saturating_sub(kv)..j {
                    b[i] -= ab[base + i - j] * bj;
                }
            }
        }
    }
}
