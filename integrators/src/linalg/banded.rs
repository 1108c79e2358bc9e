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

/// Whether a band of an `n × n` matrix may have been narrowed by [`clamped`] (then the
/// declared band is not known, and the storage cannot grow in place).
fn may_be_clamped(n: usize, lower: usize, upper: usize) -> bool {
    lower.max(upper) + 1 >= n
}

/// Band widths of an `n × n` matrix: at most `n − 1`.
fn clamped(n: usize, lower: usize, upper: usize) -> (usize, usize) {
    let m = n.saturating_sub(1);
    (lower.min(m), upper.min(m))
}

impl BandMatrix {
    /// A zero `n × n` band matrix; `lower`/`upper` are clamped to `n − 1`.
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
    /// Whether the tridiagonal solve runs its twisted halves concurrently (from
    /// [`crate::Parallelism::Halves`]' `min_len` unknowns). Set by
    /// [`super::LinearSolver::set_parallelism`].
    pub(crate) parallel: crate::Parallelism,
}

/// LU factors of a tridiagonal matrix with partial pivoting, eliminated from both ends at once
/// ("twisted", burn-at-both-ends) and stored by role instead of in the `dgbtrf` band layout.
///
/// *Why*: a tridiagonal factorisation and its solves are serial recurrences (each row waits for
/// a multiply, a subtraction and, in the factorisation, a division on the previous row), so one
/// sweep runs at the latency of that chain, not at the memory's bandwidth. Gaussian elimination
/// with partial pivoting (GEPP) in the column order `0, 1, …, k−1, n−1, n−2, …, k+1, k` touches
/// rows `0..=k` in its first `k` steps and rows `k+1..n` in the next `n−2−k`, so with
/// `k = (n−2)/2` the two halves are independent and run interleaved in one loop: two dependency
/// chains for the CPU to overlap. It is ordinary GEPP on `A` with permuted columns (each step
/// picks the larger of the two candidates in its column), so it keeps partial pivoting's
/// robustness for matrices that are not diagonally dominant; only the rounding differs from
/// the top-down `dgbtf2` order.
///
/// Storage: the forward sweep streams 9 bytes per row (multiplier and interchange flag) instead
/// of a 32-byte band column and an 8-byte pivot index; the backward sweep 24 (the `U` row's two
/// off-diagonal entries divided by the pivot and the pivot's reciprocal, interleaved into one
/// stream).
#[derive(Clone, Debug)]
struct TriLu {
    /// Twist index: rows `0..k` are eliminated downwards, `k+2..n` upwards, then rows `k+1`
    /// and `k`.
    k: usize,
    /// Multiplier of the step that pivots in row `j`.
    mult: Vec<f64>,
    /// Whether that step interchanged its two rows.
    swap: Vec<bool>,
    /// Row `j` of `U` divided by its pivot: `[u₂/pivot, u₁/pivot, 1/pivot]`, with `u₂`, `u₁`
    /// the entries two and one columns away from the pivot towards the twist (right of it for
    /// `j < k`, left of it for `j > k`).
    urow: Vec<[f64; 3]>,
}

/// One GEPP step on two rows of a tridiagonal matrix: the current (already updated) row with
/// entries `p0` in the pivot column and `p1` one column on, and the other candidate row with
/// `a` in the pivot column, `d` and `c` one and two columns on. Returns `None` on a zero or
/// non-finite pivot, else `(swapped, multiplier, [u₂/pivot, u₁/pivot, 1/pivot], remaining
/// row)`: the `U` row is stored divided by its pivot, so the back substitution's dependency
/// chain is one multiply and one subtraction per row instead of two multiplies and a
/// subtraction.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn tri_step(p0: f64, p1: f64, a: f64, d: f64, c: f64) -> Option<(bool, f64, [f64; 3], (f64, f64))> {
    let swapped = a.abs() > p0.abs();
    let piv = if swapped { a } else { p0 };
    if piv == 0.0 || !piv.is_finite() {
        return None;
    }
    let inv = 1.0 / piv;
    Some(if swapped {
        let m = p0 * inv;
        (true, m, [c * inv, d * inv, inv], (p1 - m * d, -(m * c)))
    } else {
        let m = a * inv;
        (false, m, [0.0, p1 * inv, inv], (d - m * p1, c))
    })
}

