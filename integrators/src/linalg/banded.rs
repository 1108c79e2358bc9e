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
//! multiplies instead of dividing; `(l, u) = (1, 1)` and `(2, 2)` run copies of the loops with
//! literal band widths, and the tridiagonal solve carries its running entries in registers;
//! [`BandLu::factor_combination`] builds `A + β·B` straight into the factor storage (the BDF's
//! iteration matrix `∂F/∂y + α·∂F/∂ẏ`) in the same pass that checks finiteness.

use super::{BandMatrix, SolutionMap};

/// Column entries `[A(j−1, j), A(j, j), A(j+1, j)]` of a tridiagonal matrix, for
/// [`TriLu::factor`] (a trait with always-inlined methods, not a closure, so the streaming
/// loop is not left with a call per column).
trait TriColumns {
    fn col(&self, j: usize) -> [f64; 3];
}

/// Columns read from band storage (`ld = 4`: `[fill, A(j−1, j), A(j, j), A(j+1, j)]`).
struct BandColumns<'a>(&'a [f64]);

impl TriColumns for BandColumns<'_> {
    #[inline(always)]
    fn col(&self, j: usize) -> [f64; 3] {
        let c = &self.0[4 * j..4 * j + 4];
        [c[1], c[2], c[3]]
    }
}

/// Columns of `a + beta·b` from two band storages, each entry `a_k + beta·b_k`.
struct CombinedColumns<'a> {
    a: &'a [f64],
    beta: f64,
    b: &'a [f64],
}

impl TriColumns for CombinedColumns<'_> {
    #[inline(always)]
    fn col(&self, j: usize) -> [f64; 3] {
        let (x, y) = (&self.a[4 * j..4 * j + 4], &self.b[4 * j..4 * j + 4]);
        [
            x[1] + self.beta * y[1],
            x[2] + self.beta * y[2],
            x[3] + self.beta * y[3],
        ]
    }
}

/// The identity map (a plain solve).
struct Identity;

impl SolutionMap for Identity {
    #[inline(always)]
    fn map(&mut self, _j: usize, x: f64) -> f64 {
        x
    }
}

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
    /// Reciprocals of the pivots `1/U(j, j)`: the back substitution multiplies instead of
    /// dividing, which takes a division off its serial dependency chain (the solve of a narrow
    /// band is latency-bound).
    dinv: Vec<f64>,
    factored: bool,
    /// Compact factors for `l = u = 1` (then `ab`, `ipiv` and `dinv` stay empty).
    tri: Option<TriLu>,
    /// Multiply–add count of the last factorisation.
    pub(crate) flops: usize,
}

/// LU factors of a tridiagonal matrix with partial pivoting, stored by role instead of in the
/// `dgbtrf` band layout: the forward sweep streams 9 bytes per row (multiplier and interchange
/// flag) instead of a 32-byte band column plus an 8-byte pivot index, the backward sweep 24
/// (`U`'s two super-diagonals and the pivot reciprocal, interleaved so they arrive in one
/// stream). The arithmetic is `dgbtf2`/`dgbtrs` at `l = u = 1`, operation for operation.
#[derive(Clone, Debug)]
struct TriLu {
    /// `L(j+1, j)`.
    mult: Vec<f64>,
    /// Whether rows `j` and `j+1` were interchanged at step `j`.
    swap: Vec<bool>,
    /// Column `j` of `U`: `[U(j−2, j), U(j−1, j), 1/U(j, j)]` (the first is interchange fill).
    ucol: Vec<[f64; 3]>,
}

impl TriLu {
    fn new(n: usize) -> Self {
        Self {
            mult: vec![0.0; n],
            swap: vec![false; n],
            ucol: vec![[0.0; 3]; n],
        }
    }

    /// `dgbtf2` at `l = u = 1` on the matrix whose column `j` holds `col(j) = [A(j−1, j),
    /// A(j, j), A(j+1, j)]` (entries outside the matrix are read and must be finite, as the
    /// band storage's zero slots are). One streaming pass: the entries are loaded as the
    /// elimination reaches them, so a combined matrix `A + β·B` is never stored. Returns the
    /// multiply–add count, or `Err(column)`: the first column holding a non-finite entry if
    /// there is one (as the band path's up-front check reports), else the zero pivot's.
    #[inline(always)]
    fn factor<C: TriColumns>(&mut self, n: usize, cols: &C) -> Result<usize, usize> {
        debug_assert!(n >= 2);
        let col = |j| cols.col(j);
        let first_bad = |cols: &C| (0..n).find(|&j| cols.col(j).iter().any(|v| !v.is_finite()));
        let (mult, swap, ucol) = (&mut self.mult[..n], &mut self.swap[..n], &mut self.ucol[..n]);
        let c0 = col(0);
        let c1 = col(1);
        let mut finite = c0.iter().chain(&c1).all(|v| v.is_finite());
        // the current (partly eliminated) row j: entries at columns j and j+1
        let (mut p0, mut p1) = (c0[1], c1[0]);
        // original row j+1 is (c_j[2], c_{j+1}[1], c_{j+2}[0]); the next column is loaded ahead
        let mut cur = c0;
        let mut next = c1;
        // U(j−2, j) and U(j−1, j) for the column being finished, U(j−1, j+1) for the next
        let (mut u2, mut u1, mut u2_next) = (0.0, 0.0, 0.0);
        let mut flops = 0usize;
        let mut ju = 0usize;
        for j in 0..n - 1 {
            let after = if j + 2 < n {
                let c = col(j + 2);
                finite &= c.iter().all(|v| v.is_finite());
                c
            } else {
                [0.0; 3]
            };
            let (a, d, c) = (cur[2], next[1], after[0]);
            let swapped = a.abs() > p0.abs();
            let piv = if swapped { a } else { p0 };
            if piv == 0.0 || !piv.is_finite() {
                return Err(first_bad(cols).unwrap_or(j));
            }
            let inv = 1.0 / piv;
            ju = ju.max((j + 1 + usize::from(swapped)).min(n - 1));
            flops += ju - j;
            swap[j] = swapped;
            ucol[j] = [u2, u1, inv];
            // U(j, j+1), U(j, j+2); the remaining row j+1
            let (r1, r2, q0, q1);
            if swapped {
                let m = p0 * inv;
                mult[j] = m;
                (r1, r2) = (d, c);
                q0 = if d != 0.0 { p1 - m * d } else { p1 };
                // the fill slot starts at zero; it exists only while j+2 < n
                q1 = if c != 0.0 { 0.0 - m * c } else { 0.0 };
            } else {
                let m = a * inv;
                mult[j] = m;
                (r1, r2) = (p1, 0.0);
                q0 = if p1 != 0.0 { d - m * p1 } else { d };
                q1 = c;
            }
            u1 = r1;
            u2 = u2_next;
            u2_next = r2;
            (p0, p1) = (q0, q1);
            cur = next;
            next = after;
        }
        // last column: a 1×1 pivot
        if p0 == 0.0 || !p0.is_finite() {
            return Err(first_bad(cols).unwrap_or(n - 1));
        }
        swap[n - 1] = false;
        mult[n - 1] = 0.0;
        ucol[n - 1] = [u2, u1, 1.0 / p0];
        if !finite {
            return Err(first_bad(cols).unwrap_or(n - 1));
        }
        Ok(flops)
    }

