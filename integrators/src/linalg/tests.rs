//! Unit tests of the linear algebra: banded and sparse LU against dense LU, singular and NaN
//! input, symbolic reuse, the banded operation count and the complex-pair construction.

use std::sync::Arc;

use super::*;
use crate::pattern::SparsityPattern;

/// Small deterministic generator (xorshift64*), values in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn to_dense(m: &Matrix) -> Matrix {
    let n = m.n();
    let mut d = Matrix::zeros(n, &Pattern::Dense);
    for j in 0..n {
        for i in 0..n {
            d.add(i, j, m.get(i, j));
        }
    }
    d
}

fn solve(m: &Matrix, pattern: &Pattern, b: &[f64]) -> Result<Vec<f64>, usize> {
    let mut lu = LinearSolver::new(m.n(), pattern);
    lu.factor(m)?;
    let mut x = b.to_vec();
    lu.solve_in_place(&mut x);
    Ok(x)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn residual_norm(m: &Matrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    m.mul_vec(x, &mut ax);
    max_diff(&ax, b)
}

fn random_band(rng: &mut Rng, n: usize, l: usize, u: usize, dominant: bool) -> Matrix {
    let p = Pattern::Banded { lower: l, upper: u };
    let mut m = Matrix::zeros(n, &p);
    for j in 0..n {
        for i in p.column_rows(n, j) {
            let mut v = rng.next();
            if i == j {
                v = if dominant {
                    2.0 * (l + u + 1) as f64 + v
                } else if l == 0 || u == 0 {
                    // triangular: keep it well conditioned, but not dominant
                    1.0 + 0.5 * v
                } else if j % 3 == 0 {
                    0.0 // forces a row interchange
                } else {
                    1e-3 * v
                };
            }
            m.add(i, j, v);
        }
    }
    m
}

#[test]
fn banded_lu_matches_dense_lu() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let shapes = [
        (1, 0, 0),
        (1, 2, 3),
        (2, 1, 0),
        (5, 0, 0),
        (7, 0, 2),
        (7, 2, 0),
        (10, 1, 1),
        (12, 2, 3),
        (20, 3, 1),
        (9, 8, 8),
        (40, 4, 2),
    ];
    let mut checked = 0;
    for &(n, l, u) in &shapes {
        for dominant in [true, false] {
            let p = Pattern::Banded { lower: l, upper: u };
            let m = random_band(&mut rng, n, l, u, dominant);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let d = to_dense(&m);
            let Ok(xd) = solve(&d, &Pattern::Dense, &b) else {
                // a singular draw (only possible for 1×1 with zero diagonal): banded must agree
                assert!(solve(&m, &p, &b).is_err(), "n={n} l={l} u={u}");
                continue;
            };
            let xb = solve(&m, &p, &b).expect("banded factor");
            let scale = xd.iter().fold(1.0f64, |a, x| a.max(x.abs()));
            assert!(
                max_diff(&xb, &xd) <= 1e-10 * scale,
                "n={n} l={l} u={u} dominant={dominant}: {:e}",
                max_diff(&xb, &xd)
            );
            assert!(residual_norm(&m, &xb, &b) < 1e-11 * scale);
            checked += 1;
        }
    }
    assert!(checked >= 20, "{checked}");
}

#[test]
fn banded_lu_pivots_on_zero_diagonal() {
    // [[0, 1], [1, 0]] needs a row interchange
    let p = Pattern::Banded { lower: 1, upper: 1 };
    let mut m = Matrix::zeros(2, &p);
    m.add(0, 1, 1.0);
    m.add(1, 0, 1.0);
    let x = solve(&m, &p, &[2.0, 3.0]).unwrap();
    assert_eq!(x, vec![3.0, 2.0]);
}