/// The running state of one of the two elimination sweeps of [`TriLu::factor`]: the current
/// row's entries in the pivot column and the next (`p0`, `p1`), and the two columns loaded
/// ahead of it. The downward sweep reads a column as `[above, diagonal, below]`, the upward
/// sweep mirrored, so one step function serves both (`DOWN` picks the orientation).
#[derive(Clone, Copy)]
struct Sweep<const DOWN: bool> {
    p0: f64,
    p1: f64,
    cur: [f64; 3],
    next: [f64; 3],
}

impl<const DOWN: bool> Sweep<DOWN> {
    /// Starts from the first two columns of the sweep (`first`, then its neighbour inwards).
    #[inline(always)]
    fn new(first: [f64; 3], next: [f64; 3]) -> Self {
        let (p1, _) = Self::outer(next);
        Self {
            p0: first[1],
            p1,
            cur: first,
            next,
        }
    }

    /// A column's `(entry towards the start of the sweep, entry away from it)`.
    #[inline(always)]
    fn outer(c: [f64; 3]) -> (f64, f64) {
        if DOWN {
            (c[0], c[2])
        } else {
            (c[2], c[0])
        }
    }

    /// One GEPP step, with `after` the column two on from the pivot column; `None` on a bad
    /// pivot.
    #[inline(always)]
    fn step(&mut self, after: [f64; 3]) -> Option<(bool, f64, [f64; 3])> {
        let (_, away) = Self::outer(self.cur);
        let (towards, _) = Self::outer(after);
        let (sw, m, u, q) = tri_step(self.p0, self.p1, away, self.next[1], towards)?;
        (self.p0, self.p1) = q;
        (self.cur, self.next) = (self.next, after);
        Some((sw, m, u))
    }
}

/// One sweep of [`TriLu::factor`] with its bookkeeping: multiply–adds so far and whether
/// every column it loaded was finite.
struct Half<const DOWN: bool> {
    sweep: Sweep<DOWN>,
    flops: usize,
    finite: bool,
}

impl<const DOWN: bool> Half<DOWN> {
    /// Loads the sweep's first two columns.
    #[inline(always)]
    fn start<C: TriColumns>(cols: &C, first: usize, second: usize) -> Self {
        let (a, b) = (cols.col(first), cols.col(second));
        Self {
            sweep: Sweep::new(a, b),
            flops: 0,
            finite: a.iter().chain(&b).all(|v| v.is_finite()),
        }
    }

    /// Eliminates the current pivot column, loading column `after` (two on), and stores the
    /// row's interchange flag, multiplier and scaled `U` row in `out`. `Err` on a zero or
    /// non-finite pivot.
    #[inline(always)]
    fn step<C: TriColumns>(
        &mut self,
        cols: &C,
        after: usize,
        out: (&mut bool, &mut f64, &mut [f64; 3]),
    ) -> Result<(), ()> {
        let c = cols.col(after);
        self.finite &= c.iter().all(|v| v.is_finite());
        let (sw, m, u) = self.sweep.step(c).ok_or(())?;
        (*out.0, *out.1, *out.2) = (sw, m, u);
        self.flops += 1 + usize::from(sw);
        Ok(())
    }
}

impl TriLu {
    fn new(n: usize) -> Self {
        Self {
            k: 0,
            mult: vec![0.0; n],
            swap: vec![false; n],
            urow: vec![[0.0; 3]; n],
        }
    }

