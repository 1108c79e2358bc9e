//! Band storage and banded LU with partial pivoting (LAPACK `dgbtrf`/`dgbtrs` layout).
//!
//! faer (like every other maintained pure-Rust crate we know of) has no banded LU, so this one
//! is hand-written: the unblocked `dgbtf2` algorithm. Time is O(n·l·(l+u)) and memory
//! O(n·(2l+u+1)); a band matrix with `l` sub- and `u` super-diagonals is stored column by column
//! with `ld = 2l+u+1` slots per column, entry `(i, j)` at `data[j·ld + l+u+i−j]`. The top `l`
//! slots of every column are zero in a [`BandMatrix`] and receive the fill created by row
//! interchanges (which widen `U` to `l+u` super-diagonals).
//!
//! Performance notes (the solve of a narrow band is bound by the latency of its serial
//! recurrences, not by flops): the pivots' reciprocals are stored so the back substitution
//! multiplies instead of dividing; `(l, u) = (2, 2)` runs a copy of the loops with literal band
//! widths; tridiagonal matrices (`l = u = 1`, the lines and the heat equation) get
//! their own compact, two-ended factorisation with partial pivoting ([`TriLu`]: two independent
//! dependency chains, and a third of the memory traffic of the band layout);
//! [`BandLu::factor_combination`] builds `A + β·B` straight into the factor storage (the BDF's
//! iteration matrix `∂F/∂y + α·∂F/∂ẏ`) in the same pass that checks finiteness; a `(2, 2)`
//! band whose alternate unknowns couple only to their two neighbours (a growing line) is
//! condensed to a tridiagonal Schur complement ([`condensed`]) instead of eliminated as a
//! pentadiagonal band.

use super::{BandMatrix, SolutionMap};

mod condensed;
mod tridiagonal;
use condensed::{Condensed, Entries};
use tridiagonal::{BandColumns, CombinedColumns, Identity, TriColumns, TriLu};

#[cfg(test)]
mod tests;
/// Columns `j0..=j1` of a [`BandMatrix::remap`] that move whole by the shift `s`.
type ColumnBlock = (usize, usize, usize);

fn may_be_clamped(n: usize, lower: usize, upper: usize) -> bool {
    lower.max(upper) + 1 >= n
}

/// Band widths of an `n × n` matrix: at most `n − 1`.
fn clamped(n: usize, lower: usize, upper: usize) -> (usize, usize) {
    let m = n.saturating_sub(1);
    (lower.min(m), upper.min(m))
}

impl BandMatrix {
    /// See [`Matrix::remap`]. Entries of the band keep their offset `i − j` in the storage, so
    /// an entry whose row and column moved by the same amount moves with its column; new
    /// columns are written from the last down, which never overwrites a column still to be
    /// read (`src[j] ≤ j`).
    pub(crate) fn remap(&mut self, src: &[usize], fresh_rows: &[bool]) -> bool {
        let n = self.n;
        if src.len() != n || fresh_rows.len() != n {
            return false;
        }
        let Some((first, blocks)) = self.whole_column_blocks(src, fresh_rows) else {
            return false;
        };
        let ld = self.ld();
        let diag = self.lower + self.upper;
        // columns whose band lies before the first moved or fresh row are unchanged
        let start = first.saturating_sub(self.lower);
        let mut blocks = blocks.into_iter().rev().filter(|b| b.1 >= start).peekable();
        let mut j = n;
        while j > start {
            j -= 1;
            if let Some(&(j0, j1, s)) = blocks.peek() {
                if j == j1 {
                    // whole columns: one copy (`src[j] = j − s`, so the source lies below)
                    let j0 = j0.max(start);
                    if s > 0 {
                        self.data
                            .copy_within((j0 - s) * ld..(j1 + 1 - s) * ld, j0 * ld);
                    }
                    blocks.next();
                    j = j0;
                    continue;
                }
            }
            let sj = src[j];
            let lo = j.saturating_sub(self.upper);
            let hi = (j + self.lower).min(n - 1);
            for i in lo..=hi {
                // slot of (i, j) in column j, and of the same offset in the source column
                let off = diag + i - j;
                let moved = sj != usize::MAX
                    && !fresh_rows[i]
                    && src[i] != usize::MAX
                    && src[i] + j == sj + i;
                self.data[j * ld + off] = if moved { self.data[sj * ld + off] } else { 0.0 };
            }
        }
        true
    }

