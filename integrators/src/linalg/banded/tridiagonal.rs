//! The tridiagonal special case of the banded LU ([`TriLu`]): a compact, two-ended ("twisted")
//! factorisation with partial pivoting for `l = u = 1` (the lines and the heat equation), with
//! two independent dependency chains and a third of the band layout's memory traffic. The
//! column readers ([`TriColumns`]) let [`super::BandLu`] factor a band matrix or the combination
//! `A + β·B` without copying it first.

use crate::linalg::SolutionMap;

/// Column entries `[A(j−1, j), A(j, j), A(j+1, j)]` of a tridiagonal matrix, for
/// [`TriLu::factor`] (a trait with always-inlined methods, not a closure, so the streaming
/// loop is not left with a call per column).
pub(super) trait TriColumns {
    fn col(&self, j: usize) -> [f64; 3];
}

/// Columns read from band storage (`ld = 4`: `[fill, A(j−1, j), A(j, j), A(j+1, j)]`).
pub(super) struct BandColumns<'a>(pub(super) &'a [f64]);

impl TriColumns for BandColumns<'_> {
    #[inline(always)]
    fn col(&self, j: usize) -> [f64; 3] {
        let c = &self.0[4 * j..4 * j + 4];
        [c[1], c[2], c[3]]
    }
}

/// Columns of `a + beta·b` from two band storages, each entry `a_k + beta·b_k`.
pub(super) struct CombinedColumns<'a> {
    pub(super) a: &'a [f64],
    pub(super) beta: f64,
    pub(super) b: &'a [f64],
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
pub(super) struct Identity;

impl SolutionMap for Identity {
    #[inline(always)]
    fn map(&mut self, _j: usize, x: f64) -> f64 {
        x
    }

    fn split(self, _mid: usize) -> Result<(Self, Self), Self> {
        Ok((Identity, Identity))
    }
}

/// Whether a band of an `n × n` matrix may have been narrowed by [`clamped`] (then the
/// declared band is not known, and the storage cannot grow in place).
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
pub(super) struct TriLu {
    /// Twist index: rows `0..k` are eliminated downwards, `k+2..n` upwards, then rows `k+1`
    /// and `k`.
    k: usize,
    /// Multiplier of the step that pivots in row `j`.
    pub(super) mult: Vec<f64>,
    /// Whether that step interchanged its two rows.
    pub(super) swap: Vec<bool>,
    /// Row `j` of `U` divided by its pivot: `[u₂/pivot, u₁/pivot, 1/pivot]`, with `u₂`, `u₁`
    /// the entries two and one columns away from the pivot towards the twist (right of it for
    /// `j < k`, left of it for `j > k`).
    pub(super) urow: Vec<[f64; 3]>,
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
    pub(super) fn new(n: usize) -> Self {
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
    pub(super) fn factor<C: TriColumns + Sync>(
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
    pub(super) fn solve_map<M: SolutionMap>(&self, b: &mut [f64], mut map: M) -> M {
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
                tc = flush_subnormal(nx - mult[j] * tc);
            }
            let j = n - 1 - i;
            let mut nx = b[j - 1];
            if swap[j] {
                std::mem::swap(&mut bc, &mut nx);
            }
            b[j] = bc;
            bc = flush_subnormal(nx - mult[j] * bc);
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
                let x = flush_subnormal((b[j] * inv - v2 * t2) - v1 * t1);
                b[j] = map.map(j, x);
                (t1, t2) = (x, t1);
            }
            let j = k + 2 + i;
            let [v2, v1, inv] = urow[j];
            let x = flush_subnormal((b[j] * inv - v2 * d2) - v1 * d1);
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
    pub(super) fn solve_map_two_threads<M: SolutionMap + Send>(&self, b: &mut [f64], map: M) -> M {
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
                tc = flush_subnormal(nx - mult[j] * tc);
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
                bc = flush_subnormal(nx - mult[j] * bc);
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
                    let x = flush_subnormal((top[j] * inv - v2 * t2) - v1 * t1);
                    top[j] = first.map(j, x);
                    (t1, t2) = (x, t1);
                }
            },
            || {
                let (mut d1, mut d2) = (xk1, xk);
                for (j, &[v2, v1, inv]) in urow.iter().enumerate().skip(k + 2) {
                    let i = j - (k + 1);
                    let x = flush_subnormal((bot[i] * inv - v2 * d2) - v1 * d1);
                    bot[i] = second.map(j, x);
                    (d1, d2) = (x, d1);
                }
            },
        );
        first.merge(second);
        first
    }
}

/// `x`, or 0 if it is subnormal (|x| < `f64::MIN_POSITIVE` ≈ 2.2e-308). A Newton correction
/// decays into the far field of a long line (the macroscale family's tail beyond the
/// disturbance) and reaches the subnormal range there, where every operation on it costs about
/// a hundred cycles on x86: measured on the macroscale line at N = 10⁶, rtol 1e-6, the solve
/// took 2.3× as long per call as at rtol 1e-8, and the run 29 % longer than with the
/// processor's flush-to-zero mode. Flushing here changes the solution by less than 2.2e-308
/// per component: far below any tolerance.
#[inline(always)]
pub(crate) fn flush_subnormal(x: f64) -> f64 {
    if x.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        x
    }
}
