//! Tests of the banded LU and its tridiagonal special case against dense references.

use super::tridiagonal::*;
use super::*;

/// Records each component once (at its global index) and splits at any point.
struct Record<'a> {
    off: usize,
    out: &'a mut [Option<f64>],
    calls: usize,
}

impl<'a> Record<'a> {
    /// A record of every component, none mapped yet.
    fn new(out: &'a mut [Option<f64>]) -> Self {
        Record {
            off: 0,
            out,
            calls: 0,
        }
    }
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
        let rec = lu.solve_map_two_threads(&mut two, Record::new(&mut seen));
        assert_eq!(rec.calls, n, "n={n}");
        for j in 0..n {
            assert_eq!(seen[j], Some(one[j]), "n={n} j={j}");
            assert_eq!(two[j], -one[j], "n={n} j={j}");
        }
    }
}

/// A `(2, 2)` band matrix whose unknowns of parity `p0` couple only to their two neighbours
/// (zeros two off the diagonal in their rows), as a growing line's `g` rows; not diagonally
/// dominant in the kept rows, so the Schur complement's factorisation pivots.
fn separable(n: usize, p0: usize, seed: f64) -> BandMatrix {
    let mut m = BandMatrix::zeros(n, 2, 2);
    for i in 0..n {
        for j in i.saturating_sub(2)..(i + 3).min(n) {
            let off = j as isize - i as isize;
            if i % 2 == p0 && off.abs() == 2 {
                continue;
            }
            let f = (3 * i + 7 * j) as f64 + seed;
            let v = if off == 0 {
                if i % 2 == p0 {
                    2.0 + f.sin()
                } else {
                    0.2 * f.cos()
                }
            } else {
                (1.7 * f).sin()
            };
            let k = m.index(i, j).unwrap();
            m.data[k] = v;
        }
    }
    m
}

/// `‖A x − b‖∞` for band storage.
fn band_residual(m: &BandMatrix, x: &[f64], b: &[f64]) -> f64 {
    (0..m.n)
        .map(|i| {
            let ax: f64 = (0..m.n)
                .filter_map(|j| m.index(i, j).map(|k| m.data[k] * x[j]))
                .sum();
            (ax - b[i]).abs()
        })
        .fold(0.0, f64::max)
}

/// `‖A x − b‖∞` of `lu`'s solution of `A x = b` (solved on a copy of `b`).
fn solve_residual(lu: &BandLu, m: &BandMatrix, b: &[f64]) -> f64 {
    let mut x = b.to_vec();
    lu.solve(&mut x);
    band_residual(m, &x, b)
}

/// Whether two vectors are equal bit for bit.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// A separable `(2, 2)` band matrix of order `n` whose rows of parity `p0` are eliminated,
/// and its LU, checked to have taken the condensed path.
fn condensed_lu(n: usize, p0: usize) -> (BandMatrix, BandLu) {
    let m = separable(n, p0, 0.3 * n as f64);
    let mut lu = BandLu::new(n, 2, 2);
    lu.factor(&m).unwrap();
    assert!(lu.condensed, "n = {n}, p0 = {p0}: should condense");
    (m, lu)
}

#[test]
fn condensed_solves_match_the_pivoted_band_lu_for_either_parity_and_length() {
    for n in [4, 5, 8, 9, 31, 200] {
        for p0 in [0, 1] {
            let (m, lu) = condensed_lu(n, p0);
            let b: Vec<f64> = (0..n).map(|i| (0.9 * i as f64).cos() + 0.5).collect();
            let mut x = b.clone();
            lu.solve(&mut x);
            let r = band_residual(&m, &x, &b);
            assert!(r < 1e-11, "n = {n}, p0 = {p0}: residual {r}");
            // against the pivoted dgbtf2 path on the same matrix (forced by a far entry of
            // 1e-300, which changes no solution digit)
            let mut g = m.clone();
            let k = g.index(p0, p0 + 2).unwrap();
            g.data[k] = 1e-300;
            let mut general = BandLu::new(n, 2, 2);
            general.factor(&g).unwrap();
            assert!(!general.condensed);
            let mut y = b.clone();
            general.solve(&mut y);
            let gap = x
                .iter()
                .zip(&y)
                .map(|(a, c)| (a - c).abs())
                .fold(0.0, f64::max);
            let size = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(gap <= 1e-12 * size, "n = {n}, p0 = {p0}: {gap} of {size}");
        }
    }
}

