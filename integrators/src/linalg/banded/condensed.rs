//! Static condensation of a pentadiagonal matrix whose every other unknown couples only to its
//! two neighbours ([`Condensed`]), reducing it to a tridiagonal Schur complement solved by the
//! compact [`TriLu`].
//!
//! *Why*: a line whose cells carry an internal variable (growth `g`, interleaved with the
//! boundary positions) has a `(2, 2)` band, but the internal variable's row touches only the
//! cell's two boundaries: in the alternate ordering the matrix is
//! `[[D, C], [B, A]]` with `D` diagonal (the internal rows), `A` tridiagonal (the boundaries)
//! and the Schur complement `S = A − B D⁻¹ C` tridiagonal again. Eliminating the internal
//! unknowns first turns a pivoted `(2, 2)` band LU on `n` unknowns into a division per internal
//! row and a twisted tridiagonal LU on the `n/2` others: half the length of the serial
//! recurrence that bounds a narrow band's solve, no pivot search on the internal rows, and
//! the two-ended factorisation's two dependency chains. [`super::BandLu`] takes this path
//! whenever the values allow it (the alternate rows have zeros two off the diagonal and
//! pivots that are not negligible against their couplings) and the general `dgbtf2` path
//! otherwise, so the answer is the same linear solve up to rounding.

use std::sync::Mutex;

use super::tridiagonal::{flush_subnormal, Identity, TriColumns, TriLu};
use crate::linalg::SolutionMap;

/// Smallest `|D_p|` accepted, relative to the sum of its row's and column's coupling
/// magnitudes: eliminating a pivot that small first could amplify rounding where partial
/// pivoting would not, so such a matrix takes the pivoted band LU instead.
const MIN_PIVOT_RATIO: f64 = 1e-8;

/// Band storage of a `(2, 2)` matrix: `ld = 2·2 + 2 + 1` slots per column, entry `(i, j)` at
/// `j·7 + 4 + i − j`.
const LD: usize = 7;
const KV: usize = 4;

/// The entries `a + β·b` of one or two `(2, 2)` band storages (`b = a`, `β = 0` for one).
#[derive(Clone, Copy)]
pub(super) struct Entries<'a> {
    pub(super) a: &'a [f64],
    pub(super) beta: f64,
    pub(super) b: &'a [f64],
    pub(super) n: usize,
}

impl Entries<'_> {
    /// `A(i, j)`, or 0 outside the matrix (the caller stays within the band).
    #[inline(always)]
    fn get(&self, i: usize, j: usize) -> f64 {
        if i >= self.n || j >= self.n {
            return 0.0;
        }
        let k = j * LD + KV + i - j;
        self.a[k] + self.beta * self.b[k]
    }

    /// `A(i, j)` for `i`, `j` inside the matrix and `|i − j| ≤ 2` (no range checks: the
    /// interior rows' fast path). The factorisation spells out each row's entries twice, with
    /// this and with [`at`](Self::at): one helper mapping an offset list through either was
    /// measured 6 % slower in instructions on a dividing line (13.79e9 against 12.99e9).
    #[inline(always)]
    fn inner(&self, i: usize, j: usize) -> f64 {
        let k = j * (LD - 1) + KV + i;
        self.a[k] + self.beta * self.b[k]
    }

    /// `A(i, j)` for `i` or `j` possibly one or two before the start (as `isize`).
    #[inline(always)]
    fn at(&self, i: isize, j: isize) -> f64 {
        if i < 0 || j < 0 {
            return 0.0;
        }
        self.get(i as usize, j as usize)
    }
}

/// The Schur complement's columns `[S(m−1, m), S(m, m), S(m+1, m)]`, for [`TriLu::factor`].
struct SchurColumns<'a>(&'a [[f64; 3]]);

impl TriColumns for SchurColumns<'_> {
    #[inline(always)]
    fn col(&self, j: usize) -> [f64; 3] {
        self.0[j]
    }
}