    /// Twisted GEPP on the `n × n` (`n ≥ 2`) matrix whose column `j` holds `cols.col(j) =
    /// [A(j−1, j), A(j, j), A(j+1, j)]` (entries outside the matrix are read and must be
    /// finite, as the band storage's zero slots are). One streaming pass from each end: the
    /// entries are loaded as the elimination reaches them, so a combined matrix `A + β·B` is
    /// never stored. With `two_threads` the downward and the upward sweep run concurrently
    /// ([`rayon::join`]: the caller's thread and a pool worker, no thread started)
    /// (they touch disjoint rows until the twist), else interleaved in one loop; the
    /// arithmetic is the same. Returns the multiply–add count, or `Err(column)`: the first
    /// column holding a non-finite entry if there is one (as the band path's up-front check
    /// reports), else the column whose pivot was zero (the first the one-thread order meets).
    #[inline(always)]
    fn factor<C: TriColumns + Sync>(
        &mut self,
        n: usize,
        cols: &C,
        two_threads: bool,
    ) -> Result<usize, usize> {
        debug_assert!(n >= 2);
        let first_bad = |cols: &C| (0..n).find(|&j| cols.col(j).iter().any(|v| !v.is_finite()));
        let k = (n - 2) / 2;
        let (top_len, bot_len) = (k, n - 2 - k);
        self.k = k;
        let (mult, swap, urow) = (
            &mut self.mult[..n],
            &mut self.swap[..n],
            &mut self.urow[..n],
        );
        // downwards: the current row j has its entries in columns (j, j+1); the other
        // candidate is row j+1 = (col(j)[2], col(j+1)[1], col(j+2)[0]). Upwards mirrored: row
        // j in columns (j, j−1) against row j−1 = (col(j)[0], col(j−1)[1], col(j−2)[2]).
        let mut down = Half::<true>::start(cols, 0, 1);
        let mut up = Half::<false>::start(cols, n - 1, n - 2);
        let failed = if two_threads {
            let (m_top, m_bot) = mult.split_at_mut(k + 1);
            let (s_top, s_bot) = swap.split_at_mut(k + 1);
            let (u_top, u_bot) = urow.split_at_mut(k + 1);
            // the upward sweep's state moves to its thread and back (two sweeps' running
            // states side by side on one stack would share a cache line, written every row)
            let upward = move || {
                for i in 0..bot_len {
                    let j = n - 1 - i;
                    let r = j - (k + 1);
                    let out = (&mut s_bot[r], &mut m_bot[r], &mut u_bot[r]);
                    if up.step(cols, j - 2, out).is_err() {
                        return (up, Err((i, 1, j)));
                    }
                }
                (up, Ok(()))
            };
            let downward = || {
                for j in 0..top_len {
                    if down
                        .step(cols, j + 2, (&mut s_top[j], &mut m_top[j], &mut u_top[j]))
                        .is_err()
                    {
                        return Err((j, 0, j));
                    }
                }
                Ok(())
            };
            let (rd, (up_back, ru)) = rayon::join(downward, upward);
            up = up_back;
            // the failure the interleaved loop meets first: step i, downward before upward
            match (rd, ru) {
                (Ok(()), Ok(())) => None,
                (Err(e), Ok(())) | (Ok(()), Err(e)) => Some(e.2),
                (Err(d), Err(u)) => Some(d.min(u).2),
            }
        } else {
            let mut failed = None;
            for i in 0..bot_len {
                if i < top_len {
                    let j = i;
                    if down
                        .step(cols, j + 2, (&mut swap[j], &mut mult[j], &mut urow[j]))
                        .is_err()
                    {
                        failed = Some(j);
                        break;
                    }
                }
                let j = n - 1 - i;
                if up
                    .step(cols, j - 2, (&mut swap[j], &mut mult[j], &mut urow[j]))
                    .is_err()
                {
                    failed = Some(j);
                    break;
                }
            }
            failed
        };
        if let Some(j) = failed {
            return Err(first_bad(cols).unwrap_or(j));
        }
        // column k+1: the upward current row k+1 against the downward current row k (which
        // has p0 in column k and p1 in column k+1); then the 1×1 pivot of column k
        let (d, u) = (down.sweep, up.sweep);
        let Some((sw, m, ur, (r, _))) = tri_step(u.p0, u.p1, d.p1, d.p0, 0.0) else {
            return Err(first_bad(cols).unwrap_or(k + 1));
        };
        (swap[k + 1], mult[k + 1], urow[k + 1]) = (sw, m, ur);
        if r == 0.0 || !r.is_finite() {
            return Err(first_bad(cols).unwrap_or(k));
        }
        (swap[k], mult[k], urow[k]) = (false, 0.0, [0.0, 0.0, 1.0 / r]);
        if !(down.finite && up.finite) {
            return Err(first_bad(cols).unwrap_or(k));
        }
        Ok(down.flops + up.flops + 1)
    }

