//! Work–precision comparison with diffsol's BDF on the banded heat equation `u_t = u_xx`
//! (`sin(πx)` data, t ∈ [0, 0.05], error = max-norm distance to the exact semi-discrete
//! solution): both solvers swept over tolerances, then ours compared with diffsol *at equal
//! accuracy* — for each diffsol run, the cheapest of our runs that is at least as accurate. Equal nominal tolerances are not equal accuracy: the two codes turn `rtol`
//! into different global errors.
//!
//! Run (opt-in feature, never compiled by plain builds or CI):
//! `cargo run --release -p integrators --features diffsol-compare --example diffsol_work_precision [N ...]`
//! (default N = 1000 10000; diffsol's problem build grows like N² here, so N > 10⁴ is skipped).

#[path = "../tests/common/mod.rs"]
mod common;

use common::Heat;
use diffsol::{
    DenseMatrix, FaerSparseLU, FaerSparseMat, MatrixCommon, OdeBuilder, OdeSolverMethod,
};
use integrators::adapters::Ode;
use integrators::{MethodKind, Options, Solver};
use std::time::Instant;

const T_END: f64 = 0.05;
/// Repetitions per point (best time kept).
const REPS: usize = 3;

/// (error, seconds, steps) of our BDF at `rtol` (atol = rtol·1e-3).
fn ours(n: usize, rtol: f64) -> (f64, f64, usize) {
    let mut best = f64::INFINITY;
    let mut out = (0.0, 0);
    for _ in 0..REPS {
        let mut p = Ode(Heat {
            n,
            exact_jacobian: true,
        });
        let y0 = p.0.initial();
        let opts = Options {
            rtol,
            atol: rtol * 1e-3,
            ..Default::default()
        };
        let start = Instant::now();
        let sol = Solver::new(MethodKind::Bdf, opts)
            .solve(&mut p, 0.0, &y0, &[T_END])
            .expect("heat solve");
        best = best.min(start.elapsed().as_secs_f64());
        let err = (0..n)
            .map(|i| (sol.y[0][i] - p.0.exact_semidiscrete(T_END, i)).abs())
            .fold(0.0, f64::max);
        out = (err, sol.stats.steps);
    }
    (out.0, best, out.1)
}

/// (error, seconds of the solve only, steps) of diffsol's BDF at `rtol` (atol = rtol·1e-3).
fn theirs(n: usize, rtol: f64) -> (f64, f64, usize) {
    let inv = ((n + 1) * (n + 1)) as f64;
    let heat = Heat {
        n,
        exact_jacobian: true,
    };
    let y0 = heat.initial();
    let problem = OdeBuilder::<FaerSparseMat<f64>>::new()
        .rtol(rtol)
        .atol([rtol * 1e-3])
        .rhs_implicit(
            move |u: &[f64], _p: &[f64], _t: f64, f: &mut [f64]| laplacian(u, f, inv),
            move |_u: &[f64], _p: &[f64], _t: f64, v: &[f64], f: &mut [f64]| laplacian(v, f, inv),
        )
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
            n,
        )
        .build()
        .expect("diffsol problem");
    let mut best = f64::INFINITY;
    let mut out = (0.0, 0);
    for _ in 0..REPS {
        let start = Instant::now();
        let mut solver = problem.bdf::<FaerSparseLU<f64>>().expect("diffsol bdf");
        let (ys, _ts, _) = solver.solve(T_END).expect("diffsol solve");
        best = best.min(start.elapsed().as_secs_f64());
        let last = ys.ncols() - 1;
        let err = (0..n)
            .map(|i| (ys.get_index(i, last) - heat.exact_semidiscrete(T_END, i)).abs())
            .fold(0.0, f64::max);
        out = (err, solver.get_statistics().number_of_steps);
    }
    (out.0, best, out.1)
}

/// `f = inv·(u_{i−1} − 2u_i + u_{i+1})` with zero Dirichlet ends.
fn laplacian(u: &[f64], f: &mut [f64], inv: f64) {
    let n = u.len();
    for i in 0..n {
        let l = if i > 0 { u[i - 1] } else { 0.0 };
        let r = if i + 1 < n { u[i + 1] } else { 0.0 };
        f[i] = (l - 2.0 * u[i] + r) * inv;
    }
}

/// Our cheapest run that is at least as accurate as `e` (None if no run of the sweep is). No
/// interpolation: BDF errors are not monotone in `rtol`, so "at least as accurate, fastest" is
/// the honest reading of a work–precision sweep.
fn time_at(sweep: &[(f64, f64, usize)], e: f64) -> Option<f64> {
    sweep
        .iter()
        .filter(|&&(err, _, _)| err <= e)
        .map(|&(_, t, _)| t)
        .min_by(f64::total_cmp)
}

fn main() {
    let sizes: Vec<usize> = {
        let v: Vec<usize> = std::env::args()
            .skip(1)
            .filter_map(|a| a.parse().ok())
            .collect();
        if v.is_empty() {
            vec![1000, 10_000]
        } else {
            v
        }
    };
    for n in sizes {
        if n > 10_000 {
            println!("N = {n}: skipped (diffsol's sparsity detection costs O(N²) here)");
            continue;
        }
        let our_sweep: Vec<_> = (3..=11).map(|k| ours(n, 10f64.powi(-k))).collect();
        println!("N = {n}: ours (BDF, banded LU)");
        for (k, (e, t, s)) in (3..=11).zip(&our_sweep) {
            println!("  rtol 1e-{k:<2}  err {e:.2e}  {t:.3e} s  {s} steps");
        }
        println!("N = {n}: diffsol 0.18 BDF (faer sparse LU), solve time only");
        for k in 3..=8 {
            let (e, t, s) = theirs(n, 10f64.powi(-k));
            let cmp = match time_at(&our_sweep, e) {
                Some(ours_t) => format!(
                    "ours, at least as accurate: {ours_t:.3e} s (diffsol/ours {:.2})",
                    t / ours_t
                ),
                None => "outside our sweep".into(),
            };
            println!("  rtol 1e-{k:<2}  err {e:.2e}  {t:.3e} s  {s} steps  | {cmp}");
        }
    }
}