/// Factors of a condensed `(2, 2)` band matrix: the eliminated ("P") unknowns are
/// `p = p0 + 2m`, the kept ("Q") unknowns `q = q0 + 2m` with `q0 = 1 − p0`.
#[derive(Debug)]
pub(super) struct Condensed {
    /// Parity of the eliminated unknowns (0 or 1).
    p0: usize,
    /// Dimension of the full matrix.
    n: usize,
    /// Per eliminated unknown `p`: `[A(p, p−1)/D_p, A(p, p+1)/D_p, 1/D_p]`.
    prow: Vec<[f64; 3]>,
    /// Per kept unknown `q`: `[A(q, q−1), A(q, q+1)]`.
    qrow: Vec<[f64; 2]>,
    /// The Schur complement's columns (read by the factorisation).
    cols: Vec<[f64; 3]>,
    tri: TriLu,
    /// The reduced right-hand side of a solve (one buffer reused; a solve takes `&self`).
    scratch: Mutex<Vec<f64>>,
    /// Multiply–add count of the last factorisation.
    pub(super) flops: usize,
}

impl Condensed {
    pub(super) fn new() -> Self {
        Self {
            p0: 0,
            n: 0,
            prow: Vec::new(),
            qrow: Vec::new(),
            cols: Vec::new(),
            tri: TriLu::new(0),
            scratch: Mutex::new(Vec::new()),
            flops: 0,
        }
    }

    /// Number of kept unknowns for dimension `n` and eliminated parity `p0`.
    fn kept(n: usize, p0: usize) -> usize {
        (n + p0) / 2
    }

    /// Condenses and factorises the matrix `e` (dimension ≥ 4). `false` when it does not
    /// condense (no separable parity, a negligible or non-finite pivot of an eliminated row, a
    /// non-finite entry, or a singular Schur complement): the caller then factorises the
    /// band as it is, which also reports the failing column. With `two_threads` the
    /// eliminated rows, the Schur columns and the tridiagonal factorisation each run in two
    /// halves ([`rayon::join`]): the same operations per row, so the same factors bit for bit.
    pub(super) fn factor(&mut self, e: &Entries<'_>, two_threads: bool) -> bool {
        // the parity that condensed last time first; the other fails at its first row
        let first = self.p0;
        self.factor_parity(e, first, two_threads) || self.factor_parity(e, 1 - first, two_threads)
    }

    /// [`factor`](Self::factor) with the unknowns of parity `p0` eliminated: `false` when one
    /// of their rows couples to another unknown of their parity (a non-zero two off the
    /// diagonal) or the factorisation fails.
    fn factor_parity(&mut self, e: &Entries<'_>, p0: usize, two_threads: bool) -> bool {
        let n = e.n;
        let nq = Self::kept(n, p0);
        let np = n - nq;
        if nq < 2 {
            return false;
        }
        self.p0 = p0;
        self.n = n;
        self.prow.resize(np, [0.0; 3]);
        self.qrow.resize(nq, [0.0; 2]);
        self.cols.resize(nq, [0.0; 3]);
        self.reserve(n);
        // every eliminated row, then every Schur column, depends only on the matrix (and the
        // eliminated rows): the same operations per row in two halves as in one pass
        let eliminated = if two_threads {
            let (a, b) = self.prow.split_at_mut(np / 2);
            let (ra, rb) = rayon::join(
                || eliminate_rows(e, p0, a, 0),
                || eliminate_rows(e, p0, b, np / 2),
            );
            ra && rb
        } else {
            eliminate_rows(e, p0, &mut self.prow, 0)
        };
        if !eliminated {
            return false;
        }
        let prow = &self.prow;
        let finite = if two_threads {
            let (qa, qb) = self.qrow.split_at_mut(nq / 2);
            let (ca, cb) = self.cols.split_at_mut(nq / 2);
            let (ra, rb) = rayon::join(
                || schur_columns(e, p0, prow, qa, ca, 0),
                || schur_columns(e, p0, prow, qb, cb, nq / 2),
            );
            ra && rb
        } else {
            schur_columns(e, p0, prow, &mut self.qrow, &mut self.cols, 0)
        };
        if !finite {
            return false;
        }
        match self.tri.factor(nq, &SchurColumns(&self.cols), two_threads) {
            Ok(f) => {
                self.flops = f + 3 * np + 6 * nq;
                true
            }
            Err(_) => false,
        }
    }