/// `lu.solve_map` of `rhs` through a [`Record`]: what it stored (the map's values) and the
/// solution it mapped, each component mapped exactly once.
fn mapped_solve(lu: &BandLu, rhs: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = rhs.len();
    let mut out = vec![None; n];
    let mut x = rhs.to_vec();
    let rec = lu.solve_map(&mut x, Record::new(&mut out));
    assert_eq!(rec.calls, n, "every component mapped once");
    (x, out.iter().map(|v| v.unwrap()).collect())
}

#[test]
fn condensed_combination_and_map_are_those_of_the_sum() {
    let n = 41;
    let (a, bm) = (separable(n, 1, 0.1), separable(n, 1, 2.9));
    let beta = 3.7;
    let mut sum = a.clone();
    for (s, v) in sum.data.iter_mut().zip(&bm.data) {
        *s += beta * v;
    }
    let mut lu = BandLu::new(n, 2, 2);
    lu.factor_combination(&a, beta, &bm).unwrap();
    assert!(lu.condensed);
    let rhs: Vec<f64> = (0..n).map(|i| 1.0 - 0.01 * (i * i) as f64).collect();
    let (x, sol) = mapped_solve(&lu, &rhs);
    assert!(
        x.iter().zip(&sol).all(|(m, s)| *m == -s),
        "the map's value is stored"
    );
    assert!(band_residual(&sum, &sol, &rhs) < 1e-11);
}

#[test]
fn a_negligible_eliminated_pivot_takes_the_pivoted_path() {
    let n = 12;
    let mut m = separable(n, 0, 0.0);
    // row 4's pivot is 1e-12 of its couplings: eliminating it first is refused
    let k = m.index(4, 4).unwrap();
    m.data[k] = 1e-12;
    let mut lu = BandLu::new(n, 2, 2);
    lu.factor(&m).unwrap();
    assert!(!lu.condensed);
    assert!(solve_residual(&lu, &m, &vec![1.0; n]) < 1e-10);
    // a zero pivot in the kept rows' Schur complement is still reported by its column
    let z = BandMatrix::zeros(n, 2, 2);
    assert!(lu.factor(&z).is_err());
}

#[test]
fn condensed_storage_grows_in_place() {
    let mut lu = BandLu::new(9, 2, 2);
    lu.factor(&separable(9, 1, 0.5)).unwrap();
    assert!(lu.grow(30));
    let m = separable(30, 1, 0.5);
    lu.factor(&m).unwrap();
    assert!(lu.condensed);
    assert!(solve_residual(&lu, &m, &[0.25; 30]) < 1e-11);
}

#[test]
fn condensed_factor_on_two_threads_is_the_one_thread_factor_bit_for_bit() {
    for n in [5, 8, 9, 31, 200, 1001] {
        for p0 in [0, 1] {
            let (m, serial) = condensed_lu(n, p0);
            let mut split = BandLu::new(n, 2, 2);
            split.parallel = crate::Parallelism::Halves { min_len: 2 };
            split.factor(&m).unwrap();
            assert!(
                split.condensed,
                "n = {n}, p0 = {p0}: should condense on two threads"
            );
            // solved on one thread with each factor: equal only if every factor entry is
            split.parallel = crate::Parallelism::Serial;
            let rhs: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos() + 0.1).collect();
            let (a, b) = (mapped_solve(&serial, &rhs).1, mapped_solve(&split, &rhs).1);
            assert!(band_residual(&m, &a, &rhs) < 1e-11);
            assert!(same_bits(&a, &b), "n = {n}, p0 = {p0}: the factors differ");
        }
    }
}