#[test]
fn banded_lu_cost_is_linear_in_n() {
    let mut rng = Rng(7);
    let (l, u) = (2, 3);
    let p = Pattern::Banded { lower: l, upper: u };
    let mut flops = Vec::new();
    for n in [200, 400, 800] {
        for dominant in [true, false] {
            let m = random_band(&mut rng, n, l, u, dominant);
            let mut lu = LinearSolver::new(n, &p);
            lu.factor(&m).unwrap();
            let f = lu.last_factor_flops();
            // at most l multiply-adds for each of at most l+u columns right of the pivot
            assert!(f <= n * l * (l + u), "n={n}: {f}");
            assert!(f >= n * l, "n={n}: {f}");
            if dominant {
                flops.push(f);
            }
        }
    }
    // doubling n doubles the work (up to the boundary columns)
    for w in flops.windows(2) {
        let ratio = w[1] as f64 / w[0] as f64;
        assert!((ratio - 2.0).abs() < 0.05, "{ratio}");
    }
}

#[test]
fn singular_and_nan_matrices_are_errors() {
    // dense: rank 1
    let mut d = Matrix::zeros(2, &Pattern::Dense);
    d.add(0, 0, 1.0);
    d.add(0, 1, 2.0);
    d.add(1, 0, 2.0);
    d.add(1, 1, 4.0);
    assert_eq!(solve(&d, &Pattern::Dense, &[1.0, 1.0]), Err(1));
    // banded: zero column 2
    let p = Pattern::Banded { lower: 1, upper: 1 };
    let mut b = Matrix::zeros(4, &p);
    for i in 0..4 {
        if i != 2 {
            b.add(i, i, 1.0);
        }
    }
    assert_eq!(solve(&b, &p, &[1.0; 4]), Err(2));
    // sparse: zero column 3
    let sp = cyclic(6);
    let ps = Pattern::Sparse(sp.clone());
    let mut s = Matrix::zeros(6, &ps);
    for i in 0..6 {
        if i != 3 {
            s.add(i, i, 2.0);
            s.add((i + 1) % 6, i, 0.5);
        }
    }
    assert!(solve(&s, &ps, &[1.0; 6]).is_err());
    // NaN / inf anywhere: Err naming the column, never a panic
    for (pattern, mut m) in [
        (Pattern::Dense, Matrix::zeros(3, &Pattern::Dense)),
        (p.clone(), Matrix::zeros(3, &p)),
        (
            Pattern::Sparse(cyclic(3)),
            Matrix::zeros(3, &Pattern::Sparse(cyclic(3))),
        ),
    ] {
        for i in 0..3 {
            m.add(i, i, 1.0);
        }
        m.add(2, 1, f64::NAN);
        assert_eq!(solve(&m, &pattern, &[1.0; 3]), Err(1), "{pattern:?}");
        m.set(2, 1, 0.0);
        m.set(0, 0, f64::INFINITY);
        assert_eq!(solve(&m, &pattern, &[1.0; 3]), Err(0), "{pattern:?}");
        m.set(0, 0, 1.0);
        assert_eq!(
            solve(&m, &pattern, &[1.0, 2.0, 3.0]),
            Ok(vec![1.0, 2.0, 3.0])
        );
    }
}

fn cyclic(n: usize) -> Arc<SparsityPattern> {
    let mut e = Vec::new();
    for i in 0..n {
        e.push((i, (i + 1) % n));
        e.push(((i + 1) % n, i));
    }
    Arc::new(SparsityPattern::from_entries(n, &e))
}

fn random_sparse(rng: &mut Rng, n: usize, per_col: usize) -> Arc<SparsityPattern> {
    let mut e = Vec::new();
    for j in 0..n {
        for _ in 0..per_col {
            let i = (((rng.next() + 1.0) * 0.5) * n as f64) as usize % n;
            e.push((i, j));
        }
    }
    Arc::new(SparsityPattern::from_entries(n, &e))
}

fn fill_random(rng: &mut Rng, m: &mut Matrix, diag: f64) {
    let n = m.n();
    for j in 0..n {
        for i in m.column_rows(j) {
            let v = if i == j {
                diag + 0.1 * rng.next()
            } else {
                rng.next()
            };
            m.set(i, j, v);
        }
    }
}

