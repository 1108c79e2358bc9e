//! Banded heat equation `u_t = u_xx` (central differences, tridiagonal Jacobian, N = 10³ … 10⁶
//! unknowns) through the BDF: time per step should be linear in N.
//!
//! `cargo bench -p integrators --bench heat` first prints a one-shot report (`REPORT` lines:
//! steps, seconds per step for each N, and the least-squares exponent of time/step against N;
//! target ≤ 1.1), then runs the criterion group (time per step, via `iter_custom`). Set
//! `HEAT_REPORT=0` to skip the report, `HEAT_MAX_N` to cap N (default 1e6), `THREADS=2` to pass
//! `Options::parallel = Parallelism::from_threads(2)` (default 1: benchmarks are single-threaded unless asked).
//!
//! With `--features diffsol-compare` the same problem is also solved by diffsol's BDF at equal
//! tolerances and the report prints both times and both errors against the exact semi-discrete
//! solution.

#[path = "../tests/common/mod.rs"]
mod common;

use common::Heat;
use criterion::{BenchmarkId, Criterion};
use integrators::adapters::Ode;
use integrators::{MethodKind, Options, Solver};
use std::time::{Duration, Instant};

const T_END: f64 = 0.05;

fn opts() -> Options {
    Options {
        rtol: 1e-6,
        atol: 1e-9,
        parallel: integrators::Parallelism::from_threads(threads()).expect("THREADS is 1 or 2"),
        ..Default::default()
    }
}

/// `THREADS` from the environment of the bench run (default 1).
fn threads() -> usize {
    std::env::var("THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1)
}

/// One solve: (wall time, steps, max error against the exact semi-discrete solution).
fn solve_once(n: usize) -> (Duration, usize, f64) {
    let mut p = Ode(Heat {
        n,
        exact_jacobian: true,
    });
    let y0 = p.0.initial();
    let start = Instant::now();
    let sol = Solver::new(MethodKind::Bdf, opts())
        .solve(&mut p, 0.0, &y0, &[T_END])
        .expect("heat solve");
    let el = start.elapsed();
    let err = (0..n)
        .map(|i| (sol.y[0][i] - p.0.exact_semidiscrete(T_END, i)).abs())
        .fold(0.0, f64::max);
    (el, sol.stats.steps, err)
}

fn sizes() -> Vec<usize> {
    let max: f64 = std::env::var("HEAT_MAX_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1e6);
    [1e3, 1e4, 1e5, 1e6]
        .into_iter()
        .filter(|&n| n <= max)
        .map(|n| n as usize)
        .collect()
}

fn report() {
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for n in sizes() {
        let reps = if n >= 1_000_000 { 3 } else { 5 };
        let mut best = f64::INFINITY;
        let mut steps = 0;
        let mut err = 0.0;
        for _ in 0..reps {
            let (t, s, e) = solve_once(n);
            best = best.min(t.as_secs_f64() / s as f64);
            steps = s;
            err = e;
        }
        println!(
            "REPORT heat bdf N={n:>8} steps={steps} s/step={best:.3e} ns/step/unknown={:.1} err={err:.2e}",
            best / n as f64 * 1e9
        );
        xs.push((n as f64).ln());
        ys.push(best.ln());
        #[cfg(feature = "diffsol-compare")]
        diffsol_cmp::report(n);
    }
    if xs.len() >= 2 {
        let m = xs.len() as f64;
        let mx = xs.iter().sum::<f64>() / m;
        let my = ys.iter().sum::<f64>() / m;
        let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
        println!(
            "REPORT heat bdf fitted exponent (time/step ~ N^p): p = {:.3}",
            sxy / sxx
        );
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("heat_bdf_time_per_step");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(3));
    for n in sizes() {
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let (t, steps, _) = solve_once(n);
                    total += t / steps as u32;
                }
                total
            })
        });
    }
    g.finish();
}

fn main() {
    if std::env::var("HEAT_REPORT")
        .map(|v| v != "0")
        .unwrap_or(true)
    {
        report();
    }
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}

#[cfg(feature = "diffsol-compare")]
mod diffsol_cmp {
    //! The same problem through diffsol's BDF (faer sparse matrices and sparse LU, Jacobian
    //! from the exact Jacobian-vector product with diffsol's colouring), equal tolerances.
    use super::{Heat, T_END};
    use diffsol::{
        DenseMatrix, FaerSparseLU, FaerSparseMat, MatrixCommon, OdeBuilder, OdeSolverMethod,
    };
    use std::time::Instant;

    type M = FaerSparseMat<f64>;

    pub fn report(n: usize) {
        if n > 10_000 {
            println!(
                "REPORT heat diffsol-bdf N={n:>8} skipped: building the problem costs O(N²) \
                 (sparsity detection) and panicked in faer at N = 1e5"
            );
            return;
        }
        let inv = ((n + 1) * (n + 1)) as f64;
        let heat = Heat {
            n,
            exact_jacobian: true,
        };
        let y0 = heat.initial();
        let start = Instant::now();
        let problem = OdeBuilder::<M>::new()
            .rtol(super::opts().rtol)
            .atol([super::opts().atol])
            .rhs_implicit(
                move |u: &[f64], _p: &[f64], _t: f64, f: &mut [f64]| {
                    let n = u.len();
                    for i in 0..n {
                        let l = if i > 0 { u[i - 1] } else { 0.0 };
                        let r = if i + 1 < n { u[i + 1] } else { 0.0 };
                        f[i] = (l - 2.0 * u[i] + r) * inv;
                    }
                },
                move |_u: &[f64], _p: &[f64], _t: f64, v: &[f64], f: &mut [f64]| {
                    let n = v.len();
                    for i in 0..n {
                        let l = if i > 0 { v[i - 1] } else { 0.0 };
                        let r = if i + 1 < n { v[i + 1] } else { 0.0 };
                        f[i] = (l - 2.0 * v[i] + r) * inv;
                    }
                },
            )
            .init(
                move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
                n,
            )
            .build()
            .expect("diffsol problem");
        let built = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let mut solver = problem.bdf::<FaerSparseLU<f64>>().expect("diffsol bdf");
        let (ys, _ts, _) = solver.solve(T_END).expect("diffsol solve");
        let el = start.elapsed().as_secs_f64();
        let last = ys.ncols() - 1;
        let err = (0..n)
            .map(|i| (ys.get_index(i, last) - heat.exact_semidiscrete(T_END, i)).abs())
            .fold(0.0, f64::max);
        let steps = solver.get_statistics().number_of_steps;
        println!(
            "REPORT heat diffsol-bdf N={n:>8} steps={steps} build={built:.3e}s solve={el:.3e}s \
             s/step={:.3e} err={err:.2e}",
            el / steps as f64
        );
    }
}