#[test]
fn condensed_factor_on_two_threads_rejects_what_one_thread_rejects() {
    // a row of the eliminated parity coupling two off the diagonal, in the second half
    let n = 40;
    let mut m = separable(n, 1, 0.5);
    let k = m.index(31, 33).unwrap();
    m.data[k] = 0.5;
    for parallel in [
        crate::Parallelism::Serial,
        crate::Parallelism::Halves { min_len: 2 },
    ] {
        let mut lu = BandLu::new(n, 2, 2);
        lu.parallel = parallel;
        lu.factor(&m).unwrap();
        assert!(
            !lu.condensed,
            "{parallel:?}: a coupled row must take the pivoted band LU"
        );
        assert!(solve_residual(&lu, &m, &vec![1.0; n]) < 1e-11);
    }
}

#[test]
fn condensed_solve_on_two_threads_is_the_one_thread_solve_bit_for_bit() {
    for n in [5, 8, 9, 31, 200, 1001] {
        for p0 in [0, 1] {
            let (m, mut lu) = condensed_lu(n, p0);
            let rhs: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).sin() - 0.2).collect();
            let solve = |lu: &BandLu| {
                let (x, mapped) = mapped_solve(lu, &rhs);
                let mut plain = rhs.clone();
                lu.solve(&mut plain);
                (x, mapped, plain)
            };
            let serial = solve(&lu);
            lu.parallel = crate::Parallelism::Halves { min_len: 2 };
            let split = solve(&lu);
            assert!(band_residual(&m, &serial.1, &rhs) < 1e-11);
            for (a, b) in [
                (&serial.0, &split.0),
                (&serial.1, &split.1),
                (&serial.2, &split.2),
            ] {
                assert!(same_bits(a, b), "n = {n}, p0 = {p0}: the halves differ");
            }
            assert!(serial.1.iter().zip(&serial.2).all(|(x, y)| x == y));
        }
    }
}

/// [`BandMatrix::remap`] entry by entry (its definition), for checking the whole-column copies.
fn remap_by_entry(m: &mut BandMatrix, src: &[usize], fresh_rows: &[bool]) {
    let (n, ld, diag) = (m.n, m.ld(), m.lower + m.upper);
    for j in (0..n).rev() {
        let sj = src[j];
        for i in j.saturating_sub(m.upper)..=(j + m.lower).min(n - 1) {
            let off = diag + i - j;
            let moved =
                sj != usize::MAX && !fresh_rows[i] && src[i] != usize::MAX && src[i] + j == sj + i;
            m.data[j * ld + off] = if moved { m.data[sj * ld + off] } else { 0.0 };
        }
    }
}

#[test]
fn remap_moves_whole_columns_as_it_moves_entries() {
    // insertions at the start, in the middle (adjacent and apart), at the end; fresh rows
    // around some of them; bands (1, 1), (2, 2) and (2, 1)
    for (l, u) in [(1, 1), (2, 2), (2, 1)] {
        for inserted in [
            vec![0],
            vec![5, 6],
            vec![3, 17, 40],
            vec![1, 2, 3, 30, 59],
            vec![59],
            vec![],
        ] {
            let n = 60;
            let old = n - inserted.len();
            let mut src = Vec::with_capacity(n);
            let mut next = 0;
            for i in 0..n {
                if inserted.contains(&i) {
                    src.push(usize::MAX);
                } else {
                    src.push(next);
                    next += 1;
                }
            }
            assert_eq!(next, old);
            let fresh: Vec<bool> = (0..n)
                .map(|i| inserted.iter().any(|&k| i + 2 >= k && i <= k + 1) && i % 3 != 0)
                .collect();
            // the old matrix in the grown storage (as `grow` leaves it), fill slots zero
            let mut m = filled(old, l, u);
            let ld = m.ld();
            assert!(m.grow(n));
            for j in old..n {
                for v in &mut m.data[j * ld..(j + 1) * ld] {
                    *v = 1e3 + j as f64; // stale values the map must overwrite or zero
                }
            }
            let mut reference = m.clone();
            assert!(m.remap(&src, &fresh));
            remap_by_entry(&mut reference, &src, &fresh);
            // every band entry is the definition's, bit for bit
            for j in 0..n {
                for i in j.saturating_sub(u)..=(j + l).min(n - 1) {
                    let k = j * ld + l + u + i - j;
                    assert_eq!(
                        m.data[k].to_bits(),
                        reference.data[k].to_bits(),
                        "band ({l}, {u}), inserted {inserted:?}: entry ({i}, {j})"
                    );
                }
            }
        }
    }
}