#[test]
fn sparse_lu_matches_dense_and_reuses_symbolic() {
    let mut rng = Rng(99);
    for (name, sp) in [
        ("random", random_sparse(&mut rng, 60, 4)),
        ("cyclic", cyclic(12)),
        ("random-big", random_sparse(&mut rng, 400, 3)),
    ] {
        let n = sp.n();
        let p = Pattern::Sparse(sp);
        let mut lu = LinearSolver::new(n, &p);
        let mut m = Matrix::zeros(n, &p);
        for (round, diag) in [0.05, 3.0, 0.0].into_iter().enumerate() {
            fill_random(&mut rng, &mut m, diag);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let xd = match solve(&to_dense(&m), &Pattern::Dense, &b) {
                Ok(x) => x,
                Err(_) => continue,
            };
            lu.factor(&m).expect("sparse factor");
            assert_eq!(lu.last_factor_was_symbolic(), round == 0, "{name}");
            let mut x = b.clone();
            lu.solve_in_place(&mut x);
            let scale = xd.iter().fold(1.0f64, |a, x| a.max(x.abs()));
            assert!(
                max_diff(&x, &xd) < 1e-9 * scale,
                "{name} round {round}: {:e}",
                max_diff(&x, &xd)
            );
        }
    }
}

#[test]
fn matrix_ops() {
    let sp = cyclic(5);
    for p in [
        Pattern::Dense,
        Pattern::Banded { lower: 1, upper: 2 },
        Pattern::Sparse(sp),
    ] {
        let mut a = Matrix::zeros(5, &p);
        let mut rng = Rng(5);
        fill_random(&mut rng, &mut a, 2.0);
        let b = {
            let mut b = a.clone();
            fill_random(&mut rng, &mut b, 1.0);
            b
        };
        let x: Vec<f64> = (0..5).map(|i| i as f64 - 1.5).collect();
        let (mut ya, mut yb, mut yc) = (vec![0.0; 5], vec![0.0; 5], vec![0.0; 5]);
        a.mul_vec(&x, &mut ya);
        b.mul_vec(&x, &mut yb);
        let mut c = a.clone();
        c.axpby(2.0, -3.0, &b);
        c.mul_vec(&x, &mut yc);
        for i in 0..5 {
            assert!((yc[i] - (2.0 * ya[i] - 3.0 * yb[i])).abs() < 1e-13);
            let manual: f64 = (0..5).map(|j| a.get(i, j) * x[j]).sum();
            assert!((manual - ya[i]).abs() < 1e-13);
        }
        assert_eq!(
            a.get(4, 0),
            if matches!(p, Pattern::Banded { .. }) {
                0.0
            } else {
                a.get(4, 0)
            }
        );
        c.set_zero();
        assert!((0..5).all(|i| (0..5).all(|j| c.get(i, j) == 0.0)));
    }
}

// ---- complex pair ----

type C = (f64, f64);
fn cmul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn cdiv(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// Complex Gaussian elimination with partial pivoting (independent reference).
fn complex_solve(mut a: Vec<Vec<C>>, mut b: Vec<C>) -> Vec<C> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| {
                let (x, y) = (a[i][k], a[j][k]);
                (x.0.hypot(x.1)).partial_cmp(&y.0.hypot(y.1)).unwrap()
            })
            .unwrap();
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..n {
            let f = cdiv(a[i][k], a[k][k]);
            let pivot_row = a[k].clone();
            for (aij, &akj) in a[i][k..].iter_mut().zip(&pivot_row[k..]) {
                let t = cmul(f, akj);
                *aij = (aij.0 - t.0, aij.1 - t.1);
            }
            let t = cmul(f, b[k]);
            b[i] = (b[i].0 - t.0, b[i].1 - t.1);
        }
    }
    let mut x = vec![(0.0, 0.0); n];
    for k in (0..n).rev() {
        let mut s = b[k];
        for j in k + 1..n {
            let t = cmul(a[k][j], x[j]);
            s = (s.0 - t.0, s.1 - t.1);
        }
        x[k] = cdiv(s, a[k][k]);
    }
    x
}

