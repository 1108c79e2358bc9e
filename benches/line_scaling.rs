//! Cost of the line of cells, on the macroscale-fixed family of
//! docs/model.md §5.4 where N cells and n continuum segments resolve the same tissue problem:
//! `l₀ = N`, `K = 1/N`, exponential ramp with ramp time `N`, `k₁ = 0.1`, `t ∈ [0, N]`, BDF with
//! rtol 1e-6 (η = 0, and η = N as the viscous case). Plus the thesis's raw Chapter 2 problem
//! (K = 1, η = 0, l₀ = N, unit ramp, t ∈ [0, 10]) at N = 1000, and the linear-theory reference
//! a Fig 2.5 run records.
//!
//! Sizes 10²…10⁵ (N = 10⁶ is a one-shot run of `examples/line_accuracy_vs_cost.rs`).
//! Run: `cargo bench --bench line_scaling` (all groups), or one group, e.g.
//! `cargo bench --bench line_scaling -- discrete_vs_N`. Numbers: BENCHMARKS.md.

use celltissue::line::build::{continuum, discrete, LineParams};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::line::LineConfig;
use celltissue::{ArrayProblem, NeoHookean};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::time::Duration;

/// The macroscale-fixed family at `n_cells` cells; `viscous` sets η = N.
fn family(n_cells: usize, viscous: bool) -> LineParams {
    let n = n_cells as f64;
    let cfg = LineConfig {
        cells: n_cells,
        k: (1.0 / n).into(),
        t_ramp: n,
        eta: (if viscous { n } else { 0.0 }).into(),
        ..Default::default()
    };
    cfg.params(1e-8)
}

fn settings() -> SolveSettings {
    SolveSettings {
        rtol: 1e-6,
        atol: 1e-8,
        ..Default::default()
    }
}

/// Integrates the discrete family (or its continuum on `nodes` segments) to `t = N`; returns the
/// number of accepted steps so the work cannot be optimised away.
fn solve_family(n_cells: usize, nodes: Option<usize>, viscous: bool) -> usize {
    let p = family(n_cells, viscous);
    let law = NeoHookean::new(1.0).expect("valid modulus");
    let line = match nodes {
        None => discrete(law, &p),
        Some(m) => continuum(law, &p, m),
    }
    .expect("valid line");
    let mut prob = ArrayProblem::new(line);
    let traj = integrate(&mut prob, &settings(), &[n_cells as f64]);
    assert!(traj.error.is_none(), "{:?}", traj.error);
    traj.stats.steps
}

fn discrete_vs_n(c: &mut Criterion) {
    for (name, viscous) in [("discrete_vs_N", false), ("discrete_vs_N_viscous", true)] {
        let mut g = c.benchmark_group(name);
        g.sample_size(10).warm_up_time(Duration::from_millis(500));
        // N = 10⁶ (≈ 10 s a solve on the shared machine) is too slow for ten criterion
        // samples; its one-shot number comes from `examples/line_accuracy_vs_cost.rs`.
        for n in [100usize, 1_000, 10_000, 100_000] {
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
                b.iter(|| solve_family(n, None, viscous))
            });
        }
        g.finish();
    }
}

fn continuum_vs_n(c: &mut Criterion) {
    let mut g = c.benchmark_group("continuum_vs_n");
    g.sample_size(10).warm_up_time(Duration::from_millis(500));
    // the tissue of N = 10⁴ cells resolved on n segments
    for n in [10usize, 100, 1_000, 10_000] {
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| solve_family(10_000, Some(n), false))
        });
    }
    g.finish();
}

fn thesis_raw(c: &mut Criterion) {
    let mut g = c.benchmark_group("thesis_raw_ch2");
    g.sample_size(10);
    for n in [100usize, 1_000] {
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| {
                let cfg = LineConfig {
                    cells: n,
                    ..Default::default()
                };
                let p = cfg.params(1e-8);
                let line = discrete(NeoHookean::new(1.0).expect("valid"), &p).expect("line");
                let mut prob = ArrayProblem::new(line);
                let traj = integrate(&mut prob, &settings(), &[10.0]);
                assert!(traj.error.is_none(), "{:?}", traj.error);
                traj.stats.steps
            })
        });
    }
    g.finish();
}

/// The linear-theory reference of a Fig 2.5 run (η = 0, exponential ramp, K = 10) at `fig2_5.toml`'s
/// 122 series times: its Fourier series summed at ≤ 201 positions per time, the part of a run's
/// record outside the solve that grows with l₀ (more terms until the series converges).
fn linear_reference(c: &mut Criterion) {
    let mut g = c.benchmark_group("linear_reference_fig2_5_K10");
    g.sample_size(10);
    let series: Vec<f64> = std::iter::once(0.0)
        .chain((0..121).map(|i| 10f64.powf(-3.0 + 6.0 * i as f64 / 120.0)))
        .collect();
    for n in [100usize, 1_000] {
        let cfg = LineConfig {
            cells: n,
            k: 10.0.into(),
            ..Default::default()
        };
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                let r = celltissue::line::analytic::reference(&cfg, &series, &[0.0, 1.0, 10.0])
                    .expect("a linear-theory reference");
                r.series.t.len()
            })
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    discrete_vs_n,
    continuum_vs_n,
    thesis_raw,
    linear_reference
);
criterion_main!(benches);
