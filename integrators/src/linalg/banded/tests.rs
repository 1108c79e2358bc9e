//! Tests of the banded LU and its tridiagonal special case against dense references.

use super::tridiagonal::*;
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