#[test]
fn complex_pair_solves_the_complex_system() {
    let mut rng = Rng(2024);
    let n = 7;
    let (alpha, beta) = (2.68, 3.05);
    for p in [
        Pattern::Dense,
        Pattern::Banded { lower: 1, upper: 2 },
        Pattern::Banded { lower: 0, upper: 0 },
        Pattern::Sparse(cyclic(n)),
    ] {
        let mut j0 = Matrix::zeros(n, &p);
        let mut j1 = Matrix::zeros(n, &p);
        fill_random(&mut rng, &mut j0, 0.3);
        fill_random(&mut rng, &mut j1, 1.0);
        let cp = complex_pair_pattern(n, &p);
        if let Pattern::Banded { lower, upper } = p {
            assert_eq!(
                cp,
                Pattern::Banded {
                    lower: 2 * lower + 1,
                    upper: 2 * upper + 1
                }
            );
        }
        let mut big = Matrix::zeros(2 * n, &cp);
        fill_complex_pair(&j0, &j1, alpha, beta, &mut big);
        let b: Vec<C> = (0..n).map(|_| (rng.next(), rng.next())).collect();
        let mut x: Vec<f64> = b.iter().flat_map(|&(re, im)| [re, im]).collect();
        let mut lu = LinearSolver::new(2 * n, &cp);
        lu.factor(&big).unwrap();
        lu.solve_in_place(&mut x);
        let a: Vec<Vec<C>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let (g0, g1) = (j0.get(i, j), j1.get(i, j));
                        (g0 + alpha * g1, beta * g1)
                    })
                    .collect()
            })
            .collect();
        let z = complex_solve(a, b);
        for k in 0..n {
            assert!(
                (x[2 * k] - z[k].0).abs() < 1e-12 && (x[2 * k + 1] - z[k].1).abs() < 1e-12,
                "{p:?} k={k}: ({}, {}) vs {:?}",
                x[2 * k],
                x[2 * k + 1],
                z[k]
            );
        }
    }
}

#[test]
fn twisted_tridiagonal_lu_matches_dense_lu() {
    // the two-ended tridiagonal path at every small size (both halves, the twist rows and the
    // odd/even split), on matrices that are not diagonally dominant and on ones whose diagonal
    // is zero (every step must pivot), against faer's dense LU
    let mut rng = Rng(11);
    let p = Pattern::Banded { lower: 1, upper: 1 };
    let mut checked = 0;
    for n in (2..=41).chain([100, 257]) {
        for kind in 0..3 {
            let mut m = random_band(&mut rng, n, 1, 1, kind == 0);
            if kind == 2 {
                for i in 0..n {
                    m.set(i, i, 0.0);
                }
            }
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let d = to_dense(&m);
            let Ok(xd) = solve(&d, &Pattern::Dense, &b) else {
                // a singular draw (zero diagonal, odd n): the banded path must say so too
                assert!(solve(&m, &p, &b).is_err(), "n={n} kind={kind}");
                continue;
            };
            let xb = solve(&m, &p, &b).expect("nonsingular");
            let scale = xd.iter().fold(1.0f64, |a, x| a.max(x.abs()));
            assert!(max_diff(&xb, &xd) <= 1e-9 * scale, "n={n} kind={kind}");
            assert!(
                residual_norm(&m, &xb, &b) <= 1e-10 * scale,
                "n={n} kind={kind}"
            );
            // the fused map sees every component once, with its own index
            let mut lu = LinearSolver::new(n, &p);
            lu.factor(&m).unwrap();
            struct Record(Vec<Option<f64>>);
            impl crate::linalg::SolutionMap for Record {
                fn map(&mut self, j: usize, x: f64) -> f64 {
                    assert!(self.0[j].is_none(), "component {j} mapped twice");
                    self.0[j] = Some(x);
                    2.0 * x
                }
            }
            let mut x2 = b.clone();
            let rec = lu.solve_in_place_map(&mut x2, None, Record(vec![None; n]));
            for j in 0..n {
                assert_eq!(rec.0[j], Some(xb[j]), "n={n} j={j}");
                assert_eq!(x2[j], 2.0 * xb[j]);
            }
            checked += 1;
        }
    }
    assert!(checked >= 100, "{checked}");
}