    /// For [`remap`](Self::remap), in one pass over the rows: `None` if the map is not a growth
    /// by insertions (sources must increase and never lie ahead), else the first moved or
    /// fresh row and the column ranges `(j0, j1, s)`, increasing, whose every band row moved
    /// by the column's own shift `s` and is not fresh. Each such column is its source column
    /// `j − s` whole, so a run of them moves in one copy instead of entry by entry (the band's
    /// fill slots above each column are zero in a matrix that is not factored in place, and
    /// stay so). Between a dividing line's insertions the shift is constant, so all but a few
    /// columns around each insertion fall in such runs (the entry-by-entry map had cost 7 %
    /// of a dividing line's instructions).
    fn whole_column_blocks(
        &self,
        src: &[usize],
        fresh_rows: &[bool],
    ) -> Option<(usize, Vec<ColumnBlock>)> {
        let n = self.n;
        let mut blocks = Vec::new();
        let mut first = n;
        let mut prev = None;
        // the current run of rows a..i with one shift (`usize::MAX`: inserted or fresh rows)
        let (mut a, mut run) = (0, usize::MAX);
        let mut close = |a: usize, b: usize, s: usize| {
            if s == usize::MAX {
                return;
            }
            // columns whose band rows [j − upper, j + lower] (clipped) lie in rows a..=b
            let lo = if a == 0 { 0 } else { a + self.upper };
            let hi = if b == n - 1 {
                b
            } else if b >= self.lower {
                b - self.lower
            } else {
                return;
            };
            if lo <= hi {
                blocks.push((lo, hi, s));
            }
        };
        for (i, (&s, &fresh)) in src.iter().zip(fresh_rows).enumerate() {
            let shift = if s == usize::MAX {
                usize::MAX
            } else {
                if s > i || prev.is_some_and(|p| s <= p) {
                    return None;
                }
                prev = Some(s);
                if fresh {
                    usize::MAX
                } else {
                    i - s
                }
            };
            if first == n && (s != i || fresh) {
                first = i;
            }
            if i == 0 {
                run = shift;
            } else if shift != run {
                close(a, i - 1, run);
                (a, run) = (i, shift);
            }
        }
        if n > 0 {
            close(a, n - 1, run);
        }
        Some((first, blocks))
    }

    /// A zero `n × n` band matrix; `lower`/`upper` are clamped to `n − 1`.
    ///
    /// ```
    /// use integrators::linalg::BandMatrix;
    /// let b = BandMatrix::zeros(3, 5, 1); // lower clamped to n − 1 = 2
    /// assert_eq!((b.lower, b.upper, b.data.len()), (2, 1, b.ld() * 3));
    /// ```
    pub fn zeros(n: usize, lower: usize, upper: usize) -> Self {
        let (lower, upper) = clamped(n, lower, upper);
        let ld = 2 * lower + upper + 1;
        Self {
            n,
            lower,
            upper,
            data: vec![0.0; ld * n],
        }
    }

    /// Grows the matrix to `n × n` in place, keeping its storage, when its clamped band is the
    /// same at the new size (`false` otherwise, the matrix unchanged). The added columns are
    /// zero; the old entries stay, so the caller refills the matrix before use, as a reused
    /// one's (a line that gains cells keeps its band: this saves a zeroed allocation).
    pub(crate) fn grow(&mut self, n: usize) -> bool {
        if n < self.n || may_be_clamped(self.n, self.lower, self.upper) {
            return false;
        }
        self.data.resize(self.ld() * n, 0.0);
        self.n = n;
        true
    }

    /// Slots per column of the storage (`2·lower + upper + 1`).
    ///
    /// ```
    /// use integrators::linalg::BandMatrix;
    /// assert_eq!(BandMatrix::zeros(10, 1, 1).ld(), 4); // room for the pivoting fill
    /// ```
    pub fn ld(&self) -> usize {
        2 * self.lower + self.upper + 1
    }