    /// Solves with the last successful [`factor`](Self::factor) and stores `map.map(j, x_j)` in
    /// `b[j]`, in increasing `j`. With `two_threads` the reduced right-hand side, the reduced
    /// tridiagonal solve and the back substitution each run in two halves ([`rayon::join`];
    /// the map split at `n/2`, each half in increasing `j`): the same operations per component,
    /// so the same solution bit for bit.
    pub(super) fn solve_map<M: SolutionMap + Send>(
        &self,
        b: &mut [f64],
        map: M,
        two_threads: bool,
    ) -> M {
        let (n, p0) = (self.n, self.p0);
        assert_eq!(b.len(), n, "right-hand side length mismatch");
        let q0 = 1 - p0;
        let mut guard = self.scratch.try_lock();
        let mut own = Vec::new();
        let s: &mut Vec<f64> = match guard.as_mut() {
            Ok(g) => g,
            Err(_) => &mut own,
        };
        let nq = self.qrow.len();
        s.resize(nq, 0.0);
        let prow = &self.prow;
        // the reduced right-hand side of kept rows m0.. (written to `out`)
        let gather = |out: &mut [f64], m0: usize, b: &[f64]| {
            // D⁻¹ b_p of the eliminated neighbour (zero past either end)
            let scaled = |p: isize| -> f64 {
                if p < 0 || p as usize >= n {
                    0.0
                } else {
                    b[p as usize] * prow[(p as usize - p0) / 2][2]
                }
            };
            for (m, (sv, qr)) in (m0..).zip(out.iter_mut().zip(&self.qrow[m0..])) {
                let q = q0 + 2 * m;
                let (bl, br) = if q >= 1 && q + 1 < n {
                    (
                        b[q - 1] * prow[(q - 1 - p0) / 2][2],
                        b[q + 1] * prow[(q + 1 - p0) / 2][2],
                    )
                } else {
                    let qi = q as isize;
                    (scaled(qi - 1), scaled(qi + 1))
                };
                *sv = b[q] - qr[0] * bl - qr[1] * br;
            }
        };
        let s = &mut s[..nq];
        if two_threads {
            let (sa, sb) = s.split_at_mut(nq / 2);
            let bs = &*b;
            rayon::join(|| gather(sa, 0, bs), || gather(sb, nq / 2, bs));
            self.tri.solve_map_two_threads(s, Identity);
        } else {
            gather(s, 0, b);
            self.tri.solve_map(s, Identity);
        }
        let s = &*s;
        // back: x_q from the reduced solve, x_p = D⁻¹b_p − (A(p,p±1)/D_p)·x_{p±1}
        let x_kept = |q: usize| -> f64 {
            if q >= n {
                0.0
            } else {
                s[(q - q0) / 2]
            }
        };
        // components j0.. (`out` holds their right-hand sides)
        let scatter = |out: &mut [f64], j0: usize, mut map: M| -> M {
            for (j, bj) in (j0..).zip(out.iter_mut()) {
                let x = if j % 2 == q0 {
                    s[(j - q0) / 2]
                } else {
                    let [l, r, inv] = prow[(j - p0) / 2];
                    let (left, right) = if j >= 1 && j + 1 < n {
                        (s[(j - 1 - q0) / 2], s[(j + 1 - q0) / 2])
                    } else {
                        (if j == 0 { 0.0 } else { x_kept(j - 1) }, x_kept(j + 1))
                    };
                    flush_subnormal(*bj * inv - l * left - r * right)
                };
                *bj = map.map(j, x);
            }
            map
        };
        if !two_threads {
            return scatter(b, 0, map);
        }
        // each component reads only its own right-hand side and the reduced solution
        match map.split(n / 2) {
            Ok((first, second)) => {
                let (ba, bb) = b.split_at_mut(n / 2);
                let (mut first, second) =
                    rayon::join(|| scatter(ba, 0, first), || scatter(bb, n / 2, second));
                first.merge(second);
                first
            }
            Err(map) => scatter(b, 0, map),
        }
    }

    /// Keeps the storage for a larger dimension (refilled by the next factorisation).
    pub(super) fn reserve(&mut self, n: usize) {
        let nq = n.div_ceil(2);
        if self.tri.mult.len() < nq {
            self.tri.mult.resize(nq, 0.0);
            self.tri.swap.resize(nq, false);
            self.tri.urow.resize(nq, [0.0; 3]);
        }
    }
}