    /// `dgbtrs` at `l = u = 1`; `map(j, x_j)` is stored in `b[j]` as each solution component
    /// is found (in decreasing `j`), so a caller's pass over the solution rides along with the
    /// latency-bound backward sweep instead of being a separate pass over memory.
    #[inline(always)]
    fn solve_map<M: SolutionMap>(&self, b: &mut [f64], map: &mut M) {
        let n = b.len();
        let (mult, swap, ucol) = (&self.mult[..n], &self.swap[..n], &self.ucol[..n]);
        // forward: L with the row interchanges; the running entries stay in registers
        let mut cur = b[0];
        for j in 0..n - 1 {
            let mut nxt = b[j + 1];
            if swap[j] {
                std::mem::swap(&mut cur, &mut nxt);
            }
            b[j] = cur;
            if cur != 0.0 {
                nxt -= mult[j] * cur;
            }
            cur = nxt;
        }
        // backward: U has two super-diagonals (the second from interchanges); U(−1, 0),
        // U(−2, 0) and U(−1, 1) are stored as zeros, so the updates past the top are harmless
        let mut a0 = cur;
        let mut a1 = b[n - 2];
        for j in (0..n).rev() {
            let [u2, u1, dinv] = ucol[j];
            let x = a0 * dinv;
            let mut a2 = if j >= 2 { b[j - 2] } else { 0.0 };
            if x != 0.0 {
                a1 -= u1 * x;
                a2 -= u2 * x;
            }
            b[j] = map.map(j, x);
            a0 = a1;
            a1 = a2;
        }
    }
}

impl BandLu {
    pub(crate) fn new(n: usize, lower: usize, upper: usize) -> Self {
        let shape = BandMatrix::zeros(n, lower, upper);
        if (shape.lower, shape.upper) == (1, 1) {
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
            };
        }
        Self {
            n,
            l: shape.lower,
            u: shape.upper,
            ab: vec![0.0; shape.data.len()],
            ipiv: vec![0; n],
            dinv: vec![0.0; n],
            factored: false,
            tri: None,
            flops: 0,
        }
    }

    /// Runs the compact tridiagonal factorisation on the column entries `col(j)`.
    fn factor_tri<C: TriColumns>(&mut self, cols: &C) -> Result<(), usize> {
        self.factored = false;
        self.flops = 0;
        let tri = self.tri.as_mut().expect("tridiagonal solver");
        let res = tri.factor(self.n, cols);
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

    fn check_shape(&self, m: &BandMatrix) {
        assert!(
            m.n == self.n && m.lower == self.l && m.upper == self.u,
            "band matrix shape mismatch"
        );
    }

    /// Factorises the matrix already copied into `self.ab`. The common narrow bands are
    /// dispatched to copies of the same code with the band widths as literal constants, so the
    /// compiler unrolls the short inner loops (a tridiagonal line is the hot case).
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
        match (self.l, self.u, &self.tri) {
            (_, _, Some(tri)) => tri.solve_map(b, &mut Identity),
            (2, 2, _) => self.solve_impl(2, 2, b),
            (l, u, _) => self.solve_impl(l, u, b),
        }
    }

    /// [`solve`](Self::solve), then `b[j] = map(j, x_j)` for every component. The tridiagonal
    /// path applies `map` inside its backward sweep (in decreasing `j`); the others after the
    /// solve, in increasing `j`.
    pub(crate) fn solve_map<M: SolutionMap>(&self, b: &mut [f64], map: &mut M) {
        assert!(
            self.factored,
            "LinearSolver::solve_in_place before a successful factor"
        );
        assert_eq!(b.len(), self.n, "right-hand side length mismatch");
        match &self.tri {
            Some(tri) => tri.solve_map(b, map),
            None => {
                self.solve(b);
                for (j, v) in b.iter_mut().enumerate() {
                    *v = map.map(j, *v);
                }
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
                let bj = b[j];
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
            b[j] *= dinv;
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