    /// Storage index of `(i, j)`, or `None` outside the band.
    ///
    /// ```
    /// use integrators::linalg::BandMatrix;
    /// let b = BandMatrix::zeros(10, 1, 1);
    /// assert!(b.index(4, 3).is_some() && b.index(4, 6).is_none());
    /// ```
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
    /// Reciprocals of the pivots `1/U(j, j)`: the back substitution multiplies instead of
    /// dividing, which takes a division off its serial dependency chain (the solve of a narrow
    /// band is latency-bound).
    dinv: Vec<f64>,
    factored: bool,
    /// Compact factors for `l = u = 1` (then `ab`, `ipiv` and `dinv` stay empty).
    tri: Option<TriLu>,
    /// Multiply–add count of the last factorisation.
    pub(crate) flops: usize,
    /// Whether the tridiagonal solve runs its twisted halves concurrently (from
    /// [`crate::Parallelism::Halves`]' `min_len` unknowns). Set by
    /// [`super::LinearSolver::set_parallelism`].
    pub(crate) parallel: crate::Parallelism,
    /// The condensed factors of a `(2, 2)` band whose alternate unknowns separate (see
    /// [`condensed`]); created by the first factorisation that condenses.
    cond: Option<Box<Condensed>>,
    /// Whether the last successful factorisation is `cond` (else `ab`).
    condensed: bool,
}

impl BandLu {
    pub(crate) fn new(n: usize, lower: usize, upper: usize) -> Self {
        let (lower, upper) = clamped(n, lower, upper);
        if (lower, upper) == (1, 1) {
            return Self {
                n,
                l: 1,
                u: 1,
                ab: Vec::new(),
                ipiv: Vec::new(),
                dinv: Vec::new(),
                factored: false,
                tri: Some(TriLu::new(n)),
                flops: 0,
                parallel: crate::Parallelism::Serial,
                cond: None,
                condensed: false,
            };
        }
        Self {
            n,
            l: lower,
            u: upper,
            ab: vec![0.0; (2 * lower + upper + 1) * n],
            ipiv: vec![0; n],
            dinv: vec![0.0; n],
            factored: false,
            tri: None,
            flops: 0,
            parallel: crate::Parallelism::Serial,
            cond: None,
            condensed: false,
        }
    }

    /// Grows the factor storage to `n` unknowns in place when the clamped band stays the same
    /// (`false` otherwise, nothing changed); the factorisation is then stale, as after
    /// [`new`](Self::new).
    pub(crate) fn grow(&mut self, n: usize) -> bool {
        if n < self.n || may_be_clamped(self.n, self.l, self.u) {
            return false;
        }
        match &mut self.tri {
            Some(t) => {
                t.mult.resize(n, 0.0);
                t.swap.resize(n, false);
                t.urow.resize(n, [0.0; 3]);
            }
            None => {
                self.ab.resize((2 * self.l + self.u + 1) * n, 0.0);
                self.ipiv.resize(n, 0);
                self.dinv.resize(n, 0.0);
                if let Some(c) = &mut self.cond {
                    c.reserve(n);
                }
            }
        }
        self.n = n;
        self.factored = false;
        self.condensed = false;
        true
    }

    /// Runs the compact tridiagonal factorisation on the column entries `col(j)`.
    fn factor_tri<C: TriColumns + Sync>(&mut self, cols: &C) -> Result<(), usize> {
        self.factored = false;
        self.flops = 0;
        let tri = self.tri.as_mut().expect("tridiagonal solver");
        let two = self.parallel.splits(self.n);
        let res = tri.factor(self.n, cols, two);
        if let Ok(f) = res {
            self.flops = f;
        }
        self.factored = res.is_ok();
        res.map(|_| ())
    }

    /// Factorises `m` (same shape as given to [`BandLu::new`]). `Err(column)` on a zero or
    /// non-finite pivot, or a non-finite entry.
    pub(crate) fn factor(&mut self, m: &BandMatrix) -> Result<(), usize> {
        self.check_shape(m);
        if self.tri.is_some() {
            // band column j: [fill, A(j−1, j), A(j, j), A(j+1, j)]
            return self.factor_tri(&BandColumns(&m.data[..4 * self.n]));
        }
        let data = &m.data[..];
        if self.factor_condensed(data, 0.0, data) {
            return Ok(());
        }
        self.ab.copy_from_slice(&m.data);
        self.factor_loaded()
    }