#[test]
fn twisted_tridiagonal_combination_and_errors() {
    // factor_combination (A + β·B streamed into the factors) agrees with factorising the sum;
    // a NaN or a zero column anywhere (either half, or the twist) is Err(that column)
    let mut rng = Rng(5);
    let p = Pattern::Banded { lower: 1, upper: 1 };
    for n in [2, 3, 4, 9, 10, 33] {
        let a = random_band(&mut rng, n, 1, 1, false);
        let bm = random_band(&mut rng, n, 1, 1, false);
        let beta = 0.37;
        let mut sum = Matrix::zeros(n, &p);
        sum.axpby(1.0, 1.0, &a);
        sum.axpby(1.0, beta, &bm);
        let rhs: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let Ok(x_sum) = solve(&sum, &p, &rhs) else {
            continue;
        };
        let mut lu = LinearSolver::new(n, &p);
        let mut scratch = Matrix::zeros(n, &p);
        lu.factor_combination(&a, beta, &bm, &mut scratch).unwrap();
        let mut x = rhs.clone();
        lu.solve_in_place(&mut x);
        assert_eq!(x, x_sum, "n={n}");
        for col in 0..n {
            let mut bad = sum.clone();
            bad.set(col, col, f64::NAN);
            assert_eq!(solve(&bad, &p, &rhs), Err(col), "NaN n={n} col={col}");
            let mut zero = sum.clone();
            for i in col.saturating_sub(1)..(col + 2).min(n) {
                zero.set(i, col, 0.0);
            }
            assert_eq!(
                solve(&zero, &p, &rhs),
                Err(col),
                "zero column n={n} col={col}"
            );
        }
    }
}

#[test]
fn first_non_finite_finds_the_first_in_any_block() {
    // every position around the 64-entry blocks, each kind of non-finite value, two of them
    for n in [0, 1, 63, 64, 65, 200] {
        let clean = vec![1.5; n];
        assert_eq!(super::first_non_finite(&clean), None, "n={n}");
        for i in 0..n {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut v = clean.clone();
                v[i] = bad;
                if i + 70 < n {
                    v[i + 70] = f64::NAN;
                }
                assert_eq!(super::first_non_finite(&v), Some(i), "n={n} i={i} {bad}");
            }
        }
    }
    // the largest finite values are finite
    assert_eq!(
        super::first_non_finite(&[f64::MAX, -f64::MAX, f64::MIN_POSITIVE]),
        None
    );
}

/// A tridiagonal solution that decays geometrically (ratio 2 − √3 ≈ 0.27 per row) from a unit
/// right-hand side at row 0 reaches the subnormal range after about 540 rows: the solve flushes
/// it to exact zeros there (no subnormal arithmetic) and the result still solves the system to
/// rounding, since what was dropped is below 2.2e-308.
#[test]
fn tridiagonal_solve_flushes_the_subnormal_tail_to_zero() {
    let n = 1000;
    let pattern = Pattern::Banded { lower: 1, upper: 1 };
    let mut m = Matrix::zeros(n, &pattern);
    for i in 0..n {
        m.set(i, i, 4.0);
        if i + 1 < n {
            m.set(i, i + 1, -1.0);
            m.set(i + 1, i, -1.0);
        }
    }
    let mut b = vec![0.0; n];
    b[0] = 1.0;
    let x = solve(&m, &pattern, &b).unwrap();
    assert!(x.iter().all(|v| *v == 0.0 || v.abs() >= f64::MIN_POSITIVE));
    let zeros = x.iter().filter(|v| **v == 0.0).count();
    assert!((400..=500).contains(&zeros), "{zeros} zeros");
    assert!(x[100] > 0.0 && x[100] < 1e-50); // the normal part of the tail is kept
    assert!(residual_norm(&m, &x, &b) <= 1e-15);
}