/// The eliminated rows `m0..m0 + out.len()` of parity `p0`: `[A(p, p−1)/D_p, A(p, p+1)/D_p,
/// 1/D_p]` each. `false` when a row couples to an unknown of its own parity (a non-zero two off
/// the diagonal) or its pivot is negligible against its couplings or not finite.
fn eliminate_rows(e: &Entries<'_>, p0: usize, out: &mut [[f64; 3]], m0: usize) -> bool {
    let n = e.n;
    for (m, pr) in (m0..).zip(out.iter_mut()) {
        let pu = p0 + 2 * m;
        // the row's far entries, its couplings, its pivot and its column's couplings
        let [far_l, far_r, left, right, d, above, below] = if pu >= 2 && pu + 2 < n {
            [
                e.inner(pu, pu - 2),
                e.inner(pu, pu + 2),
                e.inner(pu, pu - 1),
                e.inner(pu, pu + 1),
                e.inner(pu, pu),
                e.inner(pu - 1, pu),
                e.inner(pu + 1, pu),
            ]
        } else {
            let p = pu as isize;
            [
                e.at(p, p - 2),
                e.at(p, p + 2),
                e.at(p, p - 1),
                e.at(p, p + 1),
                e.at(p, p),
                e.at(p - 1, p),
                e.at(p + 1, p),
            ]
        };
        if far_l != 0.0 || far_r != 0.0 {
            return false;
        }
        let scale = left.abs() + right.abs() + above.abs() + below.abs();
        if !(d.abs() > MIN_PIVOT_RATIO * scale && d.is_finite() && scale.is_finite()) {
            return false;
        }
        let inv = 1.0 / d;
        *pr = [left * inv, right * inv, inv];
    }
    true
}

/// The kept rows `m0..m0 + qrow.len()` (eliminated parity `p0`, rows `prow` from
/// [`eliminate_rows`]): their couplings `[A(q, q−1), A(q, q+1)]` and the Schur complement's
/// columns `[S(q−2, q), S(q, q), S(q+2, q)]`. `false` when an entry is not finite.
fn schur_columns(
    e: &Entries<'_>,
    p0: usize,
    prow: &[[f64; 3]],
    qrow: &mut [[f64; 2]],
    cols: &mut [[f64; 3]],
    m0: usize,
) -> bool {
    let n = e.n;
    let q0 = 1 - p0;
    // the eliminated neighbour of a kept unknown (zeros past either end)
    let p_of = |p: isize| -> [f64; 3] {
        if p < 0 || p as usize >= n {
            [0.0; 3]
        } else {
            prow[(p as usize - p0) / 2]
        }
    };
    let mut finite = true;
    for (m, (qr, col)) in (m0..).zip(qrow.iter_mut().zip(cols.iter_mut())) {
        let qu = q0 + 2 * m;
        // A(q, q∓1), A(q−2, q), A(q−2, q−1), A(q, q), A(q+2, q), A(q+2, q+1) and the
        // eliminated neighbours' rows
        let ([l, r, a_up, a_upl, a_qq, a_dn, a_dnr], pl, pr) = if qu >= 2 && qu + 2 < n {
            (
                [
                    e.inner(qu, qu - 1),
                    e.inner(qu, qu + 1),
                    e.inner(qu - 2, qu),
                    e.inner(qu - 2, qu - 1),
                    e.inner(qu, qu),
                    e.inner(qu + 2, qu),
                    e.inner(qu + 2, qu + 1),
                ],
                prow[(qu - 1 - p0) / 2],
                prow[(qu + 1 - p0) / 2],
            )
        } else {
            let q = qu as isize;
            (
                [
                    e.at(q, q - 1),
                    e.at(q, q + 1),
                    e.at(q - 2, q),
                    e.at(q - 2, q - 1),
                    e.at(q, q),
                    e.at(q + 2, q),
                    e.at(q + 2, q + 1),
                ],
                p_of(q - 1),
                p_of(q + 1),
            )
        };
        *qr = [l, r];
        // S(q−2, q), S(q, q), S(q+2, q): A minus the couplings through p = q ∓ 1
        let up = a_up - a_upl * pl[1];
        let diag = a_qq - qr[0] * pl[1] - qr[1] * pr[0];
        let down = a_dn - a_dnr * pr[0];
        *col = [up, diag, down];
        finite &= up.is_finite() && diag.is_finite() && down.is_finite();
    }
    finite
}

impl Clone for Condensed {
    fn clone(&self) -> Self {
        Self {
            p0: self.p0,
            n: self.n,
            prow: self.prow.clone(),
            qrow: self.qrow.clone(),
            cols: self.cols.clone(),
            tri: self.tri.clone(),
            scratch: Mutex::new(Vec::new()),
            flops: self.flops,
        }
    }
}