    /// Factorises `a + beta·b` (both of the solver's shape) without materialising the sum in a
    /// separate matrix: the combination is written straight into the factor storage, one pass
    /// instead of zero + two `axpby` + copy. Each entry is `a_k + beta·b_k`, bitwise what
    /// `set_zero; axpby(1, 1, a); axpby(1, beta, b)` produces.
    pub(crate) fn factor_combination(
        &mut self,
        a: &BandMatrix,
        beta: f64,
        b: &BandMatrix,
    ) -> Result<(), usize> {
        self.check_shape(a);
        self.check_shape(b);
        if self.tri.is_some() {
            // the same `a_k + beta·b_k` per entry, fed to the elimination as it streams
            return self.factor_tri(&CombinedColumns {
                a: &a.data[..4 * self.n],
                beta,
                b: &b.data[..4 * self.n],
            });
        }
        if self.factor_condensed(&a.data, beta, &b.data) {
            return Ok(());
        }
        self.factored = false;
        self.flops = 0;
        // one pass: combine, zero the fill slots, check finiteness
        let (l, ld) = (self.l, a.ld());
        for (j, ((d, x), y)) in self
            .ab
            .chunks_exact_mut(ld)
            .zip(a.data.chunks_exact(ld))
            .zip(b.data.chunks_exact(ld))
            .enumerate()
        {
            d[..l].iter_mut().for_each(|v| *v = 0.0);
            let mut finite = true;
            for ((dv, &xv), &yv) in d[l..].iter_mut().zip(&x[l..]).zip(&y[l..]) {
                *dv = xv + beta * yv;
                finite &= dv.is_finite();
            }
            if !finite {
                return Err(j);
            }
        }
        self.eliminate()
    }

    /// Factorises `a + beta·b` by static condensation ([`Condensed`]) when the band is
    /// `(2, 2)` and the matrix condenses; `false` (nothing factorised) otherwise.
    fn factor_condensed(&mut self, a: &[f64], beta: f64, b: &[f64]) -> bool {
        self.factored = false;
        self.condensed = false;
        if (self.l, self.u) != (2, 2) || self.n < 4 {
            return false;
        }
        let e = Entries {
            a,
            beta,
            b,
            n: self.n,
        };
        // the passes cover every row (eliminated and kept), as the condensed solve's do: the
        // same threshold on `n`
        let two = self.parallel.splits(self.n);
        let cond = self.cond.get_or_insert_with(|| Box::new(Condensed::new()));
        if !cond.factor(&e, two) {
            return false;
        }
        self.flops = cond.flops;
        self.factored = true;
        self.condensed = true;
        true
    }

    /// Whether the last factorisation condensed ([`condensed`]).
    pub(crate) fn is_condensed(&self) -> bool {
        self.factored && self.condensed
    }

    /// The condensed factors, when the last factorisation condensed.
    fn active_condensed(&self) -> Option<&Condensed> {
        self.cond.as_deref().filter(|_| self.condensed)
    }

    fn check_shape(&self, m: &BandMatrix) {
        assert!(
            m.n == self.n && m.lower == self.l && m.upper == self.u,
            "band matrix shape mismatch"
        );
    }

    /// Factorises the matrix already copied into `self.ab`. The pentadiagonal band is
    /// dispatched to a copy of the same code with the band widths as literal constants, so the
    /// compiler unrolls the short inner loops (tridiagonal matrices take [`TriLu`] instead).
    fn factor_loaded(&mut self) -> Result<(), usize> {
        self.factored = false;
        self.flops = 0;
        let (l, ld) = (self.l, 2 * self.l + self.u + 1);
        for (j, col) in self.ab.chunks_exact_mut(ld).enumerate() {
            // fill slots must start at zero whatever the caller stored there
            col[..l].iter_mut().for_each(|x| *x = 0.0);
            if col[l..].iter().any(|x| !x.is_finite()) {
                return Err(j);
            }
        }
        self.eliminate()
    }

    /// Elimination on the loaded, checked storage.
    fn eliminate(&mut self) -> Result<(), usize> {
        let res = match (self.l, self.u) {
            (2, 2) => self.factor_impl(2, 2),
            (l, u) => self.factor_impl(l, u),
        };
        if res.is_ok() {
            let ld = 2 * self.l + self.u + 1;
            let kv = self.l + self.u;
            for (di, col) in self.dinv.iter_mut().zip(self.ab.chunks_exact(ld)) {
                *di = 1.0 / col[kv];
            }
        }
        self.factored = res.is_ok();
        res
    }

