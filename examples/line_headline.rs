//! The line's headline numbers with the accuracy each was bought at: solve time and work
//! counters at rtol 1e-6 (atol 1e-8, BDF, max norm), and the largest stretch and pressure errors
//! over every cell and output time against a tight run of the same problem (rtol 1e-10,
//! atol 1e-12 by default; `REF_RTOL=1e-8` for N ≥ 10⁵, where positions reach 10⁵–10⁶ cell
//! lengths and rounding alone, about 2ε·N, comes within 4× of a stretch tolerance of 1e-10: the
//! solver refuses such a reference, `ErrorKind::TooMuchAccuracy`; atol is always rtol/100).
//!
//! Families (docs/model.md §5.4): `macro` — the macroscale-fixed line, `l₀ = N`, `K = 1/N`,
//! exponential ramp with ramp time `N`, `k₁ = 0.1`, outputs at `t = N/4, N/2, N`; `raw` — the
//! thesis's Chapter 2 problem, `K = 1`, unit-time ramp, outputs at `t = 1, 5, 10`.
//!
//! Run: `cargo run --release --example line_headline -- FAMILY N [THREADS]`, e.g.
//! `cargo run --release --example line_headline -- macro 1000000 2`. The reference run is not
//! timed. Prints one markdown table row. `JACOBIAN_AGE=K` sets the timed run's
//! `SolveSettings::jacobian_age` (scenario key `solver.jacobian_age`; default 50), and
//! `NEWTON_ALPHA_BOUND=1` its `SolveSettings::newton_alpha_bound` (`solver.newton_alpha_bound`).

use celltissue::line::build::discrete;
use celltissue::line::run::{integrate, SolveSettings};
use celltissue::line::LineConfig;
use celltissue::{ArrayProblem, NeoHookean};
use std::time::Instant;

/// The problem and its output times.
fn family(name: &str, n: usize) -> (LineConfig, Vec<f64>) {
    let nf = n as f64;
    match name {
        "macro" => (
            LineConfig {
                cells: n,
                k: (1.0 / nf).into(),
                t_ramp: nf,
                ..Default::default()
            },
            vec![0.25 * nf, 0.5 * nf, nf],
        ),
        "raw" => (
            LineConfig {
                cells: n,
                k: 1.0.into(),
                ..Default::default()
            },
            vec![1.0, 5.0, 10.0],
        ),
        other => {
            eprintln!("unknown family {other:?}: macro | raw");
            std::process::exit(2);
        }
    }
}

/// Stretches and pressures of every cell, one pair per output time.
type Fields = Vec<(Vec<f64>, Vec<f64>)>;

/// Stretches and pressures at the output times, the solve's wall time and counters.
fn solve(
    cfg: &LineConfig,
    t_out: &[f64],
    settings: &SolveSettings,
) -> (Fields, f64, integrators::Stats) {
    let p = cfg.params(settings.atol);
    let line = discrete(NeoHookean::new(1.0).expect("valid"), &p).expect("valid line");
    let rtol = settings.rtol;
    let mut prob = ArrayProblem::new(line);
    let start = Instant::now();
    let traj = integrate(&mut prob, settings, t_out);
    let wall = start.elapsed().as_secs_f64();
    if let Some(e) = traj.error {
        eprintln!("rtol {rtol:e}: {e}");
        std::process::exit(1);
    }
    let fields = traj
        .snapshots
        .into_iter()
        .map(|s| (s.lambda, s.pressure))
        .collect();
    (fields, wall, traj.stats)
}

/// Largest |a − b| over every cell and time, for the stretch (0) or the pressure (1).
fn max_err(a: &[(Vec<f64>, Vec<f64>)], b: &[(Vec<f64>, Vec<f64>)], pressure: bool) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| {
            let (u, v) = if pressure { (&x.1, &y.1) } else { (&x.0, &y.0) };
            u.iter().zip(v).map(|(p, q)| (p - q).abs())
        })
        .fold(0.0, f64::max)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("macro");
    let n: usize = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(10_000);
    let threads: usize = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(1);
    let (cfg, t_out) = family(name, n);
    let defaults = SolveSettings::default();
    let timed = SolveSettings {
        rtol: 1e-6,
        atol: 1e-8,
        threads,
        jacobian_age: std::env::var("JACOBIAN_AGE")
            .ok()
            .and_then(|v| v.parse().ok())
            .filter(|&k: &usize| k >= 1)
            .unwrap_or(defaults.jacobian_age),
        newton_alpha_bound: std::env::var("NEWTON_ALPHA_BOUND").is_ok_and(|v| v == "1"),
        ..defaults
    };
    let (run, wall, s) = solve(&cfg, &t_out, &timed);
    let ref_rtol: f64 = std::env::var("REF_RTOL")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|v: &f64| *v > 0.0 && *v < 1e-6)
        .unwrap_or(1e-10);
    let reference_settings = SolveSettings {
        rtol: ref_rtol,
        atol: 1e-2 * ref_rtol,
        threads,
        ..defaults
    };
    let (reference, _, _) = solve(&cfg, &t_out, &reference_settings);
    println!(
        "| {name} | {n} | {threads} | {wall:.3} s | {} | {} | {} | {:.1e} | {:.1e} |",
        s.steps,
        s.newton_iterations,
        s.factorizations,
        max_err(&run, &reference, false),
        max_err(&run, &reference, true),
    );
}