    /// The two twist rows `k`, `k+1` of the solve: the last forward elimination (column
    /// `k+1`) on the running entries `tc` (downward sweep) and `bc` (upward sweep), then
    /// `(x_k, x_{k+1})`, where the backward sweeps start.
    #[inline(always)]
    fn twist(&self, mut tc: f64, mut bc: f64) -> (f64, f64) {
        let k = self.k;
        if self.swap[k + 1] {
            std::mem::swap(&mut bc, &mut tc);
        }
        tc -= self.mult[k + 1] * bc;
        let xk = tc * self.urow[k][2];
        let [_, v1, inv] = self.urow[k + 1];
        (xk, bc * inv - v1 * xk)
    }

    /// Solve with the twisted factors; `map.map(j, x_j)` is stored in `b[j]` as each solution
    /// component is found (outwards from the twist), so a caller's pass over the solution
    /// rides along with the latency-bound back substitution instead of being a separate pass
    /// over memory.
    #[inline(always)]
    fn solve_map<M: SolutionMap>(&self, b: &mut [f64], mut map: M) -> M {
        let n = b.len();
        let k = self.k;
        let (top_len, bot_len) = (k, n - 2 - k);
        let (mult, swap, urow) = (&self.mult[..n], &self.swap[..n], &self.urow[..n]);
        // forward: L⁻¹ with the interchanges, both halves at once (running entries in registers)
        let (mut tc, mut bc) = (b[0], b[n - 1]);
        for i in 0..bot_len {
            if i < top_len {
                let j = i;
                let mut nx = b[j + 1];
                if swap[j] {
                    std::mem::swap(&mut tc, &mut nx);
                }
                b[j] = tc;
                tc = nx - mult[j] * tc;
            }
            let j = n - 1 - i;
            let mut nx = b[j - 1];
            if swap[j] {
                std::mem::swap(&mut bc, &mut nx);
            }
            b[j] = bc;
            bc = nx - mult[j] * bc;
        }
        // column k+1 (rows k+1 and k), then column k; backward: x_k, x_{k+1}, then outwards in
        // both directions at once
        let (xk, xk1) = self.twist(tc, bc);
        b[k] = map.map(k, xk);
        b[k + 1] = map.map(k + 1, xk1);
        // (x_{j+1}, x_{j+2}) going up, (x_{j−1}, x_{j−2}) going down
        let (mut t1, mut t2) = (xk, xk1);
        let (mut d1, mut d2) = (xk1, xk);
        for i in 0..bot_len {
            if i < top_len {
                let j = k - 1 - i;
                let [v2, v1, inv] = urow[j];
                let x = (b[j] * inv - v2 * t2) - v1 * t1;
                b[j] = map.map(j, x);
                (t1, t2) = (x, t1);
            }
            let j = k + 2 + i;
            let [v2, v1, inv] = urow[j];
            let x = (b[j] * inv - v2 * d2) - v1 * d1;
            b[j] = map.map(j, x);
            (d1, d2) = (x, d1);
        }
        map
    }

