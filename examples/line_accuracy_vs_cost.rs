//! Accuracy vs cost of the continuum model on the macroscale-fixed family (docs/model.md §5.4:
//! `l₀ = N`, `K = 1/N`, ramp time `N`, `k₁ = 0.1`, compared at `t = N`): the continuum on `n`
//! segments against the discrete model with `N` cells, error in scaled positions `x/N`, next to
//! wall time and step counts — the thesis's "significant computational saving", quantified.
//!
//! Run: `cargo run --release --example line_accuracy_vs_cost [N]` (default N = 10000); the
//! environment variables `METHOD` (bdf, esdirk, radau), `RTOL` (default 1e-6) and `NORM` (max,
//! the default, or rms) override the solver.
//! `DISCRETE_ONLY=1` skips the continuum runs. Prints the work counters of the discrete run.
//! `THREADS=2` passes `threads = 2` to the solve (default 1): from 2¹⁵ unknowns the residual,
//! the BDF's vector sweeps and the tridiagonal solve then run in two halves on two threads.
//! Single-shot wall times; the criterion numbers are in `benches/line_scaling.rs`.

use celltissue::line::build::{continuum, discrete};
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::line::LineConfig;
use celltissue::{ArrayProblem, NeoHookean};
use integrators::{ErrorNorm, MethodKind};
use std::time::Instant;

/// Boundary positions at `t = N`, scaled by `N`, with the run's wall time and steps.
fn run(n_cells: usize, nodes: Option<usize>) -> (Vec<f64>, f64, integrators::Stats) {
    let nf = n_cells as f64;
    let cfg = LineConfig {
        cells: n_cells,
        k: (1.0 / nf).into(),
        t_ramp: nf,
        ..Default::default()
    };
    let p = cfg.params(1e-8);
    let law = NeoHookean::new(1.0).expect("valid");
    let line = match nodes {
        None => discrete(law, &p),
        Some(m) => continuum(law, &p, m),
    }
    .expect("valid line");
    let env = |k: &str| std::env::var(k).ok();
    let settings = SolveSettings {
        rtol: env("RTOL").and_then(|v| v.parse().ok()).unwrap_or(1e-6),
        atol: 1e-8,
        method: env("METHOD")
            .and_then(|v| v.parse().ok())
            .unwrap_or(MethodKind::Bdf.into()),
        norm: env("NORM")
            .map(|v| ErrorNorm::parse(&v).expect("NORM = max | rms"))
            .unwrap_or(ErrorNorm::Max),
        threads: env("THREADS").and_then(|v| v.parse().ok()).unwrap_or(1),
        ..Default::default()
    };
    let start = Instant::now();
    let mut prob = ArrayProblem::new(line);
    let traj = integrate(&mut prob, &settings, &[nf]);
    let wall = start.elapsed().as_secs_f64();
    if let Some(e) = traj.error {
        eprintln!("run N = {n_cells}, nodes = {nodes:?} failed: {e}");
        std::process::exit(1);
    }
    let x = traj.snapshots[0].x.iter().map(|x| x / nf).collect();
    (x, wall, traj.stats)
}

fn main() {
    let n_cells: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    let (xd, wd, sd) = run(n_cells, None);
    println!(
        "discrete N = {n_cells}: {wd:.4} s, {} steps ({:.1} ns per unknown per step)",
        sd.steps,
        wd * 1e9 / (sd.steps.max(1) as f64 * n_cells as f64)
    );
    println!("  counters: {sd:?}");
    if std::env::var("DISCRETE_ONLY").is_ok() {
        return;
    }
    println!(
        "{:>7} {:>12} {:>12} {:>10} {:>7} {:>10}",
        "n", "max|Δx|/N", "rel. to l", "wall s", "steps", "cost ratio"
    );
    for n in [10usize, 25, 50, 101, 200, 500, 1000] {
        if n > n_cells {
            continue;
        }
        let (xc, wc, sc) = run(n_cells, Some(n));
        // compare at the continuum nodes X_i = i·l₀/n, interpolating the discrete boundaries
        let h = n_cells as f64 / n as f64;
        let err = (0..=n)
            .map(|i| {
                let xr = i as f64 * h;
                let j = (xr.floor() as usize).min(n_cells - 1);
                let w = xr - j as f64;
                let xdi = (1.0 - w) * xd[j] + w * xd[j + 1];
                (xc[i] - xdi).abs()
            })
            .fold(0.0, f64::max);
        let l = xd[n_cells] - xd[0];
        println!(
            "{n:>7} {err:>12.3e} {:>12.3e} {wc:>10.4} {:>7} {:>10.1}",
            err / l,
            sc.steps,
            wd / wc
        );
    }
}