    /// Unblocked `dgbtf2` on `self.ab` (see [`factor_loaded`](Self::factor_loaded)).
    #[inline(always)]
    fn factor_impl(&mut self, l: usize, u: usize) -> Result<(), usize> {
        let n = self.n;
        let ld = 2 * l + u + 1;
        let kv = l + u;
        let ab = &mut self.ab[..];
        let mut flops = 0usize;
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
                self.flops = flops;
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
                        // the multipliers (column j) lie before column c's slots
                        let (left, right) = ab.split_at_mut(top + 1);
                        let mult = &left[base + 1..=base + km];
                        for (t, &mlt) in right[..km].iter_mut().zip(mult) {
                            *t -= mlt * a;
                        }
                    }
                    flops += km;
                }
            }
        }
        self.flops = flops;
        Ok(())
    }

    /// Solves `A·x = b` in place (`dgbtrs`, no transpose).
    pub(crate) fn solve(&self, b: &mut [f64]) {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        assert_eq!(b.len(), self.n, "right-hand side length mismatch");
        if let Some(c) = self.active_condensed() {
            c.solve_map(b, Identity, self.parallel.splits(b.len()));
            return;
        }
        match (self.l, self.u, &self.tri) {
            (_, _, Some(tri)) => {
                tri.solve_map(b, Identity);
            }
            (2, 2, _) => self.solve_impl(2, 2, b),
            (l, u, _) => self.solve_impl(l, u, b),
        }
    }

    /// [`solve`](Self::solve), then `b[j] = map(j, x_j)` for every component. The tridiagonal
    /// path applies `map` inside its backward sweep (in decreasing `j`); the others after the
    /// solve, in increasing `j`.
    pub(crate) fn solve_map<M: SolutionMap + Send>(&self, b: &mut [f64], mut map: M) -> M {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        assert_eq!(b.len(), self.n, "right-hand side length mismatch");
        match &self.tri {
            Some(tri) => {
                if self.parallel.splits(b.len()) {
                    tri.solve_map_two_threads(b, map)
                } else {
                    tri.solve_map(b, map)
                }
            }
            None => {
                if let Some(c) = self.active_condensed() {
                    return c.solve_map(b, map, self.parallel.splits(b.len()));
                }
                self.solve(b);
                for (j, v) in b.iter_mut().enumerate() {
                    *v = map.map(j, *v);
                }
                map
            }
        }
    }

    /// `dgbtrs` with the band widths as arguments (inlined with constants by [`solve`](Self::solve)).
    #[inline(always)]
    fn solve_impl(&self, l: usize, u: usize, b: &mut [f64]) {
        let n = self.n;
        let ld = 2 * l + u + 1;
        let kv = l + u;
        let ab = &self.ab[..];
        if l > 0 {
            for j in 0..n.saturating_sub(1) {
                let lm = l.min(n - 1 - j);
                let p = self.ipiv[j];
                if p != j {
                    b.swap(j, p);
                }
                let bj = tridiagonal::flush_subnormal(b[j]);
                b[j] = bj;
                if bj != 0.0 {
                    let base = j * ld + kv;
                    let mult = &ab[base + 1..=base + lm];
                    for (bi, &m) in b[j + 1..=j + lm].iter_mut().zip(mult) {
                        *bi -= m * bj;
                    }
                }
            }
        }
        for (j, (col, &dinv)) in ab.chunks_exact(ld).zip(&self.dinv).enumerate().rev() {
            // (a subnormal tail costs ~100 cycles per operation: see `flush_subnormal`)
            b[j] = tridiagonal::flush_subnormal(b[j] * dinv);
            let bj = b[j];
            if bj != 0.0 {
                // U(i, j) for i = j−kv..j lives at col[kv + i − j]
                let lo = j.saturating_sub(kv);
                let ucol = &col[kv - (j - lo)..kv];
                for (bi, &uij) in b[lo..j].iter_mut().zip(ucol) {
                    *bi -= uij * bj;
                }
            }
        }
    }
}