    /// [`solve_map`](Self::solve_map) with the two halves run concurrently ([`rayon::join`]):
    /// the downward half
    /// (rows `0..=k`) and the upward half (rows `k+1..n`) of each sweep touch disjoint parts
    /// of `b`, and only the twist rows `k`, `k+1` join them. `map` is split at `k + 1`
    /// ([`SolutionMap::split`]; a map that cannot be split gets the one-thread solve). Same
    /// operations per component as the one-thread solve.
    fn solve_map_two_threads<M: SolutionMap + Send>(&self, b: &mut [f64], map: M) -> M {
        let n = b.len();
        let k = self.k;
        let (mut first, mut second) = match map.split(k + 1) {
            Ok(halves) => halves,
            Err(map) => return self.solve_map(b, map),
        };
        let (mult, swap, urow) = (&self.mult[..n], &self.swap[..n], &self.urow[..n]);
        let (top, bot) = b.split_at_mut(k + 1);
        // forward: downward over rows 0..=k, upward over rows n−1..=k+1 (bot[i] is row k+1+i)
        let down = |top: &mut [f64]| {
            let mut tc = top[0];
            for j in 0..k {
                let mut nx = top[j + 1];
                if swap[j] {
                    std::mem::swap(&mut tc, &mut nx);
                }
                top[j] = tc;
                tc = nx - mult[j] * tc;
            }
            tc
        };
        let up = |bot: &mut [f64]| {
            let m = bot.len();
            let mut bc = bot[m - 1];
            for j in (k + 2..n).rev() {
                let i = j - (k + 1);
                let mut nx = bot[i - 1];
                if swap[j] {
                    std::mem::swap(&mut bc, &mut nx);
                }
                bot[i] = bc;
                bc = nx - mult[j] * bc;
            }
            bc
        };
        let (tc, bc) = rayon::join(|| down(&mut *top), || up(&mut *bot));
        let (xk, xk1) = self.twist(tc, bc);
        top[k] = first.map(k, xk);
        bot[0] = second.map(k + 1, xk1);
        // backward: outwards from the twist, one half per worker
        rayon::join(
            || {
                let (mut t1, mut t2) = (xk, xk1);
                for j in (0..k).rev() {
                    let [v2, v1, inv] = urow[j];
                    let x = (top[j] * inv - v2 * t2) - v1 * t1;
                    top[j] = first.map(j, x);
                    (t1, t2) = (x, t1);
                }
            },
            || {
                let (mut d1, mut d2) = (xk1, xk);
                for (j, &[v2, v1, inv]) in urow.iter().enumerate().skip(k + 2) {
                    let i = j - (k + 1);
                    let x = (bot[i] * inv - v2 * d2) - v1 * d1;
                    bot[i] = second.map(j, x);
                    (d1, d2) = (x, d1);
                }
            },
        );
        first.merge(second);
        first
    }
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
            }
        }
        self.n = n;
        self.factored = false;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Records each component once (at its global index) and splits at any point.
    struct Record<'a> {
        off: usize,
        out: &'a mut [Option<f64>],
        calls: usize,
    }

    impl SolutionMap for Record<'_> {
        fn map(&mut self, j: usize, x: f64) -> f64 {
            let slot = &mut self.out[j - self.off];
            assert!(slot.is_none(), "component {j} mapped twice");
            *slot = Some(x);
            self.calls += 1;
            -x
        }
        fn split(self, mid: usize) -> Result<(Self, Self), Self> {
            let (a, b) = self.out.split_at_mut(mid - self.off);
            Ok((
                Record {
                    off: self.off,
                    out: a,
                    calls: self.calls,
                },
                Record {
                    off: mid,
                    out: b,
                    calls: 0,
                },
            ))
        }
        fn merge(&mut self, other: Self) {
            self.calls += other.calls;
        }
    }

    /// Column entries for the tests: pivoting forced by zero diagonals every third column.
    fn test_columns(n: usize) -> Vec<f64> {
        let mut data = vec![0.0; 4 * n];
        for j in 0..n {
            let f = j as f64;
            data[4 * j + 1] = if j > 0 { (1.3 * f).sin() } else { 0.0 };
            data[4 * j + 2] = if j % 3 == 1 {
                0.0
            } else {
                0.5 + (0.7 * f).cos()
            };
            data[4 * j + 3] = if j + 1 < n { (2.1 * f).cos() } else { 0.0 };
        }
        data
    }

    /// A band matrix with entries at every in-band slot (diagonally dominant).
    fn filled(n: usize, l: usize, u: usize) -> BandMatrix {
        let mut m = BandMatrix::zeros(n, l, u);
        for j in 0..n {
            let (r0, r1) = m.col_range(j);
            for i in r0..r1 {
                let k = m.index(i, j).unwrap();
                m.data[k] = if i == j {
                    4.0 + j as f64
                } else {
                    (i + 2 * j) as f64 * 0.1 - 0.3
                };
            }
        }
        m
    }

    #[test]
    fn grown_storage_factors_and_solves_as_new_storage() {
        for (l, u) in [(1, 1), (2, 2), (1, 3)] {
            // a factor of the small matrix leaves stale entries in every buffer
            let (mut m, mut lu) = (filled(7, l, u), BandLu::new(7, l, u));
            lu.factor(&m).unwrap();
            assert!(m.grow(12) && lu.grow(12));
            assert!(!m.grow(5) && !lu.grow(5), "shrinking is not growth");
            let fresh = filled(12, l, u);
            m.data.copy_from_slice(&fresh.data); // the caller refills a grown matrix
            let mut lu_new = BandLu::new(12, l, u);
            lu.factor(&m).unwrap();
            lu_new.factor(&fresh).unwrap();
            let b: Vec<f64> = (0..12).map(|i| (i as f64).sin()).collect();
            let (mut x, mut x_new) = (b.clone(), b);
            lu.solve(&mut x);
            lu_new.solve(&mut x_new);
            assert_eq!(x, x_new, "l = {l}, u = {u}");
        }
        // a band clamped by a small size widens when it grows: no growth in place
        let mut m = BandMatrix::zeros(2, 2, 2);
        assert!(!m.grow(10));
    }

    #[test]
    fn two_thread_tridiagonal_factor_is_the_one_thread_factor() {
        // bitwise equal factors and flop counts; the same error column for singular matrices
        // (a zero pivot in either half, or in both) and for a non-finite entry
        for n in (2..=40).chain([101, 256]) {
            let data = test_columns(n);
            let (mut one, mut two) = (TriLu::new(n), TriLu::new(n));
            let f1 = one.factor(n, &BandColumns(&data), false);
            let f2 = two.factor(n, &BandColumns(&data), true);
            assert_eq!(f1, f2, "n={n}");
            if f1.is_ok() {
                assert_eq!(one.mult, two.mult, "n={n}");
                assert_eq!(one.swap, two.swap, "n={n}");
                assert_eq!(one.urow, two.urow, "n={n}");
            }
            let mut zeroed = data.clone();
            for j in [n / 4, 3 * n / 4] {
                zeroed[4 * j..4 * j + 4].iter_mut().for_each(|v| *v = 0.0);
                let a = TriLu::new(n).factor(n, &BandColumns(&zeroed), false);
                let b = TriLu::new(n).factor(n, &BandColumns(&zeroed), true);
                assert!(a.is_err(), "n={n}: a zero column is singular");
                assert_eq!(a, b, "n={n}, zero column {j}");
            }
            let mut bad = data.clone();
            bad[4 * (n - 1) + 2] = f64::NAN;
            let a = TriLu::new(n).factor(n, &BandColumns(&bad), false);
            let b = TriLu::new(n).factor(n, &BandColumns(&bad), true);
            assert_eq!((a, b), (Err(n - 1), Err(n - 1)), "n={n}");
        }
    }

    #[test]
    fn two_thread_tridiagonal_solve_is_the_one_thread_solve() {
        // every small size, with pivoting forced (zero diagonal entries): bitwise equal
        // components, each mapped exactly once, the split map's state merged back
        for n in (2..=40).chain([101, 256]) {
            let data = test_columns(n);
            let mut lu = TriLu::new(n);
            if lu.factor(n, &BandColumns(&data), false).is_err() {
                continue;
            }
            let rhs: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect();
            let mut one = rhs.clone();
            lu.solve_map(&mut one, Identity);
            let mut seen = vec![None; n];
            let mut two = rhs.clone();
            let rec = lu.solve_map_two_threads(
                &mut two,
                Record {
                    off: 0,
                    out: &mut seen,
                    calls: 0,
                },
            );
            assert_eq!(rec.calls, n, "n={n}");
            for j in 0..n {
                assert_eq!(seen[j], Some(one[j]), "n={n} j={j}");
                assert_eq!(two[j], -one[j], "n={n} j={j}");
            }
        }
    }
}
